// Implicit Euler's resting contacts (integrators/implicit_euler.h, "Particles resting on an
// obstacle"): which particles a step holds on their surface, along the normal only (sliding) or
// in all three directions (sticking), the checks after the solve, and the impulses handed back to
// the collision stage.
#include <algorithm>
#include <cmath>

#include "integrators/implicit_euler.h"

namespace clothsim {

void ImplicitEuler::set_hold(std::size_t p, Hold hold, const Vec3& normal) {
  hold_[p] = hold;
  held_normal_[p] = hold == Hold::none ? Vec3{} : normal;
  const Mat3& diagonal = block_[diagonal_block(p)];
  switch (hold) {
    case Hold::none: preconditioner_[p] = inverse(diagonal); break;
    case Hold::normal: {
      // Block Jacobi on the two free directions: the inverse of S D S, completed by n n^T so that
      // it is invertible (the filter removes n again). With D symmetric,
      // S D S = D - n (D n)^T - (D n) n^T + (n . D n) n n^T.
      const Vec3 dn = diagonal * normal;
      preconditioner_[p] =
          inverse(diagonal - outer(normal, dn) - outer(dn, normal) + (dot(normal, dn) + 1.0) * outer(normal, normal));
      break;
    }
    case Hold::all: preconditioner_[p] = Mat3{}; break;
  }
}

void ImplicitEuler::hold_on_surfaces(const ClothState& state, double h) {
  holding_ = false;
  const SurfaceContacts* contacts = surface_contacts_;
  if (contacts == nullptr || !contacts->any) return;
  const std::size_t n = model_.particle_count();
  for (std::size_t p = 0; p < n; ++p) {
    hold_[p] = Hold::none;
    held_normal_[p] = Vec3{};
    if (!free_[p] || contacts->collider[p] == SurfaceContacts::kNone) continue;
    const Vec3& normal = contacts->normal[p];
    const Vec3& surface_velocity = contacts->velocity[p];
    const Vec3 relative = state.velocity[p] - surface_velocity;
    // Held when the explicit prediction of the step's end velocity moves it into the surface.
    const double mass = model_.particle_mass[p];
    const Vec3 predicted = relative + (h / mass) * force_[p];
    if (dot(predicted, normal) >= 0.0) continue;
    // Stuck when friction can stop its slide and hold it against the tangential force within the
    // step: |m v_t / h + f_t| <= mu |f_n|, the force along the normal f_n pressing it on.
    const double pressing = -dot(force_[p], normal) - dot(relative, normal) * mass / h;  // N, >= 0 here
    const Vec3 slide = mass / h * relative + force_[p];
    const Vec3 tangential = slide - dot(slide, normal) * normal;
    // A particle the last step found needing more than that slides in this one.
    const bool stuck = !slipped_[p] && norm(tangential) <= contacts->friction[p] * std::max(0.0, pressing);
    slipped_[p] = 0;
    set_hold(p, stuck ? Hold::all : Hold::normal, normal);
    holding_ = true;
    // The held part of dv is known: the step ends moving with the surface, along the normal or
    // altogether.
    const Vec3 to_surface = surface_velocity - state.velocity[p];
    dv_[p] = stuck ? to_surface : dv_[p] - dot(dv_[p], normal) * normal + dot(to_surface, normal) * normal;
  }
}

bool ImplicitEuler::release_held_particles() {
  if (!holding_) return false;
  bool changed = false;
  const std::size_t n = model_.particle_count();
  for (std::size_t p = 0; p < n; ++p) {
    if (hold_[p] == Hold::none) continue;
    const Vec3 normal = held_normal_[p];
    // The impulse the surface exerts, A dv - b: a surface cannot pull, and friction cannot exceed
    // mu times the normal impulse (Coulomb): then the particle slides.
    const Vec3 impulse = row_product(p, dv_) - rhs_[p];
    const double pressing = dot(normal, impulse);
    if (pressing < 0.0) {
      set_hold(p, Hold::none, normal);
      changed = true;
    } else if (hold_[p] == Hold::all && norm(impulse - pressing * normal) > surface_contacts_->friction[p] * pressing) {
      // Held by more than Coulomb's friction: it slides from the next step on. (Solving again for
      // it, as for a pulling surface, took a second solve in most steps of a sheet on a table.)
      slipped_[p] = 1;
    }
  }
  return changed;
}

void ImplicitEuler::book_surface_impulses(ClothState& state) {
  if (!holding_) return;
  SurfaceContacts& contacts = *surface_contacts_;
  const std::size_t n = model_.particle_count();
  double work = 0.0;
  for (std::size_t p = 0; p < n; ++p) {
    if (hold_[p] == Hold::none) continue;
    const Vec3 normal = held_normal_[p];
    Vec3 impulse = row_product(p, dv_) - rhs_[p];  // N s
    if (hold_[p] == Hold::normal) impulse = dot(normal, impulse) * normal;
    contacts.impulse[p] = std::max(0.0, dot(normal, impulse));
    // Its work, with the end-of-step velocity like the other work integrals: zero on a surface at
    // rest, where the particle ends with no normal velocity (and, stuck, no velocity at all).
    work += dot(impulse, state.velocity[p]);
  }
  state.contact_work += work;
}

}  // namespace clothsim

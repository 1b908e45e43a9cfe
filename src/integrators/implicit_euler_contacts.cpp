// Implicit Euler's resting contacts (integrators/implicit_euler.h, "Particles resting on an
// obstacle"): which particles a step holds on their surface, along the normal only (sliding) or
// in all three directions (sticking), the checks after the solve, and the impulses handed back to
// the collision stage.
#include <algorithm>
#include <cmath>

#include "integrators/implicit_euler.h"

namespace clothsim {

void ImplicitEuler::hold_on_surfaces(const ClothState& state, double h) {
  system_.holding = false;
  const SurfaceContacts* contacts = surface_contacts_;
  if (contacts == nullptr || !contacts->any) return;
  const std::size_t n = model_.particle_count();
  for (std::size_t p = 0; p < n; ++p) {
    system_.hold[p] = Hold::none;
    system_.held_normal[p] = Vec3{};
    if (!system_.free[p] || contacts->collider[p] == SurfaceContacts::kNone) continue;
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
    system_.set_hold(p, stuck ? Hold::all : Hold::normal, normal);
    system_.holding = true;
    // The held part of dv is known: the step ends moving with the surface, along the normal or
    // altogether.
    const Vec3 to_surface = surface_velocity - state.velocity[p];
    Vec3& dv = system_.solution[p];
    dv = stuck ? to_surface : dv - dot(dv, normal) * normal + dot(to_surface, normal) * normal;
  }
}

bool ImplicitEuler::release_held_particles() {
  if (!system_.holding) return false;
  bool changed = false;
  const std::size_t n = model_.particle_count();
  for (std::size_t p = 0; p < n; ++p) {
    if (system_.hold[p] == Hold::none) continue;
    const Vec3 normal = system_.held_normal[p];
    // The impulse the surface exerts, A dv - b: a surface cannot pull, and friction cannot exceed
    // mu times the normal impulse (Coulomb): then the particle slides.
    const Vec3 impulse = system_.row_product(p, system_.solution) - system_.rhs[p];
    const double pressing = dot(normal, impulse);
    if (pressing < 0.0) {
      system_.set_hold(p, Hold::none, normal);
      changed = true;
    } else if (system_.hold[p] == Hold::all && norm(impulse - pressing * normal) > surface_contacts_->friction[p] * pressing) {
      // Held by more than Coulomb's friction: it slides from the next step on. (Solving again for
      // it, as for a pulling surface, took a second solve in most steps of a sheet on a table.)
      slipped_[p] = 1;
    }
  }
  return changed;
}

void ImplicitEuler::book_surface_impulses(ClothState& state) {
  if (!system_.holding) return;
  SurfaceContacts& contacts = *surface_contacts_;
  const std::size_t n = model_.particle_count();
  double work = 0.0;
  for (std::size_t p = 0; p < n; ++p) {
    if (system_.hold[p] == Hold::none) continue;
    const Vec3 normal = system_.held_normal[p];
    Vec3 impulse = system_.row_product(p, system_.solution) - system_.rhs[p];  // N s
    if (system_.hold[p] == Hold::normal) impulse = dot(normal, impulse) * normal;
    contacts.impulse[p] = std::max(0.0, dot(normal, impulse));
    // Its work, with the end-of-step velocity like the other work integrals: zero on a surface at
    // rest, where the particle ends with no normal velocity (and, stuck, no velocity at all).
    work += dot(impulse, state.velocity[p]);
  }
  state.contact_work += work;
}

}  // namespace clothsim

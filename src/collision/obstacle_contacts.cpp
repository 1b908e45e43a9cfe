#include "collision/obstacle_contacts.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/parallel.h"
#include "core/shared_text.h"

namespace clothsim {
namespace {

// The contact law, the text the device's obstacle pass compiles as well: the collider at the
// step's end is the collider and that time, and its surface signed_distance()'s.
namespace law {
using Real = double;
using std::max;
struct ObstacleAtStepEnd {
  const Collider* collider;
  double time;  // s
};
inline SurfaceDistance obstacle_surface(const ObstacleAtStepEnd& obstacle, const Vec3& x) {
  return signed_distance(*obstacle.collider, x, obstacle.time);
}
#include "collision/obstacle_contact.inc"
}  // namespace law

// Resolves one particle against one collider between t0 and t1 (collision/obstacle_contact.inc).
void resolve(double mu, double thickness, double t0, double t1, const Collider& collider, const Vec3& start,
             double held, law::ParticleContact& particle) {
  const Vec3 start_in_frame = start + (collider.path.position(t1) - collider.path.position(t0));
  law::resolve_obstacle_contact(mu, thickness, t1 - t0, law::ObstacleAtStepEnd{&collider, t1}, start_in_frame, held,
                                particle);
}

}  // namespace

void ObstacleContacts::resize(const ClothModel& model) {
  const std::size_t n = model.particle_count();
  if (moved_.size() == n) return;
  resolved_position_.assign(n, Vec3{0.0, 0.0, 0.0});
  resolved_velocity_.assign(n, Vec3{0.0, 0.0, 0.0});
  moved_.assign(n, 0);
  arrival_.assign(n, 0.0);
  surface_.resize(n);
}

double ObstacleContacts::begin_step(const ClothModel& model, const ClothState& state, int threads) {
  if (model.colliders.empty()) {
    surface_.any = false;
    return std::numeric_limits<double>::infinity();
  }
  resize(model);
  const double thickness = model.collision.thickness;
  const double depth = law::impact_depth(thickness);  // m
  parallel_for(model.particle_count(), threads, [&](std::size_t p) {
    arrival_[p] = std::numeric_limits<double>::infinity();
    surface_.collider[p] = SurfaceContacts::kNone;
    surface_.impulse[p] = 0.0;
    if (model.is_anchored(p)) return;
    for (std::size_t c = 0; c < model.colliders.size(); ++c) {
      const SurfaceDistance surface = signed_distance(model.colliders[c], state.position[p], state.time);
      // A particle already within the shell is in contact, not approaching one: the pass resolves
      // it where it ends, without a sweep. (After this pass every particle is at the thickness with
      // no approach; one within it and approaching was pressed there by the self-collision pass,
      // which runs after this one, and limiting the step for it halved the steps of `pile`.) An
      // integrator may hold it on the surface during the step (model/surface_contacts.h).
      if (law::within_shell(surface, thickness)) {
        if (surface_.collider[p] == SurfaceContacts::kNone) {
          surface_.collider[p] = static_cast<std::uint32_t>(c);
          surface_.normal[p] = surface.normal;
          surface_.velocity[p] = surface.velocity;
          surface_.friction[p] = collider_friction(model.colliders[c], model.collision);
        }
        continue;
      }
      const double arrival = law::arrival_time(surface, state.velocity[p], thickness, depth);  // s
      if (arrival >= 0.0) arrival_[p] = std::min(arrival_[p], arrival);
    }
  });
  surface_.any = std::any_of(surface_.collider.begin(), surface_.collider.end(),
                             [](std::uint32_t c) { return c != SurfaceContacts::kNone; });
  // The minimum does not depend on the order, so a serial pass over the per-particle values is
  // the same for any thread count.
  double arrival = std::numeric_limits<double>::infinity();
  for (double a : arrival_) arrival = std::min(arrival, a);
  const double limit = state.time + arrival;
  // A limit that rounds to the current time (a huge approach speed late in a long run) is no
  // limit: the step must move time forward.
  return limit > state.time ? limit : std::numeric_limits<double>::infinity();
}

ContactCounts ObstacleContacts::apply(const ClothModel& model, ClothState& state, std::span<const Vec3> start,
                                      double start_time, ForceTerms terms, int threads) {
  ContactCounts counts;
  if (model.colliders.empty()) return counts;
  resize(model);
  const double thickness = model.collision.thickness;
  const double t1 = state.time;
  parallel_for(model.particle_count(), threads, [&](std::size_t p) {
    moved_[p] = 0;
    if (model.is_anchored(p)) return;
    law::ParticleContact particle{state.position[p], state.velocity[p], false};
    for (std::size_t c = 0; c < model.colliders.size(); ++c) {
      const Collider& collider = model.colliders[c];
      const double mu = collider_friction(collider, model.collision);
      const double held =
          surface_.collider[p] == c ? surface_.impulse[p] * model.particle_inverse_mass[p] : 0.0;  // m/s
      resolve(mu, thickness, start_time, t1, collider, start[p], held, particle);
    }
    if (!particle.touched) return;
    moved_[p] = 1;
    resolved_position_[p] = particle.position;
    resolved_velocity_[p] = particle.velocity;
  });

  energy_.collect(model, moved_, threads);
  counts.contacts = energy_.particles().size();
  if (counts.contacts == 0) return counts;
  const double before = energy_.energy(model, state.position, state.velocity, terms, threads);
  for (std::uint32_t p : energy_.particles()) {
    state.position[p] = resolved_position_[p];
    state.velocity[p] = resolved_velocity_[p];
  }
  const double after = energy_.energy(model, state.position, state.velocity, terms, threads);
  counts.work = after - before;
  state.contact_work += counts.work;
  return counts;
}

std::size_t ObstacleContacts::bytes() const {
  return arrival_.capacity() * sizeof(double) +
         (resolved_position_.capacity() + resolved_velocity_.capacity()) * sizeof(Vec3) + moved_.capacity() +
         energy_.bytes() + surface_.bytes();
}

}  // namespace clothsim

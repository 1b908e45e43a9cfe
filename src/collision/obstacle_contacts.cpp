#include "collision/obstacle_contacts.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/parallel.h"

namespace clothsim {
namespace {

// Conservative advancement stops within this distance outside the thickness shell: each march
// covers at least this much, so a grazing segment costs at most length / tolerance queries,
// capped by kMaxMarches (a segment still marching then is resolved at its end point).
double shell_tolerance(double thickness) { return std::max(0.01 * thickness, 1e-9); }
constexpr int kMaxMarches = 64;
// The end point is resolved where it is when its normal is within 60 degrees of the entry
// point's: a particle that entered through one face and ends nearer another (a box's edge), or
// past a sphere's centre, would be pushed out the wrong side.
constexpr double kSameSideCosine = 0.5;
// The step limit of begin_step(): a particle approaching an obstacle at its current velocity may
// go this fraction of the thickness into the shell before the step ends. The stage resolves
// contacts at step ends, so a particle stopped there has been stopped late by what it moved
// inside; its neighbours moved on meanwhile, and the springs between them store energy that
// grows with the square of that depth while the kinetic energy the contact removes does not
// shrink: with a small depth the stage never adds energy (docs/collisions.md).
constexpr double kImpactDepth = 0.1;

struct ParticleContact {
  Vec3 position;
  Vec3 velocity;
  bool touched = false;
};

// Resolves one particle against one collider (steps 1 to 4 of the header). `particle` holds its
// position and velocity after the step (and after earlier colliders), `start` its position at the
// step's start t0; the collider is taken at the step's end t1. `held` is the normal velocity change
// the integrator's surface constraint made during the step (impulse / mass, m/s; zero if it did
// not hold the particle on this collider): friction acts on it as on the speed removed here.
void resolve(double mu, double thickness, double t0, double t1, const Collider& collider, const Vec3& start,
             double held, ParticleContact& particle) {
  const double tolerance = shell_tolerance(thickness);
  const Vec3 x1 = particle.position;
  // The sweep runs in the collider's frame: the start point moves with the shape's translation
  // over the step, so that a collider moving faster than its size per step cannot pass through a
  // particle either, and the start distance is the one at the step's start.
  const Vec3 x0 = start + (collider.path.position(t1) - collider.path.position(t0));
  const SurfaceDistance at_end = signed_distance(collider, x1, t1);
  const SurfaceDistance at_start = signed_distance(collider, x0, t1);
  const bool sustained = at_start.distance <= thickness + tolerance;

  SurfaceDistance contact = at_end;
  Vec3 contact_point = x1;
  if (!sustained) {
    // 1. Sweep x0 -> x1 by conservative advancement.
    const Vec3 segment = x1 - x0;
    const double length = norm(segment);
    bool hit = false;
    SurfaceDistance entry = at_start;
    Vec3 entry_point = x0;
    if (length > 0.0) {
      const Vec3 direction = segment / length;
      double s = 0.0;  // m along the segment
      for (int march = 0; march < kMaxMarches; ++march) {
        s += entry.distance - thickness;
        if (s >= length) break;
        entry_point = x0 + s * direction;
        entry = signed_distance(collider, entry_point, t1);
        if (entry.distance <= thickness + tolerance) {
          hit = true;
          break;
        }
      }
    }
    const bool same_side = dot(at_end.normal, entry.normal) >= kSameSideCosine;
    if (!hit || (same_side && at_end.distance >= thickness)) {
      // A free flight past the collider, or a graze: the motion came within the shell's tolerance
      // and ended outside on the side it came from (a particle beside a collider sliding along its
      // own surface, which the sweep in the collider's frame sees as a long motion parallel to it).
      if (at_end.distance >= thickness) return;
    } else if (at_end.distance >= thickness || !same_side) {
      // 2. Passed through, or ended nearer another side: the entry point.
      contact = entry;
      contact_point = entry_point;
    }
  } else if (at_end.distance >= thickness && held <= 0.0) {
    return;  // resting at x0 and lifted off (or sliding) outside the shell, not held on it
  }

  // 2. To exactly the thickness along the normal (a held particle that ended outside the shell,
  // on a curved surface, stays where it is: only friction acts on it).
  const Vec3& n = contact.normal;
  Vec3 position = contact_point + std::max(0.0, thickness - contact.distance) * n;

  // 3. Inelastic normal, Coulomb tangential, relative to the shape.
  const Vec3 relative = particle.velocity - contact.velocity;
  const double normal_speed = dot(relative, n);  // m/s, negative approaching
  const double removed = std::max(0.0, -normal_speed);
  const double pressed = removed + (sustained ? held : 0.0);  // m/s, the normal impulse over the mass
  Vec3 tangential = relative - normal_speed * n;
  const double tangential_speed = norm(tangential);
  double keep = 1.0;  // fraction of the tangential relative velocity friction leaves
  if (pressed > 0.0 && mu > 0.0) {
    keep = tangential_speed > mu * pressed ? 1.0 - mu * pressed / tangential_speed : 0.0;
  }
  const Vec3 friction_change = (keep - 1.0) * tangential;  // m/s, the velocity friction removes
  const Vec3 velocity = contact.velocity + keep * tangential + std::max(0.0, normal_speed) * n;

  // 4. Friction on positions, for a particle that was in contact during the whole step: the
  // friction deceleration acted through the step, so the slide shrinks by half the step times the
  // velocity friction removed (exact for constant deceleration). At rest on a slope below the
  // friction angle this undoes the step's slide exactly: no creep.
  if (sustained) position = position + 0.5 * (t1 - t0) * friction_change;
  particle.position = position;
  particle.velocity = velocity;
  particle.touched = true;
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
  const double tolerance = shell_tolerance(thickness);
  // With no thickness at all, a micrometre: the limit must leave the step some length.
  const double impact_depth = std::max(kImpactDepth * thickness, 1e-6);  // m
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
      if (surface.distance <= thickness + tolerance) {
        if (surface_.collider[p] == SurfaceContacts::kNone) {
          surface_.collider[p] = static_cast<std::uint32_t>(c);
          surface_.normal[p] = surface.normal;
          surface_.velocity[p] = surface.velocity;
          surface_.friction[p] = collider_friction(model.colliders[c], model.collision);
        }
        continue;
      }
      const double approach = -dot(state.velocity[p] - surface.velocity, surface.normal);  // m/s
      if (approach <= 0.0) continue;
      const double gap = surface.distance - thickness;
      arrival_[p] = std::min(arrival_[p], (gap + impact_depth) / approach);
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
    ParticleContact particle{state.position[p], state.velocity[p], false};
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

  energy_.collect(model, moved_);
  counts.contacts = energy_.particles().size();
  if (counts.contacts == 0) return counts;
  const double before = energy_.energy(model, state.position, state.velocity, terms);
  for (std::uint32_t p : energy_.particles()) {
    state.position[p] = resolved_position_[p];
    state.velocity[p] = resolved_velocity_[p];
  }
  const double after = energy_.energy(model, state.position, state.velocity, terms);
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

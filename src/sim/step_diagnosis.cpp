// What limits the step at a particle (step_diagnosis.h).
#include "sim/step_diagnosis.h"

#include <cmath>
#include <limits>
#include <numbers>

#include "core/diagnostic_text.h"
#include "forces/element.h"

namespace clothsim {
namespace {

constexpr double kDegree = std::numbers::pi / 180.0;

// The kink a radial spring is nearest (0 or pi) and how far it is from it, rad; a kink its rest
// angle sits at is no kink (its energy is smooth there).
struct NearestKink {
  double angle = 0.0;
  double distance = std::numeric_limits<double>::infinity();
};

NearestKink nearest_kink(double angle, double rest_angle) {
  NearestKink kink;
  for (const double end : {0.0, std::numbers::pi}) {
    if (std::abs(rest_angle - end) < kKinkWindow) continue;
    const double distance = std::abs(angle - end);
    if (distance < kink.distance) kink = {end, distance};
  }
  return kink;
}

}  // namespace

StepLimit find_step_limit(const ClothModel& model, std::span<const Vec3> position, std::size_t particle) {
  StepLimit best;
  double best_kink = kKinkWindow;  // at a kink: nearer is worse
  double best_departure = -1.0;    // otherwise: further from rest is worse
  for (std::size_t r = 0; r < model.radial_particles.size(); ++r) {
    const auto [a, b, c] = model.radial_particles[r];
    if (model.radial_live[r] == 0 || (a != particle && b != particle && c != particle)) continue;
    const double angle = element::radial_angle(position[a], position[b], position[c]);
    const NearestKink kink = nearest_kink(angle, model.radial_rest_angle[r]);
    const StepLimit here{StepLimit::Kind::radial, r, kink.distance < kKinkWindow, kink.angle, angle, 0.0};
    if (here.at_kink && (kink.distance < best_kink || !best.at_kink)) {
      best = here;
      best_kink = kink.distance;
    } else if (!best.at_kink && std::abs(angle - model.radial_rest_angle[r]) > best_departure) {
      best = here;
      best.at_kink = false;
      best_departure = std::abs(angle - model.radial_rest_angle[r]);
    }
  }
  if (best.at_kink) return best;
  for (std::size_t e = 0; e < model.connector_particles.size(); ++e) {
    const auto [a, b] = model.connector_particles[e];
    if (model.connector_live[e] == 0 || (a != particle && b != particle)) continue;
    const double strain = norm(position[b] - position[a]) / model.connector_rest_length[e] - 1.0;
    // A strain of 1 % weighs as much as a radial spring 0.01 rad from its rest.
    if (std::abs(strain) > best_departure) {
      best = StepLimit{StepLimit::Kind::connector, e, false, 0.0, 0.0, strain};
      best_departure = std::abs(strain);
    }
  }
  return best;
}

std::string describe_step_limit(const ClothModel& model, const StepLimit& limit, std::span<const Vec3> position) {
  switch (limit.kind) {
    case StepLimit::Kind::none: return "";
    case StepLimit::Kind::connector: {
      const auto [a, b] = model.connector_particles[limit.element];
      const double length = norm(position[b] - position[a]);
      return "connector " + std::to_string(limit.element) + " between " + model.describe_particle(a) + " and " +
             model.describe_particle(b) + " is at strain " + diagnostic_number(100.0 * limit.strain) + " % (" +
             diagnostic_number(length) + " m against its rest length of " +
             diagnostic_number(model.connector_rest_length[limit.element]) + " m)";
    }
    case StepLimit::Kind::radial: {
      const auto [a, b, c] = model.radial_particles[limit.element];
      const char* kind = model.radial_kind[limit.element] == RadialKind::adjacent ? "adjacent" : "opposite";
      std::string text = std::string("the ") + kind + " radial spring " + std::to_string(limit.element) +
                         " centred at " + model.describe_particle(a) + ", arms to " + model.describe_particle(b) +
                         " and " + model.describe_particle(c) + ", is at " + diagnostic_number(limit.angle / kDegree) +
                         " degrees";
      if (limit.at_kink) {
        text += ", " + diagnostic_number(std::abs(limit.angle - limit.kink_angle) / kDegree) +
                " degrees from its kink at " + diagnostic_number(limit.kink_angle / kDegree) +
                " degrees, where the angle is not differentiable and the spring's force turns abruptly";
      } else {
        text += " against its rest angle of " + diagnostic_number(model.radial_rest_angle[limit.element] / kDegree) +
                " degrees";
      }
      return text;
    }
  }
  return "";
}

}  // namespace clothsim

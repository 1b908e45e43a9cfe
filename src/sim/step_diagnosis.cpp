// What limits the step at a particle (step_diagnosis.h).
#include "sim/step_diagnosis.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <utility>
#include <vector>

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

// sum_i |d theta / d x_i|^2 / m_i, 1/(kg m^2): a spring of damping c along its angle decays at
// c times this, and one of stiffness k oscillates at sqrt(k times this). The gradients' lengths
// hold at the kinks too, where only their directions are undefined: 1/|u| at the end of arm u,
// 1/|w| at the end of w, and at the centre the length of their sum, whose directions meet at
// pi - theta.
double angle_mobility(const Vec3& xa, const Vec3& xb, const Vec3& xc, double ma, double mb, double mc) {
  const double u = norm(xb - xa);
  const double w = norm(xc - xa);
  const double angle = element::radial_angle(xa, xb, xc);
  const double centre = 1.0 / (u * u) + 1.0 / (w * w) - 2.0 * std::cos(angle) / (u * w);
  return 1.0 / (u * u * mb) + 1.0 / (w * w * mc) + centre / ma;
}

// An explicit Runge-Kutta method of order 4 is stable on a decay of rate lambda for steps up to
// about 2.8 / lambda (Hairer and Wanner, Solving ODEs II, sec. IV.2).
std::string rate_text(double rate) {
  return "; its rate (damping rate or elastic frequency, the larger) is " + diagnostic_number(rate) +
         " /s, which keeps an explicit step below about " + diagnostic_number(2.8 / rate) + " s";
}

}  // namespace

StepLimit find_step_limit(const ClothModel& model, std::span<const Vec3> position, std::size_t particle) {
  // A collapsing connector first, wherever it is.
  std::size_t shortest = model.connector_particles.size();
  double shortest_ratio = kCollapsedLength;
  for (std::size_t e = 0; e < model.connector_particles.size(); ++e) {
    if (model.connector_live[e] == 0) continue;
    const auto [a, b] = model.connector_particles[e];
    const double ratio = norm(position[b] - position[a]) / model.connector_rest_length[e];
    if (ratio < shortest_ratio) {
      shortest = e;
      shortest_ratio = ratio;
    }
  }
  if (shortest < model.connector_particles.size()) {
    StepLimit limit;
    limit.kind = StepLimit::Kind::connector;
    limit.element = shortest;
    limit.collapsed = true;
    limit.strain = shortest_ratio - 1.0;
    return limit;
  }
  // Every live spring touching the particle, with how far it is from rest and how fast it is.
  std::vector<std::pair<StepLimit, double>> springs;  // the spring, its departure from rest
  for (std::size_t r = 0; r < model.radial_particles.size(); ++r) {
    const auto [a, b, c] = model.radial_particles[r];
    if (model.radial_live[r] == 0 || (a != particle && b != particle && c != particle)) continue;
    const double angle = element::radial_angle(position[a], position[b], position[c]);
    const NearestKink kink = nearest_kink(angle, model.radial_rest_angle[r]);
    const double mobility = angle_mobility(position[a], position[b], position[c], model.particle_mass[a],
                                           model.particle_mass[b], model.particle_mass[c]);
    const double rate = std::max(model.radial_damping[r] * mobility, std::sqrt(model.radial_stiffness[r] * mobility));
    StepLimit limit{StepLimit::Kind::radial, r, kink.distance < kKinkWindow, kink.angle, angle, 0.0, rate};
    springs.emplace_back(limit, limit.at_kink ? -kink.distance : std::abs(angle - model.radial_rest_angle[r]));
  }
  for (std::size_t e = 0; e < model.connector_particles.size(); ++e) {
    const auto [a, b] = model.connector_particles[e];
    if (model.connector_live[e] == 0 || (a != particle && b != particle)) continue;
    const double strain = norm(position[b] - position[a]) / model.connector_rest_length[e] - 1.0;
    const double mobility = 1.0 / model.particle_mass[a] + 1.0 / model.particle_mass[b];
    const double rate =
        std::max(model.connector_damping[e] * mobility, std::sqrt(model.connector_stiffness[e] * mobility));
    springs.emplace_back(StepLimit{StepLimit::Kind::connector, e, false, 0.0, 0.0, strain, rate}, std::abs(strain));
  }
  if (springs.empty()) return {};
  const auto worst = [&springs](auto better) {
    return std::max_element(springs.begin(), springs.end(), better)->first;
  };
  // At a kink, the nearest (its departure is minus its distance, so the largest of those).
  const bool any_kink = std::any_of(springs.begin(), springs.end(), [](const auto& s) { return s.first.at_kink; });
  if (any_kink) {
    return worst([](const auto& x, const auto& y) {
      return x.first.at_kink != y.first.at_kink ? y.first.at_kink : x.second < y.second;
    });
  }
  const bool far = std::any_of(springs.begin(), springs.end(), [](const auto& s) { return s.second > kFarFromRest; });
  if (far) return worst([](const auto& x, const auto& y) { return x.second < y.second; });
  return worst([](const auto& x, const auto& y) { return x.first.rate < y.first.rate; });
}

std::string describe_step_limit(const ClothModel& model, const StepLimit& limit, std::span<const Vec3> position) {
  switch (limit.kind) {
    case StepLimit::Kind::none: return "";
    case StepLimit::Kind::connector: {
      const auto [a, b] = model.connector_particles[limit.element];
      const double length = norm(position[b] - position[a]);
      if (limit.collapsed) {
        return "connector " + std::to_string(limit.element) + " between " + model.describe_particle(a) + " and " +
               model.describe_particle(b) + " has collapsed to " + diagnostic_number(length) + " m, " +
               diagnostic_number(100.0 * length / model.connector_rest_length[limit.element]) +
               " % of its rest length (one particle is passing through the other): the radial springs on it have "
               "faded out with it, but its own force keeps a magnitude near stiffness x rest length and turns "
               "round as the length passes through 0";
      }
      return "connector " + std::to_string(limit.element) + " between " + model.describe_particle(a) + " and " +
             model.describe_particle(b) + " is at strain " + diagnostic_number(100.0 * limit.strain) + " % (" +
             diagnostic_number(length) + " m against its rest length of " +
             diagnostic_number(model.connector_rest_length[limit.element]) + " m)" + rate_text(limit.rate);
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
                " degrees" + rate_text(limit.rate);
      }
      return text;
    }
  }
  return "";
}

}  // namespace clothsim

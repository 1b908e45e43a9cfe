#include "events/spring_events.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/assert.h"
#include "core/parallel.h"
#include "forces/element.h"
#include "forces/forces.h"
#include "model/model_edits.h"

namespace clothsim {

double connector_break_energy(const ClothModel& model, std::span<const Vec3> position, std::uint32_t connector) {
  if (model.connector_live[connector] == 0) return 0.0;
  double energy = connector_spring_energy(model, position, connector);
  for (std::uint32_t k = model.connector_radial_offset[connector]; k < model.connector_radial_offset[connector + 1];
       ++k) {
    energy += radial_spring_energy(model, position, model.radial_of_connector[k]);
  }
  return energy;
}

void SpringEvents::resize(const ClothModel& model) {
  const std::size_t connectors = model.connector_count();
  const std::size_t radials = model.radial_count();
  breaks_.assign(connectors, 0);
  connector_rest_.assign(connectors, 0.0);
  connector_yield_.assign(connectors, 0.0);
  radial_rest_.assign(radials, -1.0);
  cos_upper_.assign(radials, -2.0);
  cos_lower_.assign(radials, 2.0);
  bounds_revision_ = ~0ull;
  released_.assign(std::max(connectors, radials), 0.0);
  block_sums_.assign(deterministic_sum_blocks(released_.size()), 0.0);
}

void SpringEvents::set_crease_bounds(const ClothModel& model, std::size_t r) {
  const double rest = model.radial_rest_angle[r];
  const double yield = model.radial_yield_angle[r];
  cos_upper_[r] = rest + yield < std::numbers::pi ? std::cos(rest + yield) : -2.0;
  cos_lower_[r] = rest - yield > 0.0 ? std::cos(rest - yield) : 2.0;
}

SpringEventCounts SpringEvents::apply(ClothModel& model, ClothState& state, int threads) {
  const SpringLimits& limits = model.limits;
  const bool tearing = limits.break_strain != SpringLimits::kNever;
  const bool stretching = limits.yield_strain != SpringLimits::kNever;
  const bool creasing =
      limits.adjacent_yield_angle != SpringLimits::kNever || limits.opposite_yield_angle != SpringLimits::kNever;
  SpringEventCounts counts;
  if (!tearing && !stretching && !creasing) return counts;
  if (breaks_.size() != model.connector_count() || radial_rest_.size() != model.radial_count()) resize(model);
  const std::span<const Vec3> x = state.position;
  const std::size_t connectors = model.connector_count();
  const std::size_t radials = model.radial_count();

  // 1. Tearing: find every connector past its threshold, then break them in index order.
  if (tearing) {
    parallel_for(connectors, threads, [&](std::size_t e) {
      const auto [a, b] = model.connector_particles[e];
      const double strain = norm(x[b] - x[a]) / model.connector_original_length[e] - 1.0;
      breaks_[e] = model.connector_live[e] != 0 && strain > model.connector_break_strain[e] ? 1 : 0;
    });
    for (std::size_t e = 0; e < connectors; ++e) {
      if (breaks_[e] == 0) continue;
      const auto connector = static_cast<std::uint32_t>(e);
      state.fracture_work -= connector_break_energy(model, x, connector);
      break_connector(model, connector, state.time);
      ++counts.breaks;
    }
  }

  // 2. Permanent stretching: the return mapping on each intact connector.
  if (stretching) {
    const double hardening = limits.hardening;
    parallel_for(connectors, threads, [&](std::size_t e) {
      connector_rest_[e] = 0.0;
      released_[e] = 0.0;
      if (model.connector_live[e] == 0) return;
      const auto [a, b] = model.connector_particles[e];
      const double length = norm(x[b] - x[a]);
      const double rest = model.connector_rest_length[e];
      const double strain = length / rest - 1.0;
      const double yield = model.connector_yield_strain[e];
      // In compression the mapping needs 1 - y_e > 0 (a rest length, not a negative one).
      if (std::abs(strain) <= yield || (strain < 0.0 && yield >= 1.0)) return;
      const double sign = strain > 0.0 ? 1.0 : -1.0;
      const double new_rest = length / (1.0 + sign * yield);
      const double stiffness = model.connector_stiffness[e];
      connector_rest_[e] = new_rest;
      connector_yield_[e] = yield + hardening * (std::abs(strain) - yield);
      released_[e] = element::connector_energy(x[a], x[b], new_rest, stiffness) -
                     element::connector_energy(x[a], x[b], rest, stiffness);
    });
    state.plastic_work += deterministic_sum(std::span<const double>(released_.data(), connectors), threads, block_sums_);
    for (std::size_t e = 0; e < connectors; ++e) {
      if (connector_rest_[e] == 0.0) continue;
      const auto connector = static_cast<std::uint32_t>(e);
      set_connector_rest_length(model, connector, connector_rest_[e]);
      if (connector_yield_[e] != model.connector_yield_strain[e]) {
        set_connector_yield_strain(model, connector, connector_yield_[e]);
      }
      ++counts.yields;
    }
  }

  // 3. Creasing: the same mapping on the rest angle of each intact radial spring, after the
  // cosine test of the file comment.
  if (creasing) {
    if (bounds_revision_ != model.revision) {
      parallel_for(radials, threads, [&](std::size_t r) { set_crease_bounds(model, r); });
    }
    constexpr double kMargin = 1e-12;
    parallel_for(radials, threads, [&](std::size_t r) {
      radial_rest_[r] = -1.0;
      released_[r] = 0.0;
      if (model.radial_live[r] == 0) return;
      const auto [centre, b, c] = model.radial_particles[r];
      const Vec3 eb = x[b] - x[centre];
      const Vec3 ec = x[c] - x[centre];
      const double lengths = std::sqrt(dot(eb, eb) * dot(ec, ec));
      if (!(lengths > 0.0)) return;
      const double cosine = dot(eb, ec) / lengths;
      if (cosine > cos_upper_[r] + kMargin && cosine < cos_lower_[r] - kMargin) return;
      const double yield = model.radial_yield_angle[r];
      const double angle = element::radial_angle(x[centre], x[b], x[c]);
      const double rest = model.radial_rest_angle[r];
      if (std::abs(angle - rest) <= yield) return;
      const double new_rest = std::clamp(angle - std::copysign(yield, angle - rest), 0.0, std::numbers::pi);
      if (new_rest == rest) return;
      const double stiffness = model.radial_stiffness[r];
      radial_rest_[r] = new_rest;
      released_[r] = element::radial_energy(x[centre], x[b], x[c], new_rest, stiffness) -
                     element::radial_energy(x[centre], x[b], x[c], rest, stiffness);
    });
    state.plastic_work += deterministic_sum(std::span<const double>(released_.data(), radials), threads, block_sums_);
    for (std::size_t r = 0; r < radials; ++r) {
      if (radial_rest_[r] < 0.0) continue;
      set_radial_rest_angle(model, static_cast<std::uint32_t>(r), radial_rest_[r]);
      set_crease_bounds(model, r);
      ++counts.creases;
    }
  }
  // Every change from here on comes from outside (a live edit, a cut): it recomputes the bounds.
  bounds_revision_ = model.revision;
  return counts;
}

}  // namespace clothsim

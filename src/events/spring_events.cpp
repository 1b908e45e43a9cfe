#include "events/spring_events.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/assert.h"
#include "core/parallel.h"
#include "events/spring_laws.h"
#include "forces/element.h"
#include "forces/forces.h"
#include "model/model_edits.h"

namespace clothsim {

bool tear_connector(ClothModel& model, ClothState& state, std::uint32_t connector) {
  if (model.connector_live[connector] == 0) return false;
  double released = connector_spring_energy(model, state.position, connector);
  for (std::uint32_t k = model.connector_radial_offset[connector]; k < model.connector_radial_offset[connector + 1];
       ++k) {
    released += radial_spring_energy(model, state.position, model.radial_of_connector[k]);
  }
  break_connector(model, connector, state.time);
  state.fracture_work -= released;
  return true;
}

void SpringEvents::resize(const ClothModel& model) {
  const std::size_t connectors = model.connector_count();
  const std::size_t radials = model.radial_count();
  connector_unit_.assign(connectors, Vec3{});
  connector_flag_.assign(connectors, 0);
  radial_flag_.assign(radials, 0);
  radial_orientation_.resize(radials);
  for (std::size_t r = 0; r < radials; ++r) {
    // +1 when both connectors point away from the centre or both towards it.
    const std::uint32_t centre = model.radial_particles[r][0];
    const auto [first, second] = model.radial_connectors[r];
    const bool away_first = model.connector_particles[first][0] == centre;
    const bool away_second = model.connector_particles[second][0] == centre;
    radial_orientation_[r] = away_first == away_second ? 1.0 : -1.0;
  }
  cos_upper_.assign(radials, -2.0);
  cos_lower_.assign(radials, 2.0);
  bounds_revision_ = ~0ull;
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
  if (connector_flag_.size() != model.connector_count() || radial_flag_.size() != model.radial_count()) {
    resize(model);
  }
  const std::span<const Vec3> x = state.position;
  const std::size_t connectors = model.connector_count();
  const std::size_t radials = model.radial_count();

  // The checks, in parallel: one byte per spring says which laws may act on it. The laws then
  // act serially, in index order, on the few springs flagged (on most steps, none).
  parallel_for(connectors, threads, [&](std::size_t e) {
    const auto [a, b] = model.connector_particles[e];
    const Vec3 edge = x[b] - x[a];
    const double length = norm(edge);
    if (creasing) connector_unit_[e] = length > 0.0 ? edge / length : Vec3{};
    std::uint8_t flag = 0;
    if (model.connector_live[e] != 0) {
      if (spring_laws::connector_breaks(length, model.connector_original_length[e], model.connector_break_strain[e])) {
        flag |= kBreaks;
      }
      if (spring_laws::connector_yields(length, model.connector_rest_length[e], model.connector_yield_strain[e])) {
        flag |= kYields;
      }
    }
    connector_flag_[e] = flag;
  });

  // 1. Tearing: every connector past its threshold breaks, in index order.
  if (tearing) {
    for (std::size_t e = 0; e < connectors; ++e) {
      if ((connector_flag_[e] & kBreaks) == 0) continue;
      tear_connector(model, state, static_cast<std::uint32_t>(e));
      ++counts.breaks;
    }
  }

  // 2. Permanent stretching: the return mapping on each intact connector past its yield strain.
  if (stretching) {
    for (std::size_t e = 0; e < connectors; ++e) {
      if ((connector_flag_[e] & kYields) == 0 || model.connector_live[e] == 0) continue;
      const auto [a, b] = model.connector_particles[e];
      const double rest = model.connector_rest_length[e];
      const spring_laws::ReturnMapping mapping =
          spring_laws::return_mapping(norm(x[b] - x[a]), rest, model.connector_yield_strain[e], limits.hardening);
      if (!mapping.yields) continue;
      const double stiffness = model.connector_stiffness[e];
      state.plastic_work += element::connector_energy(x[a], x[b], mapping.rest_length, stiffness) -
                            element::connector_energy(x[a], x[b], rest, stiffness);
      const auto connector = static_cast<std::uint32_t>(e);
      set_connector_rest_length(model, connector, mapping.rest_length);
      if (limits.hardening != 0.0) set_connector_yield_strain(model, connector, mapping.yield_strain);
      ++counts.yields;
    }
  }

  // 3. Creasing: the same mapping on the rest angle of each intact radial spring, for the springs
  // that the cosine test of the file comment does not clear.
  if (creasing) {
    if (bounds_revision_ != model.revision) {
      parallel_for(radials, threads, [&](std::size_t r) { set_crease_bounds(model, r); });
    }
    constexpr double kMargin = 1e-12;
    parallel_for(radials, threads, [&](std::size_t r) {
      const auto [first, second] = model.radial_connectors[r];
      const double cosine = radial_orientation_[r] * dot(connector_unit_[first], connector_unit_[second]);
      const bool inside = cosine > cos_upper_[r] + kMargin && cosine < cos_lower_[r] - kMargin;
      radial_flag_[r] = model.radial_live[r] != 0 && !inside ? 1 : 0;
    });
    for (std::size_t r = 0; r < radials; ++r) {
      if (radial_flag_[r] == 0) continue;
      const auto [centre, b, c] = model.radial_particles[r];
      const double rest = model.radial_rest_angle[r];
      const double new_rest = spring_laws::creased_rest_angle(element::radial_angle(x[centre], x[b], x[c]), rest,
                                                              model.radial_yield_angle[r]);
      if (new_rest == rest) continue;
      const double stiffness = model.radial_stiffness[r];
      const std::array<double, 2> fade = radial_fade_lengths(model, r);
      state.plastic_work += element::radial_energy(x[centre], x[b], x[c], new_rest, stiffness, fade[0], fade[1]) -
                            element::radial_energy(x[centre], x[b], x[c], rest, stiffness, fade[0], fade[1]);
      set_radial_rest_angle(model, static_cast<std::uint32_t>(r), new_rest);
      set_crease_bounds(model, r);
      ++counts.creases;
    }
  }
  // Every change from here on comes from outside (a live edit, a cut): it recomputes the bounds.
  bounds_revision_ = model.revision;
  return counts;
}

}  // namespace clothsim

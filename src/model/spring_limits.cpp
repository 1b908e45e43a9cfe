#include "model/spring_limits.h"

#include "core/assert.h"
#include "model/cloth_model.h"

namespace clothsim {
namespace {

// SplitMix64's finaliser (Steele, Lea and Flood 2014): a bijection that mixes every input bit
// into every output bit.
std::uint64_t mix(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
  return z ^ (z >> 31);
}

}  // namespace

double break_strain_offset(std::uint64_t seed, std::uint64_t connector) {
  const std::uint64_t bits = mix(mix(seed + 0x9e3779b97f4a7c15ULL) ^ (connector * 0x9e3779b97f4a7c15ULL + 1));
  // The top 53 bits as a double in [0, 1), then onto [-1, 1).
  const double unit = static_cast<double>(bits >> 11) * 0x1.0p-53;
  return 2.0 * unit - 1.0;
}

double connector_break_threshold(const SpringLimits& limits, std::uint64_t connector) {
  if (limits.break_strain == SpringLimits::kNever) return SpringLimits::kNever;
  return limits.break_strain *
         (1.0 + limits.break_strain_variation * break_strain_offset(limits.variation_seed, connector));
}

void apply_spring_limits(ClothModel& model, const SpringLimits& limits) {
  CLOTHSIM_ASSERT(limits.break_strain > 0.0 && limits.break_strain_variation >= 0.0 &&
                      limits.break_strain_variation < 1.0 && limits.yield_strain > 0.0 && limits.hardening >= 0.0 &&
                      limits.adjacent_yield_angle >= 0.0 && limits.opposite_yield_angle >= 0.0,
                  "spring limits are validated by the caller");
  model.limits = limits;
  for (std::size_t e = 0; e < model.connector_count(); ++e) {
    model.connector_break_strain[e] = connector_break_threshold(limits, e);
    model.connector_yield_strain[e] = limits.yield_strain;
  }
  for (std::size_t r = 0; r < model.radial_count(); ++r) {
    model.radial_yield_angle[r] =
        model.radial_kind[r] == RadialKind::adjacent ? limits.adjacent_yield_angle : limits.opposite_yield_angle;
  }
  ++model.revision;
}

}  // namespace clothsim

// The Vulkan backend's lattice path on the host side (gpu/device_integrator.h): the model's
// springs laid out by particle for lattice_elements and the event passes, and the events the
// device applied during an advance carried back into the model.
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "core/assert.h"
#include "gpu/device_integrator.h"
#include "gpu/real_arrays.h"
#include "gpu/shaders/device_step.h"
#include "model/lattice_springs.h"
#include "model/model_edits.h"

namespace clothsim::gpu {
namespace {

// Where a spring's parameters start in `lattice_params` and `event_params` (shaders/device_step.h).
std::size_t connector_params(std::uint32_t p, bool south) {
  return std::size_t{p} * kLatticeParams + kConnectorParams + kSpringParams * (south ? 1u : 0u);
}
std::size_t radial_params(std::uint32_t p, std::size_t pair) {
  return std::size_t{p} * kLatticeParams + kRadialParams + kSpringParams * pair;
}
std::size_t connector_events(std::uint32_t p, bool south) {
  return std::size_t{p} * kEventParams + kEventsPerConnector * (south ? 1u : 0u);
}

}  // namespace

void DeviceIntegrator::upload_lattice_params() {
  // Active: live and its term on (the CPU's condition, as DeviceForces' flags); missing springs
  // at the border stay 0. The events' thresholds: +inf where a law never acts.
  const ForceTerms terms = options_.terms;
  constexpr double kNever = std::numeric_limits<double>::infinity();
  std::vector<double> params(std::size_t{particles_} * kLatticeParams, 0.0);
  std::vector<double> events(std::size_t{particles_} * kEventParams, kNever);
  for_each_lattice_spring(
      static_cast<std::size_t>(model_.rows), static_cast<std::size_t>(model_.cols),
      [&](std::uint32_t e, std::uint32_t p, bool south) {
        double* c = &params[connector_params(p, south)];
        c[kParamRest] = model_.connector_rest_length[e];
        c[kParamStiffness] = model_.connector_stiffness[e];
        c[kParamDamping] = model_.connector_damping[e];
        c[kParamActive] = (terms & kConnectorSprings) != 0 && model_.connector_live[e] != 0 ? 1.0 : 0.0;
        double* t = &events[connector_events(p, south)];
        t[kEventOriginalLength] = model_.connector_original_length[e];
        t[kEventBreakStrain] = model_.connector_break_strain[e];
        t[kEventYieldStrain] = model_.connector_yield_strain[e];
        return true;
      },
      [&](std::uint32_t r, std::uint32_t p, std::size_t pair) {
        double* c = &params[radial_params(p, pair)];
        const ForceTerms term =
            model_.radial_kind[r] == RadialKind::adjacent ? kAdjacentRadialSprings : kOppositeRadialSprings;
        c[kParamRest] = model_.radial_rest_angle[r];
        c[kParamStiffness] = model_.radial_stiffness[r];
        c[kParamDamping] = model_.radial_damping[r];
        c[kParamActive] = (terms & term) != 0 && model_.radial_live[r] != 0 ? 1.0 : 0.0;
        events[std::size_t{p} * kEventParams + kRadialYieldAngles + pair] = model_.radial_yield_angle[r];
        return true;
      });
  upload(device_, arrays_[lattice_params], real_bytes(params, precision_));
  upload(device_, arrays_[event_params], real_bytes(events, precision_));
  const std::uint32_t params_particle = uniform_params_particle(params, events);
  if (params_particle != params_particle_) {
    // In the recorded attempts' push constants: record them again.
    params_particle_ = params_particle;
    release_recorded();
  }
}

std::uint32_t DeviceIntegrator::uniform_params_particle(const std::vector<double>& params,
                                                        const std::vector<double>& events) const {
  // The interior particle (1, 1) owns every kind of spring; every spring of the sheet must have
  // its four values and, for a connector, its original length (the radial springs' fade). No law
  // may change them on the device during an advance.
  const auto lattice_rows = static_cast<std::uint32_t>(model_.rows);
  const auto lattice_cols = static_cast<std::uint32_t>(model_.cols);
  if (lattice_rows < 3 || lattice_cols < 3 || model_.limits.changes_sheet()) return kOwnParams;
  const std::uint32_t reference = lattice_cols + 1;
  const auto same = [&](std::size_t at, std::size_t reference_at) {
    for (std::uint32_t k = 0; k < kSpringParams; ++k) {
      if (params[at + k] != params[reference_at + k]) return false;
    }
    return true;
  };
  const bool uniform = for_each_lattice_spring(
      lattice_rows, lattice_cols,
      [&](std::uint32_t, std::uint32_t p, bool south) {
        return same(connector_params(p, south), connector_params(reference, south)) &&
               events[connector_events(p, south) + kEventOriginalLength] ==
                   events[connector_events(reference, south) + kEventOriginalLength];
      },
      [&](std::uint32_t, std::uint32_t p, std::size_t pair) {
        return same(radial_params(p, pair), radial_params(reference, pair));
      });
  return uniform ? reference : kOwnParams;
}

void DeviceIntegrator::set_laws() {
  const SpringLimits& limits = model_.limits;
  // Where the host applies the laws (runs_spring_events), the device applies none.
  const bool on_device = runs_spring_events();
  std::uint32_t laws = 0;
  if (on_device && limits.break_strain != SpringLimits::kNever) laws |= kLawTearing;
  if (on_device && limits.yield_strain != SpringLimits::kNever) laws |= kLawPlasticity;
  if (on_device &&
      (limits.adjacent_yield_angle != SpringLimits::kNever || limits.opposite_yield_angle != SpringLimits::kNever)) {
    laws |= kLawCreasing;
  }
  if (laws == laws_) return;
  // The laws are in the recorded attempts' push constants: record them again.
  laws_ = laws;
  release_recorded();
}

IntegratorEvents DeviceIntegrator::take_spring_events(ClothModel& model) {
  CLOTHSIM_ASSERT(&model == &model_, "take_spring_events: the integrator's own model");
  const IntegratorEvents counts = std::exchange(events_, IntegratorEvents{});
  if (counts.breaks + counts.yields + counts.creases == 0) return counts;
  // Whether the device holds the model as it is, but for these changes: an edit made since the
  // advance (an anchor let go at its end) goes up with everything else before the next one.
  const bool device_current = model.revision == model_revision_;
  // The device's per-particle parameters back, each change made to the model by the edit the
  // CPU's event stage makes; values compared in the device's precision, so only what the device
  // changed differs. A break's time is the end of the step it came after.
  const double t0 = events_t0_;
  std::vector<std::byte> bytes(std::uint64_t{particles_} * kLatticeParams * real_size(precision_));
  download(device_, arrays_[lattice_params], bytes);
  const std::vector<double> params = reals_from_bytes(bytes, precision_);
  bytes.resize(std::uint64_t{particles_} * kEventParams * real_size(precision_));
  download(device_, arrays_[event_params], bytes);
  const std::vector<double> events = reals_from_bytes(bytes, precision_);
  const auto on_device = [this](double value) {
    return precision_ == Precision::float64 ? value : static_cast<double>(static_cast<float>(value));
  };
  for_each_lattice_spring(
      static_cast<std::size_t>(model.rows), static_cast<std::size_t>(model.cols),
      [&](std::uint32_t e, std::uint32_t p, bool south) {
        const double* c = &params[connector_params(p, south)];
        const double* t = &events[connector_events(p, south)];
        if (model.connector_live[e] != 0 && c[kParamActive] == 0.0) {
          break_connector(model, e, t0 + t[kEventBreakTime]);
        } else if (model.connector_live[e] != 0) {
          if (c[kParamRest] != on_device(model.connector_rest_length[e])) {
            set_connector_rest_length(model, e, c[kParamRest]);
          }
          if (t[kEventYieldStrain] != on_device(model.connector_yield_strain[e])) {
            set_connector_yield_strain(model, e, t[kEventYieldStrain]);
          }
        }
        return true;
      },
      [&](std::uint32_t r, std::uint32_t p, std::size_t pair) {
        const double* c = &params[radial_params(p, pair)];
        if (model.radial_live[r] != 0 && c[kParamRest] != on_device(model.radial_rest_angle[r])) {
          set_radial_rest_angle(model, r, c[kParamRest]);
        }
        return true;
      });
  // The device holds these changes already: nothing to upload for them.
  if (device_current) {
    model_revision_ = model.revision;
    forces_.adopt_revision(model.revision);
  }
  return counts;
}

}  // namespace clothsim::gpu

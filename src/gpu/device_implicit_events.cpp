// Implicit Euler's spring laws on the device (gpu/device_implicit_euler.h): tearing, permanent
// stretching and creasing after each step and its obstacle pass (shaders/implicit_events.comp, the
// CPU's laws of events/spring_laws.inc on DeviceForces' element arrays), their work booked after
// each step and their changes carried into the host's model after each advance. docs/gpu.md,
// "Implicit Euler on the device", says what differs from the CPU.
#include <array>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "core/assert.h"
#include "core/step_profile.h"
#include "gpu/device_implicit_euler.h"
#include "gpu/real_arrays.h"
#include "gpu/shaders/device_step.h"
#include "model/model_edits.h"

namespace clothsim::gpu {

std::uint32_t DeviceImplicitEuler::laws() const {
  const SpringLimits& limits = model_.limits;
  std::uint32_t bits = 0;
  if (limits.break_strain != SpringLimits::kNever) bits |= kLawTearing;
  if (limits.yield_strain != SpringLimits::kNever) bits |= kLawPlasticity;
  if (limits.adjacent_yield_angle != SpringLimits::kNever || limits.opposite_yield_angle != SpringLimits::kNever) {
    bits |= kLawCreasing;
  }
  return bits;
}

bool DeviceImplicitEuler::records_spring_events() const {
  constexpr ForceTerms kSprings = kConnectorSprings | kAdjacentRadialSprings | kOppositeRadialSprings;
  return laws() != 0 && (options_.terms & kSprings) == kSprings;
}

bool DeviceImplicitEuler::runs_spring_events() const {
  // After the step's collision passes, self-collision's included, which run on the device too.
  return records_spring_events();
}

void DeviceImplicitEuler::upload_events() {
  const std::size_t connectors = model_.connector_count();
  const std::size_t radials = model_.radial_count();
  std::vector<double> events(connectors * kEventsPerConnector, 0.0);
  for (std::size_t e = 0; e < connectors; ++e) {
    double* t = &events[e * kEventsPerConnector];
    t[kEventOriginalLength] = model_.connector_original_length[e];
    t[kEventBreakStrain] = model_.connector_break_strain[e];
    t[kEventYieldStrain] = model_.connector_yield_strain[e];
  }
  std::vector<std::uint32_t> arms(2 * radials);
  for (std::size_t r = 0; r < radials; ++r) {
    arms[2 * r] = model_.radial_connectors[r][0];
    arms[2 * r + 1] = model_.radial_connectors[r][1];
  }
  upload(device_, arrays_[connector_events], real_bytes(events, precision_));
  upload(device_, arrays_[radial_arms], index_bytes<std::uint32_t>(arms));
  upload(device_, arrays_[radial_yield_angle], real_bytes(model_.radial_yield_angle, precision_));
}

void DeviceImplicitEuler::bind_event_passes() {
  const auto own = [&](Array a) { return &arrays_[a]; };
  const auto shared = [&](DeviceForces::Array a) { return &forces_.buffer(a); };
  using F = DeviceForces;
  events_pass_.bind(std::vector<const Buffer*>{
      shared(F::position), shared(F::connector_particles), shared(F::connector_rest_length),
      shared(F::connector_stiffness), shared(F::connector_active), shared(F::radial_particles),
      shared(F::radial_rest_angle), shared(F::radial_stiffness), shared(F::radial_fade_length),
      shared(F::radial_active), own(connector_events), own(radial_arms), own(radial_yield_angle), own(connector_broke),
      own(block_sums), own(solve_real), own(solve_uint)});
}

// The connectors' phase, then the radial springs' (which read which connectors broke), their
// blocks one after the other, and their sums.
void DeviceImplicitEuler::record_event_buffers() {
  recorded_laws_ = laws();
  if (!records_spring_events()) return;
  const std::uint32_t bits = recorded_laws_;
  events_commands_ = record_timed(1, [&](VkCommandBuffer commands, PassTimer& timer) {
    const std::array<std::uint32_t, 2> counts = {connectors_, radials_};
    std::uint32_t first_block = 0;
    for (std::uint32_t phase = kEventsConnectorsPhase; phase <= kEventsRadialsPhase; ++phase) {
      const EventElementConstants pass{counts[phase], phase, first_block, bits};
      events_pass_.dispatch(commands, &pass, counts[phase]);
      first_block += workgroups_for(counts[phase], kImplicitReduceWorkgroup);
    }
    ImplicitPassConstants reduce = constants(kReduceEvents);
    reduce.blocks = first_block;
    reduce_pass_.dispatch(commands, &reduce, kImplicitReduceWorkgroup);
    timer.mark(commands, StepStage::events);
    record_solve_readback(commands);
  });
}

void DeviceImplicitEuler::apply_spring_events(ClothState& state) {
  submit(events_commands_);
  const IntegratorEvents step{output_uint(kEventBreaks), output_uint(kEventYields), output_uint(kEventCreases)};
  if (step.breaks + step.yields + step.creases == 0) return;
  state.fracture_work += output_real(kEventFracture);
  state.plastic_work += output_real(kEventPlastic);
  events_.breaks += step.breaks;
  events_.yields += step.yields;
  events_.creases += step.creases;
  // The next step's forces are those of the changed springs.
  forces_current_ = false;
}

IntegratorEvents DeviceImplicitEuler::take_spring_events(ClothModel& model) {
  CLOTHSIM_ASSERT(&model == &model_, "take_spring_events: the integrator's own model");
  const IntegratorEvents counts = std::exchange(events_, IntegratorEvents{});
  if (counts.breaks + counts.yields + counts.creases == 0) return counts;
  // Whether the device holds the model as it is, but for these changes: an edit made since the
  // advance (an anchor let go at its end) goes up with everything else before the next one.
  const bool device_current = model.revision == model_revision_;
  // The device's springs back, each change made to the model by the edit the CPU's event stage
  // makes (model/model_edits.h). A break's time is the end of the step it came after.
  const auto reals = [&](DeviceForces::Array array, std::size_t count) {
    std::vector<std::byte> bytes(count * real_size(precision_));
    download(device_, forces_.buffer(array), bytes);
    return reals_from_bytes(bytes, precision_);
  };
  const std::size_t connectors = model.connector_count();
  const std::size_t radials = model.radial_count();
  std::vector<std::uint32_t> active(connectors);
  download(device_, forces_.buffer(DeviceForces::connector_active), std::as_writable_bytes(std::span(active)));
  const std::vector<double> rest_length = reals(DeviceForces::connector_rest_length, connectors);
  const std::vector<double> rest_angle = reals(DeviceForces::radial_rest_angle, radials);
  std::vector<std::byte> bytes(connectors * kEventsPerConnector * real_size(precision_));
  download(device_, arrays_[connector_events], bytes);
  const std::vector<double> events = reals_from_bytes(bytes, precision_);
  for (std::uint32_t e = 0; e < connectors; ++e) {
    if (model.connector_live[e] == 0) continue;
    const double* t = &events[std::size_t{e} * kEventsPerConnector];
    if (active[e] == 0u) {
      break_connector(model, e, t[kEventBreakTime]);
      continue;
    }
    if (rest_length[e] != model.connector_rest_length[e]) set_connector_rest_length(model, e, rest_length[e]);
    if (t[kEventYieldStrain] != model.connector_yield_strain[e]) {
      set_connector_yield_strain(model, e, t[kEventYieldStrain]);
    }
  }
  for (std::uint32_t r = 0; r < radials; ++r) {
    if (model.radial_live[r] != 0 && rest_angle[r] != model.radial_rest_angle[r]) {
      set_radial_rest_angle(model, r, rest_angle[r]);
    }
  }
  // The device holds these changes already: nothing to upload for them.
  if (device_current) {
    model_revision_ = model.revision;
    forces_.adopt_revision(model.revision);
  }
  return counts;
}

}  // namespace clothsim::gpu

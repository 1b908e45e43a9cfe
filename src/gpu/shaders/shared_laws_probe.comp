#version 450
#extension GL_GOOGLE_include_directive : require
// The shared laws as the shaders compile them, one case per invocation, for tests/gpu's
// test_shared_laws.cpp, which holds them to their closed forms and to the CPU's: the arctangent,
// x / sin x, the event laws, the step-size controller and clip_step, and the lattice's spring
// order (core/shared_text.h lists the files). No pass of the backend uses it.
#include "gpu/shaders/element_math.glsl"
#include "events/spring_laws.inc"
#define StepFactor float
#include "integrators/step_control.inc"
#include "model/lattice_springs.inc"

layout(constant_id = 0) const uint kWorkgroupSize = 64u;  // the workgroup size, specialized by ComputePipeline
layout(local_size_x_id = 0) in;
#include "gpu/shaders/invocation.glsl"

layout(std430, binding = 0) readonly buffer Inputs { Real inputs[]; };     // [cases][4]
layout(std430, binding = 1) writeonly buffer Outputs { Real outputs[]; };  // [cases][4]

// Which law (the cases of main), and how many cases.
layout(push_constant) uniform Constants {
  uint law;
  uint count;
} constants;

Real flag(bool value) { return value ? Real(1.0) : Real(0.0); }

void main() {
  const uint i = invocation_index();
  if (i >= constants.count) return;
  const Real a = inputs[4u * i];
  const Real b = inputs[4u * i + 1u];
  const Real c = inputs[4u * i + 2u];
  const Real d = inputs[4u * i + 3u];
  Real result[4] = Real[4](Real(0.0), Real(0.0), Real(0.0), Real(0.0));
  if (constants.law == 0u) {
    // (y, x): the upper half plane's angle, and the first quadrant's of (y, |x|).
    result[0] = arctangent_upper_half(a, b);
    result[1] = arctangent_first_quadrant(a, abs(b));
  } else if (constants.law == 1u) {
    // (x, sin x)
    result[0] = x_over_sin(a, b);
  } else if (constants.law == 2u) {
    // (length, rest length, yield strain, hardening)
    const ReturnMapping mapping = return_mapping(a, b, c, d);
    result[0] = flag(mapping.yields);
    result[1] = mapping.rest_length;
    result[2] = mapping.yield_strain;
    result[3] = flag(connector_yields(a, b, c));
  } else if (constants.law == 3u) {
    // (length, original length, break strain) and (angle, rest angle, yield angle)
    result[0] = flag(connector_breaks(a, b, c));
    result[1] = creased_rest_angle(a, b, c);
  } else if (constants.law == 4u) {
    // (step, error, previous error, 1 if an attempt was rejected before + 2 if clipped), with
    // safety 0.9, growth 5, shrink 0.1 and the step as the old proposal; error > 1 rejects.
    StepController controller;
    controller.safety = StepFactor(0.9);
    controller.max_growth = StepFactor(5.0);
    controller.max_shrink = StepFactor(0.1);
    controller.proposed_step = a;
    controller.previous_error = c;
    const uint flags = uint(d);
    controller.rejected_before = (flags & 1u) != 0u;
    if (b > Real(1.0)) {
      reject_step(controller, a, b, false);
    } else {
      accept_step(controller, a, b, (flags & 2u) != 0u);
    }
    result[0] = controller.proposed_step;
    result[1] = controller.previous_error;
    result[2] = flag(controller.rejected_before);
  } else if (constants.law == 5u) {
    // (time, step, limit)
    const ClippedStep clipped = clip_step(a, b, c);
    result[0] = clipped.step;
    result[1] = flag(clipped.clipped);
  } else if (constants.law == 6u) {
    // The spring order: case i's spring i % 6.
    const uint pair = i % uint(kRadialsPerParticle);
    result[0] = Real(kRadialArmB[pair]);
    result[1] = Real(kRadialArmC[pair]);
  }
  for (uint k = 0u; k < 4u; ++k) outputs[4u * i + k] = result[k];
}

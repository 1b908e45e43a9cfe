#version 450
#extension GL_GOOGLE_include_directive : require
// The candidates whose flags (self_detect.comp) have any bit of a mask, listed in candidate order
// (gpu/device_self_contacts.h; SelfContacts::select_flagged on the CPU): each flag counted, the
// counts scanned (gpu/prefix_scan.h), then each flagged candidate's index written at its count's
// sum, and their number.
#include "gpu/shaders/self_step.h"

layout(constant_id = 0) const uint kWorkgroupSize = 64u;  // the workgroup size, specialized by ComputePipeline
layout(local_size_x_id = 0) in;
#include "gpu/shaders/invocation.glsl"

layout(std430, binding = 0) readonly buffer Flags { uint flags[]; };  // [candidates]: kPair* bits
layout(std430, binding = 1) buffer Slot { uint slot[]; };             // [candidates]: 1 flagged, then scanned
layout(std430, binding = 2) writeonly buffer List { uint list[]; };   // [listed]
layout(std430, binding = 3) writeonly buffer Listed { uint listed[]; };  // [1]

layout(push_constant) uniform Constants { ListPassConstants constants; };

void main() {
  const uint c = invocation_index();
  if (constants.phase == kListTotal) {
    if (c > 0u) return;
    if (constants.candidates == 0u) {
      listed[0] = 0u;
      return;
    }
    const uint last = constants.candidates - 1u;
    listed[0] = slot[last] + ((flags[last] & constants.mask) != 0u ? 1u : 0u);
    return;
  }
  if (c >= constants.candidates) return;
  const bool flagged = (flags[c] & constants.mask) != 0u;
  if (constants.phase == kListCount) {
    slot[c] = flagged ? 1u : 0u;
  } else if (flagged) {
    list[slot[c]] = c;
  }
}

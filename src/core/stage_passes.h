// How the Vulkan backend runs an explicit method's stages on a lattice sheet (docs/gpu.md, "One
// pass per stage", "Stages chained in a pass"). Every choice gives the same bits; they differ in
// the passes an attempt dispatches and the bytes it moves. Here, below both the simulation's
// settings (sim/backend.h) and the device's (gpu/device.h), which carry it.
#pragma once

#include <cstdint>
#include <string_view>

namespace clothsim {

enum class StagePasses : std::uint8_t {
  split,    // three passes a stage: rk_stage_state, lattice_elements, stage_acceleration
  fused,    // one pass a stage (lattice_stage)
  chained,  // as many stages a pass as the precision's shared memory holds (lattice_stage)
};

constexpr const char* to_string(StagePasses passes) {
  return passes == StagePasses::split ? "split" : passes == StagePasses::fused ? "fused" : "chained";
}

constexpr bool parse_stage_passes(std::string_view text, StagePasses& passes) {
  for (StagePasses candidate : {StagePasses::split, StagePasses::fused, StagePasses::chained}) {
    if (text == to_string(candidate)) {
      passes = candidate;
      return true;
    }
  }
  return false;
}

}  // namespace clothsim

// The layout shared by self-collision's stages on the device (gpu/device_self_candidates.h) and
// their shaders self_boxes.comp and self_detect.comp: the phases, the flags and the push
// constants, read by C++ and by GLSL.
#if defined(__cplusplus)
#pragma once
#include <cstdint>
namespace clothsim::gpu {
using uint = std::uint32_t;
#define CLOTHSIM_SLOT inline constexpr uint
#else
#define CLOTHSIM_SLOT const uint
#endif

// self_boxes.comp's phases, each one pass.
CLOTHSIM_SLOT kBoxesPoints = 0;    // per particle: its motion's box
CLOTHSIM_SLOT kBoxesElements = 1;  // per triangle, then per edge: its particles' boxes' union, grown
CLOTHSIM_SLOT kBoxesGrow = 2;      // per particle: its box grown
CLOTHSIM_SLOT kBoxesCells = 3;     // one invocation: the two grids' cell sizes

struct BoxesPassConstants {
  uint phase;  // kBoxes*
  uint particles;
  uint triangles;
  uint edges;
};

// self_detect.comp's flags of a candidate.
CLOTHSIM_SLOT kPairActive = 1;    // the elements' boxes over the motion, grown by half the thickness, overlap
CLOTHSIM_SLOT kPairNear = 2;      // within the thickness at the start or the end, apart at the start
CLOTHSIM_SLOT kPairTouching = 4;  // its first touch is within the motion

struct DetectPassConstants {
  uint point_pairs;  // the particle-triangle candidates, then
  uint edge_pairs;   // the edge-edge ones
};

#if defined(__cplusplus)
#undef CLOTHSIM_SLOT
}  // namespace clothsim::gpu
#endif

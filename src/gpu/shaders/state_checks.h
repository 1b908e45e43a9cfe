// The layout of the state-checks pass (state_checks.comp, gpu/state_checks.h), read by C++ and
// by GLSL so that the two cannot disagree: its push constants and what each workgroup writes.
#ifndef CLOTHSIM_STATE_CHECKS_H
#define CLOTHSIM_STATE_CHECKS_H
#if defined(__cplusplus)
#pragma once
#include <cstdint>
namespace clothsim::gpu {
using uint = std::uint32_t;
#define CLOTHSIM_SLOT inline constexpr uint
#else
#define CLOTHSIM_SLOT const uint
#endif

// Per workgroup of kStateChecksWorkgroup particles, kStateCheckReals doubles in `block_checks`:
// the energies of its particles and of the springs they own (EnergyReport's terms), then the
// particles among them that fail a check.
CLOTHSIM_SLOT kCheckKinetic = 0;
CLOTHSIM_SLOT kCheckGravitational = 1;
CLOTHSIM_SLOT kCheckConnector = 2;
CLOTHSIM_SLOT kCheckRadialAdjacent = 3;
CLOTHSIM_SLOT kCheckRadialOpposite = 4;
CLOTHSIM_SLOT kCheckFailures = 5;  // a non-finite position or velocity, or a live connector it owns stretched too far
CLOTHSIM_SLOT kStateCheckReals = 6;
CLOTHSIM_SLOT kStateChecksWorkgroup = 256;

// 8-byte fields after 4-byte ones, at the offsets std430 gives them (16, 24, ...): the C++ struct
// has the same layout.
struct StateCheckConstants {
  uint particle_count;
  uint rows;
  uint cols;
  uint pad;
  double gravity_x;      // m/s^2, the model's, in double in either precision
  double gravity_y;
  double gravity_z;
  // SimulationSettings::explosion_stretch: a live connector longer than this times its rest length fails.
  double explosion_stretch;
};

// The general path's pass (state_checks_elements.comp): three dispatches, the particles, the
// connectors and the radial springs, each writing its workgroups' sums from first_block on (the
// terms it has no part in as zeros).
CLOTHSIM_SLOT kCheckParticlesPhase = 0;
CLOTHSIM_SLOT kCheckConnectorsPhase = 1;
CLOTHSIM_SLOT kCheckRadialsPhase = 2;

struct ElementCheckConstants {
  uint count;        // the phase's items: particles, connectors or radial springs
  uint phase;        // kCheck*Phase
  uint first_block;  // its first workgroup's place in block_checks
  uint pad;
  double gravity_x;  // as StateCheckConstants
  double gravity_y;
  double gravity_z;
  double explosion_stretch;
};

#if defined(__cplusplus)
#undef CLOTHSIM_SLOT
}  // namespace clothsim::gpu
#endif
#endif  // CLOTHSIM_STATE_CHECKS_H

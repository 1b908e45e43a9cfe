// The springs a lattice particle owns, in build_lattice's order: its east and south connectors and
// the six radial springs centred at it (arms 0 east, 1 south, 2 west, 3 north; pairs (E,S), (S,W),
// (W,N), (N,E), (E,W), (S,N)), with element_math.inc's formulas: the sum of their forces on the
// particle, on each of its four neighbours, and their damping power. Parameters come per particle
// (lattice_params), so torn, plastic and creased sheets take this path too: a missing, broken or
// switched-off spring has active 0. The radial springs fade as an arm vanishes, with the arm
// connector's original length from event_params. A uniform sheet's particles all read one interior
// particle's parameters (params_particle).
//
// lattice_elements writes every particle's sums for stage_acceleration to gather; lattice_stage
// forms a neighbour's share of a particle where it needs it (`only_arm`), adding the same terms in
// the same order, so that both give the same bits.
//
// The includer declares `lattice_params`, `event_params` and the push constants `constants` (a
// LatticePassConstants), and includes stage_offsets.glsl, whose stage_offset_point(q) reads the
// stage arrays or forms the stage state (CLOTHSIM_STAGE_COMPUTED).
#ifndef CLOTHSIM_LATTICE_SPRING_SUMS_GLSL
#define CLOTHSIM_LATTICE_SPRING_SUMS_GLSL

#include "gpu/shaders/lattice_cell.glsl"

struct LatticeSpringSums {
  Vec3 own;    // N, on the particle
  Vec3 to[4];  // N, on its neighbour in each direction
  Real power;  // W, the springs' damping power
};

// particle_spring_sums' `only_arm` for every spring.
const uint kEveryArm = 4u;

// The sums of particle p's springs. With only_arm < 4, only the springs acting on that arm are
// evaluated: to[only_arm] is then the whole sum's, and the rest partial.
LatticeSpringSums particle_spring_sums(uint p, uint only_arm) {
  const LatticeCell cell = lattice_cell(p, constants.rows, constants.cols);
  const bool has[4] = cell.has;
  const uint neighbour[4] = cell.neighbour;
  // Near p: in float32, relative to p (stage_offsets.glsl).
  const StagePoint stage_here = stage_offset_point(p);
  const StagePoint here = stage_point_relative(p, stage_here, p, stage_here);
  const bool one_source = constants.params_particle != kOwnParams;
  const uint source = one_source ? constants.params_particle : p;
  Vec3 arm_x[4];
  Vec3 arm_v[4];
  Real fade_length[4];
  for (uint d = 0u; d < 4u; ++d) {
    // Every arm is needed whichever arm is asked for: each is paired with all three others.
    const StagePoint arm =
        has[d] ? stage_point_relative(neighbour[d], stage_offset_point(neighbour[d]), p, stage_here) : here;
    arm_x[d] = arm.position;
    arm_v[d] = arm.velocity;
    // On a uniform sheet the west and north arms are as long as the east and south ones.
    const uint at = one_source ? source * kEventParams + kEventsPerConnector * (d % 2u) : arm_event_params(d, cell, p);
    fade_length[d] = has[d] ? kRadialFadeFraction * event_params[at + kEventOriginalLength] : Real(0.0);
  }
  const uint base = source * kLatticeParams;
  const Real damped = constants.damped != 0u ? Real(1.0) : Real(0.0);
  LatticeSpringSums sums;
  sums.own = Vec3(0.0);
  sums.to = Vec3[4](Vec3(0.0), Vec3(0.0), Vec3(0.0), Vec3(0.0));
  sums.power = Real(0.0);
  // East (d 0) and south (d 1) connectors.
  for (uint d = 0u; d < 2u; ++d) {
    const uint c = base + kConnectorParams + kSpringParams * d;
    if (!has[d] || lattice_params[c + kParamActive] == Real(0.0)) continue;
    if (only_arm != kEveryArm && only_arm != d) continue;
    const ConnectorForce f = connector_force(here.position, arm_x[d], here.velocity, arm_v[d],
                                             lattice_params[c + kParamRest], lattice_params[c + kParamStiffness],
                                             damped * lattice_params[c + kParamDamping]);
    sums.own += f.force_on_a;
    sums.to[d] -= f.force_on_a;
    sums.power += f.damping_power;
  }
  // The six radial springs.
  for (uint k = 0u; k < uint(kRadialsPerParticle); ++k) {
    const uint r = base + kRadialParams + kSpringParams * k;
    const uint b = uint(kRadialArmB[k]);
    const uint c = uint(kRadialArmC[k]);
    if (!has[b] || !has[c] || lattice_params[r + kParamActive] == Real(0.0)) continue;
    if (only_arm != kEveryArm && only_arm != b && only_arm != c) continue;
    const RadialForce f = radial_force(here.position, arm_x[b], arm_x[c], here.velocity, arm_v[b], arm_v[c],
                                       lattice_params[r + kParamRest], lattice_params[r + kParamStiffness],
                                       damped * lattice_params[r + kParamDamping], fade_length[b], fade_length[c]);
    sums.own -= f.force_on_b + f.force_on_c;
    sums.to[b] += f.force_on_b;
    sums.to[c] += f.force_on_c;
    sums.power += f.damping_power;
  }
  return sums;
}

#endif

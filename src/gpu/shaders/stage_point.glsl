// A particle's state in a Runge-Kutta stage, as the force passes see it (stage_offsets.glsl,
// stage_state.glsl).
#ifndef CLOTHSIM_STAGE_POINT_GLSL
#define CLOTHSIM_STAGE_POINT_GLSL

struct StagePoint {
  Vec3 position;  // m (float32: an offset, from the state or from another particle)
  Vec3 velocity;  // m/s
};

#endif

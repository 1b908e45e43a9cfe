// The element Jacobians' factors in GLSL: forces/element_jacobian.inc, the text the CPU compiles
// in forces/element_jacobian.h, after the element formulas it builds on (element_math.glsl).
#ifndef CLOTHSIM_ELEMENT_JACOBIAN_GLSL
#define CLOTHSIM_ELEMENT_JACOBIAN_GLSL
#include "gpu/shaders/element_math.glsl"
#include "forces/element_jacobian.inc"
#endif

// The element formulas in GLSL: the shared text's spelling (shared_text.glsl), the helpers they
// need (real_math.glsl), then the formulas themselves, forces/element_math.inc, the same text the
// CPU compiles in forces/element.h.
#include "gpu/shaders/shared_text.glsl"
#include "gpu/shaders/real_math.glsl"
#include "forces/element_math.inc"

// The GLSL spelling of the shared text (core/shared_text.h lists the files and the macros).
// CLOTHSIM_FLOAT64 (1 or 0, set by the build for each of a shader's two variants) chooses double
// or float.
#ifndef CLOTHSIM_SHARED_TEXT_GLSL
#define CLOTHSIM_SHARED_TEXT_GLSL

#if CLOTHSIM_FLOAT64
#define Real double
#define Vec3 dvec3
#define Mat3 dmat3
#else
#define Real float
#define Vec3 vec3
#define Mat3 mat3
#endif
// A literal in Real precision. GLSL's own way for doubles is the lf suffix, which a macro cannot
// paste (glslang refuses ## on numbers); Real(literal) is a constant conversion that glslang
// folds from the literal's full double value (double(0.1) becomes the double nearest 0.1, as
// the SPIR-V shows). tests/gpu holds the result against the CPU's, which would see a float-rounded
// pi or atan coefficient at the 1e-7 level.
#define CLOTHSIM_REAL(literal) Real(literal)
#define CLOTHSIM_INLINE
#define CLOTHSIM_CONSTANT const
#define CLOTHSIM_IN(T) const T
#define CLOTHSIM_INOUT(T) inout T
#define CLOTHSIM_DEFAULT(value)
#define CLOTHSIM_ZERO_VECTOR Vec3(0.0)
#define CLOTHSIM_VECTOR(x, y, z) Vec3(x, y, z)
#define CLOTHSIM_ARRAY6(T, a, b, c, d, e, f) T[6](a, b, c, d, e, f)

#endif

// The C++ spelling of the shared text: the files named *.inc that both the CPU and the Vulkan
// backend's compute shaders compile, so that a law both sides compute is written once.
//
//   forces/element_math.inc     the connector and radial spring forces and energies, x / sin x
//   forces/element_jacobian.inc the element Jacobians' factors (implicit Euler's matrix)
//   forces/arctangent.inc       the arctangent of the lattice kernel and of the shaders
//   events/spring_laws.inc      tearing, the return mapping of permanent stretching, the crease law
//   integrators/step_control.inc  the PI step-size controller and the clipping of a step to a target
//   integrators/multigrid_stencil.inc  the lattice multigrid's stencil slots and prolongation weights
//   model/lattice_springs.inc   the order of a lattice particle's radial springs
//   model/collider_shapes.inc   the signed distances of the analytic collider shapes
//   model/mesh_distance.inc     the signed distance of a triangle mesh collider, through its hierarchy
//   core/closest_points.inc     the nearest point of a triangle, the nearest points of two segments
//   collision/self_pair.inc     self-collision's pair distances and their first touch along a motion
//   collision/obstacle_contact.inc  the obstacle pass's sweep, placement, friction and step limit
//
// Each is written in the subset of C++ and GLSL the two share: structs of plain fields, functions
// of values, if/else and the ternary operator, arithmetic, min/max/clamp/abs/sqrt/pow, constant
// arrays. No references, no constructors, no overloading, no templates, no namespaces (the C++
// includer wraps the text in one), no C++ library. What the two languages spell differently is a
// macro, defined here for C++ and in gpu/shaders/shared_text.glsl for GLSL:
//
//   CLOTHSIM_INLINE            a function of the shared text: `inline`, and always inlined, so that
//                              it vectorises inside the loops that call it (core/multiversion.h);
//                              nothing in GLSL
//   CLOTHSIM_CONSTANT          a constant: `inline constexpr`; `const`
//   CLOTHSIM_IN(T)             a read-only parameter: `const T&`; `const T`
//   CLOTHSIM_INOUT(T)          a parameter the function updates: `T&`; `inout T`
//   CLOTHSIM_DEFAULT(value)    a field's default: `= value`; nothing (the functions set every field)
//   CLOTHSIM_REAL(literal)     a literal in Real precision: `Real(literal)` on both sides (in GLSL a
//                              constant conversion that glslang folds from the literal's full double
//                              value, so that 1e-4 or 1.0 / 6.0 is not rounded to float first)
//   CLOTHSIM_ZERO_VECTOR       Vec3(); Vec3(0.0)
//   CLOTHSIM_VECTOR(x, y, z)   a vector of three Reals: `Vec3{x, y, z}` (an aggregate, which not every
//                              compiler builds from parentheses); `Vec3(x, y, z)`
//   CLOTHSIM_ARRAY6(T, ...)    a constant array of six: `{...}`; `T[6](...)` (GLSL's preprocessor
//                              has no variadic macros, hence the fixed count)
//
// The includer also names the types and functions a file uses (Real, Vec3, dot, ...; each file's
// comment lists them) and, for a file written for both precisions, CLOTHSIM_FLOAT64 (1 or 0).
#pragma once

#define CLOTHSIM_INLINE [[gnu::always_inline]] inline
#define CLOTHSIM_CONSTANT inline constexpr
#define CLOTHSIM_IN(T) const T&
#define CLOTHSIM_INOUT(T) T&
#define CLOTHSIM_DEFAULT(value) = value
#define CLOTHSIM_REAL(literal) Real(literal)
#define CLOTHSIM_ZERO_VECTOR Vec3()
#define CLOTHSIM_VECTOR(x, y, z) \
  Vec3 { x, y, z }
#define CLOTHSIM_ARRAY6(T, a, b, c, d, e, f) \
  { a, b, c, d, e, f }

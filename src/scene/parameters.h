// The scene parameter registry: one table of every scalar scene parameter (STYLE.md rule 10).
//
// Each entry names a parameter by its dotted scene-file key ("lattice.rows",
// "springs.opposite.damping", "output.fps", "threads"), gives its type, SI unit, allowed range and
// a one-line description, and reaches the SceneSpec member through a pair of captureless
// functions that convert to and from double. The JSON parser, set_scene_field() (the CLI's
// `--set key=value`), validate_scene(), scene_to_json(), the viewer's panel and scripts, the
// Python module and the docs-sync test all read this one table, so a parameter added here is
// parsed, validated, written and checked against docs/scene-format.md without further code. An
// entry marked live may change while a simulation runs (live_parameter_keys()).
//
// Values that are not one scalar have their own small tables or constants here: the 3-vectors
// (gravity, initial velocity and spin), the ranges of per-anchor fields, and the keys handled by
// hand in scene.cpp (name, description, integrator.method, anchors, paper_args, material), and the
// fields of a material object.
//
// Rejected alternative: an X-macro list (MuJoCo's mjxmacro.h). A constexpr array of structs with
// lambdas keeps every entry plain C++ that reads and debugs like any other code.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "core/vec3.h"
#include "model/material.h"
#include "scene/scene.h"

namespace clothsim {

enum class ParameterType : std::uint8_t {
  real,     // any finite number in the range
  integer,  // a whole number in the range (2.5 is rejected, 3.0 accepted)
  boolean,  // JSON true/false; "true"/"false" in --set text
  // A threshold that may be absent: a finite number in the range, or +inf for "never" (written
  // JSON null in files, "none" in --set text; an absent key keeps the default, never).
  limit,
};

// An interval of allowed values; each end closed ("[") or open ("(").
struct ValueRange {
  double min = 0.0;
  double max = 0.0;
  bool min_inclusive = true;
  bool max_inclusive = true;

  // False for NaN and infinities (outside every finite range).
  bool contains(double value) const;
};

constexpr ValueRange closed_range(double min, double max) { return {min, max, true, true}; }
// (min, max]: the usual range of a positive quantity with an upper sanity bound.
constexpr ValueRange left_open_range(double min, double max) { return {min, max, false, true}; }

struct ScalarParameter {
  std::string_view key;  // dotted scene-file key
  ParameterType type;
  std::string_view unit;         // SI unit as written in the docs; "" for counts and ratios
  ValueRange range;              // in the file's unit (degrees for rest angles)
  std::string_view description;  // one line, for docs and help text
  double (*get)(const SceneSpec& spec);
  void (*set)(SceneSpec& spec, double value);  // value already checked against `range`
  bool live = false;                           // may change while the simulation runs (live_parameter_keys())
};

struct VectorParameter {
  std::string_view key;  // dotted scene-file key of a [x, y, z] array
  std::string_view unit;
  ValueRange component_range;  // applies to each of x, y, z
  std::string_view description;
  Vec3 (*get)(const SceneSpec& spec);
  void (*set)(SceneSpec& spec, const Vec3& value);
  bool live = false;  // may change while the simulation runs (live_parameter_keys())
};

// A field of a material object (`"material": {...}` in a scene; model/material.h): key as
// written inside the object, with the same type, unit, range and description conventions.
struct MaterialParameter {
  std::string_view key;  // "areal_density", ...; the docs list it as material.<key>
  ParameterType type;
  std::string_view unit;
  ValueRange range;
  std::string_view description;
  double (*get)(const MaterialDef& material);
  void (*set)(MaterialDef& material, double value);
};

std::span<const ScalarParameter> scalar_parameters();
std::span<const VectorParameter> vector_parameters();
// nullptr when `key` is not in the table.
const ScalarParameter* find_scalar_parameter(std::string_view key);
const VectorParameter* find_vector_parameter(std::string_view key);
std::span<const MaterialParameter> material_parameters();
const MaterialParameter* find_material_parameter(std::string_view key);

// Keys parsed by hand in scene.cpp: strings, the integrator enum, the anchor list and the paper's
// argument vector. Listed so that unknown-key suggestions and the docs-sync test see every key.
std::span<const std::string_view> special_keys();

// Every key a scene file may contain, scalar, vector and special, in table order.
std::span<const std::string_view> all_scene_keys();

// The keys marked live in the tables: what may change while a simulation runs (the springs'
// stiffness and damping, gravity, air drag, the particle mass, the integrator with its tolerances
// and steps), applied between steps by apply_live_parameters() (scene/scene_simulation.h) for the
// viewer's panel and scripts and the Python module's Simulation.set(). The others define the
// model's topology or rest state, the initial conditions or the output: change them in the scene
// and start again. In all_scene_keys() order.
std::span<const std::string_view> live_parameter_keys();
bool is_live_parameter(std::string_view key);
// "lattice.particle_mass, springs.connector.stiffness, ..., integrator.method".
std::string live_parameter_list();

// Per-anchor fields (one set per anchor, so not in the table above).
inline constexpr ValueRange kAnchorComponentRange = closed_range(-1e6, 1e6);  // origin m, velocity m/s, amplitude m
inline constexpr ValueRange kAnchorFrequencyRange = closed_range(0.0, 1e4);   // Hz
inline constexpr ValueRange kAnchorPhaseRange = closed_range(-1e6, 1e6);      // rad
inline constexpr ValueRange kAnchorKeyTimeRange = closed_range(0.0, 1e7);     // s, keyframe times

// Largest integer a double holds exactly, 2^53: the upper bound of the seed, so that the seed
// survives its trip through the registry's double accessors and through JSON readers in any
// language.
inline constexpr double kLargestExactInteger = 9007199254740992.0;

// Shortest text that reads back to the same double, with a compact exponent: "1e9", "1e-6",
// "0.1", "4096".
std::string format_number(double value);
// "[1, 4096]", "(0, 1000]".
std::string describe_range(const ValueRange& range);
// What a value must be: "an integer in [1, 4096]", "a number in (0, 1000]",
// "a boolean (true or false)".
std::string describe_allowed(ParameterType type, const ValueRange& range);
// True when `value` is allowed for a parameter of this type and range (whole for integers; +inf,
// never, for limits).
bool is_allowed(ParameterType type, const ValueRange& range, double value);
// A value as the docs and `clothsim params` write it: "true"/"false" for booleans, "none" for a
// limit that is never reached, the number otherwise.
std::string format_parameter_value(ParameterType type, double value);

// Rest angles are degrees in scene files and radians in LatticeDef. Dividing by the straight
// angle first keeps the common angles exact both ways: 90 <-> pi/2 and 180 <-> pi round-trip bit
// for bit (90/180 = 0.5 exactly, and scaling by 0.5 is exact).
double degrees_to_radians(double degrees);
double radians_to_degrees(double radians);

}  // namespace clothsim

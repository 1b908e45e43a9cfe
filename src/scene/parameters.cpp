#include "scene/parameters.h"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <limits>
#include <numbers>
#include <vector>

namespace clothsim {
namespace {

constexpr ValueRange kCountRange = closed_range(1.0, 4096.0);        // lattice rows and columns
constexpr ValueRange kSpringRange = closed_range(0.0, 1e9);          // stiffness and damping
constexpr ValueRange kRestAngleRange = closed_range(0.0, 180.0);     // degrees
constexpr ValueRange kStrainLimitRange = left_open_range(0.0, 1e6);  // break and yield strains
constexpr ValueRange kVariationRange = {0.0, 1.0, true, false};      // [0, 1)
constexpr ValueRange kHardeningRange = closed_range(0.0, 1e6);
constexpr ValueRange kYieldAngleRange = closed_range(0.0, 180.0);  // degrees
// Marks an entry live: it may change while the simulation runs (live_parameter_keys()).
constexpr bool kLive = true;

// The table. Accessors are captureless lambdas (converted to function pointers); setters receive
// values already checked against the range, so the casts to int cannot overflow.
constexpr std::array kScalarParameters = {
    // Lattice.
    ScalarParameter{"lattice.rows", ParameterType::integer, "", kCountRange,
                    "particles along z (the paper's vertical points)",
                    [](const SceneSpec& s) { return double(s.lattice.rows); },
                    [](SceneSpec& s, double v) { s.lattice.rows = static_cast<int>(v); }},
    ScalarParameter{"lattice.cols", ParameterType::integer, "", kCountRange,
                    "particles along x (the paper's horizontal points)",
                    [](const SceneSpec& s) { return double(s.lattice.cols); },
                    [](SceneSpec& s, double v) { s.lattice.cols = static_cast<int>(v); }},
    ScalarParameter{"lattice.spacing", ParameterType::real, "m", left_open_range(0.0, 1000.0),
                    "connector rest length L (distance between neighbouring particles)",
                    [](const SceneSpec& s) { return s.lattice.spacing; },
                    [](SceneSpec& s, double v) { s.lattice.spacing = v; }},
    ScalarParameter{"lattice.particle_mass", ParameterType::real, "kg", left_open_range(0.0, 1e6),
                    "mass of every particle", [](const SceneSpec& s) { return s.lattice.particle_mass; },
                    [](SceneSpec& s, double v) { s.lattice.particle_mass = v; }, kLive},
    // Springs.
    ScalarParameter{"springs.connector.stiffness", ParameterType::real, "N/m", kSpringRange,
                    "stiffness k of the connector springs between 4-neighbours",
                    [](const SceneSpec& s) { return s.lattice.connector.stiffness; },
                    [](SceneSpec& s, double v) { s.lattice.connector.stiffness = v; }, kLive},
    ScalarParameter{"springs.connector.damping", ParameterType::real, "N s/m", kSpringRange,
                    "damping c of the connector springs",
                    [](const SceneSpec& s) { return s.lattice.connector.damping; },
                    [](SceneSpec& s, double v) { s.lattice.connector.damping = v; }, kLive},
    ScalarParameter{"springs.connector.break_strain", ParameterType::limit, "", kStrainLimitRange,
                    "tearing: a connector breaks when l / L0 - 1 exceeds this (varied by break_strain_variation); "
                    "none: never",
                    [](const SceneSpec& s) { return s.lattice.limits.break_strain; },
                    [](SceneSpec& s, double v) { s.lattice.limits.break_strain = v; }},
    ScalarParameter{"springs.connector.break_strain_variation", ParameterType::real, "", kVariationRange,
                    "relative spread of the break strain: connector e breaks at break_strain (1 + variation u_e), "
                    "u_e uniform in [-1, 1] from initial.seed",
                    [](const SceneSpec& s) { return s.lattice.limits.break_strain_variation; },
                    [](SceneSpec& s, double v) { s.lattice.limits.break_strain_variation = v; }},
    ScalarParameter{"springs.connector.yield_strain", ParameterType::limit, "", kStrainLimitRange,
                    "permanent stretching: beyond this strain a connector's rest length follows it (return "
                    "mapping); none: elastic",
                    [](const SceneSpec& s) { return s.lattice.limits.yield_strain; },
                    [](SceneSpec& s, double v) { s.lattice.limits.yield_strain = v; }},
    ScalarParameter{"springs.connector.hardening", ParameterType::real, "", kHardeningRange,
                    "linear hardening: the yield strain grows by hardening times each plastic strain increment",
                    [](const SceneSpec& s) { return s.lattice.limits.hardening; },
                    [](SceneSpec& s, double v) { s.lattice.limits.hardening = v; }},
    ScalarParameter{"springs.adjacent.stiffness", ParameterType::real, "N m/rad", kSpringRange,
                    "stiffness k of the radial springs between adjacent (perpendicular) connectors",
                    [](const SceneSpec& s) { return s.lattice.adjacent.stiffness; },
                    [](SceneSpec& s, double v) { s.lattice.adjacent.stiffness = v; }, kLive},
    ScalarParameter{"springs.adjacent.damping", ParameterType::real, "N m s/rad", kSpringRange,
                    "damping c of the adjacent radial springs",
                    [](const SceneSpec& s) { return s.lattice.adjacent.damping; },
                    [](SceneSpec& s, double v) { s.lattice.adjacent.damping = v; }, kLive},
    ScalarParameter{"springs.adjacent.rest_angle_deg", ParameterType::real, "deg", kRestAngleRange,
                    "rest angle of the adjacent radial springs",
                    [](const SceneSpec& s) { return radians_to_degrees(s.lattice.adjacent_rest_angle); },
                    [](SceneSpec& s, double v) { s.lattice.adjacent_rest_angle = degrees_to_radians(v); }},
    ScalarParameter{"springs.adjacent.yield_angle_deg", ParameterType::limit, "deg", kYieldAngleRange,
                    "in-plane shear that stays: an adjacent spring's rest angle follows beyond this; none: elastic",
                    [](const SceneSpec& s) { return radians_to_degrees(s.lattice.limits.adjacent_yield_angle); },
                    [](SceneSpec& s, double v) { s.lattice.limits.adjacent_yield_angle = degrees_to_radians(v); }},
    ScalarParameter{"springs.opposite.stiffness", ParameterType::real, "N m/rad", kSpringRange,
                    "stiffness k of the radial springs between opposite (collinear) connectors",
                    [](const SceneSpec& s) { return s.lattice.opposite.stiffness; },
                    [](SceneSpec& s, double v) { s.lattice.opposite.stiffness = v; }, kLive},
    ScalarParameter{"springs.opposite.damping", ParameterType::real, "N m s/rad", kSpringRange,
                    "damping c of the opposite radial springs",
                    [](const SceneSpec& s) { return s.lattice.opposite.damping; },
                    [](SceneSpec& s, double v) { s.lattice.opposite.damping = v; }, kLive},
    ScalarParameter{"springs.opposite.rest_angle_deg", ParameterType::real, "deg", kRestAngleRange,
                    "rest angle of the opposite radial springs",
                    [](const SceneSpec& s) { return radians_to_degrees(s.lattice.opposite_rest_angle); },
                    [](SceneSpec& s, double v) { s.lattice.opposite_rest_angle = degrees_to_radians(v); }},
    ScalarParameter{"springs.opposite.yield_angle_deg", ParameterType::limit, "deg", kYieldAngleRange,
                    "creasing: folds that stay; an opposite spring's rest angle follows beyond this; none: elastic",
                    [](const SceneSpec& s) { return radians_to_degrees(s.lattice.limits.opposite_yield_angle); },
                    [](SceneSpec& s, double v) { s.lattice.limits.opposite_yield_angle = degrees_to_radians(v); }},
    // Environment.
    ScalarParameter{"environment.air_drag", ParameterType::real, "kg/s", closed_range(0.0, 1e6),
                    "linear air drag per particle: f = -air_drag v",
                    [](const SceneSpec& s) { return s.environment.air_drag; },
                    [](SceneSpec& s, double v) { s.environment.air_drag = v; }, kLive},
    // Initial conditions.
    ScalarParameter{"initial.position_noise", ParameterType::real, "m", closed_range(0.0, 1000.0),
                    "each free coordinate moved by a uniform random value in [-a, a]",
                    [](const SceneSpec& s) { return s.initial.position_noise; },
                    [](SceneSpec& s, double v) { s.initial.position_noise = v; }},
    ScalarParameter{"initial.velocity_noise", ParameterType::real, "m/s", closed_range(0.0, 1e4),
                    "each free velocity component changed by a uniform random value in [-a, a]",
                    [](const SceneSpec& s) { return s.initial.velocity_noise; },
                    [](SceneSpec& s, double v) { s.initial.velocity_noise = v; }},
    ScalarParameter{"initial.seed", ParameterType::integer, "", closed_range(0.0, kLargestExactInteger),
                    "seed of the random perturbation; the same seed gives the same sheet",
                    [](const SceneSpec& s) { return static_cast<double>(s.initial.seed); },
                    [](SceneSpec& s, double v) { s.initial.seed = static_cast<std::uint64_t>(v); }},
    // Integrator.
    ScalarParameter{"integrator.relative_tolerance", ParameterType::real, "", closed_range(1e-14, 1.0),
                    "RKF45 and imex: relative error allowed per step and coordinate",
                    [](const SceneSpec& s) { return s.integrator.relative_tolerance; },
                    [](SceneSpec& s, double v) { s.integrator.relative_tolerance = v; }, kLive},
    ScalarParameter{"integrator.absolute_tolerance", ParameterType::real, "m, m/s", left_open_range(0.0, 1000.0),
                    "RKF45 and imex: absolute error allowed per step (m for positions, m/s for velocities)",
                    [](const SceneSpec& s) { return s.integrator.absolute_tolerance; },
                    [](SceneSpec& s, double v) { s.integrator.absolute_tolerance = v; }, kLive},
    ScalarParameter{"integrator.time_step", ParameterType::real, "s", closed_range(0.0, 10.0),
                    "fixed-step methods: the step; RKF45 and imex: the first trial step; 0 (the default): "
                    "the method's own, the frame step 1/fps for implicit-euler and 0.001 s for the others",
                    [](const SceneSpec& s) { return s.integrator.time_step; },
                    [](SceneSpec& s, double v) { s.integrator.time_step = v; }, kLive},
    ScalarParameter{"integrator.min_step", ParameterType::real, "s", left_open_range(0.0, 1.0),
                    "RKF45 and imex: smallest step; needing a smaller one stops the run with a diagnosis",
                    [](const SceneSpec& s) { return s.integrator.min_step; },
                    [](SceneSpec& s, double v) { s.integrator.min_step = v; }, kLive},
    ScalarParameter{"integrator.max_step", ParameterType::real, "s", left_open_range(0.0, 1000.0),
                    "RKF45 and imex: largest step", [](const SceneSpec& s) { return s.integrator.max_step; },
                    [](SceneSpec& s, double v) { s.integrator.max_step = v; }, kLive},
    ScalarParameter{"integrator.safety", ParameterType::real, "", left_open_range(0.0, 1.0),
                    "RKF45 and imex: safety factor on the optimal step",
                    [](const SceneSpec& s) { return s.integrator.safety; },
                    [](SceneSpec& s, double v) { s.integrator.safety = v; }, kLive},
    ScalarParameter{"integrator.max_growth", ParameterType::real, "", closed_range(1.0, 100.0),
                    "RKF45 and imex: largest step increase factor per step",
                    [](const SceneSpec& s) { return s.integrator.max_growth; },
                    [](SceneSpec& s, double v) { s.integrator.max_growth = v; }, kLive},
    ScalarParameter{"integrator.max_shrink", ParameterType::real, "", left_open_range(0.0, 1.0),
                    "RKF45 and imex: smallest step decrease factor after a rejected step",
                    [](const SceneSpec& s) { return s.integrator.max_shrink; },
                    [](SceneSpec& s, double v) { s.integrator.max_shrink = v; }, kLive},
    ScalarParameter{"integrator.cg_tolerance", ParameterType::real, "", closed_range(1e-14, 1.0),
                    "implicit Euler (imex derives its own from absolute_tolerance): conjugate gradients stop when "
                    "|residual| <= cg_tolerance |right-hand side|",
                    [](const SceneSpec& s) { return s.integrator.cg_tolerance; },
                    [](SceneSpec& s, double v) { s.integrator.cg_tolerance = v; }},
    ScalarParameter{"integrator.cg_max_iterations", ParameterType::integer, "", closed_range(1.0, 100000.0),
                    "implicit Euler and imex: most conjugate-gradient iterations per step (imex: per stage solve)",
                    [](const SceneSpec& s) { return double(s.integrator.cg_max_iterations); },
                    [](SceneSpec& s, double v) { s.integrator.cg_max_iterations = static_cast<int>(v); }},
    ScalarParameter{"integrator.energy_error_limit", ParameterType::real, "", closed_range(1e-6, 1e6),
                    "a run whose energy balance error gains more than this fraction of its energy scale stops as "
                    "failed (blown up)",
                    [](const SceneSpec& s) { return s.integrator.energy_error_limit; },
                    [](SceneSpec& s, double v) { s.integrator.energy_error_limit = v; }},
    ScalarParameter{"integrator.cg_two_level", ParameterType::boolean, "", closed_range(0.0, 1.0),
                    "implicit Euler and imex: add a coarse-grid correction (4 x 4 aggregates) to the Jacobi "
                    "preconditioner",
                    [](const SceneSpec& s) { return s.integrator.cg_two_level ? 1.0 : 0.0; },
                    [](SceneSpec& s, double v) { s.integrator.cg_two_level = v != 0.0; }},
    ScalarParameter{"integrator.cg_multigrid", ParameterType::boolean, "", closed_range(0.0, 1.0),
                    "implicit Euler and imex, with cg_two_level: the coarse-grid correction is a multigrid V-cycle "
                    "(bilinear interpolation, Gauss-Seidel smoothing) instead of an exact solve on 4 x 4 aggregates; "
                    "implicit Euler sets it up only where the system is stiff (on either backend; the vulkan "
                    "backend takes block Jacobi where this is off)",
                    [](const SceneSpec& s) { return s.integrator.cg_multigrid ? 1.0 : 0.0; },
                    [](SceneSpec& s, double v) { s.integrator.cg_multigrid = v != 0.0; }},
    ScalarParameter{"integrator.cg_line_smoother", ParameterType::boolean, "", closed_range(0.0, 1.0),
                    "implicit Euler and imex, with cg_multigrid: the V-cycle smooths the fine level by solving "
                    "whole lattice rows and columns (block line Gauss-Seidel; fewer CG iterations on stiff "
                    "cloth) instead of single particles, on either backend",
                    [](const SceneSpec& s) { return s.integrator.cg_line_smoother ? 1.0 : 0.0; },
                    [](SceneSpec& s, double v) { s.integrator.cg_line_smoother = v != 0.0; }},
    // Output.
    ScalarParameter{"output.duration", ParameterType::real, "s", left_open_range(0.0, 1e7),
                    "simulated time to run; with until_rest, the upper limit",
                    [](const SceneSpec& s) { return s.output.duration; },
                    [](SceneSpec& s, double v) { s.output.duration = v; }},
    ScalarParameter{"output.fps", ParameterType::integer, "1/s", closed_range(1.0, 10000.0),
                    "frames written per simulated second", [](const SceneSpec& s) { return double(s.output.fps); },
                    [](SceneSpec& s, double v) { s.output.fps = static_cast<int>(v); }},
    ScalarParameter{"output.until_rest", ParameterType::boolean, "", closed_range(0.0, 1.0),
                    "stop once the kinetic energy has stayed below rest_kinetic_energy for rest_duration",
                    [](const SceneSpec& s) { return s.output.until_rest ? 1.0 : 0.0; },
                    [](SceneSpec& s, double v) { s.output.until_rest = v != 0.0; }},
    ScalarParameter{"output.rest_kinetic_energy", ParameterType::real, "J", left_open_range(0.0, 1e12),
                    "kinetic energy below which the sheet counts as at rest",
                    [](const SceneSpec& s) { return s.output.rest_kinetic_energy; },
                    [](SceneSpec& s, double v) { s.output.rest_kinetic_energy = v; }},
    ScalarParameter{"output.rest_duration", ParameterType::real, "s", closed_range(0.0, 1e6),
                    "how long the kinetic energy must stay below rest_kinetic_energy, at every frame, for "
                    "the sheet to count as at rest (0: the first frame below)",
                    [](const SceneSpec& s) { return s.output.rest_duration; },
                    [](SceneSpec& s, double v) { s.output.rest_duration = v; }},
    ScalarParameter{"output.checkpoint_every", ParameterType::real, "s", closed_range(0.0, 1e7),
                    "write a checkpoint (checkpoints/ in the output folder) after the first frame at least this "
                    "much simulated time after the last one, so that `clothsim run --resume` can continue the run "
                    "(0: none)",
                    [](const SceneSpec& s) { return s.output.checkpoint_every; },
                    [](SceneSpec& s, double v) { s.output.checkpoint_every = v; }},
    // Collisions (the obstacles themselves are the "colliders" list).
    ScalarParameter{"collision.thickness", ParameterType::real, "m", left_open_range(0.0, 1.0),
                    "particles are kept this far outside every collider, and (with self) the sheet from itself",
                    [](const SceneSpec& s) { return s.collision.thickness; },
                    [](SceneSpec& s, double v) { s.collision.thickness = v; }},
    ScalarParameter{"collision.self", ParameterType::boolean, "", closed_range(0.0, 1.0),
                    "self-collision: the sheet is kept from passing through itself",
                    [](const SceneSpec& s) { return s.collision.self ? 1.0 : 0.0; },
                    [](SceneSpec& s, double v) { s.collision.self = v != 0.0; }},
    ScalarParameter{"collision.friction", ParameterType::real, "", closed_range(0.0, 10.0),
                    "Coulomb friction coefficient of cloth on cloth, and of colliders without their own friction",
                    [](const SceneSpec& s) { return s.collision.friction; },
                    [](SceneSpec& s, double v) { s.collision.friction = v; }},
    // Execution.
    ScalarParameter{"threads", ParameterType::integer, "", closed_range(0.0, 1024.0),
                    "worker threads; 0 chooses from the lattice size and the idle cores",
                    [](const SceneSpec& s) { return double(s.threads); },
                    [](SceneSpec& s, double v) { s.threads = static_cast<int>(v); }},
    ScalarParameter{"device", ParameterType::integer, "", closed_range(0.0, 1024.0),
                    "the Vulkan device of backend vulkan, as `clothsim devices` numbers them",
                    [](const SceneSpec& s) { return double(s.backend.device); },
                    [](SceneSpec& s, double v) { s.backend.device = static_cast<std::uint32_t>(v); }},
};

constexpr std::array kVectorParameters = {
    VectorParameter{"environment.gravity", "m/s^2", closed_range(-1000.0, 1000.0),
                    "gravitational acceleration (y is up)", [](const SceneSpec& s) { return s.environment.gravity; },
                    [](SceneSpec& s, const Vec3& v) { s.environment.gravity = v; }, kLive},
    VectorParameter{"initial.velocity", "m/s", closed_range(-1e4, 1e4),
                    "uniform initial velocity of every free particle",
                    [](const SceneSpec& s) { return s.initial.velocity; },
                    [](SceneSpec& s, const Vec3& v) { s.initial.velocity = v; }},
    VectorParameter{"initial.angular_velocity", "rad/s", closed_range(-1e4, 1e4),
                    "initial rigid spin about the lattice centre (axis times rate)",
                    [](const SceneSpec& s) { return s.initial.angular_velocity; },
                    [](SceneSpec& s, const Vec3& v) { s.initial.angular_velocity = v; }},
};

constexpr std::array kMaterialParameters = {
    MaterialParameter{"areal_density", ParameterType::real, "kg/m^2", left_open_range(0.0, 1000.0),
                      "mass per unit area (rho)", [](const MaterialDef& m) { return m.areal_density; },
                      [](MaterialDef& m, double v) { m.areal_density = v; }},
    MaterialParameter{"stretch_stiffness", ParameterType::real, "N/m", kSpringRange,
                      "tension per unit width per unit strain (Y = E t)",
                      [](const MaterialDef& m) { return m.stretch_stiffness; },
                      [](MaterialDef& m, double v) { m.stretch_stiffness = v; }},
    MaterialParameter{"shear_stiffness", ParameterType::real, "N/m per rad", kSpringRange,
                      "in-plane shear force per unit length per radian of shear (G)",
                      [](const MaterialDef& m) { return m.shear_stiffness; },
                      [](MaterialDef& m, double v) { m.shear_stiffness = v; }},
    MaterialParameter{"bending_rigidity", ParameterType::real, "N m", kSpringRange,
                      "bending moment per unit width per unit curvature (B)",
                      [](const MaterialDef& m) { return m.bending_rigidity; },
                      [](MaterialDef& m, double v) { m.bending_rigidity = v; }},
    MaterialParameter{"damping_time", ParameterType::real, "s", closed_range(0.0, 10.0),
                      "every spring's damping is damping_time times its stiffness",
                      [](const MaterialDef& m) { return m.damping_time; },
                      [](MaterialDef& m, double v) { m.damping_time = v; }},
    MaterialParameter{
        "break_strain", ParameterType::limit, "", kStrainLimitRange, "strain at which the sheet tears; none: never",
        [](const MaterialDef& m) { return m.break_strain; }, [](MaterialDef& m, double v) { m.break_strain = v; }},
    MaterialParameter{"break_strain_variation", ParameterType::real, "", kVariationRange,
                      "relative spread of the break strain over the connectors",
                      [](const MaterialDef& m) { return m.break_strain_variation; },
                      [](MaterialDef& m, double v) { m.break_strain_variation = v; }},
    MaterialParameter{"yield_strain", ParameterType::limit, "", kStrainLimitRange,
                      "strain beyond which the sheet stretches for good; none: elastic",
                      [](const MaterialDef& m) { return m.yield_strain; },
                      [](MaterialDef& m, double v) { m.yield_strain = v; }},
    MaterialParameter{
        "hardening", ParameterType::real, "", kHardeningRange, "growth of the yield strain per unit plastic strain",
        [](const MaterialDef& m) { return m.hardening; }, [](MaterialDef& m, double v) { m.hardening = v; }},
    MaterialParameter{"adjacent_yield_angle_deg", ParameterType::limit, "deg", kYieldAngleRange,
                      "in-plane shear angle that stays; none: elastic",
                      [](const MaterialDef& m) { return radians_to_degrees(m.adjacent_yield_angle); },
                      [](MaterialDef& m, double v) { m.adjacent_yield_angle = degrees_to_radians(v); }},
    MaterialParameter{"opposite_yield_angle_deg", ParameterType::limit, "deg", kYieldAngleRange,
                      "fold angle that stays (creasing); none: elastic",
                      [](const MaterialDef& m) { return radians_to_degrees(m.opposite_yield_angle); },
                      [](MaterialDef& m, double v) { m.opposite_yield_angle = degrees_to_radians(v); }},
};

// The keys parsed by hand in scene.cpp, with the same live mark as the tables'.
struct SpecialKey {
  std::string_view key;
  bool live = false;
};
constexpr std::array kSpecialKeys = {
    SpecialKey{"name"},          SpecialKey{"description"},
    SpecialKey{"paper_args"},    SpecialKey{"material"},
    SpecialKey{"anchors"},       SpecialKey{"cuts"},
    SpecialKey{"colliders"},     SpecialKey{"integrator.method", kLive},
    SpecialKey{"output.export"}, SpecialKey{"backend"},
    SpecialKey{"precision"},
};

// "1e+09" -> "1e9", "1e-06" -> "1e-6".
std::string compact_exponent(std::string text) {
  const std::size_t e = text.find('e');
  if (e == std::string::npos) return text;
  std::string mantissa = text.substr(0, e);
  std::string exponent = text.substr(e + 1);
  const bool negative = !exponent.empty() && exponent[0] == '-';
  if (!exponent.empty() && (exponent[0] == '-' || exponent[0] == '+')) exponent.erase(0, 1);
  while (exponent.size() > 1 && exponent[0] == '0') exponent.erase(0, 1);
  return mantissa + "e" + (negative ? "-" : "") + exponent;
}

}  // namespace

bool ValueRange::contains(double value) const {
  if (!std::isfinite(value)) return false;
  const bool above_min = min_inclusive ? value >= min : value > min;
  const bool below_max = max_inclusive ? value <= max : value < max;
  return above_min && below_max;
}

std::span<const ScalarParameter> scalar_parameters() { return kScalarParameters; }
std::span<const VectorParameter> vector_parameters() { return kVectorParameters; }
std::span<const std::string_view> special_keys() {
  static const std::vector<std::string_view> keys = [] {
    std::vector<std::string_view> list;
    for (const SpecialKey& special : kSpecialKeys) list.push_back(special.key);
    return list;
  }();
  return keys;
}

const ScalarParameter* find_scalar_parameter(std::string_view key) {
  for (const ScalarParameter& parameter : kScalarParameters) {
    if (parameter.key == key) return &parameter;
  }
  return nullptr;
}

std::span<const MaterialParameter> material_parameters() { return kMaterialParameters; }

const MaterialParameter* find_material_parameter(std::string_view key) {
  for (const MaterialParameter& parameter : kMaterialParameters) {
    if (parameter.key == key) return &parameter;
  }
  return nullptr;
}

const VectorParameter* find_vector_parameter(std::string_view key) {
  for (const VectorParameter& parameter : kVectorParameters) {
    if (parameter.key == key) return &parameter;
  }
  return nullptr;
}

std::span<const std::string_view> all_scene_keys() {
  static const std::vector<std::string_view> keys = [] {
    std::vector<std::string_view> list;
    for (const ScalarParameter& parameter : kScalarParameters) list.push_back(parameter.key);
    for (const VectorParameter& parameter : kVectorParameters) list.push_back(parameter.key);
    for (const SpecialKey& special : kSpecialKeys) list.push_back(special.key);
    return list;
  }();
  return keys;
}

std::span<const std::string_view> live_parameter_keys() {
  static const std::vector<std::string_view> keys = [] {
    std::vector<std::string_view> list;
    for (const ScalarParameter& parameter : kScalarParameters) {
      if (parameter.live) list.push_back(parameter.key);
    }
    for (const VectorParameter& parameter : kVectorParameters) {
      if (parameter.live) list.push_back(parameter.key);
    }
    for (const SpecialKey& special : kSpecialKeys) {
      if (special.live) list.push_back(special.key);
    }
    return list;
  }();
  return keys;
}

bool is_live_parameter(std::string_view key) {
  const std::span<const std::string_view> keys = live_parameter_keys();
  return std::find(keys.begin(), keys.end(), key) != keys.end();
}

std::string live_parameter_list() {
  std::string text;
  for (std::string_view key : live_parameter_keys()) {
    if (!text.empty()) text += ", ";
    text += key;
  }
  return text;
}

std::string format_number(double value) {
  if (value == 0.0) return "0";  // also turns -0 into 0
  std::array<char, 64> buffer{};
  const auto [end, error] = std::to_chars(buffer.data(), buffer.data() + buffer.size(), value);
  if (error != std::errc()) return "?";
  return compact_exponent(std::string(buffer.data(), end));
}

std::string describe_range(const ValueRange& range) {
  return std::string(range.min_inclusive ? "[" : "(") + format_number(range.min) + ", " + format_number(range.max) +
         (range.max_inclusive ? "]" : ")");
}

std::string describe_allowed(ParameterType type, const ValueRange& range) {
  switch (type) {
    case ParameterType::boolean: return "a boolean (true or false)";
    case ParameterType::integer: return "an integer in " + describe_range(range);
    case ParameterType::limit: return "a number in " + describe_range(range) + " or none (never)";
    case ParameterType::real: break;
  }
  return "a number in " + describe_range(range);
}

bool is_allowed(ParameterType type, const ValueRange& range, double value) {
  if (type == ParameterType::limit && value == std::numeric_limits<double>::infinity()) return true;
  if (!range.contains(value)) return false;
  if (type == ParameterType::integer || type == ParameterType::boolean) return std::floor(value) == value;
  return true;
}

std::string format_parameter_value(ParameterType type, double value) {
  if (type == ParameterType::boolean) return value != 0.0 ? "true" : "false";
  if (type == ParameterType::limit && value == std::numeric_limits<double>::infinity()) return "none";
  return format_number(value);
}

double degrees_to_radians(double degrees) { return degrees / 180.0 * std::numbers::pi; }
double radians_to_degrees(double radians) { return radians / std::numbers::pi * 180.0; }

}  // namespace clothsim

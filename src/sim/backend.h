// Where a simulation's steps run: on the CPU (every integrator and every feature), or on a Vulkan
// device (gpu/device_integrator.h: RKF45, RK4 and symplectic Euler with the whole step on the
// device; docs/gpu.md lists what it covers). The scene's `backend`, `device` and `precision`, and
// the flags of the same names.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

#include "core/precision.h"
#include "core/stage_passes.h"
#include "integrators/integrator.h"
#include "model/cloth_model.h"
#include "model/spring_limits.h"

namespace clothsim {

enum class Backend : std::uint8_t { cpu, vulkan };

std::string_view to_string(Backend backend);
// "cpu" or "vulkan"; false for any other text (`backend` is then unchanged).
bool parse_backend(std::string_view text, Backend& backend);

struct BackendSettings {
  Backend kind = Backend::cpu;
  std::uint32_t device = 0;                   // the Vulkan device, as `clothsim devices` numbers it
  std::optional<PrecisionRequest> precision;  // unset: the backend's default (resolved_precision)
  // The device's explicit methods on a lattice sheet: three passes a stage, one, or several stages
  // chained in a pass (core/stage_passes.h), the same bits; unset, the device's choice
  // (gpu::DeviceSelection::stage_passes).
  std::optional<StagePasses> stage_passes = std::nullopt;
  // The precision the backend computes in for `integrator` on a sheet that is a lattice or not
  // (the CPU's float32 forces are the lattice kernel's): the one asked for; for `auto`,
  // automatic_precision's choice (float64 on the CPU for a sheet that is not a lattice); unset,
  // `auto` on the CPU and float32 on a device (twice the throughput there, and every device has
  // it), but float64 for implicit Euler on either. Where the CPU resolves `auto` to float32, that
  // is the precision it starts in: it then chooses frame by frame (chooses_by_frame).
  Precision resolved_precision(const IntegratorSettings& integrator, bool lattice) const;
  // Whether the run chooses its forces' precision frame by frame (sim/precision_choice.h): on the
  // CPU, where `auto` (asked for, or the default) resolves to float32.
  bool chooses_by_frame(const IntegratorSettings& integrator, bool lattice) const;
  bool operator==(const BackendSettings&) const = default;
};

// `auto`'s rule: float32 where RKF45's requested tolerances are loose enough that float32 forces
// cannot spoil them, float64 everywhere else (fixed-step methods ask for no accuracy to check
// against, and implicit Euler runs float64 only). docs/performance.md, "Mixed precision", has
// the measurements behind the threshold. On the CPU a run that starts in float32 then checks
// each frame's forces (sim/precision_choice.h).
Precision automatic_precision(const IntegratorSettings& integrator);
// The tightest tolerances (relative and absolute, each) at which `auto` picks float32: RKF45's
// default. There float32 forces keep a paper scene as close to the exact motion as float64 ones
// and take no more steps; at 1e-7 their rounding is four times the float64 run's error and costs
// 14 % more evaluations (docs/performance.md, "Mixed precision").
inline constexpr double kAutomaticFloat32Tolerance = 1e-6;

// Whether the CPU computes the forces of `model` with the lattice kernel, whose forces alone can
// be float32 (forces/lattice_kernel.h): the lattice layout, and `kernel` not the general one.
bool lattice_forces(const ClothModel& model, ForceKernel kernel);

// Whether this build has the Vulkan backend (CLOTHSIM_BUILD_VULKAN).
bool vulkan_backend_built();

// What of a simulation not every backend runs: read from a model (features_of) or from a scene
// before its model is built (validate_scene).
struct BackendFeatures {
  IntegratorSettings integrator;  // the method, and for `auto` its tolerances
  SpringLimits limits;            // tearing, permanent stretching, creasing
  bool colliders = false;         // any obstacle
  bool self_collision = false;    // collision.self
  bool lattice = true;            // the lattice layout of build_lattice (every scene's)
};
BackendFeatures features_of(const ClothModel& model, const IntegratorSettings& integrator);
// A plain sheet integrated with `kind`: the features of the benchmark's cases.
BackendFeatures features_of(IntegratorKind kind);

// What `backend` cannot run of these features, as a phrase naming the feature and the scene field
// that asks for it ("tearing (springs.connector.break_strain)"); empty when it runs all of them.
// The CPU runs everything in float64, and float32 forces for the explicit methods on a lattice;
// implicit Euler runs in float64 only, on either backend.
std::string unsupported_by_backend(const BackendFeatures& features, const BackendSettings& backend);

// "the vulkan backend does not run <unsupported> yet; use backend cpu (...)"; a phrase that carries
// its own advice ("...; use precision float64 or auto") ends with it, on either backend.
std::string backend_refusal(const std::string& unsupported, const BackendSettings& backend);

// Thrown by make_backend_integrator for a backend that cannot run the simulation: a feature it
// does not cover, no Vulkan in this build, no device, a device without the precision or the
// memory. The message reads on its own.
class BackendError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Checks, before a model of these counts (and `colliders` obstacles) is built, that `backend` has
// the device and the device memory for it: opens the device (a Vulkan instance, a few
// milliseconds) and compares. Nothing to check on the CPU (its memory is checked from the scene:
// sim/memory_estimate.h). Throws BackendError.
// `self_collision`: collision.self, whose pass implicit Euler runs on the device.
void check_backend_fits(const LatticeCounts& counts, std::size_t anchors, const IntegratorSettings& integrator,
                        const BackendSettings& backend, std::size_t colliders = 0, bool self_collision = false);

// The integrator of `integrator.kind` on `backend`. Throws BackendError.
std::unique_ptr<Integrator> make_backend_integrator(const ClothModel& model, const IntegratorSettings& integrator,
                                                    const ForceOptions& options, const BackendSettings& backend);

}  // namespace clothsim

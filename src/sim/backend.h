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
  std::uint32_t device = 0;            // the Vulkan device, as `clothsim devices` numbers it
  std::optional<Precision> precision;  // unset: the backend's default, precision()
  // The precision the backend computes in: the one set, else float64 on the CPU and float32 on
  // a device (the default: twice the throughput, and every device has it).
  Precision resolved_precision() const {
    return precision.value_or(kind == Backend::cpu ? Precision::float64 : Precision::float32);
  }
  bool operator==(const BackendSettings&) const = default;
};

// Whether this build has the Vulkan backend (CLOTHSIM_BUILD_VULKAN).
bool vulkan_backend_built();

// What of a simulation not every backend runs: read from a model (features_of) or from a scene
// before its model is built (validate_scene).
struct BackendFeatures {
  IntegratorKind integrator = IntegratorKind::rkf45;
  SpringLimits limits;          // tearing, permanent stretching, creasing
  bool colliders = false;       // any obstacle
  bool self_collision = false;  // collision.self
  bool lattice = true;          // the lattice layout of build_lattice (every scene's)
};
BackendFeatures features_of(const ClothModel& model, const IntegratorSettings& integrator);
// A plain sheet integrated with `kind`: the features of the benchmark's cases.
BackendFeatures features_of(IntegratorKind kind);

// What `backend` cannot run of these features, as a phrase naming the feature and the scene field
// that asks for it ("tearing (springs.connector.break_strain)"); empty when it runs all of them.
// The CPU runs everything, in float64; float32 is a device precision.
std::string unsupported_by_backend(const BackendFeatures& features, const BackendSettings& backend);

// "the vulkan backend does not run <unsupported> yet; use backend cpu (...)".
std::string backend_refusal(const std::string& unsupported, const BackendSettings& backend);

// Thrown by make_backend_integrator for a backend that cannot run the simulation: a feature it
// does not cover, no Vulkan in this build, no device, a device without the precision or the
// memory. The message reads on its own.
class BackendError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Checks, before a model of these counts is built, that `backend` has the device and the device
// memory for it: opens the device (a Vulkan instance, a few milliseconds) and compares. Nothing
// to check on the CPU (its memory is checked from the scene: sim/memory_estimate.h). Throws
// BackendError.
void check_backend_fits(const LatticeCounts& counts, std::size_t anchors, IntegratorKind integrator,
                        const BackendSettings& backend);

// The integrator of `integrator.kind` on `backend`. Throws BackendError.
std::unique_ptr<Integrator> make_backend_integrator(const ClothModel& model, const IntegratorSettings& integrator,
                                                    const ForceOptions& options, const BackendSettings& backend);

}  // namespace clothsim

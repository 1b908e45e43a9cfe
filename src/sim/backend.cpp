#include "sim/backend.h"

#if CLOTHSIM_HAVE_VULKAN
#include "gpu/device_implicit_euler.h"
#include "gpu/device_integrator.h"
#include "gpu/gpu_error.h"
#endif

namespace clothsim {
namespace {

[[maybe_unused]] constexpr const char* kNoVulkan =
    "this clothsim was built without the Vulkan backend (CLOTHSIM_BUILD_VULKAN=OFF, or Vulkan and glslc were not "
    "found when it was configured); use backend cpu";

}  // namespace

std::string_view to_string(Backend backend) { return backend == Backend::cpu ? "cpu" : "vulkan"; }

bool parse_backend(std::string_view text, Backend& backend) {
  if (text == "cpu") {
    backend = Backend::cpu;
    return true;
  }
  if (text == "vulkan") {
    backend = Backend::vulkan;
    return true;
  }
  return false;
}

bool vulkan_backend_built() {
#if CLOTHSIM_HAVE_VULKAN
  return true;
#else
  return false;
#endif
}

BackendFeatures features_of(const ClothModel& model, const IntegratorSettings& integrator) {
  return {integrator, model.limits, !model.colliders.empty(), model.collision.self,
          model.layout == ModelLayout::lattice};
}

BackendFeatures features_of(IntegratorKind kind) {
  BackendFeatures features;
  features.integrator.kind = kind;
  return features;
}

bool lattice_forces(const ClothModel& model, ForceKernel kernel) {
  return model.layout == ModelLayout::lattice && kernel != ForceKernel::general;
}

Precision automatic_precision(const IntegratorSettings& integrator) {
  const bool loose = integrator.relative_tolerance >= kAutomaticFloat32Tolerance &&
                     integrator.absolute_tolerance >= kAutomaticFloat32Tolerance;
  return integrator.kind == IntegratorKind::rkf45 && loose ? Precision::float32 : Precision::float64;
}

Precision BackendSettings::resolved_precision(const IntegratorSettings& integrator, bool lattice) const {
  // The device's default is float32 for the explicit methods; implicit Euler runs float64 on both.
  if (!precision && kind == Backend::vulkan) {
    return integrator.kind == IntegratorKind::implicit_euler ? Precision::float64 : Precision::float32;
  }
  // The CPU's default is `auto`, checked frame by frame (sim/precision_choice.h).
  switch (precision.value_or(PrecisionRequest::automatic)) {
    case PrecisionRequest::float64: return Precision::float64;
    case PrecisionRequest::float32: return Precision::float32;
    case PrecisionRequest::automatic:
      // The CPU's float32 forces are the lattice kernel's.
      return kind == Backend::cpu && !lattice ? Precision::float64 : automatic_precision(integrator);
  }
  return Precision::float64;
}

bool BackendSettings::chooses_by_frame(const IntegratorSettings& integrator, bool lattice) const {
  const bool automatic = precision.value_or(PrecisionRequest::automatic) == PrecisionRequest::automatic;
  return kind == Backend::cpu && automatic && resolved_precision(integrator, lattice) == Precision::float32;
}

std::string unsupported_by_backend(const BackendFeatures& features, const BackendSettings& backend) {
  const bool float32 = backend.resolved_precision(features.integrator, features.lattice) == Precision::float32;
  const bool implicit_euler = features.integrator.kind == IntegratorKind::implicit_euler;
  if (float32 && implicit_euler) {
    return "float32 (precision) with implicit-euler (integrator.method), whose Newton solve needs float64 forces; "
           "use precision float64 or auto";
  }
  if (backend.kind == Backend::cpu) {
    // float32 is the lattice kernel's, for the methods that only evaluate forces.
    if (float32 && !features.lattice)
      return "float32 (precision) on a sheet that is not a lattice; use precision float64";
    return "";
  }
  if (features.integrator.kind == IntegratorKind::imex) return "imex (integrator.method)";
  // Self-collision runs on the host between the device's steps (Simulation::host_works_between_steps);
  // implicit Euler's obstacle pass and laws run on the device on any sheet, on its element arrays
  // (gpu/device_implicit_euler.h).
  if (implicit_euler) return "";
  // The laws run on the device's lattice path only (gpu/device_lattice.cpp).
  if (!features.lattice && features.limits.changes_sheet()) {
    return "tearing, permanent stretching or creasing of a sheet that is not a lattice (springs.*)";
  }
  // The obstacle pass runs on the device's lattice path (gpu/device_obstacles.cpp).
  if (features.colliders && !features.lattice) return "obstacles (colliders) on a sheet that is not a lattice";
  return "";
}

std::string backend_refusal(const std::string& unsupported, const BackendSettings& backend) {
  std::string message = "the " + std::string(to_string(backend.kind)) + " backend does not run " + unsupported;
  // A phrase with its own advice (after "; ") names what no backend runs; the rest the CPU runs.
  const bool advised = unsupported.find("; ") != std::string::npos;
  if (backend.kind == Backend::vulkan && !advised)
    message += " yet; use backend cpu (docs/gpu.md lists what runs where)";
  return message;
}

void check_backend_fits(const LatticeCounts& counts, std::size_t anchors, const IntegratorSettings& integrator,
                        const BackendSettings& backend, std::size_t colliders, bool self_collision) {
  if (backend.kind == Backend::cpu) return;
#if CLOTHSIM_HAVE_VULKAN
  try {
    const Precision precision = backend.resolved_precision(integrator, true);
    const gpu::Device device(gpu::DeviceOptions{backend.device, false});
    device.require_precision(precision);
    const std::uint64_t bytes =
        integrator.kind == IntegratorKind::implicit_euler
            ? gpu::DeviceImplicitEuler::device_bytes_for(counts, anchors, precision, colliders, integrator,
                                                         self_collision)
            : gpu::DeviceIntegrator::device_bytes_for(
                  counts, anchors, integrator.kind, precision, gpu::DeviceForcePath::lattice, colliders,
                  gpu::DeviceIntegrator::chained_stages_for(device, precision, backend.stage_passes,
                                                            gpu::DeviceForcePath::lattice));
    device.require_memory(bytes, "the scene");
  } catch (const gpu::GpuError& error) {
    throw BackendError(std::string("the vulkan backend cannot run: ") + error.what());
  }
#else
  (void)counts;
  (void)anchors;
  (void)integrator;
  (void)colliders;
  (void)self_collision;
  throw BackendError(kNoVulkan);
#endif
}

std::unique_ptr<Integrator> make_backend_integrator(const ClothModel& model, const IntegratorSettings& integrator,
                                                    const ForceOptions& options, const BackendSettings& backend) {
  BackendFeatures features = features_of(model, integrator);
  if (backend.kind == Backend::cpu) features.lattice = lattice_forces(model, options.kernel);
  const std::string unsupported = unsupported_by_backend(features, backend);
  if (!unsupported.empty()) throw BackendError(backend_refusal(unsupported, backend));
  const Precision precision = backend.resolved_precision(integrator, features.lattice);
  if (backend.kind == Backend::cpu) {
    ForceOptions cpu = options;
    cpu.precision = precision;
    cpu.both_precisions = backend.chooses_by_frame(integrator, features.lattice);
    return make_integrator(model, integrator, cpu);
  }
#if CLOTHSIM_HAVE_VULKAN
  try {
    gpu::DeviceSelection selection{backend.device, precision};
    selection.stage_passes = backend.stage_passes;
    if (integrator.kind == IntegratorKind::implicit_euler) {
      return std::make_unique<gpu::DeviceImplicitEuler>(model, integrator, options, selection);
    }
    return std::make_unique<gpu::DeviceIntegrator>(model, integrator, options, selection);
  } catch (const gpu::GpuError& error) {
    throw BackendError(std::string("the vulkan backend cannot run: ") + error.what());
  }
#else
  throw BackendError(kNoVulkan);
#endif
}

}  // namespace clothsim

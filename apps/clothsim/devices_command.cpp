// `clothsim devices`: the Vulkan devices of this machine, one per line, numbered as the Vulkan
// module (src/gpu) opens them. Without a Vulkan driver, or in a build without the module, a clear
// message and exit code 3 (kExitOutputError's number: "the tool cannot do this here", as for a
// missing OpenGL context; docs/cli.md).
#include <cstdio>
#include <vector>

#include "commands.h"

#if defined(CLOTHSIM_HAS_VULKAN)
#include "gpu/device.h"
#include "gpu/gpu_error.h"
#include "gpu/instance.h"
#endif

namespace clothsim::cli {
namespace {

int list_devices() {
#if defined(CLOTHSIM_HAS_VULKAN)
  std::vector<gpu::DeviceInfo> devices;
  try {
    const gpu::Instance instance;
    devices = instance.devices();
  } catch (const gpu::GpuError& error) {
    print_error(error.what());
    return kExitOutputError;
  }
  if (devices.empty()) {
    print_error(
        "no Vulkan device: the Vulkan loader found no device (install a driver: mesa-vulkan-drivers "
        "provides lavapipe, which runs on the CPU)");
    return kExitOutputError;
  }
  for (const gpu::DeviceInfo& device : devices) {
    std::printf("%u: %s, %s, driver %s, Vulkan %s, %s device memory, float64 %s\n", device.index, device.name.c_str(),
                device.type.c_str(), device.driver.c_str(), device.api_version.c_str(),
                gpu::mebibytes(device.device_local_bytes).c_str(), device.float64 ? "yes" : "no");
  }
  return kExitSuccess;
#else
  print_error("this clothsim was built without Vulkan (CLOTHSIM_BUILD_VULKAN=OFF): no devices to list");
  return kExitOutputError;
#endif
}

}  // namespace

Subcommand add_devices_command(CLI::App& parent) {
  CLI::App* app = parent.add_subcommand("devices", "List the Vulkan devices (GPUs, and lavapipe on the CPU)");
  app->footer(
      "One line per device: index, name, type, driver, Vulkan version, device memory, float64 support.\n"
      "Exit codes: 0 listed, 3 no Vulkan driver or device (or a build without Vulkan).\n"
      "Documentation: docs/gpu.md, docs/cli.md.\n"
      "\n"
      "Examples:\n"
      "  clothsim devices\n");
  return {app, [] { return list_devices(); }};
}

}  // namespace clothsim::cli

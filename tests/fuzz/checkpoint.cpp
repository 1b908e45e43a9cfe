// Fuzz target: checkpoint files (src/io/checkpoint.h), read the way `clothsim run --resume` reads
// them (load_run_checkpoint into a simulation of the built-in paper-fig5 scene, run/run_checkpoints.h).
// A CheckpointError is the expected outcome of a bad file; after a file is accepted, the restored
// simulation must hold a state of the right size.
//
// An input that starts with the checkpoint magic is the whole file, so the header's checks are
// fuzzed; any other input is taken as the payload and given a valid header and checksum, so that
// the fuzzer reaches the field parser instead of stopping at the checksum every time.
#include <unistd.h>

#include <array>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "core/crc32.h"
#include "fuzz_target.h"
#include "io/checkpoint.h"
#include "run/run_checkpoints.h"
#include "scene/builtin_scenes.h"
#include "scene/scene.h"
#include "scene/scene_model.h"

namespace {

using namespace clothsim;

constexpr std::array<char, 8> kMagic = {'\x89', 'C', 'S', 'C', 'K', 'P', 'T', '\n'};

// The file to read: the input itself, or the input as the payload of a well-formed file.
std::vector<char> checkpoint_bytes(const std::uint8_t* data, std::size_t size) {
  const auto* begin = reinterpret_cast<const char*>(data);
  if (size >= kMagic.size() && std::memcmp(begin, kMagic.data(), kMagic.size()) == 0) return {begin, begin + size};
  std::vector<char> file(kMagic.begin(), kMagic.end());
  const std::uint32_t version = kCheckpointVersion;
  const std::uint32_t reserved = 0;
  const std::uint64_t payload = size;
  const std::uint32_t crc = crc32(data, size);
  const auto append = [&file](const void* bytes, std::size_t count) {
    const auto* p = static_cast<const char*>(bytes);
    file.insert(file.end(), p, p + count);
  };
  append(&version, sizeof version);
  append(&reserved, sizeof reserved);
  append(&payload, sizeof payload);
  append(data, size);
  append(&crc, sizeof crc);
  return file;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const SceneSpec spec = builtin_scene("paper-fig5");
  static const ClothModel model = build_model(spec);
  static const ClothState initial = build_initial_state(model, spec);
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / ("clothsim-fuzz-checkpoint-" + std::to_string(::getpid()) + ".ckpt");
  {
    const std::vector<char> bytes = checkpoint_bytes(data, size);
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  }
  SimulationSettings settings;
  settings.integrator = spec.integrator;
  settings.threads = 1;
  Simulation simulation(model, initial, settings);
  RunCheckpoint run;
  const std::vector<std::filesystem::path> candidates = {path};
  try {
    load_run_checkpoint(candidates, simulation, run, [](const std::string&) {});
    FUZZ_CHECK(simulation.state().position.size() == model.particle_count());
    FUZZ_CHECK(run.writer.frames > 0);
  } catch (const CheckpointError&) {
    // A bad file, refused: what --resume reports.
  }
  std::filesystem::remove(path);
  return 0;
}

// Checkpoint files (io/checkpoint.h) and a simulation's state through them (sim/simulation.h,
// transfer_state): every damaged or truncated file is refused before a field is applied, fields
// are checked by name and length, and a simulation restored from a checkpoint goes on bit for bit
// as the one saved, whichever integrator and whatever the sheet went through.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

#include "core/crc32.h"
#include "io/checkpoint.h"
#include "io/restored_run.h"
#include "scene/builtin_scenes.h"
#include "scene/scene.h"
#include "scene_simulation.h"
#include "test_checks.h"

namespace clothsim {
namespace {

namespace fs = std::filesystem;
using testing::expect_restored_run_matches;

fs::path test_folder() { return checks::fresh_test_folder("checkpoint"); }

std::vector<char> read_bytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

void write_bytes(const fs::path& path, const std::vector<char>& bytes) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
}

// One field of every kind.
struct Sample {
  double real = 0.0;
  std::uint64_t count = 0;
  std::string text;
  std::vector<double> reals;
  std::vector<Vec3> points;
  std::vector<std::uint8_t> flags;
  std::vector<std::uint32_t> indices;
  std::vector<std::int32_t> signed_indices;

  void transfer(StateArchive& archive) {
    archive.value("real", real);
    archive.value("count", count);
    archive.text("text", text);
    archive.vector("reals", reals);
    archive.array("points", points);
    archive.array("flags", flags);
    archive.array("indices", indices);
    archive.array("signed_indices", signed_indices);
  }
};

Sample filled_sample() {
  Sample sample;
  sample.real = -1.25e-300;
  sample.count = std::numeric_limits<std::uint64_t>::max() - 7;
  sample.text = "scene \"x\"\n";
  sample.reals = {1.0, std::numeric_limits<double>::infinity(), -0.0};
  sample.points = {{1, 2, 3}, {4, 5, 6}};
  sample.flags = {0, 1, 255};
  sample.indices = {7, 0xffffffffu};
  sample.signed_indices = {-1, 42};
  return sample;
}

// An empty sample whose fixed-length arrays have the filled one's lengths (as a built model has).
Sample empty_sample() {
  Sample sample;
  sample.points.resize(2);
  sample.flags.resize(3);
  sample.indices.resize(2);
  sample.signed_indices.resize(2);
  return sample;
}

TEST(Crc32, MatchesTheStandardCheckValue) {
  const std::string digits = "123456789";
  EXPECT_EQ(crc32(digits.data(), digits.size()), 0xCBF43926u);
  EXPECT_EQ(crc32(digits.data() + 4, 5, crc32(digits.data(), 4)), 0xCBF43926u);
}

TEST(Checkpoint, EveryKindOfFieldComesBackBitForBit) {
  const fs::path path = test_folder() / "sample.ckpt";
  Sample saved = filled_sample();
  write_checkpoint(path, [&](StateArchive& archive) { saved.transfer(archive); });
  Sample loaded = empty_sample();
  CheckpointReader reader(path);
  loaded.transfer(reader);
  reader.finish();
  EXPECT_EQ(std::memcmp(&loaded.real, &saved.real, sizeof(double)), 0);
  EXPECT_EQ(loaded.count, saved.count);
  EXPECT_EQ(loaded.text, saved.text);
  ASSERT_EQ(loaded.reals.size(), saved.reals.size());
  EXPECT_EQ(std::memcmp(loaded.reals.data(), saved.reals.data(), saved.reals.size() * sizeof(double)), 0);
  EXPECT_EQ(std::memcmp(loaded.points.data(), saved.points.data(), saved.points.size() * sizeof(Vec3)), 0);
  EXPECT_EQ(loaded.flags, saved.flags);
  EXPECT_EQ(loaded.indices, saved.indices);
  EXPECT_EQ(loaded.signed_indices, saved.signed_indices);
  // Nothing but the file is left: the temporary file was renamed.
  EXPECT_EQ(std::distance(fs::directory_iterator(path.parent_path()), fs::directory_iterator()), 1);
}

TEST(Checkpoint, EveryFlippedByteAndEveryTruncationIsRefused) {
  const fs::path folder = test_folder();
  const fs::path path = folder / "sample.ckpt";
  Sample saved = filled_sample();
  write_checkpoint(path, [&](StateArchive& archive) { saved.transfer(archive); });
  const std::vector<char> good = read_bytes(path);
  const fs::path damaged = folder / "damaged.ckpt";
  for (std::size_t at = 0; at < good.size(); ++at) {
    std::vector<char> bytes = good;
    bytes[at] = static_cast<char>(bytes[at] ^ 0x01);
    write_bytes(damaged, bytes);
    EXPECT_THROW(CheckpointReader{damaged}, CheckpointError) << "byte " << at << " of " << good.size();
  }
  for (std::size_t length = 0; length < good.size(); ++length) {
    write_bytes(damaged, std::vector<char>(good.begin(), good.begin() + static_cast<std::ptrdiff_t>(length)));
    EXPECT_THROW(CheckpointReader{damaged}, CheckpointError) << length << " of " << good.size() << " bytes";
  }
}

TEST(Checkpoint, MessagesNameTheFileAndTheField) {
  const fs::path folder = test_folder();
  const fs::path path = folder / "sample.ckpt";
  Sample saved = filled_sample();
  write_checkpoint(path, [&](StateArchive& archive) { saved.transfer(archive); });

  std::vector<char> bytes = read_bytes(path);
  bytes[bytes.size() / 2] = static_cast<char>(bytes[bytes.size() / 2] ^ 0x40);
  write_bytes(folder / "flipped.ckpt", bytes);
  try {
    CheckpointReader reader(folder / "flipped.ckpt");
    ADD_FAILURE() << "a damaged file was accepted";
  } catch (const CheckpointError& error) {
    EXPECT_TRUE(checks::contains(error.what(), "flipped.ckpt"));
    EXPECT_TRUE(checks::contains(error.what(), "checksum"));
  }

  // A field of another name, and an array of another length.
  {
    CheckpointReader reader(path);
    double real = 0.0;
    try {
      reader.value("energy", real);
      ADD_FAILURE() << "a field of another name was accepted";
    } catch (const CheckpointError& error) {
      EXPECT_TRUE(checks::contains(error.what(), "expected field 'energy', found 'real'"));
    }
  }
  {
    CheckpointReader reader(path);
    Sample other = empty_sample();
    other.points.resize(3);
    EXPECT_THROW(other.transfer(reader), CheckpointError);
  }
  // A list whose stored length is far longer than the file (written with a valid checksum) fails
  // before it allocates.
  write_checkpoint(folder / "long.ckpt", [](StateArchive& archive) {
    std::uint64_t size = std::uint64_t{1} << 60;
    archive.value("reals.size", size);
  });
  CheckpointReader reader(folder / "long.ckpt");
  std::vector<double> reals;
  EXPECT_THROW(reader.vector("reals", reals), CheckpointError);
  EXPECT_TRUE(reals.empty());
}

TEST(SimulationCheckpoint, EveryIntegratorGoesOnBitForBit) {
  for (IntegratorKind kind : all_integrator_kinds()) {
    SCOPED_TRACE(std::string(to_string(kind)));
    SceneSpec spec = builtin_scene("paper-fig5");
    spec.integrator.kind = kind;
    spec.integrator.time_step = kind == IntegratorKind::implicit_euler ? 1e-3 : 1e-4;
    expect_restored_run_matches(spec, 0.3, 0.6, 6);
  }
}

TEST(SimulationCheckpoint, Float32SpringsGoOnInFloat32BitForBit) {
  // The CPU's mixed precision (float32 springs, float64 state): the restored simulation's
  // integrator is made on the run's backend and precision, as the saved one was.
  SceneSpec spec = builtin_scene("paper-fig5");
  spec.backend.precision = PrecisionRequest::float32;
  expect_restored_run_matches(spec, 0.3, 0.6, 6);
}

TEST(SimulationCheckpoint, AutoPrecisionChoosesAsTheSavedRunBitForBit) {
  // `auto` frame by frame (sim/precision_choice.h) on the paper's material 30 times stiffer, which
  // changes precision back and forth: the restored run chooses from the state as the saved one
  // does, window by window, and its counts of windows go on from the saved ones.
  SceneSpec spec = scene_from_paper_args("16,16,1,120,1,42000,200,2400,5,1", "test");
  spec.backend.precision = PrecisionRequest::automatic;
  expect_restored_run_matches(spec, 0.25, 0.5, 15);
}

TEST(SimulationCheckpoint, TornAndYieldedSheetGoesOnBitForBit) {
  // tear-pull has broken connectors and yielded rest lengths by 0.6 s, and keeps tearing after.
  const SceneSpec spec = builtin_scene("tear-pull");
  Simulation probe = testing::one_thread_simulation(spec);
  ASSERT_TRUE(probe.advance_to(0.6));
  ASSERT_GT(probe.model_changes().max_plastic_strain, 0.0);
  expect_restored_run_matches(spec, 0.6, 1.0, 4);
}

TEST(SimulationCheckpoint, ReleasedAnchorsAndCreasesGoOnBitForBit) {
  // paper-crease: creased by 0.6 s, and its anchors let go at 0.8 s; saved before and after.
  const SceneSpec spec = builtin_scene("paper-crease");
  expect_restored_run_matches(spec, 0.6, 1.0, 4);
  expect_restored_run_matches(spec, 0.9, 1.1, 2);
}

TEST(SimulationCheckpoint, ACheckpointOfAnotherLatticeIsRefused) {
  const fs::path path = test_folder() / "simulation.ckpt";
  Simulation small = testing::one_thread_simulation(builtin_scene("paper-fig5"));
  write_checkpoint(path, [&](StateArchive& archive) { small.transfer_state(archive); });
  Simulation large = testing::one_thread_simulation(builtin_scene("paper-fig4"));
  CheckpointReader reader(path);
  try {
    large.transfer_state(reader);
    ADD_FAILURE() << "a checkpoint of an 11 x 11 sheet went into a 21 x 21 one";
  } catch (const CheckpointError& error) {
    EXPECT_TRUE(checks::contains(error.what(), "'position' has 121 values, but the simulation has 441"));
  }
}

}  // namespace
}  // namespace clothsim

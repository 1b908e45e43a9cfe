// Tests of animation.glb (--export gltf-animation: run/run_exports.h, io/gltf.h), read back by
// tinygltf's loader compiled apart from the writer (glb_reader.h): a glTF 2.0 file of float32
// accessors (uint32 indices) each with its min and max; one morph target per frame whose
// displacement plus the base mesh is that frame of positions.npy within float32 rounding; an
// animation whose LINEAR weights keyframes are the frame times of energy.csv, one-hot; a torn
// sheet's mesh is final.obj's split mesh, placed at every frame; and a run whose file would pass
// the size limit is refused before anything is written.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "core/error.h"
#include "glb_reader.h"
#include "io/gltf.h"
#include "io/npy.h"
#include "run/run_scene.h"
#include "run/run_writer.h"
#include "scene/builtin_scenes.h"
#include "scene/scene.h"
#include "scene_simulation.h"
#include "test_checks.h"

namespace clothsim {
namespace {

namespace fs = std::filesystem;

// The "time" column of energy.csv, s.
std::vector<double> energy_times(const fs::path& out) {
  std::ifstream in(out / RunWriter::kEnergyFile);
  std::string line;
  std::getline(in, line);
  std::size_t column = 0;
  {
    std::istringstream header(line);
    std::string name;
    while (std::getline(header, name, ',') && name != "time") ++column;
  }
  std::vector<double> times;
  while (std::getline(in, line)) {
    std::istringstream row(line);
    std::string cell;
    for (std::size_t c = 0; c <= column; ++c) std::getline(row, cell, ',');
    times.push_back(std::stod(cell));
  }
  return times;
}

// final.obj's vertices, m, and its faces' vertex indices (0-based).
struct ObjMesh {
  std::vector<double> vertex;  // 3 per vertex
  std::vector<std::uint32_t> face_vertex;
};

ObjMesh read_obj(const fs::path& path) {
  std::ifstream in(path);
  ObjMesh mesh;
  for (std::string line; std::getline(in, line);) {
    std::istringstream fields(line);
    std::string word;
    fields >> word;
    if (word == "v") {
      double x = 0, y = 0, z = 0;
      fields >> x >> y >> z;
      mesh.vertex.insert(mesh.vertex.end(), {x, y, z});
    } else if (word == "f") {
      for (std::string corner; fields >> corner;) {
        mesh.face_vertex.push_back(static_cast<std::uint32_t>(std::stoul(corner.substr(0, corner.find('/')))) - 1);
      }
    }
  }
  return mesh;
}

// Checks animation.glb of the run in `out` against its positions.npy, energy.csv and final.obj.
void expect_animation_is_the_run(const fs::path& out) {
  const testing::GlbMesh glb = testing::read_glb(out / RunExports::kAnimationGlbFile);
  ASSERT_TRUE(glb.loaded) << glb.error;
  EXPECT_EQ(glb.version, "2.0");
  EXPECT_EQ(glb.scenes, 1u);
  EXPECT_EQ(glb.nodes, 1u);
  EXPECT_EQ(glb.meshes, 1u);
  EXPECT_EQ(glb.accessors_without_bounds, 0u) << "every accessor has min and max";
  EXPECT_EQ(glb.non_float_accessors, 0u) << "float32 throughout, uint32 indices aside";

  const NpyArray positions = read_npy((out / RunWriter::kPositionsFile).string());
  ASSERT_EQ(positions.shape.size(), 3u);
  const std::size_t frames = positions.shape[0];
  const std::size_t particles = positions.shape[1];
  ASSERT_GE(frames, 2u);

  // One target per frame, each moving every vertex (and its normal).
  ASSERT_EQ(glb.target_position.size(), frames);
  ASSERT_EQ(glb.target_normal.size(), frames);
  EXPECT_EQ(glb.mesh_weights, std::vector<double>(frames, 0.0)) << "at rest the mesh is the base, frame 0";
  const std::size_t vertices = glb.vertices();
  ASSERT_GE(vertices, particles);
  for (std::size_t k = 0; k < frames; ++k) {
    ASSERT_EQ(glb.target_position[k].size(), 3 * vertices);
    ASSERT_EQ(glb.target_normal[k].size(), 3 * vertices);
    // The particles (the mesh's first vertices): base + target k is frame k within float32
    // rounding (the base rounded once, the displacement once, their sum once).
    for (std::size_t i = 0; i < 3 * particles; ++i) {
      const float morphed = glb.position[i] + glb.target_position[k][i];
      const double expected = positions.data[k * 3 * particles + i];
      const double rounding =
          std::numeric_limits<float>::epsilon() * (std::abs(expected) + std::abs(positions.data[i]));
      EXPECT_NEAR(morphed, expected, rounding) << "frame " << k << ", value " << i;
    }
  }
  // The last frame, every vertex: final.obj's mesh (its topology, split along the tears), whose
  // unit normals the morphed normals are.
  const ObjMesh obj = read_obj(out / RunWriter::kFinalMeshFile);
  ASSERT_EQ(obj.vertex.size(), 3 * vertices);
  EXPECT_EQ(glb.index, obj.face_vertex);
  for (std::size_t v = 0; v < vertices; ++v) {
    double length = 0.0;
    for (std::size_t axis = 0; axis < 3; ++axis) {
      const std::size_t i = 3 * v + axis;
      EXPECT_NEAR(glb.position[i] + glb.target_position[frames - 1][i], obj.vertex[i], 2e-6) << "vertex " << v;
      const float normal = glb.normal[i] + glb.target_normal[frames - 1][i];
      length += normal * normal;
    }
    EXPECT_NEAR(length, 1.0, 1e-5) << "vertex " << v;
  }

  // The animation: one channel on the node's weights, keyframes at the frame times, target k
  // alone at frame k.
  EXPECT_EQ(glb.animations, 1u);
  EXPECT_EQ(glb.channels, 1u);
  EXPECT_EQ(glb.channel_node, 0);
  EXPECT_EQ(glb.channel_path, "weights");
  EXPECT_EQ(glb.interpolation, "LINEAR");
  const std::vector<double> times = energy_times(out);
  ASSERT_EQ(times.size(), frames);
  ASSERT_EQ(glb.animation_time.size(), frames);
  for (std::size_t k = 0; k < frames; ++k) {
    EXPECT_EQ(glb.animation_time[k], static_cast<float>(times[k])) << "frame " << k;
  }
  EXPECT_EQ(glb.animation_time_min, std::vector<double>{0.0});
  EXPECT_EQ(glb.animation_time_max, std::vector<double>{static_cast<float>(times.back())});
  ASSERT_EQ(glb.animation_weight.size(), frames * frames);
  for (std::size_t k = 0; k < frames; ++k) {
    for (std::size_t target = 0; target < frames; ++target) {
      EXPECT_EQ(glb.animation_weight[k * frames + target], target == k ? 1.0f : 0.0f)
          << "keyframe " << k << ", target " << target;
    }
  }

  std::ifstream summary_file(out / RunWriter::kSummaryFile);
  const nlohmann::json file = nlohmann::json::parse(summary_file)["files"]["animation.glb"];
  EXPECT_EQ(file["frames"], frames);
  EXPECT_EQ(file["morph_targets"], frames);
  EXPECT_EQ(file["vertices"], vertices);
}

TEST(AnimationGlb, EveryFrameIsAMorphTargetPlayedAtTheFrameTimes) {
  SceneSpec spec = builtin_scene("paper-fig5");
  spec.output.duration = 0.2;
  spec.output.fps = 30;
  spec.output.exports = {ExportFormat::gltf_animation};
  const fs::path out = checks::fresh_test_folder("run") / "animation";
  RunOptions options;
  options.out = out;
  options.info = RunInfo{"test", "test_animation_glb"};
  options.render.render = "none";
  const RunResult result = run_scene(spec, options);
  ASSERT_EQ(result.frames, 7u);
  expect_animation_is_the_run(out);

  // The size is the documented estimate's (docs/exports.md), which the refusal uses.
  const std::uint64_t size = fs::file_size(out / RunExports::kAnimationGlbFile);
  const std::uint64_t estimate = glb_animation_bytes_for(11, 11, 7);
  EXPECT_LE(size, estimate);
  EXPECT_GE(size + 4096 + 7 * 200, estimate) << "the estimate is close: " << size << " of " << estimate;
}

TEST(AnimationGlb, TornSheetIsTheLastFramesSplitMeshAtEveryFrame) {
  // A 5 x 5 sheet hanging from its centre, torn between rows 1 and 2 after frame 1.
  const SceneSpec spec = parse_scene(R"({"name": "animation_torn", "paper_args": [5, 5, 1, 4, 1, 1400, 200, 80, 5, 1],
                                        "output": {"fps": 20, "export": ["gltf-animation"]}})",
                                     "test");
  Simulation simulation = testing::one_thread_simulation(spec);
  const fs::path out = checks::fresh_test_folder("run") / "animation_torn";
  RunWriter writer(out, RunInfo{"test", "test"});
  writer.begin(spec, simulation);
  writer.write_frame(simulation);
  ASSERT_TRUE(simulation.advance_to(0.05));
  writer.write_frame(simulation);
  std::vector<std::uint32_t> cut;
  for (std::uint32_t e = 0; e < simulation.model().connector_count(); ++e) {
    const auto [a, b] = simulation.model().connector_particles[e];
    if (a / 5 == 1 && b == a + 5) cut.push_back(e);
  }
  ASSERT_EQ(simulation.cut_connectors(cut), 5u);
  for (const double time : {0.1, 0.15, 0.2}) {
    ASSERT_TRUE(simulation.advance_to(time));
    writer.write_frame(simulation);
  }
  writer.finish(simulation, RunStatus::completed, 1.0);
  EXPECT_GT(testing::read_glb(out / RunExports::kAnimationGlbFile).vertices(), 25u) << "split along the cut";
  expect_animation_is_the_run(out);
}

TEST(AnimationGlb, TooLargeIsRefusedBeforeTheRun) {
  // 400 x 400 particles for 20 s at 60 fps: about 24 bytes x 160 000 x 1201 frames, 4.3 GiB.
  SceneSpec spec = builtin_scene("paper-fig5");
  spec.lattice.rows = 400;
  spec.lattice.cols = 400;
  spec.output.exports = {ExportFormat::pc2, ExportFormat::gltf_animation};
  const fs::path out = checks::fresh_test_folder("run") / "animation_too_large";
  RunOptions options;
  options.out = out;
  options.info = RunInfo{"test", "test_animation_glb"};
  options.render.render = "none";
  try {
    run_scene(spec, options);
    ADD_FAILURE() << "a 4 GiB animation.glb was not refused";
  } catch (const InputError& error) {
    const std::string message = error.what();
    for (const char* part : {"output.export", "gltf-animation", "animation.glb", "1201 frames", "160000 particles",
                             "more than its limit of 2048 MiB", "--duration", "--fps", "pc2"}) {
      EXPECT_NE(message.find(part), std::string::npos) << part << " in: " << message;
    }
  }
  EXPECT_FALSE(fs::exists(out));
  // The same sheet for 2 s passes.
  EXPECT_NO_THROW(RunExports::check_sizes(lattice_counts(400, 400), 121, spec.output.exports));
}

// The memory check counts the writer's document, a few kB a frame (io/gltf.h), on top of the
// meshes: a long run of a small sheet needs more than a short one.
TEST(AnimationGlb, MemoryEstimateGrowsWithTheFrames) {
  const std::vector<ExportFormat> exports = {ExportFormat::gltf_animation};
  const LatticeCounts counts = lattice_counts(11, 11);
  const std::size_t short_run = RunWriter::bytes_for(counts, 31, exports);
  const std::size_t long_run = RunWriter::bytes_for(counts, 20031, exports);
  EXPECT_GE(long_run - short_run, 20000u * 6700u) << "measured: 6.7 kB a frame";
  EXPECT_EQ(RunWriter::bytes_for(counts, 31, {}), RunWriter::bytes_for(counts, 20031, {}));
}

}  // namespace
}  // namespace clothsim

// Tests of run/run_exports (and io/pc2, io/gltf) through run/run_writer: the PC2 cache read back by
// a reader written here from the format's description (plain bytes, no code of the writer) equals
// positions.npy rounded to float32, bit for bit; rest.obj has the particles as its vertices; the
// OBJ sequence has one file per frame with the right counts; a torn sheet keeps the particles as
// the cache's points and leaves the torn triangles out of rest.obj (run_exports.h); final.glb,
// loaded by tinygltf's loader, is final.obj's mesh at the last frame of positions.npy, intact or
// torn, and a GLB that cannot be written leaves no output folder.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "glb_reader.h"
#include "io/npy.h"
#include "run/run_writer.h"
#include "scene/scene.h"
#include "scene_simulation.h"

namespace clothsim {
namespace {

namespace fs = std::filesystem;

// A PC2 file as its bytes say (little-endian host assumed, as on every machine we build on).
struct Pc2File {
  std::string magic;  // the 12 bytes, '\0' included
  std::int32_t version = 0;
  std::int32_t points = 0;
  float start_frame = 0.0f;
  float sample_rate = 0.0f;
  std::int32_t samples = 0;
  std::vector<float> values;  // what follows the 32-byte header
};

template <typename T>
T read_at(const std::string& bytes, std::size_t offset) {
  T value{};
  std::memcpy(&value, bytes.data() + offset, sizeof(T));
  return value;
}

Pc2File read_pc2(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  Pc2File file;
  if (bytes.size() < 32) {
    ADD_FAILURE() << path << " is " << bytes.size() << " bytes, shorter than a PC2 header";
    return file;
  }
  file.magic = bytes.substr(0, 12);
  file.version = read_at<std::int32_t>(bytes, 12);
  file.points = read_at<std::int32_t>(bytes, 16);
  file.start_frame = read_at<float>(bytes, 20);
  file.sample_rate = read_at<float>(bytes, 24);
  file.samples = read_at<std::int32_t>(bytes, 28);
  file.values.resize((bytes.size() - 32) / sizeof(float));
  std::memcpy(file.values.data(), bytes.data() + 32, file.values.size() * sizeof(float));
  EXPECT_EQ((bytes.size() - 32) % sizeof(float), 0u);
  return file;
}

// Counts of an OBJ file's lines by their first word, its vertices and its faces' vertex indices.
struct ObjCounts {
  std::size_t v = 0, vt = 0, vn = 0, f = 0;
  std::vector<std::array<double, 3>> vertices;
  std::vector<std::uint32_t> face_vertices;  // 3 per face, 0-based
};

ObjCounts read_obj_counts(const fs::path& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in) << "cannot open " << path;
  ObjCounts counts;
  std::string word;
  for (std::string line; std::getline(in, line);) {
    std::istringstream fields(line);
    fields >> word;
    if (word == "v") {
      std::array<double, 3> p{};
      fields >> p[0] >> p[1] >> p[2];
      counts.vertices.push_back(p);
      ++counts.v;
    }
    if (word == "f") {
      for (std::string corner; fields >> corner;) {
        counts.face_vertices.push_back(static_cast<std::uint32_t>(std::stoul(corner.substr(0, corner.find('/')))) - 1);
      }
    }
    counts.vt += word == "vt";
    counts.vn += word == "vn";
    counts.f += word == "f";
    word.clear();
  }
  return counts;
}

nlohmann::json read_summary(const fs::path& out) {
  std::ifstream file(out / RunWriter::kSummaryFile);
  return nlohmann::json::parse(file);
}

// A 5 x 5 sheet hanging from its centre, with every export, run through RunWriter; `between`
// runs after frame 1 is written (to tear the sheet).
struct ExportRun {
  fs::path out;
  std::size_t frames = 0;
};

template <typename Between>
ExportRun run_with_exports(const std::string& name, Between between) {
  const SceneSpec spec = parse_scene(R"({"name": ")" + name + R"(", "paper_args": [5, 5, 1, 4, 1, 1400, 200, 80, 5, 1],
                                        "output": {"export": ["pc2", "obj-sequence", "gltf"]}})",
                                     "test");
  Simulation simulation = testing::one_thread_simulation(spec);
  ExportRun run{fs::path(CLOTHSIM_TEST_TMPDIR) / "io" / name, 0};
  fs::remove_all(run.out);
  RunWriter writer(run.out, RunInfo{"test", "test"});
  writer.begin(spec, simulation);
  writer.write_frame(simulation);
  EXPECT_TRUE(simulation.advance_to(0.05));
  writer.write_frame(simulation);
  between(simulation);
  EXPECT_TRUE(simulation.advance_to(0.1));
  writer.write_frame(simulation);
  EXPECT_TRUE(simulation.advance_to(0.15));
  writer.write_frame(simulation);
  writer.finish(simulation, RunStatus::completed, 1.0);
  run.frames = writer.frames();
  return run;
}

TEST(RunExports, PointCacheMatchesPositionsBitForBit) {
  const ExportRun run = run_with_exports("exports_intact", [](Simulation&) {});
  const Pc2File cache = read_pc2(run.out / RunExports::kPointCacheFile);
  EXPECT_EQ(cache.magic, std::string("POINTCACHE2\0", 12));
  EXPECT_EQ(cache.version, 1);
  EXPECT_EQ(cache.points, 25);
  EXPECT_EQ(cache.start_frame, 0.0f);
  EXPECT_EQ(cache.sample_rate, 1.0f);
  EXPECT_EQ(cache.samples, static_cast<std::int32_t>(run.frames));

  const NpyArray positions = read_npy((run.out / RunWriter::kPositionsFile).string());
  ASSERT_EQ(positions.shape, (std::vector<std::size_t>{run.frames, 25, 3}));
  ASSERT_EQ(cache.values.size(), positions.data.size());
  for (std::size_t k = 0; k < positions.data.size(); ++k) {
    EXPECT_EQ(std::bit_cast<std::uint32_t>(cache.values[k]),
              std::bit_cast<std::uint32_t>(static_cast<float>(positions.data[k])))
        << "value " << k;
  }

  // rest.obj: the particles at frame 0, the whole lattice's triangles.
  const ObjCounts rest = read_obj_counts(run.out / RunExports::kRestMeshFile);
  EXPECT_EQ(rest.v, 25u);
  EXPECT_EQ(rest.vt, 25u);
  EXPECT_EQ(rest.vn, 25u);
  EXPECT_EQ(rest.f, 32u);
  for (std::size_t p = 0; p < rest.vertices.size(); ++p) {
    for (std::size_t axis = 0; axis < 3; ++axis) {
      EXPECT_NEAR(rest.vertices[p][axis], positions.data[3 * p + axis], 1e-8) << "vertex " << p;
    }
  }

  const nlohmann::json summary = read_summary(run.out);
  EXPECT_EQ(summary["files"]["animation.pc2"]["samples"], run.frames);
  EXPECT_EQ(summary["files"]["rest.obj"]["left_out"], 0);
  EXPECT_EQ(summary["scene"]["output"]["export"], nlohmann::json::array({"pc2", "obj-sequence", "gltf"}));
}

TEST(RunExports, ObjSequenceHasOneFilePerFrame) {
  const ExportRun run = run_with_exports("exports_sequence", [](Simulation&) {});
  std::size_t files = 0;
  for (const auto& entry : fs::directory_iterator(run.out / RunExports::kFramesFolder)) {
    (void)entry;
    ++files;
  }
  EXPECT_EQ(files, run.frames);
  const NpyArray positions = read_npy((run.out / RunWriter::kPositionsFile).string());
  for (std::size_t frame = 0; frame < run.frames; ++frame) {
    const fs::path path = run.out / RunExports::frame_file_name(frame);
    ASSERT_TRUE(fs::exists(path)) << path;
    const ObjCounts counts = read_obj_counts(path);
    EXPECT_EQ(counts.v, 25u) << path;
    EXPECT_EQ(counts.vt, 25u) << path;
    EXPECT_EQ(counts.vn, 25u) << path;
    EXPECT_EQ(counts.f, 32u) << path;
    EXPECT_NEAR(counts.vertices[7][1], positions.data[(frame * 25 + 7) * 3 + 1], 1e-8) << path;
  }
  EXPECT_EQ(RunExports::frame_file_name(12), "frames/frame_000012.obj");
  EXPECT_EQ(read_summary(run.out)["files"]["frames/"]["files"], run.frames);
}

// Between frames 1 and 2 of run_with_exports: the 5 connectors between rows 1 and 2 are cut.
void cut_between_rows_1_and_2(Simulation& simulation) {
  std::vector<std::uint32_t> cut;
  for (std::uint32_t e = 0; e < simulation.model().connector_count(); ++e) {
    const auto [a, b] = simulation.model().connector_particles[e];
    if (a / 5 == 1 && b == a + 5) cut.push_back(e);
  }
  ASSERT_EQ(cut.size(), 5u);
  ASSERT_TRUE(simulation.advance_to(0.07));
  ASSERT_EQ(simulation.cut_connectors(cut), 5u);
}

TEST(RunExports, TornSheetKeepsParticlesAndLeavesTornTrianglesOut) {
  const ExportRun run = run_with_exports("exports_torn", cut_between_rows_1_and_2);
  const Pc2File cache = read_pc2(run.out / RunExports::kPointCacheFile);
  EXPECT_EQ(cache.points, 25);
  EXPECT_EQ(cache.samples, static_cast<std::int32_t>(run.frames));
  EXPECT_EQ(cache.values.size(), run.frames * 25 * 3);

  // The 4 quads between rows 1 and 2 lose both triangles: each has a cut vertical edge.
  const ObjCounts rest = read_obj_counts(run.out / RunExports::kRestMeshFile);
  EXPECT_EQ(rest.v, 25u);
  EXPECT_EQ(rest.f, 32u - 8u);
  EXPECT_EQ(read_summary(run.out)["files"]["rest.obj"]["left_out"], 8);

  // The sequence shows the tear when it happens: split vertices from frame 2 on.
  EXPECT_EQ(read_obj_counts(run.out / RunExports::frame_file_name(1)).v, 25u);
  EXPECT_GT(read_obj_counts(run.out / RunExports::frame_file_name(2)).v, 25u);
}

// final.glb is final.obj's mesh (the same vertices in the same order, the same triangles) at the
// last frame of positions.npy: its first 25 vertices are the particles there, rounded to float32.
void expect_glb_is_the_last_frame(const ExportRun& run) {
  const testing::GlbMesh glb = testing::read_glb(run.out / RunExports::kGlbFile);
  ASSERT_TRUE(glb.loaded) << glb.error;
  EXPECT_EQ(glb.version, "2.0");
  EXPECT_EQ(glb.scenes, 1u);
  EXPECT_EQ(glb.default_scene, 0);
  EXPECT_EQ(glb.nodes, 1u);
  EXPECT_EQ(glb.meshes, 1u);
  EXPECT_EQ(glb.primitives, 1u);
  EXPECT_EQ(glb.mode, 4) << "triangles";
  EXPECT_TRUE(glb.double_sided);
  EXPECT_EQ(glb.extras_frame, static_cast<int>(run.frames) - 1);
  EXPECT_DOUBLE_EQ(glb.extras_time, 0.15);

  const ObjCounts obj = read_obj_counts(run.out / RunWriter::kFinalMeshFile);
  ASSERT_EQ(glb.vertices(), obj.v);
  EXPECT_EQ(glb.index, obj.face_vertices);
  ASSERT_EQ(glb.normal.size(), 3 * obj.v);
  ASSERT_EQ(glb.uv.size(), 2 * obj.v);
  const NpyArray positions = read_npy((run.out / RunWriter::kPositionsFile).string());
  const std::size_t last = (run.frames - 1) * 25 * 3;
  std::array<float, 3> low = {glb.position[0], glb.position[1], glb.position[2]};
  std::array<float, 3> high = low;
  for (std::size_t v = 0; v < glb.vertices(); ++v) {
    double length = 0.0;
    for (std::size_t axis = 0; axis < 3; ++axis) {
      const float x = glb.position[3 * v + axis];
      if (v < 25) {  // a particle
        EXPECT_EQ(x, static_cast<float>(positions.data[last + 3 * v + axis])) << "vertex " << v;
      }
      EXPECT_NEAR(x, obj.vertices[v][axis], 1e-6) << "vertex " << v;
      low[axis] = std::min(low[axis], x);
      high[axis] = std::max(high[axis], x);
      length += glb.normal[3 * v + axis] * glb.normal[3 * v + axis];
    }
    EXPECT_NEAR(length, 1.0, 1e-6) << "normal " << v;
    for (std::size_t k = 0; k < 2; ++k) {
      EXPECT_GE(glb.uv[2 * v + k], 0.0f);
      EXPECT_LE(glb.uv[2 * v + k], 1.0f);
    }
  }
  // The spec requires POSITION's min and max, and loaders trust them for bounds.
  EXPECT_EQ(glb.position_min, std::vector<double>(low.begin(), low.end()));
  EXPECT_EQ(glb.position_max, std::vector<double>(high.begin(), high.end()));

  const nlohmann::json file = read_summary(run.out)["files"]["final.glb"];
  EXPECT_EQ(file["vertices"], obj.v);
  EXPECT_EQ(file["triangles"], obj.f);
  EXPECT_EQ(file["frame"], run.frames - 1);
}

TEST(RunExports, GlbIsTheLastFrame) {
  const ExportRun run = run_with_exports("exports_glb", [](Simulation&) {});
  expect_glb_is_the_last_frame(run);
  // Texture coordinates: final.obj's, with v flipped for glTF's top-left origin. Particle 0 is
  // row 0, column 0; particle 24 row 4, column 4.
  const testing::GlbMesh glb = testing::read_glb(run.out / RunExports::kGlbFile);
  ASSERT_EQ(glb.uv.size(), 50u);
  EXPECT_EQ(glb.uv[0], 0.0f);
  EXPECT_EQ(glb.uv[1], 1.0f);
  EXPECT_EQ(glb.uv[48], 1.0f);
  EXPECT_EQ(glb.uv[49], 0.0f);
  EXPECT_EQ(glb.index.size(), 32u * 3u);
}

TEST(RunExports, TornSheetGlbHasTheSplitMeshOfFinalObj) {
  const ExportRun run = run_with_exports("exports_glb_torn", cut_between_rows_1_and_2);
  EXPECT_GT(read_obj_counts(run.out / RunWriter::kFinalMeshFile).v, 25u) << "the mesh splits along the cut";
  expect_glb_is_the_last_frame(run);
}

// Starts a run of the 5 x 5 sheet with `exports` (a JSON list) into io/<name>, writes frame 0,
// hands the writer and the simulation to `then`, and drops the writer: no output folder and no
// partial folder may be left.
template <typename Then>
void expect_nothing_left(const std::string& name, const std::string& exports, Then then) {
  const SceneSpec spec = parse_scene(
      R"({"paper_args": [5, 5, 1, 4, 1, 1400, 200, 80, 5, 1], "output": {"export": )" + exports + "}}", "test");
  Simulation simulation = testing::one_thread_simulation(spec);
  const fs::path out = fs::path(CLOTHSIM_TEST_TMPDIR) / "io" / name;
  fs::remove_all(out);
  fs::path partial;
  {
    RunWriter writer(out, RunInfo{"test", "test"});
    writer.begin(spec, simulation);
    writer.write_frame(simulation);
    partial = writer.partial();
    then(writer, simulation);
    EXPECT_FALSE(fs::exists(out));
  }  // the writer gives up: the partial folder goes
  EXPECT_FALSE(fs::exists(out));
  EXPECT_FALSE(fs::exists(partial));
}

TEST(RunExports, GlbThatCannotBeWrittenLeavesNoFolder) {
  expect_nothing_left("exports_glb_unwritable", R"(["gltf"])", [](RunWriter& writer, const Simulation& simulation) {
    fs::create_directory(writer.partial() / RunExports::kGlbFile);  // in the way of the file
    try {
      writer.finish(simulation, RunStatus::completed, 1.0);
      ADD_FAILURE() << "finish() wrote final.glb over a folder";
    } catch (const OutputError& error) {
      EXPECT_NE(std::string(error.what()).find("final.glb"), std::string::npos) << error.what();
    }
  });
}

TEST(RunExports, AbandonedRunLeavesNothing) {
  expect_nothing_left("exports_abandoned", R"(["pc2", "obj-sequence"])", [](RunWriter& writer, const Simulation&) {
    EXPECT_TRUE(fs::exists(writer.partial() / RunExports::kPointCacheFile));
    EXPECT_TRUE(fs::exists(writer.partial() / RunExports::frame_file_name(0)));
  });  // no finish(): the run died
}

}  // namespace
}  // namespace clothsim

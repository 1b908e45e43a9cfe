// End-to-end tests of the clothsim tool: each test runs the real executable (CLOTHSIM_EXE) in its
// own fresh folder, capturing stdout, stderr and the exit code, and then reads what it wrote with
// the library's own readers, with nlohmann::json and with numpy.
//
// What they pin down (docs/cli.md):
//   - bad input exits 2 with "clothsim: error: " and a message naming the flag or field and what
//     is allowed, and leaves nothing behind (no output folder, no .partial folder);
//   - a run writes every file with the documented shapes, frame 0 is the rest lattice, the
//     anchor stays put, and scene.json reproduces positions.npy bit for bit;
//   - --until-rest, a blow-up (exit 1, diagnosis, finite frames kept), SIGINT (exit 130),
//     replacing a previous run, an unwritable output (exit 3).
// The other commands (validate, scenes, params, devices, bench, every --help) and run --profile
// are in test_cli_commands.cpp.
//
// The numpy check runs the real numpy.load and must not skip: scripts/install-deps.sh installs
// python3-numpy, and a missing numpy fails with a message saying how to fix it.
#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli_harness.h"
#include "cli_test.h"
#include "forces/lattice_kernel.h"
#include "glb_reader.h"
#include "io/npy.h"
#include "scene/builtin_scenes.h"
#include "scene/scene.h"
#include "test_checks.h"

namespace clothsim {
namespace {

using checks::python_with_numpy;

namespace fs = std::filesystem;
using nlohmann::json;

using Result = checks::ProcessResult;
using checks::read_text;
using checks::write_text;
using cli_harness::contains;
using cli_harness::describe;
using cli_harness::entries;
using cli_harness::wait_clothsim;
using cli_test::CliTest;
using cli_test::kSmallCentre;
using cli_test::kSmallParticles;
using cli_test::kSmallPaperArgs;

// energy.csv as numbers: rows[frame][column]; the header line is checked separately.
struct Csv {
  std::string header;
  std::vector<std::vector<double>> rows;
};

Csv read_csv(const fs::path& path) {
  Csv csv;
  std::istringstream lines(read_text(path));
  std::getline(lines, csv.header);
  std::string line;
  while (std::getline(lines, line)) {
    std::vector<double> row;
    std::istringstream cells(line);
    std::string cell;
    while (std::getline(cells, cell, ',')) row.push_back(std::strtod(cell.c_str(), nullptr));
    csv.rows.push_back(row);
  }
  return csv;
}

constexpr std::size_t kKineticColumn = 2;

// ---------------------------------------------------------------------------------------------
// Bad input: exit 2, a message naming the flag or field and what is allowed, nothing written.

struct BadInputCase {
  std::string name;
  std::vector<std::string> args;
  std::vector<std::string> pieces;  // the error message contains each
  std::string scene_file;           // written to scene.json before the run, unless empty
};

std::vector<std::string> small(std::vector<std::string> flags) {
  std::vector<std::string> args = {"run", "--paper-args", kSmallPaperArgs};
  args.insert(args.end(), flags.begin(), flags.end());
  return args;
}

const std::vector<BadInputCase> kBadInputCases = {
    {"FpsZero", small({"--fps", "0"}), {"--fps", "output.fps", "[1, 10000]", "got \"0\""}, ""},
    {"FpsNotANumber", small({"--fps", "abc"}), {"--fps", "output.fps", "number", "abc"}, ""},
    {"DurationNegative", small({"--duration", "-1"}), {"--duration", "output.duration", "(0, 1e7]"}, ""},
    {"IntegratorUnknown",
     small({"--integrator", "euler"}),
     {"--integrator", "integrator.method", "rkf45", "symplectic-euler", "euler"},
     ""},
    {"RtolZero", small({"--rtol", "0"}), {"--rtol", "integrator.relative_tolerance", "[1e-14, 1]"}, ""},
    {"AtolZero", small({"--atol", "0"}), {"--atol", "integrator.absolute_tolerance", "(0, 1000]"}, ""},
    {"TimeStepTooLarge", small({"--time-step", "100"}), {"--time-step", "integrator.time_step", "[0, 10]"}, ""},
    {"GravityTwoComponents", small({"--gravity", "1,2"}), {"--gravity", "environment.gravity", "3 numbers"}, ""},
    {"ThreadsNegative", small({"--threads", "-3"}), {"--threads", "threads", "[0, 1024]"}, ""},
    {"AnchorUnknown", small({"--anchor", "top"}), {"--anchor", "center", "edge-corners", "top"}, ""},
    {"RestEnergyZero",
     small({"--until-rest", "--rest-energy", "0"}),
     {"--rest-energy", "output.rest_kinetic_energy", "(0, 1e12]"},
     ""},
    {"SelfCollisionMaybe", small({"--self-collision", "maybe"}), {"--self-collision", "on or off", "maybe"}, ""},
    {"ThicknessZero", small({"--thickness", "0"}), {"--thickness", "collision.thickness", "(0, 1]"}, ""},
    {"ExportUnknown",
     small({"--export", "pc2,usd"}),
     {"--export", "output.export", "pc2, obj-sequence, gltf", "usd"},
     ""},
    {"SceneFileExportUnknown",
     {"run", "scene.json"},
     {"scene.json", "output.export", "pc2, obj-sequence, gltf", "fbx"},
     R"({"output": {"export": ["pc2", "fbx"]}})"},
    {"SceneFileExportNotAList",
     {"run", "scene.json"},
     {"scene.json", "output.export", "a list"},
     R"({"output": {"export": "pc2"}})"},
    {"SetRowsZero", small({"--set", "lattice.rows=0"}), {"--set", "lattice.rows", "[1, 4096]"}, ""},
    {"SetUnknownKey", small({"--set", "nosuch.key=1"}), {"--set", "nosuch.key", "unknown field"}, ""},
    {"SetWithoutEquals", small({"--set", "lattice.rows"}), {"--set", "KEY=VALUE"}, ""},
    {"SetCrossFieldRule",
     small({"--set", "integrator.min_step=0.5"}),
     {"integrator.min_step", "must be <= integrator.", "got 0.5"},
     ""},
    {"PaperArgsNineNumbers",
     {"run", "--paper-args", "5,5,1,4,1,1400,200,80,5"},
     {"--paper-args", "paper_args", "exactly 10 numbers", "got 9"},
     ""},
    {"PaperArgsNegativeMass",
     {"run", "--paper-args", "5,5,-1,4,1,1400,200,80,5,1"},
     {"--paper-args", "mass", "(0, 1e6]"},
     ""},
    {"SceneAndPaperArgs",
     {"run", "paper-fig5", "--paper-args", kSmallPaperArgs},
     {"SCENE", "--paper-args", "not both"},
     ""},
    {"NoScene", {"run"}, {"SCENE", "--paper-args"}, ""},
    {"SceneFileTypo",
     {"run", "scene.json"},
     {"scene.json", "lattice.rowz", "lattice.rows"},
     R"({"lattice": {"rowz": 5, "cols": 5}})"},
    {"SceneFileSyntaxError",
     {"run", "scene.json"},
     {"scene.json", "line 1", "syntax error"},
     R"({"lattice": {"rows": 5,}})"},
    {"SceneFileValueOutOfRange",
     {"run", "scene.json"},
     {"scene.json", "output.fps", "[1, 10000]"},
     R"({"output": {"fps": 0}})"},
    {"SceneFileMissing", {"run", "nosuch.json"}, {"nosuch.json", "cannot read"}, ""},
    {"BuiltinNameMistyped", {"run", "paper-fig7"}, {"paper-fig7", "paper-fig4"}, ""},
    {"UnknownFlag", small({"--bogus"}), {"--bogus"}, ""},
    {"MissingValue", small({"--fps"}), {"--fps"}, ""},
    {"OutIsForeignFolder", small({"--out", "taken"}), {"--out", "taken", "not a clothsim output folder"}, ""},
    {"OutIsFile", small({"--out", "notes.txt"}), {"--out", "notes.txt", "not a clothsim output folder"}, ""},
};

// Names the case in gtest's output instead of dumping its bytes.
void PrintTo(const BadInputCase& input, std::ostream* out) { *out << input.name; }

class BadInputTest : public CliTest, public ::testing::WithParamInterface<BadInputCase> {};

TEST_P(BadInputTest, ExitsTwoNamingTheProblemAndWritesNothing) {
  const BadInputCase& input = GetParam();
  if (!input.scene_file.empty()) write_text(work_ / "scene.json", input.scene_file);
  // A folder the tool must not touch, and a plain file.
  fs::create_directories(work_ / "taken");
  write_text(work_ / "taken" / "notes.txt", "not a clothsim run\n");
  write_text(work_ / "notes.txt", "a file\n");
  const std::set<std::string> before = entries(work_);

  const Result result = clothsim(input.args);

  EXPECT_EQ(result.exit_code, 2) << describe(result);
  EXPECT_TRUE(contains(result.err, "clothsim: error: "));
  for (const std::string& piece : input.pieces) EXPECT_TRUE(contains(result.err, piece));
  EXPECT_EQ(entries(work_), before) << "bad input must not create files or folders";
  EXPECT_EQ(read_text(work_ / "taken" / "notes.txt"), "not a clothsim run\n");
  EXPECT_TRUE(result.out.empty()) << describe(result);
}

INSTANTIATE_TEST_SUITE_P(Cli, BadInputTest, ::testing::ValuesIn(kBadInputCases),
                         [](const ::testing::TestParamInfo<BadInputCase>& case_info) { return case_info.param.name; });

// ---------------------------------------------------------------------------------------------
// A run and its output folder.

TEST_F(CliTest, SmallRunWritesEveryFile) {
#if CLOTHSIM_HAVE_RENDER
  const Result result = small_run("run", {"--duration", "0.5", "--fps", "20", "--render", "all", "--size", "64x48"});
#else
  const Result result = small_run("run", {"--duration", "0.5", "--fps", "20"});
#endif
  ASSERT_EQ(result.exit_code, 0) << describe(result);
  EXPECT_TRUE(contains(result.out, "completed"));
  EXPECT_TRUE(contains(result.out, "5x5 lattice, 25 particles"));

  // Exactly the documented files, and no partial folder left next to them.
  std::set<std::string> expected = checks::run_data_paths("run");
#if CLOTHSIM_HAVE_RENDER
  // The pictures, by default (tests/render/test_run_pictures.cpp checks their contents).
  expected.insert({"run/final.png", "run/animation.mp4"});
#endif
  EXPECT_EQ(entries(work_), expected);

  const NpyArray positions = read_npy((work_ / "run" / "positions.npy").string());
  ASSERT_EQ(positions.shape, (std::vector<std::size_t>{11, kSmallParticles, 3}));
  const NpyArray velocities = read_npy((work_ / "run" / "velocities.npy").string());
  ASSERT_EQ(velocities.shape, (std::vector<std::size_t>{11, kSmallParticles, 3}));
  // Frame 0 is the rest lattice: particle (i, j) at ((j - 2) L, 0, (i - 2) L), L = 1 m, at rest.
  for (std::size_t p = 0; p < kSmallParticles; ++p) {
    const double row = static_cast<double>(p / 5);
    const double col = static_cast<double>(p % 5);
    EXPECT_EQ(positions.data[3 * p + 0], col - 2.0) << "particle " << p;
    EXPECT_EQ(positions.data[3 * p + 1], 0.0) << "particle " << p;
    EXPECT_EQ(positions.data[3 * p + 2], row - 2.0) << "particle " << p;
    for (std::size_t axis = 0; axis < 3; ++axis) EXPECT_EQ(velocities.data[3 * p + axis], 0.0);
  }
  // The anchored centre stays at the origin; the sheet around it falls.
  for (std::size_t frame = 0; frame < 11; ++frame) {
    for (std::size_t axis = 0; axis < 3; ++axis) {
      EXPECT_EQ(positions.data[(frame * kSmallParticles + kSmallCentre) * 3 + axis], 0.0) << "frame " << frame;
    }
  }
  EXPECT_LT(positions.data[(10 * kSmallParticles + 0) * 3 + 1], -0.01) << "corner particle 0 has fallen";

  const Csv energy = read_csv(work_ / "run" / "energy.csv");
  EXPECT_EQ(energy.header,
            "frame,time,kinetic,gravitational,connector,radial_adjacent,radial_opposite,total,damping_work,drag_work,"
            "anchor_work,balance_error,accepted_steps,rejected_steps,broken_connectors,max_plastic_strain,"
            "max_rest_angle_change,plastic_work,fracture_work,contact_work,contacts,self_contacts");
  ASSERT_EQ(energy.rows.size(), 11u);
  for (std::size_t frame = 0; frame < energy.rows.size(); ++frame) {
    const std::vector<double>& row = energy.rows[frame];
    ASSERT_EQ(row.size(), 22u) << "frame " << frame;
    EXPECT_EQ(row[0], static_cast<double>(frame));
    EXPECT_EQ(row[1], static_cast<double>(frame) / 20.0) << "frame k at t = k / fps, exactly";
    EXPECT_LT(std::abs(row[11]), 1e-4) << "energy balance error, frame " << frame;
  }

  const json run = summary("run");
  EXPECT_TRUE(run.contains("clothsim_version"));
  EXPECT_EQ(run["status"], "completed");
  EXPECT_EQ(run["frames"], 11);
  EXPECT_EQ(run["lattice"]["particles"], 25);
  EXPECT_EQ(run["lattice"]["connectors"], 40);
  EXPECT_EQ(run["lattice"]["anchors"], 1);
  EXPECT_EQ(run["simulated_time"], 0.5);
  EXPECT_EQ(run["integrator"]["method"], "rkf45");
  EXPECT_GT(run["integrator"]["accepted_steps"].get<int>(), 0);
  EXPECT_FALSE(run.contains("diagnosis"));
  EXPECT_EQ(run["scene"]["output"]["fps"], 20);
  EXPECT_TRUE(contains(run["command_line"].get<std::string>(), "--paper-args"));
  for (const char* key : {"wall_seconds", "forces", "integration", "events", "checks", "output", "realtime_factor"}) {
    EXPECT_TRUE(run["timings"].contains(key)) << key;
  }
  for (const char* key : {"kinetic", "gravitational", "connector", "radial_adjacent", "radial_opposite", "total",
                          "damping_work", "drag_work", "anchor_work", "balance_error"}) {
    EXPECT_TRUE(run["energy"]["final"].contains(key)) << key;
  }
  EXPECT_EQ(run["energy"]["final"]["kinetic"].get<double>(), energy.rows.back()[kKineticColumn]);
  // An elastic, unbreakable sheet: nothing broke or yielded, and the topology files say so.
  EXPECT_EQ(run["sheet_changes"]["broken_connectors"], 0);
  EXPECT_EQ(run["sheet_changes"]["breaks"], 0);
  EXPECT_EQ(run["sheet_changes"]["fracture_work"], 0.0);
  const NpyArray connectors = read_npy((work_ / "run" / "connectors.npy").string());
  ASSERT_EQ(connectors.shape, (std::vector<std::size_t>{40, 2}));
  EXPECT_EQ(connectors.data[0], 0.0);  // connector 0: particle 0 and its east neighbour 1
  EXPECT_EQ(connectors.data[1], 1.0);
  const NpyArray break_time = read_npy((work_ / "run" / "connector_break_time.npy").string());
  ASSERT_EQ(break_time.shape, (std::vector<std::size_t>{40}));
  for (const double time : break_time.data) EXPECT_TRUE(std::isinf(time));

  const std::string mesh = read_text(work_ / "run" / "final.obj");
  std::size_t vertices = 0;
  std::istringstream lines(mesh);
  for (std::string line; std::getline(lines, line);) vertices += line.starts_with("v ") ? 1 : 0;
  EXPECT_EQ(vertices, kSmallParticles);
}

TEST_F(CliTest, SceneJsonReproducesTheRunBitForBit) {
  ASSERT_EQ(small_run("first", {"--duration", "0.5", "--fps", "20", "--set", "initial.position_noise=0.01"}).exit_code,
            0);
  const Result again = clothsim({"run", "first/scene.json", "--out", "second", "--quiet", "--render", "none"});
  ASSERT_EQ(again.exit_code, 0) << describe(again);
  EXPECT_TRUE(again.out.empty()) << "--quiet prints nothing";
  EXPECT_EQ(read_text(work_ / "first" / "positions.npy"), read_text(work_ / "second" / "positions.npy"));
  EXPECT_EQ(read_text(work_ / "first" / "velocities.npy"), read_text(work_ / "second" / "velocities.npy"));
  EXPECT_EQ(read_text(work_ / "first" / "scene.json"), read_text(work_ / "second" / "scene.json"));
}

TEST_F(CliTest, NumpyOpensPositions) {
  ASSERT_EQ(small_run("run", {"--duration", "0.5", "--fps", "20"}).exit_code, 0);
  const std::string python = python_with_numpy();
  ASSERT_FALSE(python.empty())
      << "no Python interpreter with numpy found (tried $CLOTHSIM_PYTHON, python3, /usr/bin/python3): run "
         "scripts/install-deps.sh, which installs python3-numpy, or set CLOTHSIM_PYTHON to a python with numpy";
  ::setenv("NPY_PATH", (work_ / "run" / "positions.npy").c_str(), 1);
  const std::string command = python +
                              " -c \"import os, numpy; a = numpy.load(os.environ['NPY_PATH']); "
                              "assert a.shape == (11, 25, 3), a.shape; assert a.dtype == numpy.float64, a.dtype; "
                              "assert numpy.all(a[:, 12, :] == 0.0); print('numpy ok')\" 2>&1";
  std::FILE* pipe = ::popen(command.c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  std::string output;
  char buffer[1024];
  for (std::size_t got; (got = std::fread(buffer, 1, sizeof buffer, pipe)) > 0;) output.append(buffer, got);
  EXPECT_EQ(::pclose(pipe), 0) << output;
  EXPECT_TRUE(contains(output, "numpy ok"));
}

// At rest means below the threshold at every frame for output.rest_duration (1 s by default: 11
// frames at 10 fps, the first and the one 1 s later included), so the run stops at the first
// frame that ends such a stretch.
TEST_F(CliTest, UntilRestStopsOnceTheKineticEnergyStayedBelowTheThresholdForTheRestDuration) {
  constexpr double kThreshold = 1e-3;  // J
  constexpr std::size_t kRestFrames = 11;
  const Result result = small_run("rest", {"--until-rest", "--rest-energy", "0.001", "--fps", "10"});
  ASSERT_EQ(result.exit_code, 0) << describe(result);
  const json run = summary("rest");
  EXPECT_EQ(run["status"], "at_rest");
  // Without --duration the cap is max(scene duration, 3600 s); the sheet settles long before.
  EXPECT_EQ(run["scene"]["output"]["duration"], 3600.0);
  EXPECT_EQ(run["scene"]["output"]["until_rest"], true);
  const Csv energy = read_csv(work_ / "rest" / "energy.csv");
  ASSERT_GE(energy.rows.size(), 3u);
  EXPECT_LT(energy.rows.size(), 36001u) << "stopped early";
  EXPECT_EQ(run["frames"], energy.rows.size());
  const std::size_t frames = energy.rows.size();
  ASSERT_GT(frames, kRestFrames + 1);
  for (std::size_t frame = frames - kRestFrames; frame < frames; ++frame) {
    EXPECT_LT(energy.rows[frame][kKineticColumn], kThreshold) << "frame " << frame << " of the resting stretch";
  }
  EXPECT_GE(energy.rows[frames - kRestFrames - 1][kKineticColumn], kThreshold) << "the stretch began a frame earlier";
  // No earlier stretch of kRestFrames quiet frames: the run stopped at the first one.
  std::size_t quiet = 0;
  for (std::size_t frame = 1; frame + 1 < frames; ++frame) {
    quiet = energy.rows[frame][kKineticColumn] < kThreshold ? quiet + 1 : 0;
    EXPECT_LT(quiet, kRestFrames) << "already at rest at frame " << frame;
  }
}

// The collision flags set their scene keys, and the run records them in scene.json.
TEST_F(CliTest, CollisionFlagsSetTheSceneKeys) {
  const Result result = small_run("collide", {"--self-collision", "off", "--thickness", "0.01", "--duration", "0.1"});
  ASSERT_EQ(result.exit_code, 0) << describe(result);
  const json scene = json::parse(read_text(work_ / "collide" / "scene.json"));
  EXPECT_EQ(scene["collision"]["self"], false);
  EXPECT_EQ(scene["collision"]["thickness"], 0.01);
  const Result on = small_run("collide-on", {"--self-collision", "on", "--duration", "0.1"});
  ASSERT_EQ(on.exit_code, 0) << describe(on);
  EXPECT_EQ(json::parse(read_text(work_ / "collide-on" / "scene.json"))["collision"]["self"], true);
  // A thickness the lattice cannot hold apart is refused with a message, exit 2, nothing written.
  const Result thick =
      small_run("collide-thick", {"--self-collision", "on", "--thickness", "0.9", "--duration", "0.1"});
  EXPECT_EQ(thick.exit_code, 2) << describe(thick);
  EXPECT_TRUE(contains(thick.err, "collision.thickness")) << describe(thick);
  EXPECT_TRUE(contains(thick.err, "half the lattice spacing")) << describe(thick);
  EXPECT_FALSE(fs::exists(work_ / "collide-thick"));
}

// --export writes the exports of every frame, also for a failed run (docs/exports.md; their
// contents are tested in tests/io/test_run_exports.cpp).
TEST_F(CliTest, ExportFlagWritesTheExportsOfEveryFrame) {
  const Result result =
      small_run("exported", {"--export", "pc2,obj-sequence,gltf,gltf-animation", "--duration", "0.5", "--fps", "20"});
  ASSERT_EQ(result.exit_code, 0) << describe(result);
  EXPECT_TRUE(contains(result.out, "export       pc2: animation.pc2 (11 samples of 25 points)")) << result.out;
  EXPECT_TRUE(contains(result.out, "export       gltf: final.glb (frame 10)")) << result.out;
  EXPECT_TRUE(contains(result.out, "export       gltf-animation: animation.glb (11 frames as morph targets, 20 fps)"))
      << result.out;
  EXPECT_TRUE(fs::exists(work_ / "exported" / "rest.obj"));
  EXPECT_TRUE(fs::exists(work_ / "exported" / "animation.glb"));
  // The PC2 header's sample count (bytes 28 to 31) is fixed up to the frame count at the end.
  const std::string cache = read_text(work_ / "exported" / "animation.pc2");
  ASSERT_EQ(cache.size(), 32u + 11u * 25u * 3u * 4u);
  std::int32_t samples = 0;
  std::memcpy(&samples, cache.data() + 28, sizeof(samples));
  EXPECT_EQ(samples, 11);
  EXPECT_TRUE(fs::exists(work_ / "exported" / "frames" / "frame_000010.obj"));
  EXPECT_FALSE(fs::exists(work_ / "exported" / "frames" / "frame_000011.obj"));
  EXPECT_EQ(json::parse(read_text(work_ / "exported" / "scene.json"))["output"]["export"],
            json::array({"pc2", "obj-sequence", "gltf", "gltf-animation"}));

  const Result failed = small_run("blow", {"--export", "pc2,gltf", "--integrator", "symplectic-euler", "--time-step",
                                           "0.5", "--duration", "5", "--fps", "2"});
  ASSERT_EQ(failed.exit_code, 1) << describe(failed);
  const json run = summary("blow");
  EXPECT_EQ(run["files"]["animation.pc2"]["samples"], run["frames"]);
  EXPECT_EQ(run["files"]["final.glb"]["frame"], run["frames"].get<int>() - 1);  // the last good frame
}

// An animation.glb that would pass its limit (2 GiB) is refused before the run, as bad input,
// naming the estimate, the limit and what to change; nothing is written.
TEST_F(CliTest, GltfAnimationPastItsSizeLimitIsRefused) {
  const Result result =
      clothsim({"run", "paper-fig5", "--out", "huge", "--set", "lattice.rows=400", "--set", "lattice.cols=400",
                "--export", "gltf-animation", "--render", "none", "--no-progress"});
  EXPECT_EQ(result.exit_code, 2) << describe(result);
  EXPECT_TRUE(contains(result.err, "animation.glb of 1201 frames of 160000 particles would take about")) << result.err;
  EXPECT_TRUE(contains(result.err, "more than its limit of 2048 MiB")) << result.err;
  EXPECT_FALSE(fs::exists(work_ / "huge"));

  // `clothsim validate` refuses it too: a scene that validates starts.
  write_text(work_ / "huge.json",
             R"({"lattice": {"rows": 400, "cols": 400}, "output": {"export": ["gltf-animation"]}})");
  const Result validated = clothsim({"validate", "huge.json"});
  EXPECT_EQ(validated.exit_code, 2) << describe(validated);
  EXPECT_TRUE(contains(validated.err, "more than its limit of 2048 MiB")) << validated.err;
}

// --export gltf of a built-in scene that tears: final.glb is final.obj's split mesh, its first
// vertices the particles at the last frame of positions.npy (tests/io/test_run_exports.cpp tests
// the file in detail); animation.glb has that mesh too, with every frame of positions.npy
// (tests/run/test_run_exports_animation.cpp tests it in detail).
TEST_F(CliTest, GltfExportOfATearingSceneIsItsSplitLastFrame) {
  const Result result = clothsim(
      {"run", "tear-pull", "--out", "torn", "--export", "gltf,gltf-animation", "--render", "none", "--no-progress"});
  ASSERT_EQ(result.exit_code, 0) << describe(result);
  const json run = summary("torn");
  const auto frames = run["frames"].get<std::size_t>();
  EXPECT_TRUE(contains(result.out, "export       gltf: final.glb (frame " + std::to_string(frames - 1) + ")"))
      << result.out;
  EXPECT_GT(run["sheet_changes"]["broken_connectors"].get<int>(), 0) << "tear-pull tears";

  const testing::GlbMesh glb = testing::read_glb(work_ / "torn" / "final.glb");
  ASSERT_TRUE(glb.loaded) << glb.error;
  std::size_t obj_vertices = 0, obj_faces = 0;
  std::istringstream obj(read_text(work_ / "torn" / "final.obj"));
  for (std::string line; std::getline(obj, line);) {
    obj_vertices += line.starts_with("v ");
    obj_faces += line.starts_with("f ");
  }
  const auto particles = run["lattice"]["particles"].get<std::size_t>();
  EXPECT_GT(glb.vertices(), particles) << "split along the tear";
  EXPECT_EQ(glb.vertices(), obj_vertices);
  EXPECT_EQ(glb.index.size(), 3 * obj_faces);
  EXPECT_EQ(run["files"]["final.glb"]["vertices"], obj_vertices);

  const NpyArray positions = read_npy((work_ / "torn" / "positions.npy").string());
  ASSERT_EQ(positions.shape, (std::vector<std::size_t>{frames, particles, 3}));
  const std::size_t last = (frames - 1) * particles * 3;
  for (std::size_t k = 0; k < particles * 3; ++k) {
    ASSERT_EQ(glb.position[k], static_cast<float>(positions.data[last + k])) << "coordinate " << k;
  }

  const testing::GlbMesh animation = testing::read_glb(work_ / "torn" / "animation.glb");
  ASSERT_TRUE(animation.loaded) << animation.error;
  EXPECT_EQ(animation.vertices(), obj_vertices);
  EXPECT_EQ(animation.index, glb.index) << "the last frame's topology";
  ASSERT_EQ(animation.target_position.size(), frames);
  for (std::size_t k = 0; k < particles * 3; ++k) {
    const double expected = positions.data[last + k];
    ASSERT_NEAR(animation.position[k] + animation.target_position[frames - 1][k], expected,
                1e-6 * (1.0 + std::abs(expected)))
        << "coordinate " << k;
  }
}

// A zero rest duration stops at the first frame below the threshold.
TEST_F(CliTest, UntilRestWithZeroRestDurationStopsAtTheFirstQuietFrame) {
  constexpr double kThreshold = 1e-3;  // J
  const Result result =
      small_run("rest0", {"--until-rest", "--rest-energy", "0.001", "--fps", "10", "--set", "output.rest_duration=0"});
  ASSERT_EQ(result.exit_code, 0) << describe(result);
  EXPECT_EQ(summary("rest0")["status"], "at_rest");
  const Csv energy = read_csv(work_ / "rest0" / "energy.csv");
  ASSERT_GE(energy.rows.size(), 3u);
  EXPECT_LT(energy.rows.back()[kKineticColumn], kThreshold);
  for (std::size_t frame = 1; frame + 1 < energy.rows.size(); ++frame) {
    EXPECT_GE(energy.rows[frame][kKineticColumn], kThreshold) << "an earlier frame was already at rest: " << frame;
  }
}

TEST_F(CliTest, BlowUpExitsOneWithDiagnosisAndKeepsFiniteFrames) {
  const Result result =
      small_run("blow", {"--integrator", "symplectic-euler", "--time-step", "0.5", "--duration", "5", "--fps", "2"});
  ASSERT_EQ(result.exit_code, 1) << describe(result);
  EXPECT_TRUE(contains(result.err, "clothsim: error: simulation failed"));
  EXPECT_TRUE(contains(result.err, "t = "));
  EXPECT_TRUE(contains(result.err, "step "));
  EXPECT_TRUE(result.err.find("particle") != std::string::npos || result.err.find("connector") != std::string::npos)
      << result.err;

  const std::set<std::string> names = entries(work_);
  for (const std::string& name : names) EXPECT_EQ(name.find(".partial-"), std::string::npos) << name;

  const json run = summary("blow");
  EXPECT_EQ(run["status"], "failed");
  ASSERT_TRUE(run.contains("diagnosis"));
  for (const char* key : {"time", "step", "element", "message"}) EXPECT_TRUE(run["diagnosis"].contains(key)) << key;
  const std::string element = run["diagnosis"]["element"].get<std::string>();
  EXPECT_TRUE(element.find("particle") != std::string::npos || element.find("connector") != std::string::npos);

  const NpyArray positions = read_npy((work_ / "blow" / "positions.npy").string());
  ASSERT_EQ(positions.shape.size(), 3u);
  EXPECT_GE(positions.shape[0], 1u);
  EXPECT_LT(positions.shape[0], 11u) << "frames only up to the last good one";
  EXPECT_EQ(run["frames"], positions.shape[0]);
  for (double value : positions.data) ASSERT_TRUE(std::isfinite(value));
  const NpyArray velocities = read_npy((work_ / "blow" / "velocities.npy").string());
  for (double value : velocities.data) ASSERT_TRUE(std::isfinite(value));
  EXPECT_EQ(read_csv(work_ / "blow" / "energy.csv").rows.size(), positions.shape[0]);
}

TEST_F(CliTest, RerunReplacesThePreviousRun) {
  ASSERT_EQ(small_run("same", {"--duration", "0.2", "--fps", "20"}).exit_code, 0);
  EXPECT_EQ(summary("same")["frames"], 5);
  // Bad input aimed at a previous run leaves it as it was.
  const Result bad = small_run("same", {"--fps", "0"});
  EXPECT_EQ(bad.exit_code, 2) << describe(bad);
  EXPECT_EQ(summary("same")["frames"], 5);

  const Result again = small_run("same", {"--duration", "0.5", "--fps", "20"});
  ASSERT_EQ(again.exit_code, 0) << describe(again);
  EXPECT_EQ(summary("same")["frames"], 11);
  EXPECT_EQ(read_npy((work_ / "same" / "positions.npy").string()).shape[0], 11u);
  // Nothing but the new folder: no partial or old copy left beside it.
  std::set<std::string> top;
  for (const fs::directory_entry& entry : fs::directory_iterator(work_)) top.insert(entry.path().filename());
  EXPECT_EQ(top, (std::set<std::string>{"same"}));
}

TEST_F(CliTest, DefaultOutputFolderIsNamedAfterTheScene) {
  const Result result = clothsim({"run", "--paper-args", kSmallPaperArgs, "--duration", "0.1", "--fps", "10",
                                  "--no-progress", "--render", "none"});
  ASSERT_EQ(result.exit_code, 0) << describe(result);
  EXPECT_TRUE(fs::exists(work_ / "out" / "paper-args" / "summary.json"));
}

TEST_F(CliTest, ArgumentsThatAreNotUtf8AreRecordedWithReplacementCharacters) {
  // A Latin-1 folder name: a valid path, not UTF-8. The run used to end with exit 3 and no output,
  // the JSON writer refusing summary.json's command_line.
  const Result result = small_run("caf\xE9", {"--duration", "0.1", "--fps", "10"});
  ASSERT_EQ(result.exit_code, 0) << describe(result);
  EXPECT_TRUE(contains(summary("caf\xE9")["command_line"].get<std::string>(), "--out 'caf\xEF\xBF\xBD'"));
}

TEST_F(CliTest, UnwritableOutputExitsThree) {
  write_text(work_ / "blocker", "a file where a folder should be\n");
  const std::set<std::string> before = entries(work_);
  const Result result = small_run("blocker/run", {"--duration", "0.1"});
  EXPECT_EQ(result.exit_code, 3) << describe(result);
  EXPECT_TRUE(contains(result.err, "clothsim: error: "));
  EXPECT_TRUE(contains(result.err, "blocker"));
  EXPECT_EQ(entries(work_), before);
}

TEST_F(CliTest, InterruptFinishesTheFolderAndExits130) {
  const pid_t pid = start({"run", "--paper-args", kSmallPaperArgs, "--duration", "100000", "--out", "long",
                           "--no-progress", "--render", "none"});
  ASSERT_GT(pid, 0);
  // Wait until the run is under way (its partial folder holds frames), then interrupt it.
  const fs::path partial = work_ / ("long.partial-" + std::to_string(pid));
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  const auto frames_written = [&] {
    std::error_code error;
    const std::uintmax_t size = fs::file_size(partial / "energy.csv", error);
    return !error && size > 1000;
  };
  while (!frames_written() && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ASSERT_TRUE(frames_written()) << "the run did not start writing frames within 60 s";
  ::kill(pid, SIGINT);
  const Result result = wait_clothsim(pid, root_);
  ASSERT_EQ(result.exit_code, 130) << describe(result);
  EXPECT_TRUE(contains(result.err, "interrupted"));
  EXPECT_FALSE(fs::exists(partial));
  const json run = summary("long");
  EXPECT_EQ(run["status"], "interrupted");
  const NpyArray positions = read_npy((work_ / "long" / "positions.npy").string());
  EXPECT_EQ(run["frames"], positions.shape[0]);
  EXPECT_GE(positions.shape[0], 2u);
}

}  // namespace
}  // namespace clothsim

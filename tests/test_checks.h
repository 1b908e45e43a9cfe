// Checks shared by the tests that exercise errors, files and the clothsim tool: the message an
// action throws, a substring assertion that prints both strings, text files and scratch paths, a
// child process's result, the errors of the mesh file writers, and the Python interpreter that
// has numpy (for the tests that open clothsim's .npy
// output with numpy itself).
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "core/vec3.h"
#include "model/cloth_model.h"

namespace clothsim::checks {

// The message of the std::runtime_error that `action` throws, or a marker if it throws none.
template <class Action>
std::string thrown_message(Action&& action) {
  try {
    std::forward<Action>(action)();
  } catch (const std::runtime_error& error) {
    return error.what();
  }
  return "<no exception thrown>";
}

// An empty folder for the running test: CLOTHSIM_TEST_TMPDIR/<area>/<suite>.<test>, made afresh
// (a parameterised test's name has a '/', which makes a folder per instance).
inline std::filesystem::path fresh_test_folder(const std::string& area) {
  const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::filesystem::path folder =
      std::filesystem::path(CLOTHSIM_TEST_TMPDIR) / area / (std::string(info->test_suite_name()) + "." + info->name());
  std::filesystem::remove_all(folder);
  std::filesystem::create_directories(folder);
  return folder;
}

// Whether `text` contains `part`; the failure shows the whole text (a command's output, a file).
inline ::testing::AssertionResult contains(const std::string& text, const std::string& part) {
  if (text.find(part) != std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "missing '" << part << "' in:\n" << text;
}

// The paths a run writes into its folder `folder` besides pictures and exports (docs/cli.md,
// "The output folder"), the folder included: what a test compares a folder's listing with.
inline std::set<std::string> run_data_paths(const std::string& folder) {
  std::set<std::string> paths = {folder};
  for (const char* file : {"positions.npy", "velocities.npy", "energy.csv", "summary.json", "final.obj", "scene.json",
                           "connectors.npy", "connector_break_time.npy", "connector_rest_length.npy"}) {
    paths.insert(folder + "/" + file);
  }
  return paths;
}

// A Python interpreter that imports numpy: $CLOTHSIM_PYTHON if set, else the first of python3
// (PATH) and /usr/bin/python3 that does, or "" if none. PATH's python3 may be a pyenv or venv
// interpreter without numpy even when Debian's python3-numpy is installed for /usr/bin/python3.
inline const std::string& python_with_numpy() {
  static const std::string found = [] {
    std::vector<std::string> candidates;
    if (const char* chosen = std::getenv("CLOTHSIM_PYTHON"); chosen != nullptr && *chosen != '\0') {
      candidates.emplace_back(chosen);
    }
    candidates.emplace_back("python3");
    candidates.emplace_back("/usr/bin/python3");
    for (const std::string& candidate : candidates) {
      const std::string probe = candidate + " -c \"import numpy\" >/dev/null 2>&1";
      if (std::system(probe.c_str()) == 0) return candidate;
    }
    return std::string();
  }();
  return found;
}

// What a child process (the clothsim tool under test) left behind.
struct ProcessResult {
  int exit_code = -1;  // 128 + signal number if the process was killed by a signal
  std::string out;     // its standard output
  std::string err;     // its standard error
};

// The whole content of a file ("" if it cannot be read), and writing one.
inline std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

inline void write_text(const std::filesystem::path& path, const std::string& text) {
  std::ofstream(path, std::ios::binary | std::ios::trunc) << text;
}

// A path for a test's scratch file `name` in the folder `module` of the test scratch area, which
// is created.
inline std::string scratch_path(const std::string& module, const std::string& name) {
  const std::filesystem::path directory = std::filesystem::path(CLOTHSIM_TEST_TMPDIR) / module;
  std::filesystem::create_directories(directory);
  return (directory / name).string();
}

// Component-wise |actual - expected| <= tolerance, each component reported on failure.
inline void expect_near(const Vec3& actual, const Vec3& expected, double tolerance) {
  EXPECT_NEAR(actual.x, expected.x, tolerance);
  EXPECT_NEAR(actual.y, expected.y, tolerance);
  EXPECT_NEAR(actual.z, expected.z, tolerance);
}

// The same positions, velocities and contact work, bit for bit (runs with different thread counts).
inline void expect_same_bits(const ClothState& actual, const ClothState& expected) {
  ASSERT_EQ(actual.position.size(), expected.position.size());
  EXPECT_EQ(0, std::memcmp(actual.position.data(), expected.position.data(), expected.position.size() * sizeof(Vec3)));
  EXPECT_EQ(0, std::memcmp(actual.velocity.data(), expected.velocity.data(), expected.velocity.size() * sizeof(Vec3)));
  EXPECT_EQ(actual.contact_work, expected.contact_work);
}

// The address space this process has mapped (VmSize of /proc/self/status), bytes; 0 if unread.
// Tests that set RLIMIT_AS set it this much above what is mapped: under AddressSanitizer a
// process maps terabytes of shadow memory before main, and an absolute limit of a few GiB
// would stop it at its start.
inline std::uint64_t mapped_address_space() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line)) {
    if (line.rfind("VmSize:", 0) == 0) return std::stoull(line.substr(7)) * 1024;  // "VmSize:  123 kB"
  }
  return 0;
}

// A mesh file writer's errors (io/obj.h, io/gltf.h) name the path: a folder that does not exist, a
// full disk (/dev/full, where there is one: the message has `full_disk`) and too few positions.
// `write(path, model, positions)` writes the file.
template <class Write>
void expect_write_errors_name_the_path(Write write, const std::string& extension, const std::string& full_disk) {
  const ClothModel model = build_lattice(LatticeDef{.rows = 2, .cols = 2}, Environment{}, {});
  const std::string missing = scratch_path("io", "no_such_directory/sheet" + extension);
  const std::string message = thrown_message([&] { write(missing, model, model.particle_rest_position); });
  EXPECT_TRUE(contains(message, missing));
  EXPECT_TRUE(contains(message, "No such file or directory"));

  if (std::filesystem::exists("/dev/full")) {  // fails every write with ENOSPC: a full disk
    EXPECT_TRUE(contains(thrown_message([&] { write("/dev/full", model, model.particle_rest_position); }), full_disk));
  }

  const std::string path = scratch_path("io", "short" + extension);
  const std::vector<Vec3> too_few(3);
  const std::string short_message = thrown_message([&] { write(path, model, too_few); });
  EXPECT_TRUE(contains(short_message, path));
  EXPECT_TRUE(contains(short_message, "3 positions"));
}

}  // namespace clothsim::checks

// Checks shared by the tests that exercise errors, files and the clothsim tool: the message an
// action throws, a substring assertion that prints both strings, text files, a child process's
// result, and the Python interpreter that has numpy (for the tests that open clothsim's .npy
// output with numpy itself).
#pragma once

#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
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

// An empty folder for the running test: CLOTHSIM_TEST_TMPDIR/<area>/<suite>.<test>, made afresh.
inline std::filesystem::path fresh_test_folder(const std::string& area) {
  const ::testing::TestInfo* info = ::testing::UnitTest::GetInstance()->current_test_info();
  const std::filesystem::path folder =
      std::filesystem::path(CLOTHSIM_TEST_TMPDIR) / area / (std::string(info->test_suite_name()) + "." + info->name());
  std::filesystem::remove_all(folder);
  std::filesystem::create_directories(folder);
  return folder;
}

inline ::testing::AssertionResult contains(const std::string& text, const std::string& part) {
  if (text.find(part) != std::string::npos) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "'" << text << "' does not contain '" << part << "'";
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

}  // namespace clothsim::checks

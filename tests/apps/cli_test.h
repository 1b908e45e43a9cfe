// The fixture of the command's own end-to-end tests (test_cli.cpp, test_cli_commands.cpp): the
// harness's folder per test under test-tmp/cli and a small run of the paper's material.
#pragma once

#include <algorithm>
#include <cstddef>
#include <string>
#include <vector>

#include "cli_harness.h"
#include "test_checks.h"

namespace clothsim::cli_test {

// The paper's material on a 5 x 5 lattice, centre particle (index 12) anchored at the origin.
inline constexpr const char* kSmallPaperArgs = "5,5,1,4,1,1400,200,80,5,1";
inline constexpr std::size_t kSmallParticles = 25;
inline constexpr std::size_t kSmallCentre = 12;

class CliTest : public cli_harness::ToolTest {
 protected:
  CliTest() : ToolTest("cli") {}

  // A small run of the paper's material into `out` (relative to the work folder).
  checks::ProcessResult small_run(const std::string& out, std::vector<std::string> extra = {}) const {
    std::vector<std::string> args = {"run", "--paper-args", kSmallPaperArgs, "--out", out, "--no-progress"};
    // No pictures unless asked for: these tests are about the data files, and rendering would
    // only slow them down (tests/render/test_run_pictures.cpp tests the pictures).
    if (std::find(extra.begin(), extra.end(), "--render") == extra.end()) {
      args.insert(args.end(), {"--render", "none"});
    }
    args.insert(args.end(), extra.begin(), extra.end());
    return clothsim(args);
  }
};

}  // namespace clothsim::cli_test

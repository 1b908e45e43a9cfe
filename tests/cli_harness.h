// What the end-to-end tests of the clothsim tool share: starting the real executable
// (CLOTHSIM_EXE) in a folder with its output captured, waiting for it, and reading the result.
#pragma once

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "test_checks.h"

namespace clothsim::cli_harness {

namespace fs = std::filesystem;
using Result = checks::ProcessResult;
using checks::read_text;

// A change to the child's environment: `name` set to `value`, or unset where there is none.
struct EnvironmentChange {
  std::string name;
  std::optional<std::string> value;
};

// What the child gets besides its arguments: environment changes, and an address-space limit
// (RLIMIT_AS, bytes; exit 125 if it cannot be set).
struct ChildSetup {
  std::vector<EnvironmentChange> environment;
  std::optional<rlim_t> address_space;
};

// Starts clothsim with `args` in folder `cwd`, stdout and stderr going to files in `capture`
// (outside `cwd`, so they do not count as output), set up as `setup` says. Returns the child's
// process id.
inline pid_t spawn_clothsim(const fs::path& cwd, const std::vector<std::string>& args, const fs::path& capture,
                            const ChildSetup& setup = {}) {
  const std::string out_path = (capture / "stdout.txt").string();
  const std::string err_path = (capture / "stderr.txt").string();
  std::vector<std::string> words = {CLOTHSIM_EXE};
  words.insert(words.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& word : words) argv.push_back(word.data());
  argv.push_back(nullptr);
  std::fflush(nullptr);
  const pid_t pid = ::fork();
  if (pid == 0) {
    const int out = ::open(out_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int err = ::open(err_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (out < 0 || err < 0 || ::chdir(cwd.c_str()) != 0) ::_exit(126);
    ::dup2(out, STDOUT_FILENO);
    ::dup2(err, STDERR_FILENO);
    for (const EnvironmentChange& change : setup.environment) {
      if (change.value) {
        ::setenv(change.name.c_str(), change.value->c_str(), 1);
      } else {
        ::unsetenv(change.name.c_str());
      }
    }
    if (setup.address_space) {
      const rlimit limit{*setup.address_space, *setup.address_space};
      if (::setrlimit(RLIMIT_AS, &limit) != 0) ::_exit(125);
    }
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  return pid;
}

// Waits for the child `pid` and reads what it wrote to `capture`. With a `limit`, a child still
// running after it is killed and the test fails.
inline Result wait_clothsim(pid_t pid, const fs::path& capture,
                            std::chrono::seconds limit = std::chrono::seconds::zero()) {
  Result result;
  int status = 0;
  if (pid > 0) {
    const auto deadline = std::chrono::steady_clock::now() + limit;
    pid_t waited = 0;
    while (limit.count() > 0 && (waited = ::waitpid(pid, &status, WNOHANG)) == 0) {
      if (std::chrono::steady_clock::now() > deadline) {
        ::kill(pid, SIGKILL);
        ADD_FAILURE() << "clothsim did not finish within " << limit.count() << " s";
        break;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    if (waited == 0) waited = ::waitpid(pid, &status, 0);
    if (waited == pid) {
      if (WIFEXITED(status)) result.exit_code = WEXITSTATUS(status);
      if (WIFSIGNALED(status)) result.exit_code = 128 + WTERMSIG(status);
    }
  }
  result.out = read_text(capture / "stdout.txt");
  result.err = read_text(capture / "stderr.txt");
  return result;
}

// Every path under `folder`, relative to it.
inline std::set<std::string> entries(const fs::path& folder) {
  std::set<std::string> names;
  for (const fs::directory_entry& entry : fs::recursive_directory_iterator(folder)) {
    names.insert(fs::relative(entry.path(), folder).string());
  }
  return names;
}

using checks::contains;

inline std::string describe(const Result& result) {
  std::ostringstream text;
  text << "exit code " << result.exit_code << "\n--- stdout\n" << result.out << "--- stderr\n" << result.err;
  return text.str();
}

// The fixture of every end-to-end test of the tool: a fresh folder per test,
// checks::fresh_test_folder(area), with the captured stdout and stderr in it and the tool's
// working folder `work_` below it, so that work_ holds only what the tool wrote.
class ToolTest : public ::testing::Test {
 protected:
  explicit ToolTest(std::string area) : area_(std::move(area)) {}

  void SetUp() override {
    root_ = checks::fresh_test_folder(area_);
    work_ = root_ / "work";
    fs::create_directories(work_);
  }

  // Runs clothsim with `args` in work_ and waits for it.
  Result clothsim(const std::vector<std::string>& args) const {
    return wait_clothsim(spawn_clothsim(work_, args, root_), root_);
  }
  // Starts clothsim with `args` in work_; wait_clothsim(pid, root_) collects it.
  pid_t start(const std::vector<std::string>& args, const ChildSetup& setup = {}) const {
    return spawn_clothsim(work_, args, root_, setup);
  }
  // The summary.json of the run folder `out` (relative to work_).
  nlohmann::json summary(const std::string& out) const {
    return nlohmann::json::parse(read_text(work_ / out / "summary.json"));
  }

  fs::path root_;  // this test's folder: the capture files
  fs::path work_;  // the tool's working folder: only what the tool writes

 private:
  std::string area_;
};

}  // namespace clothsim::cli_harness

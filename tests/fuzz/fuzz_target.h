// Fuzz targets (docs/testing.md, "Fuzzing"): one per input surface of the program, each a
// libFuzzer entry point LLVMFuzzerTestOneInput in tests/fuzz/<name>.cpp.
//
// A target feeds its bytes to the code the way the program does and accepts the outcomes the
// program accepts: the input read, or an InputError (the program's "bad input", exit code 2).
// Anything else is a bug: a crash, a sanitizer finding, another exception escaping (libFuzzer
// reports it as a deadly signal through std::terminate), a broken property checked with
// FUZZ_CHECK, a hang or a runaway allocation.
//
// The same source builds two ways (tests/fuzz/CMakeLists.txt): with clang's -fsanitize=fuzzer in
// the fuzz preset, and everywhere with replay_main.cpp, a driver that runs it once over each
// file named on its command line, so the seeds and every crash input kept in
// tests/fuzz/<name>/ run as ctest tests in every build.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string_view>

#include "core/error.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size);

namespace clothsim::fuzz {

// The input as text.
inline std::string_view as_text(const std::uint8_t* data, std::size_t size) {
  return {reinterpret_cast<const char*>(data), size};
}

// Runs `body`; an InputError is an expected outcome (rejected input), any other exception is not
// caught and so ends the run as a finding. With CLOTHSIM_FUZZ_VERBOSE set in the environment the
// message of a rejection is printed, to see what a seed exercises.
template <class Body>
void accept_input_error(Body&& body) {
  try {
    body();
    if (std::getenv("CLOTHSIM_FUZZ_VERBOSE") != nullptr) std::fprintf(stderr, "accepted\n");
  } catch (const InputError& error) {
    if (std::getenv("CLOTHSIM_FUZZ_VERBOSE") != nullptr) std::fprintf(stderr, "rejected: %s\n", error.what());
  }
}

[[noreturn]] inline void check_failed(const char* condition, const char* file, int line) {
  std::fprintf(stderr, "fuzz property broken: %s at %s:%d\n", condition, file, line);
  std::abort();
}

}  // namespace clothsim::fuzz

// A property every accepted input must have; aborts (a finding) when it does not.
#define FUZZ_CHECK(condition) ((condition) ? void(0) : ::clothsim::fuzz::check_failed(#condition, __FILE__, __LINE__))

// Bug checks (tier 1 of clothsim's three tiers of errors; see docs/architecture.md).
//
// CLOTHSIM_ASSERT guards invariants that only a programming error can break. It is on in every
// build (the checks are cheap and sit outside inner loops) and calls a replaceable handler, so an
// embedding application can log and abort its own way. CLOTHSIM_VALIDATE_ONLY wraps heavier
// checks that run only when the project is configured with -DCLOTHSIM_VALIDATE=ON.
// Bad input (tier 2) is reported with InputError (core/error.h); numerical trouble (tier 3) with
// a failed status and its diagnosis (Simulation::failure()).
#pragma once

namespace clothsim {

using AssertHandler = void (*)(const char* condition, const char* file, int line, const char* message);

// Installs a handler and returns the previous one. The default prints to stderr and aborts.
AssertHandler set_assert_handler(AssertHandler handler);
[[noreturn]] void assert_failed(const char* condition, const char* file, int line, const char* message);

}  // namespace clothsim

#define CLOTHSIM_ASSERT(condition, message)                                 \
  do {                                                                      \
    if (!(condition)) {                                                     \
      ::clothsim::assert_failed(#condition, __FILE__, __LINE__, (message)); \
    }                                                                       \
  } while (false)

#if defined(CLOTHSIM_VALIDATE)
#define CLOTHSIM_VALIDATE_ONLY(statement) statement
#else
#define CLOTHSIM_VALIDATE_ONLY(statement)
#endif

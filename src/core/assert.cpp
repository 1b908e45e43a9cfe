#include "core/assert.h"

#include <cstdio>
#include <cstdlib>

namespace clothsim {
namespace {

[[noreturn]] void default_handler(const char* condition, const char* file, int line, const char* message) {
  std::fprintf(stderr, "clothsim: internal error: %s (%s) at %s:%d\n", message, condition, file, line);
  std::abort();
}

AssertHandler g_handler = nullptr;

}  // namespace

AssertHandler set_assert_handler(AssertHandler handler) {
  AssertHandler previous = g_handler;
  g_handler = handler;
  return previous;
}

void assert_failed(const char* condition, const char* file, int line, const char* message) {
  if (g_handler != nullptr) {
    g_handler(condition, file, line, message);
  }
  // A handler that returns still must not let execution continue past a broken invariant.
  default_handler(condition, file, line, message);
}

}  // namespace clothsim

// Errors that reach the user.
//
// InputError: bad input at a boundary (scene file, command-line flag, API argument). It names
// where the value came from ("scene.json" or "--fps"), the field, and what is allowed, so the
// message alone tells the user what to fix. Parsing and validation throw it before any output is
// created.
//
// ResourceError: an InputError for input too large for the memory the process may use (a scene,
// a bench case), refused before anything is allocated. Besides the message it carries the estimate,
// its parts and the limit, so that a caller can report them or retry within its own budget.
//
// OutputError: the output could not be written (disk full, permission denied, a path component
// that is a file). Its message carries the system's, which names the path. The tools map it to
// their "output error" exit code (3), distinct from bad input (2) and a failed simulation (1).
//
// A failed simulation (non-finite or exploding state, a step-size underflow) is not an exception:
// Simulation::advance_to returns false and Simulation::failure() holds the diagnosis (time, step,
// the element), so a caller keeps the last good state; the command turns it into exit code 1, a
// run into status "failed", the Python module into clothsim.SimulationError
// (docs/architecture.md, "Errors").
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace clothsim {

class InputError : public std::runtime_error {
 public:
  // source: file name or flag; field: dotted field name (may be empty); reason: what is wrong.
  InputError(std::string source, std::string field, std::string reason)
      : std::runtime_error(format(source, field, reason)),
        source_(std::move(source)),
        field_(std::move(field)),
        reason_(std::move(reason)) {}

  const std::string& source() const { return source_; }
  const std::string& field() const { return field_; }
  const std::string& reason() const { return reason_; }

 private:
  static std::string format(const std::string& source, const std::string& field, const std::string& reason) {
    std::string text = source;
    if (!field.empty()) {
      text += text.empty() ? "" : ": ";
      text += "field '" + field + "'";
    }
    if (!text.empty()) text += ": ";
    return text + reason;
  }

  std::string source_;
  std::string field_;
  std::string reason_;
};

class ResourceError : public InputError {
 public:
  struct Part {
    std::string name;  // "model", "state", "rkf45 workspace", ...
    std::size_t bytes = 0;
  };

  ResourceError(std::string reason, std::vector<Part> parts, std::size_t estimate_bytes, std::size_t limit_bytes)
      : InputError("", "", std::move(reason)),
        parts_(std::move(parts)),
        estimate_bytes_(estimate_bytes),
        limit_bytes_(limit_bytes) {}

  const std::vector<Part>& parts() const { return parts_; }
  std::size_t estimate_bytes() const { return estimate_bytes_; }
  // The most the estimate could have been: the usable part of the memory available, or max_memory.
  std::size_t limit_bytes() const { return limit_bytes_; }

 private:
  std::vector<Part> parts_;
  std::size_t estimate_bytes_;
  std::size_t limit_bytes_;
};

class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace clothsim

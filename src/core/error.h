// Errors that reach the user.
//
// InputError: bad input at a boundary (scene file, command-line flag, API argument). It names
// where the value came from ("scene.json" or "--fps"), the field, and what is allowed, so the
// message alone tells the user what to fix. Parsing and validation throw it before any output is
// created.
//
// OutputError: the output could not be written (disk full, permission denied, a path component
// that is a file). Its message carries the system's, which names the path. The tools map it to
// their "output error" exit code (3), distinct from bad input (2) and a failed simulation (1).
//
// SimulationError: the numerical integration cannot go on (non-finite or exploding state, step
// size underflow). It carries a diagnosis: simulated time, step number and the element involved.
// The simulation core never throws from inside a step; Simulation::advance returns a status and
// the tools turn a failed status into this exception or an exit code.
#pragma once

#include <stdexcept>
#include <string>

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

class OutputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class SimulationError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace clothsim

#include "cli_support.h"

#include <cmath>
#include <cstdio>
#include <exception>
#include <new>

#include "core/error.h"
#include "run/run_writer.h"
#include "scene/parameters.h"
#include "sim/backend.h"

namespace clothsim::cli {

std::string exit_code_help() {
  return "Exit codes:\n"
         "  0    success (the run completed or came to rest)\n"
         "  1    the simulation failed; diagnosis on stderr, output folder kept with status \"failed\"\n"
         "  2    bad input (scene, flag or value; a scene too large for the memory); nothing was written\n"
         "  3    output error (the output folder could not be written)\n"
         "  130  interrupted (SIGINT); output folder kept with status \"interrupted\"";
}

void print_error(std::string_view message) {
  std::fprintf(stderr, "clothsim: error: %.*s\n", static_cast<int>(message.size()), message.data());
}

int run_subcommand(const std::function<int()>& run) {
  try {
    return run();
  } catch (const InputError& error) {
    print_error(error.what());
    return kExitBadInput;
  } catch (const OutputError& error) {
    print_error(error.what());
    return kExitOutputError;
  } catch (const BackendError& error) {
    // The backend cannot run the scene here (no device, too little device memory): refused, like
    // bad input, before anything is written.
    print_error(error.what());
    return kExitBadInput;
  } catch (const std::bad_alloc&) {
    print_error(
        "out of memory: the run needed more than its estimate and the memory it may use (see --max-memory; "
        "docs/performance.md, \"Memory\")");
    return kExitSimulationFailed;
  } catch (const std::exception& error) {
    // Not an expected failure: every anticipated error has its own type above.
    std::string message = "internal error: ";
    message += error.what();
    print_error(message);
    return kExitSimulationFailed;
  }
}

std::string join_command_line(int argc, const char* const* argv) {
  std::string line;
  for (int i = 0; i < argc; ++i) {
    const std::string_view word = argv[i];
    if (i > 0) line += ' ';
    const bool plain = !word.empty() && word.find_first_not_of(
                                            "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ"
                                            "0123456789-_=+.,/:@%") == std::string_view::npos;
    if (plain) {
      line += word;
      continue;
    }
    line += '\'';
    for (char c : word) {
      if (c == '\'') {
        line += "'\\''";
      } else {
        line += c;
      }
    }
    line += '\'';
  }
  return line;
}

std::string count_noun(std::uint64_t count, std::string_view singular, std::string_view plural) {
  std::string text = std::to_string(count);
  text += ' ';
  text += count == 1 ? singular : plural;
  return text;
}

std::string describe_lattice(const ClothModel& model) {
  std::string text = std::to_string(model.rows);
  text += 'x';
  text += std::to_string(model.cols);
  text += " lattice, ";
  text += count_noun(model.particle_count(), "particle", "particles");
  text += ", ";
  text += count_noun(model.connector_count(), "connector", "connectors");
  text += ", ";
  text += count_noun(model.radial_count(), "radial spring", "radial springs");
  text += ", ";
  text += count_noun(model.anchor_count(), "anchor", "anchors");
  return text;
}

std::string describe_run_settings(const SceneSpec& spec) {
  std::string text(to_string(spec.integrator.kind));
  text += ", ";
  if (spec.output.until_rest) {
    text += "until rest (at most ";
    text += format_number_short(spec.output.duration);
    text += " s)";
  } else {
    text += format_number_short(spec.output.duration);
    text += " s";
  }
  text += " at ";
  text += std::to_string(spec.output.fps);
  text += " fps";
  return text;
}

std::string format_number_short(double value) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.4g", value);
  return buffer;
}

std::string format_duration(double seconds) {
  char buffer[48];
  if (!std::isfinite(seconds) || seconds < 0.0) return "?";
  if (seconds < 10.0) {
    std::snprintf(buffer, sizeof buffer, "%.2f s", seconds);
  } else if (seconds < 60.0) {
    std::snprintf(buffer, sizeof buffer, "%.1f s", seconds);
  } else if (seconds < 3600.0) {
    const auto whole = static_cast<long long>(seconds);
    std::snprintf(buffer, sizeof buffer, "%lld min %02lld s", whole / 60, whole % 60);
  } else {
    const auto minutes = static_cast<long long>(seconds / 60.0);
    std::snprintf(buffer, sizeof buffer, "%lld h %02lld min", minutes / 60, minutes % 60);
  }
  return buffer;
}

std::string wrap_text(std::string_view text, std::size_t width, std::size_t indent) {
  std::string out;
  std::size_t column = indent;  // the caller has written the first line's indent
  bool line_empty = true;
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = text.find(' ', start);
    if (end == std::string_view::npos) end = text.size();
    const std::string_view word = text.substr(start, end - start);
    if (!word.empty()) {
      if (!line_empty && column + 1 + word.size() > width) {
        out += '\n';
        out.append(indent, ' ');
        column = indent;
        line_empty = true;
      }
      if (!line_empty) {
        out += ' ';
        ++column;
      }
      out += word;
      column += word.size();
      line_empty = false;
    }
    start = end + 1;
  }
  return out;
}

}  // namespace clothsim::cli

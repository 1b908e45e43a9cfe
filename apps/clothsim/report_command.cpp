// `clothsim report OUT`: the run report of a run folder, OUT/report.html (run/run_report.h,
// docs/report.md); of a sweep's folder, every run's report and the index's page.
#include <cstdio>
#include <filesystem>
#include <memory>
#include <string>

#include "commands.h"
#include "core/error.h"
#include "run/run_report.h"

namespace clothsim::cli {
namespace {

namespace fs = std::filesystem;

struct ReportOptions {
  std::string out;
};

int report(const ReportOptions& options) {
  const fs::path out = options.out;
  std::error_code error;
  if (!fs::is_directory(out, error)) throw InputError("OUT", "", out.string() + " is not a folder");
  if (!fs::exists(out / "sweep.json", error)) {
    std::printf("report       %s\n", write_run_report(out).string().c_str());
    return kExitSuccess;
  }
  // A sweep: each run that wrote its folder, then the index's page that links them.
  for (const fs::directory_entry& entry : fs::directory_iterator(out)) {
    if (entry.is_directory() && entry.path().filename().string().starts_with("run-") &&
        fs::exists(entry.path() / "summary.json", error)) {
      write_run_report(entry.path());
    }
  }
  std::printf("report       %s\n", write_sweep_report(out).string().c_str());
  return kExitSuccess;
}

}  // namespace

Subcommand add_report_command(CLI::App& parent) {
  auto options = std::make_shared<ReportOptions>();
  CLI::App* app = parent.add_subcommand("report", "Write a run's report.html: the run in a browser");
  app->add_option("OUT", options->out, "a run's output folder, or a sweep's")->required()->type_name("OUT");
  app->footer(
      "Writes OUT/report.html, one self-contained page (no network, no server): a 3D player of the run (drag to "
      "orbit; play, pause, scrub; each frame drawn with that frame's tears, anchors and obstacles), plots of "
      "energy.csv over time (every energy term, the work terms, the balance error, the step size, the events) "
      "and summary.json as a table. For a sweep's folder, every run's report and OUT/report.html, the index "
      "with a link to each. 'clothsim run --report' and 'clothsim sweep --report' write them at the end.\n"
      "\n"
      "Examples:\n"
      "  clothsim report out/paper-fig4\n"
      "  clothsim run tear-pull --render none --report   # out/tear-pull/report.html\n"
      "\n"
      "Documentation: docs/report.md.");
  return {app, [options] { return report(*options); }};
}

}  // namespace clothsim::cli

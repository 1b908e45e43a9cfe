// The run report (docs/report.md): `clothsim report OUT`, `clothsim run --report`, one page per run
// folder that opens from disk in a browser, with no network and no server. It holds a 3D player of
// the run (three.js: orbit, play, pause, scrub; each frame drawn with that frame's mesh, anchors and
// obstacles), plots of energy.csv over time and summary.json as a table.
//
// The page is made from the folder alone: scene.json rebuilds the model, connector_break_time.npy
// replays its tears frame by frame (the mesh of every frame is build_sheet_mesh's, as in the
// run's pictures and final.obj), positions.npy gives the positions, the anchors' release times and
// the obstacles' paths give where each stands at each frame.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>

namespace clothsim {

// The report's file in a run folder, and in a sweep's folder (the index's page).
inline constexpr std::string_view kReportFile = "report.html";

// The most vertex data the player holds, bytes of float32 positions: a run with more frames keeps
// every k-th frame and the last, the smallest k that fits (the page says so).
inline constexpr std::size_t kReportVertexBytes = std::size_t{96} << 20;

// Whether this build has the report (three.js was found at build time: web/node_modules).
bool report_available();

// Writes `folder`/report.html from the run folder `folder` (its scene.json, summary.json,
// energy.csv and positions.npy), replacing one already there; returns its path. Throws
// InputError naming the folder and the missing or unreadable file, and OutputError when the page
// cannot be written (nothing half-written: the page is renamed into place).
std::filesystem::path write_run_report(const std::filesystem::path& folder);

// Writes a sweep's index page, `out`/report.html: index.csv as a table, each run's folder linked
// to its report.html where it has one. Throws InputError without index.csv, OutputError.
std::filesystem::path write_sweep_report(const std::filesystem::path& out);

}  // namespace clothsim

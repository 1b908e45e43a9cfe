// The plan of a sweep, `clothsim sweep` and the Python module's clothsim.sweep() (docs/batch.md): the grid of --param
// values and its runs, which of them a shard takes, where each run's output goes, and the two files the sweep keeps in
// its folder: sweep.json, the record that ties the folder to one sweep, and index.csv, one row per run.
//
// The grid is the Cartesian product of the --param lists, the first --param varying slowest (as
// nested loops written in the order given). Run i of N writes `<out>/run-<i>`, i zero-padded to
// at least 4 digits. Shard K/N (K in 1..N) takes the runs whose index i has i mod N = K - 1:
// round robin, so that runs of neighbouring parameters, which often cost alike, spread over the
// shards. Whether a run is done is read from its folder alone (its summary.json), so shards on
// different machines sharing the folder, and a sweep run again, agree without talking.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "scene/scene.h"

namespace clothsim {

// One --param KEY=V1,V2,...: a scene field (any key --set takes) and its values, as text for
// --set. Values are split at commas outside brackets and braces, so that a vector or a list is
// one value: environment.gravity=[0,-9.81,0],[0,-1.62,0].
struct SweepParameter {
  std::string key;
  std::vector<std::string> values;
};

// Parses one --param. Throws InputError naming --param for a missing '=', an empty value, a value
// given twice or unbalanced brackets. The key itself is checked when the scene is built.
SweepParameter parse_sweep_parameter(std::string_view text);

// --shard K/N: this process runs the K-th of N shares (K from 1).
struct Shard {
  std::size_t index = 1;
  std::size_t count = 1;
  bool takes(std::size_t run) const { return run % count == index - 1; }
};

// Parses K/N. Throws InputError naming --shard with the allowed range.
Shard parse_shard(std::string_view text);

struct SweepRun {
  std::size_t index = 0;
  std::string folder;                                            // "run-0003", inside the sweep's folder
  std::vector<std::pair<std::string, std::string>> assignments;  // key and value, in --param order
};

// The grid's runs in order. Throws InputError naming `source` (the argument that gave the
// parameters) when a key repeats, a key has no values or the grid exceeds kMaxSweepRuns.
inline constexpr std::size_t kMaxSweepRuns = 1'000'000;
std::vector<SweepRun> plan_sweep(const std::vector<SweepParameter>& parameters, std::string_view source = "--param");

// Builds every run's scene, `base` with the run's assignments set, and validates it, before the
// sweep writes anything. Throws InputError naming `source` (the argument that gave the parameters)
// and, for a scene that only the whole rules out, the run and its assignments.
void check_sweep_scenes(const SceneSpec& base, const std::vector<SweepRun>& runs, std::string_view source);

// Where a run stands, read from the sweep's folder.
enum class SweepRunState {
  pending,      // not started (or its output was removed)
  running,      // a partial folder whose process is alive
  interrupted,  // stopped early: a partial folder whose process died, or status "interrupted"
  completed,    // summary.json says "completed" or "at_rest" (the command's exit 0)
  failed,       // summary.json says "failed": the simulation stopped with a diagnosis
  error,        // it ended without an output folder (bad input, output error); see its log
};
std::string_view to_string(SweepRunState state);

struct SweepRunStatus {
  SweepRunState state = SweepRunState::pending;
  nlohmann::json summary;             // summary.json, when the run has one
  std::filesystem::path resume_from;  // for an interrupted run with a checkpoint: --resume PATH
};

// The log of a run's attempts: <out>/logs/<run folder>.log.
std::filesystem::path sweep_log_path(const std::filesystem::path& out, const SweepRun& run);

SweepRunStatus read_run_status(const std::filesystem::path& out, const SweepRun& run);

// The record of a sweep: what every run was made from. Shards and reruns of the same sweep write
// the same record; claim_sweep_folder refuses a folder that holds another sweep's.
nlohmann::json sweep_record(const std::vector<std::string>& scene_arguments,
                            const std::vector<SweepParameter>& parameters, std::size_t runs);

// Creates `out` and writes its sweep.json, or checks that the one there is `record`. Throws
// InputError naming `source` (the argument that gave `out`) when `out` holds another sweep, or
// other files and no sweep.json.
void claim_sweep_folder(const std::filesystem::path& out, const nlohmann::json& record,
                        std::string_view source = "--out");

// Rewrites <out>/index.csv (atomically) from the runs' folders: one row per run of the whole grid
// with its parameters, status, wall time and final energies. Throws OutputError.
void write_sweep_index(const std::filesystem::path& out, const std::vector<SweepParameter>& parameters,
                       const std::vector<SweepRun>& runs);

}  // namespace clothsim

// Where a run's output goes: the default output folder of a scene; for `clothsim run --resume
// PATH` (resume_run(), run/run_scene.h), which run folder PATH names, where its output goes, and
// which checkpoints it has (run/run_checkpoints.h); and, for a new run, the partial folders earlier
// runs into the same output folder left behind.
//
// PATH may name
//   a partial folder `<out>.partial-<pid>` left by a run that died (killed, out of power): it is
//     taken over and completes as `<out>`;
//   an output folder `<out>` that a run finished early (status "interrupted"): it is copied and
//     completed, and replaces `<out>` at the end;
//   a checkpoint file inside either (`.../checkpoints/frame_000120.ckpt`): that checkpoint first,
//     then the older ones of its folder.
// A partial folder whose process is still alive is refused: that run is still writing it.
#pragma once

#include <sys/types.h>
#include <filesystem>
#include <string>
#include <vector>

#include "scene/scene.h"

namespace clothsim {

// out/<scene name>, with characters that do not belong in a folder name replaced by '_' ("run"
// for a name with nothing left).
std::string default_output_folder(const SceneSpec& spec);

struct ResumeTarget {
  std::filesystem::path folder;                    // the run's folder, holding scene.json and the output so far
  std::filesystem::path out;                       // where the completed output goes
  std::vector<std::filesystem::path> checkpoints;  // to try in order: newest first
};

// Finds the run PATH names (see the top of the file). Throws InputError naming --resume when PATH
// is not a run folder or checkpoint, has no checkpoint, is still being written, or is complete.
ResumeTarget find_resume_target(const std::string& path);

// A partial folder `<out>.partial-<pid>`: its path, the process id in its name, and whether that
// process is still running (writing it) or died and left it behind.
struct LeftoverRun {
  std::filesystem::path folder;
  pid_t pid = 0;
  bool has_checkpoint = false;
  bool alive = false;  // its process is still running
};

// The partial folders `<out>.partial-<pid>` beside `out` whose process is no longer running (other
// than this process's own).
std::vector<LeftoverRun> find_leftover_runs(const std::filesystem::path& out);

// Writes `text` to `path` through a temporary file beside it renamed into place, so that a reader
// sees the old file or the new one, never a part. Throws OutputError naming the path.
void write_text_atomically(const std::filesystem::path& path, const std::string& text);

// Every partial folder beside `out` (other than this process's own), alive or not.
std::vector<LeftoverRun> find_partial_runs(const std::filesystem::path& out);

}  // namespace clothsim

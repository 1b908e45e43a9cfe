// Starting and waiting for child processes: ffmpeg behind the video writer (render/video_writer.h)
// and the runs of `clothsim sweep`. posix_spawnp rather than fork and exec: nothing runs in the
// child between the two, which matters in a process with OpenMP threads.
#pragma once

#include <sys/types.h>

#include <string>
#include <vector>

namespace clothsim {

struct SpawnOptions {
  int stdin_fd = -1;               // the child's stdin; -1: /dev/null
  int output_fd = -1;              // the child's stdout and stderr; -1: /dev/null
  bool own_process_group = false;  // true: the terminal's Ctrl-C does not reach the child
};

// Starts `arguments` (arguments[0] is looked up on the PATH unless it holds a '/'). Returns the
// child's process id; throws std::system_error with the reason when it cannot be started.
pid_t spawn_process(const std::vector<std::string>& arguments, const SpawnOptions& options);

// Waits for `pid` to end (retrying when a signal interrupts the wait). Returns its wait status,
// or -1 when it cannot be waited for.
int wait_process(pid_t pid);

// "exited with status 2", "was killed by signal Killed", for a status from wait_process.
std::string describe_exit_status(int status);

}  // namespace clothsim

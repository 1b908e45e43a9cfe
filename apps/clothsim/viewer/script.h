// Viewer scripts: timed events for `clothsim view --script FILE`, for tests and demos.
//
// A script is a JSON object {"events": [...]}; each event has a time, "at" (seconds on the
// viewer's frame clock) or "frame" (a frame number), and exactly one action:
//
//   {"at": 1.0, "drag": {"row": 0, "col": 0, "to": [x, y, z], "duration": 2.0}}
//   {"at": 3.0, "release": {"row": 0, "col": 0}}
//   {"at": 0.5, "pin": {"row": 4, "col": 4}}      {"at": 2.5, "unpin": {"row": 4, "col": 4}}
//   {"at": 2.0, "pause": true}                    {"at": 2.5, "play": true}
//   {"at": 1.0, "set": {"springs.connector.stiffness": 200, "environment.gravity": [0, -5, 0]}}
//   {"at": 1.5, "cut": {"from": [2.5, -1], "to": [2.5, 30]}}
//   {"frame": 120, "screenshot": "out/shot.png"}
//   {"at": 4.0, "quit": true}
//   {"at": 0.5, "self_collision": true}           (or false)
//   {"at": 0.5, "add_sphere": {"center": [x, y, z], "radius": 0.1}}
//   {"at": 1.0, "move_sphere": {"sphere": 0, "to": [x, y, z], "duration": 0.5}}
//
// A scripted run is deterministic in simulated time: frame k is shown at k * frame_time on the
// frame clock (frame_time = 1 / the scene's output.fps), and every frame that plays advances the
// simulation by exactly frame_time, whatever the wall clock does. An event fires at the start of
// the first frame whose clock time is at or after its "at" (within a millionth of a frame, so
// "at": 0.1 at 60 fps is frame 6, not 7), before that frame is drawn. Events of one frame fire in
// file order. The frame clock runs while the simulation is paused, so a script can pause and
// play again; "at" equals simulated time until the first pause.
//
// A "cut" breaks every intact connector that the segment between two rest-lattice points
// (row, col, in particle spacings, fractions allowed) crosses, whatever the sheet's shape then:
// [2.5, -1] to [2.5, 30] tears a sheet of up to 30 columns between rows 2 and 3. Lattice
// coordinates rather than screen ones keep a scripted cut independent of the camera.
//
// "move_sphere" moves a sphere's centre to "to" over "duration" s of simulated time, as the mouse
// does (Session::move_sphere); "sphere" numbers the spheres from 0: the scene's in the order of
// its colliders, then those added by "add_sphere" events, in firing order.
//
// Rejected: event times in simulated time. A paused simulation's time stands still, so a "play"
// event could never fire.
//
// Errors name the file, the event and the field: "s.json: field 'events[2].drag.to': must be an
// array of 3 numbers [x, y, z], got \"up\"". parse_script() checks the format; check_script()
// checks the events against the scene (particles inside the lattice, "set" keys that can change
// while running, values in their ranges).
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/vec3.h"
#include "scene/scene.h"

namespace clothsim::viewer {

enum class ScriptAction : std::uint8_t {
  drag,
  release,
  pin,
  unpin,
  pause,
  play,
  set,
  screenshot,
  quit,
  cut,
  self_collision,
  add_sphere,
  move_sphere
};

std::string_view to_string(ScriptAction action);

struct ScriptEvent {
  std::size_t index = 0;    // position in the file's "events" list, for messages
  bool by_frame = false;    // timed by "frame" rather than "at"
  double at = 0.0;          // s on the frame clock ("at")
  std::uint64_t frame = 0;  // frame number ("frame")
  ScriptAction action = ScriptAction::quit;
  int row = 0;  // drag, release, pin, unpin: the particle
  int col = 0;
  Vec3 to;                // drag, move_sphere: target position (of the sphere's centre), m
  double duration = 0.0;  // drag, move_sphere: s of simulated time to get there (> 0)
  std::vector<std::pair<std::string, std::string>> assignments;  // set: key and value as --set text
  std::string path;                                              // screenshot: PNG file
  std::array<double, 2> cut_from{};                              // cut: rest-lattice points (row, col), in spacings
  std::array<double, 2> cut_to{};
  bool on = false;         // self_collision: switched on (true) or off
  Vec3 center;             // add_sphere: m
  double radius = 0.0;     // add_sphere: m (> 0)
  std::size_t sphere = 0;  // move_sphere: which sphere, from 0 (see the top of this file)

  // The frame at whose start this event fires, for frames of `frame_time` seconds.
  std::uint64_t firing_frame(double frame_time) const;
  // "events[3] (drag)": where this event is in the file.
  std::string describe() const;
};

struct Script {
  std::string source;               // the file name, for messages
  std::vector<ScriptEvent> events;  // in file order
};

// Parses script text; `source` names it in messages. Throws InputError.
Script parse_script(std::string_view json_text, const std::string& source);
// Reads and parses a script file. Throws InputError naming the file.
Script load_script_file(const std::string& path);
// Checks the events against the scene the viewer runs. Throws InputError naming the file, the
// event and the field.
void check_script(const Script& script, const SceneSpec& scene);

}  // namespace clothsim::viewer

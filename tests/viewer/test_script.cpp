// Viewer scripts (apps/clothsim/viewer/script.h): every action parses into the event it names,
// times map onto frames without rounding surprises, and every mistake is reported with the file,
// the event and the field.
#include <gtest/gtest.h>

#include <array>
#include <string>

#include "core/error.h"
#include "viewer/script.h"

namespace clothsim::viewer {
namespace {

constexpr const char* kFile = "drag.json";

// The error message of parsing `text`, or "" if it parsed.
std::string parse_error(const std::string& text) {
  try {
    parse_script(text, kFile);
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

std::string check_error(const std::string& text, const SceneSpec& scene) {
  try {
    check_script(parse_script(text, kFile), scene);
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

SceneSpec five_by_five() {
  SceneSpec scene;
  scene.lattice.rows = 5;
  scene.lattice.cols = 5;
  return scene;
}

TEST(Script, EveryActionParses) {
  const Script script = parse_script(R"({
    "description": "all of them",
    "events": [
      {"at": 0.5, "drag": {"row": 1, "col": 2, "to": [1, 2.5, -3], "duration": 0.75}},
      {"at": 1.25, "release": {"row": 1, "col": 2}},
      {"frame": 3, "pin": {"row": 0, "col": 4}},
      {"at": 2, "unpin": {"row": 0, "col": 4}},
      {"at": 2, "pause": true},
      {"at": 2.5, "play": true},
      {"at": 0, "set": {"springs.connector.stiffness": 200, "environment.gravity": [0, -5, 0.5],
                        "integrator.method": "rk4"}},
      {"frame": 120, "screenshot": "out/shot.png"},
      {"at": 4, "quit": true}
    ]})",
                                     kFile);
  ASSERT_EQ(script.events.size(), 9u);
  EXPECT_EQ(script.source, kFile);
  const ScriptEvent& drag = script.events[0];
  EXPECT_EQ(drag.action, ScriptAction::drag);
  EXPECT_EQ(drag.at, 0.5);
  EXPECT_EQ(drag.row, 1);
  EXPECT_EQ(drag.col, 2);
  EXPECT_EQ(drag.to, (Vec3{1, 2.5, -3}));
  EXPECT_EQ(drag.duration, 0.75);
  EXPECT_EQ(script.events[1].action, ScriptAction::release);
  EXPECT_EQ(script.events[2].action, ScriptAction::pin);
  EXPECT_TRUE(script.events[2].by_frame);
  EXPECT_EQ(script.events[2].frame, 3u);
  EXPECT_EQ(script.events[2].col, 4);
  EXPECT_EQ(script.events[3].action, ScriptAction::unpin);
  EXPECT_EQ(script.events[4].action, ScriptAction::pause);
  EXPECT_EQ(script.events[5].action, ScriptAction::play);
  const ScriptEvent& set = script.events[6];
  ASSERT_EQ(set.action, ScriptAction::set);
  ASSERT_EQ(set.assignments.size(), 3u);
  // The values become --set text; numbers keep every digit.
  EXPECT_EQ(set.assignments[0], (std::pair<std::string, std::string>{"environment.gravity", "0,-5,0.5"}));
  EXPECT_EQ(set.assignments[1], (std::pair<std::string, std::string>{"integrator.method", "rk4"}));
  EXPECT_EQ(set.assignments[2], (std::pair<std::string, std::string>{"springs.connector.stiffness", "200"}));
  EXPECT_EQ(script.events[7].action, ScriptAction::screenshot);
  EXPECT_EQ(script.events[7].path, "out/shot.png");
  EXPECT_EQ(script.events[8].action, ScriptAction::quit);
  EXPECT_EQ(script.events[8].describe(), "events[8] (quit)");
  EXPECT_EQ(check_error(R"({"events": [{"at": 0, "set": {"springs.connector.stiffness": 200}},
                                        {"at": 1, "drag": {"row": 4, "col": 4, "to": [0, 0, 0], "duration": 1}}]})",
                        five_by_five()),
            "");
}

TEST(Script, ObstacleActionsParseAndTheirErrorsNameTheField) {
  const Script script = parse_script(R"({"events": [
      {"at": 0.5, "self_collision": true},
      {"at": 0.75, "self_collision": false},
      {"at": 1, "add_sphere": {"center": [0, -0.5, 1], "radius": 0.25}},
      {"frame": 80, "move_sphere": {"sphere": 0, "to": [1, 2, 3], "duration": 0.5}}]})",
                                     kFile);
  ASSERT_EQ(script.events.size(), 4u);
  EXPECT_EQ(script.events[0].action, ScriptAction::self_collision);
  EXPECT_TRUE(script.events[0].on);
  EXPECT_FALSE(script.events[1].on);
  const ScriptEvent& add = script.events[2];
  EXPECT_EQ(add.action, ScriptAction::add_sphere);
  EXPECT_EQ(add.center, (Vec3{0, -0.5, 1}));
  EXPECT_EQ(add.radius, 0.25);
  const ScriptEvent& move = script.events[3];
  EXPECT_EQ(move.action, ScriptAction::move_sphere);
  EXPECT_EQ(move.sphere, 0u);
  EXPECT_EQ(move.to, (Vec3{1, 2, 3}));
  EXPECT_EQ(move.duration, 0.5);
  EXPECT_EQ(check_error(R"({"events": [{"at": 1, "add_sphere": {"center": [0, 0, 0], "radius": 1}},
                                        {"at": 1, "move_sphere": {"sphere": 0, "to": [0, 0, 0], "duration": 1}}]})",
                        five_by_five()),
            "");

  EXPECT_EQ(parse_error(R"({"events": [{"at": 1, "self_collision": "on"}]})"),
            "drag.json: field 'events[0].self_collision': must be true or false, got string \"on\"");
  EXPECT_EQ(parse_error(R"({"events": [{"at": 1, "add_sphere": {"center": [0, 0, 0], "radius": 0}}]})"),
            "drag.json: field 'events[0].add_sphere.radius': must be a number in (0, 1e6], got 0");
  EXPECT_EQ(parse_error(R"({"events": [{"at": 1, "add_sphere": {"radius": 1}}]})"),
            "drag.json: field 'events[0].add_sphere.center': is required");
  EXPECT_EQ(parse_error(R"({"events": [{"at": 1, "move_sphere": {"sphere": -1, "to": [0, 0, 0], "duration": 1}}]})"),
            "drag.json: field 'events[0].move_sphere.sphere': must be in [0, 1000000], got -1");
  EXPECT_EQ(parse_error(R"({"events": [{"at": 1, "move_sphere": {"sphere": 0, "to": [0, 0], "duration": 1}}]})"),
            "drag.json: field 'events[0].move_sphere.to': must be an array of 3 numbers [x, y, z], got array [0,0]");
  EXPECT_EQ(parse_error(R"({"events": [{"at": 1, "move_sphere": {"sphere": 0, "to": [0, 0, 0], "time": 1}}]})"),
            "drag.json: field 'events[0].move_sphere.time': unknown field (allowed here: sphere, to, duration)");
}

TEST(Script, CutParsesAndItsErrorsNameTheField) {
  const Script script =
      parse_script(R"({"events": [{"at": 1.5, "cut": {"from": [2.5, -1], "to": [2.5, 30]}}]})", kFile);
  ASSERT_EQ(script.events.size(), 1u);
  EXPECT_EQ(script.events[0].action, ScriptAction::cut);
  EXPECT_EQ(script.events[0].cut_from, (std::array<double, 2>{2.5, -1.0}));
  EXPECT_EQ(script.events[0].cut_to, (std::array<double, 2>{2.5, 30.0}));
  EXPECT_EQ(check_error(R"({"events": [{"at": 1, "cut": {"from": [0, 0], "to": [9, 9]}}]})", five_by_five()), "");
  EXPECT_NE(parse_error(R"({"events": [{"at": 1, "cut": [1, 2]}]})").find("field 'events[0].cut': must be an object"),
            std::string::npos);
  EXPECT_NE(parse_error(R"({"events": [{"at": 1, "cut": {"from": [1, 2]}}]})").find("'events[0].cut.to': is required"),
            std::string::npos);
  EXPECT_NE(parse_error(R"({"events": [{"at": 1, "cut": {"from": [1], "to": [1, 2]}}]})")
                .find("'events[0].cut.from': must be an array of 2 numbers"),
            std::string::npos);
  EXPECT_NE(parse_error(R"({"events": [{"at": 1, "cut": {"from": [1, "x"], "to": [1, 2]}}]})")
                .find("'events[0].cut.from[1]': must be a number"),
            std::string::npos);
  EXPECT_NE(parse_error(R"({"events": [{"at": 1, "cut": {"from": [1, 2], "to": [1, 2], "by": 3}}]})")
                .find("'events[0].cut.by': unknown field"),
            std::string::npos);
}

TEST(Script, TimesMapOntoTheFirstFrameAtOrAfterThem) {
  ScriptEvent event;
  const double frame_time = 1.0 / 60.0;
  // 0.1 * 60 is 6.000000000000001 in floating point: still frame 6.
  for (const auto& [at, frame] : std::vector<std::pair<double, std::uint64_t>>{
           {0.0, 0}, {0.1, 6}, {1.0, 60}, {0.5, 30}, {0.51, 31}, {1.0 / 60.0, 1}, {2.0 / 3.0, 40}}) {
    event.at = at;
    EXPECT_EQ(event.firing_frame(frame_time), frame) << "at " << at;
  }
  event.by_frame = true;
  event.frame = 17;
  EXPECT_EQ(event.firing_frame(frame_time), 17u);
}

TEST(Script, FormatErrorsNameTheFileTheEventAndTheField) {
  struct Case {
    const char* text;
    const char* expected;  // a part of the message
  };
  const Case cases[] = {
      {R"({"events": [)", "drag.json: line 1, column 13: JSON syntax error"},
      {R"([1, 2])", "drag.json: a script is a JSON object"},
      {R"({"event": []})", "drag.json: field 'event': unknown field (allowed here: events, description)"},
      {R"({})", "drag.json: field 'events': is required"},
      {R"({"events": {}})", "field 'events': must be a list of events"},
      {R"({"events": [7]})", "field 'events[0]': must be an object"},
      {R"({"events": [{"pause": true}]})", "field 'events[0]': needs a time"},
      {R"({"events": [{"at": 1, "frame": 2, "pause": true}]})", "field 'events[0]': give either \"at\""},
      {R"({"events": [{"at": -1, "pause": true}]})", "field 'events[0].at': must be a number in [0, 86400]"},
      {R"({"events": [{"frame": 1.5, "pause": true}]})", "field 'events[0].frame': must be a whole number"},
      {R"({"events": [{"at": 1}]})", "field 'events[0]': needs an action: one of drag, release"},
      {R"({"events": [{"at": 1, "pause": true, "play": true}]})", "field 'events[0]': has more than one action"},
      {R"({"events": [{"at": 1, "jump": true}]})", "field 'events[0].jump': unknown field"},
      {R"({"events": [{"at": 0, "pause": true}, {"at": 1, "drag": {"row": 0, "col": 0, "to": [1, 2], "duration": 1}}]})",
       "field 'events[1].drag.to': must be an array of 3 numbers [x, y, z], got array [1,2]"},
      {R"({"events": [{"at": 1, "drag": {"row": 0, "col": 0, "to": [1, 2, 3], "duration": 0}}]})",
       "field 'events[0].drag.duration': must be a number in (0, 86400], got 0"},
      {R"({"events": [{"at": 1, "drag": {"row": 0, "col": 0, "to": [1, 2, 3]}}]})",
       "field 'events[0].drag.duration': is required"},
      {R"({"events": [{"at": 1, "drag": {"col": 0, "to": [1, 2, 3], "duration": 1}}]})",
       "field 'events[0].drag.row': is required"},
      {R"({"events": [{"at": 1, "drag": {"row": 0, "col": 0, "to": [1, 2, 3], "duration": 1, "speed": 2}}]})",
       "field 'events[0].drag.speed': unknown field (allowed here: row, col, to, duration)"},
      {R"({"events": [{"at": 1, "pin": {"row": -1, "col": 0}}]})",
       "field 'events[0].pin.row': must be in [0, 1000000]"},
      {R"({"events": [{"at": 1, "unpin": {"row": 0.5, "col": 0}}]})",
       "field 'events[0].unpin.row': must be a whole number"},
      {R"({"events": [{"at": 1, "pause": false}]})", "field 'events[0].pause': must be true, got boolean false"},
      {R"({"events": [{"at": 1, "set": {}}]})", "field 'events[0].set': must be an object of scene keys"},
      {R"({"events": [{"at": 1, "set": {"environment.gravity": [1, 2]}}]})",
       "field 'events[0].set.environment.gravity': must be a number, a string or an array of 3 numbers"},
      {R"({"events": [{"at": 1, "screenshot": ""}]})", "field 'events[0].screenshot': must be the path of a PNG file"},
  };
  for (const Case& c : cases) {
    const std::string message = parse_error(c.text);
    EXPECT_NE(message.find(c.expected), std::string::npos) << c.text << "\n  gave: " << message;
  }
}

TEST(Script, SceneChecksNameTheEventAndTheAllowedValues) {
  const SceneSpec scene = five_by_five();
  EXPECT_EQ(check_error(R"({"events": [{"at": 1, "pin": {"row": 4, "col": 5}}]})", scene),
            "drag.json: field 'events[0].pin.col': must be in [0, 4] (the scene has 5 columns), got 5");
  EXPECT_EQ(
      check_error(
          R"({"events": [{"at": 0, "play": true}, {"at": 1, "drag": {"row": 9, "col": 0, "to": [0, 0, 0], "duration": 1}}]})",
          scene),
      "drag.json: field 'events[1].drag.row': must be in [0, 4] (the scene has 5 rows), got 9");
  // A key that defines the lattice cannot change while the simulation runs.
  const std::string not_live = check_error(R"({"events": [{"at": 1, "set": {"lattice.rows": 7}}]})", scene);
  EXPECT_NE(not_live.find("drag.json: field 'events[0].set.lattice.rows': cannot change while the simulation runs"),
            std::string::npos)
      << not_live;
  EXPECT_NE(not_live.find("springs.connector.stiffness"), std::string::npos) << not_live;
  // A value out of range gets the registry's message, with the event in front.
  const std::string out_of_range =
      check_error(R"({"events": [{"at": 1, "set": {"springs.adjacent.damping": -2}}]})", scene);
  EXPECT_NE(out_of_range.find("drag.json: events[0].set: field 'springs.adjacent.damping': must be"), std::string::npos)
      << out_of_range;
  const std::string bad_method =
      check_error(R"({"events": [{"at": 1, "set": {"integrator.method": "euler"}}]})", scene);
  EXPECT_NE(bad_method.find("field 'integrator.method': must be one of"), std::string::npos) << bad_method;
}

TEST(Script, MissingFileIsReportedWithItsName) {
  try {
    load_script_file("/nonexistent/drag.json");
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("/nonexistent/drag.json: cannot read file"), std::string::npos)
        << error.what();
  }
}

}  // namespace
}  // namespace clothsim::viewer

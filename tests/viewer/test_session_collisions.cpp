// The viewer's obstacles without a display (apps/clothsim/viewer/session.h): self-collision is
// switched on and off live, by the session and by a script, and the switch survives a reset;
// spheres are added and moved by the hand as the window and scripts do; a moved sphere travels
// in a straight line as a moving obstacle (its path carries the motion), and a sphere dragged
// through a hanging sheet pushes it along without a particle ever inside it, even when it crosses
// the sheet within one frame.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "core/error.h"
#include "model/model_edits.h"
#include "scene/builtin_scenes.h"
#include "session_fixtures.h"
#include "viewer/session.h"

namespace clothsim::viewer {
namespace {

using fixtures::kFrameTime;
using fixtures::small_scene;

// sphere-sweep: a cotton sheet hung by its row 0 in the plane z = -0.25 (after about a second)
// and a sphere of radius 0.1 m that the scene moves along +z at 1 m/s, centre at z = -0.5 at t = 1 s.
SceneSpec sweep_scene() {
  SceneSpec scene = builtin_scene("sphere-sweep");
  scene.threads = 1;
  return scene;
}

// Plays `script` for frames 0..last as the window does: frame k > 0 first advances one frame
// while playing, then fires frame k's events.
void play(Session& session, ScriptPlayer& player, std::uint64_t first, std::uint64_t last) {
  for (std::uint64_t frame = first; frame <= last; ++frame) {
    if (frame > 0 && session.playing()) session.advance(kFrameTime);
    player.fire(frame, session);
  }
}

// The deepest a particle is inside the thickness shell of collider `collider`, m (<= 0: none).
double deepest_inside(const Session& session, std::size_t collider) {
  const Simulation& simulation = session.simulation();
  const Collider& sphere = simulation.model().colliders[collider];
  double deepest = 0.0;
  for (const Vec3& x : simulation.state().position) {
    const double depth = simulation.model().collision.thickness - signed_distance(sphere, x, session.time()).distance;
    deepest = std::max(deepest, depth);
  }
  return deepest;
}

TEST(SessionCollisions, SelfCollisionSwitchSetsTheModelFlagAndSurvivesAReset) {
  Session session(small_scene());
  EXPECT_FALSE(session.self_collision());
  const std::uint64_t revision = session.simulation().model().revision;
  session.set_self_collision(true);
  EXPECT_TRUE(session.simulation().model().collision.self);
  EXPECT_GT(session.simulation().model().revision, revision);  // what caches the model refreshes
  session.advance(0.1);
  session.reset();
  EXPECT_TRUE(session.simulation().model().collision.self);
  session.set_self_collision(false);
  EXPECT_FALSE(session.simulation().model().collision.self);
  session.reset();
  EXPECT_FALSE(session.simulation().model().collision.self);
}

// Switched on live, self-collision needs the thickness the scene validation asks for: below half
// the spacing. Refused with the field named, and the flag stays off.
TEST(SessionCollisions, SelfCollisionIsRefusedWithATooLargeThickness) {
  SceneSpec scene = small_scene();
  scene.collision.thickness = 0.6;  // the paper's 1 m spacing: the limit is 0.5 m
  Session session(scene);
  try {
    session.set_self_collision(true);
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& error) {
    EXPECT_EQ(error.field(), "collision.thickness");
    EXPECT_NE(std::string(error.what()).find("half the lattice spacing"), std::string::npos) << error.what();
  }
  EXPECT_FALSE(session.self_collision());
}

TEST(SessionCollisions, ScriptedSelfCollisionEventsSwitchTheFlagOnAndOff) {
  Session session(small_scene());
  const Script script = parse_script(R"({"events": [{"at": 0.1, "self_collision": true},
                                                    {"at": 0.2, "self_collision": false}]})",
                                     "self.json");
  check_script(script, session.scene());
  ScriptPlayer player(script, kFrameTime);
  play(session, player, 0, 5);
  EXPECT_FALSE(session.simulation().model().collision.self);
  play(session, player, 6, 11);  // 0.1 s is frame 6
  EXPECT_TRUE(session.simulation().model().collision.self);
  play(session, player, 12, 12);
  EXPECT_FALSE(session.simulation().model().collision.self);
}

TEST(SessionCollisions, AnAddedSphereIsAColliderWhereItWasAddedAndSurvivesAReset) {
  Session session(small_scene());
  session.advance(0.2);
  const std::size_t sphere = session.add_sphere({5.0, 1.0, 0.0}, 0.5);
  ASSERT_EQ(session.simulation().model().colliders.size(), 1u);
  EXPECT_EQ(session.spheres(), std::vector<std::size_t>{sphere});
  EXPECT_EQ(session.sphere_center(sphere), (Vec3{5.0, 1.0, 0.0}));
  EXPECT_EQ(session.simulation().model().colliders[sphere].radius, 0.5);
  session.move_sphere(sphere, {6.0, 1.0, 0.0}, 0.1);
  session.advance(0.1);
  session.reset();  // the hand's move is undone, the added sphere stays where it was added
  ASSERT_EQ(session.spheres(), std::vector<std::size_t>{sphere});
  EXPECT_EQ(session.sphere_center(sphere), (Vec3{5.0, 1.0, 0.0}));
}

TEST(SessionCollisions, AMovedSphereTravelsInAStraightLineAsAMovingObstacleAndStops) {
  Session session(small_scene());
  session.advance(0.3);  // a moved sphere starts from wherever it is, at any time
  const std::size_t sphere = session.add_sphere({5.0, 0.0, 0.0}, 0.5);
  session.move_sphere(sphere, {5.0, 2.0, 0.0}, 0.5);
  // The motion is the collider's path, which the collision stage sweeps and takes the surface
  // velocity from; a jump of its centre would have no velocity.
  const Collider& moving = session.simulation().model().colliders[sphere];
  EXPECT_LT(norm(moving.path.velocity_at(session.time()) - Vec3{0.0, 4.0, 0.0}), 1e-12);
  EXPECT_LT(norm(session.sphere_center(sphere) - Vec3{5.0, 0.0, 0.0}), 1e-12);  // not moved yet
  session.advance(0.25);
  EXPECT_LT(norm(session.sphere_center(sphere) - Vec3{5.0, 1.0, 0.0}), 1e-12);
  EXPECT_LT(norm(signed_distance(moving, {5.0, 1.0, 0.0}, session.time()).velocity - Vec3{0.0, 4.0, 0.0}), 1e-12);
  session.advance(0.5);
  EXPECT_LT(norm(session.sphere_center(sphere) - Vec3{5.0, 2.0, 0.0}), 1e-12);
  EXPECT_EQ(signed_distance(moving, {5.0, 2.0, 0.0}, session.time()).velocity, Vec3{});

  // Paused, there is no time to move in: the sphere is placed at once.
  session.set_playing(false);
  session.move_sphere(sphere, {5.0, 3.0, 1.0}, kFrameTime);
  EXPECT_LT(norm(session.sphere_center(sphere) - Vec3{5.0, 3.0, 1.0}), 1e-12);
  EXPECT_EQ(signed_distance(moving, {5.0, 3.0, 1.0}, session.time()).velocity, Vec3{});
}

// The mouse's way: each frame the sphere is re-aimed at the cursor's point over that frame's
// simulated time. A hand at 1.5 m/s through the hanging sheet pushes it along +z.
TEST(SessionCollisions, ASphereDraggedThroughAHangingSheetPushesItWithoutPenetration) {
  Session session(sweep_scene());
  const std::size_t sphere = session.spheres().at(0);
  session.advance(1.0);  // hanging; the scene's own motion brought the sphere to z = -0.5
  ASSERT_LT(norm(session.sphere_center(sphere) - Vec3{0.0, -0.25, -0.5}), 1e-9);
  const auto mean_z = [&session] {
    double sum = 0.0;
    for (const Vec3& x : session.simulation().state().position) sum += x.z;
    return sum / static_cast<double>(session.simulation().state().position.size());
  };
  const double before = mean_z();
  double pushed = 0.0;
  for (int frame = 1; frame <= 30; ++frame) {
    const Vec3 cursor = session.sphere_center(sphere) + Vec3{0.0, 0.0, 1.5 * kFrameTime};
    session.move_sphere(sphere, cursor, kFrameTime);
    ASSERT_GT(session.advance(kFrameTime), 0.0);
    ASSERT_FALSE(session.failed()) << session.simulation().failure()->message;
    EXPECT_LT(deepest_inside(session, sphere), 1e-9) << "frame " << frame;
    pushed = std::max(pushed, mean_z() - before);
  }
  EXPECT_LT(norm(session.sphere_center(sphere) - Vec3{0.0, -0.25, 0.25}), 1e-9);
  EXPECT_GT(pushed, 0.05) << "the sheet was not pushed along";
}

// A hand fast enough to cross the sheet within one frame (0.3 m per frame, 18 m/s, one and a half
// diameters): the part of the sheet on the sphere's track is swept along with it. Had the sphere
// jumped between frames, it would have passed through the sheet, pushing that part back out of
// its near side (measured: 5 cm back) instead of along.
TEST(SessionCollisions, ASphereThatCrossesTheSheetWithinAFrameStillSweepsItAlong) {
  Session session(sweep_scene());
  const std::size_t sphere = session.spheres().at(0);
  session.advance(1.0);
  const double radius = session.simulation().model().colliders[sphere].radius;
  const Vec3 start = session.sphere_center(sphere);
  std::vector<std::size_t> track;  // particles in the sphere's way
  std::vector<double> start_z;
  for (std::size_t p = 0; p < session.simulation().state().position.size(); ++p) {
    const Vec3& x = session.simulation().state().position[p];
    if (std::hypot(x.x - start.x, x.y - start.y) > 0.5 * radius) continue;
    ASSERT_GT(x.z, start.z + radius) << "the sheet hangs in front of the sphere";
    track.push_back(p);
    start_z.push_back(x.z);
  }
  ASSERT_GE(track.size(), 4u);
  for (const double z : {-0.2, 0.1}) {
    session.move_sphere(sphere, {0.0, -0.25, z}, kFrameTime);
    ASSERT_GT(session.advance(kFrameTime), 0.0);
    ASSERT_FALSE(session.failed()) << session.simulation().failure()->message;
    EXPECT_LT(deepest_inside(session, sphere), 1e-9) << "z = " << z;
  }
  for (std::size_t k = 0; k < track.size(); ++k) {
    EXPECT_GT(session.simulation().state().position[track[k]].z - start_z[k], 0.15)
        << session.simulation().model().describe_particle(track[k]) << " was not swept along";
  }
}

TEST(SessionCollisions, ScriptedSpheresAreAddedAndMovedAndArriveAtTheirTargets) {
  Session session(sweep_scene());
  const Script script = parse_script(R"({"events": [
      {"at": 0.5, "add_sphere": {"center": [0.5, -0.25, -0.5], "radius": 0.05}},
      {"at": 1.0, "move_sphere": {"sphere": 0, "to": [0, -0.25, 0.25], "duration": 0.5}},
      {"at": 1.0, "move_sphere": {"sphere": 1, "to": [0.5, -0.5, -0.5], "duration": 0.25}}]})",
                                     "spheres.json");
  check_script(script, session.scene());
  ScriptPlayer player(script, kFrameTime);
  play(session, player, 0, 90);  // t = 1.5 s
  const std::vector<std::size_t> spheres = session.spheres();
  ASSERT_EQ(spheres.size(), 2u);
  EXPECT_LT(norm(session.sphere_center(spheres[0]) - Vec3{0.0, -0.25, 0.25}), 1e-9);
  EXPECT_LT(norm(session.sphere_center(spheres[1]) - Vec3{0.5, -0.5, -0.5}), 1e-9);
  EXPECT_LT(deepest_inside(session, spheres[0]), 1e-9);
  EXPECT_LT(deepest_inside(session, spheres[1]), 1e-9);
}

TEST(SessionCollisions, AScriptMayMoveOnlySpheresThatExistByThen) {
  const SceneSpec scene = small_scene();  // no colliders
  const auto error = [&scene](const std::string& text) {
    try {
      check_script(parse_script(text, "s.json"), scene);
    } catch (const InputError& caught) {
      return std::string(caught.what());
    }
    return std::string();
  };
  EXPECT_NE(error(R"({"events": [{"at": 1, "move_sphere": {"sphere": 0, "to": [0, 0, 0], "duration": 1}}]})")
                .find("field 'events[0].move_sphere.sphere': there is no sphere to move yet"),
            std::string::npos);
  // Added later than the move: still none by then.
  EXPECT_NE(error(R"({"events": [{"at": 1, "move_sphere": {"sphere": 0, "to": [0, 0, 0], "duration": 1}},
                                 {"at": 2, "add_sphere": {"center": [0, 0, 0], "radius": 1}}]})")
                .find("there is no sphere to move yet"),
            std::string::npos);
  EXPECT_EQ(error(R"({"events": [{"at": 2, "move_sphere": {"sphere": 0, "to": [0, 0, 0], "duration": 1}},
                                 {"at": 1, "add_sphere": {"center": [0, 0, 0], "radius": 1}}]})"),
            "");
  EXPECT_NE(error(R"({"events": [{"at": 0, "add_sphere": {"center": [0, 0, 0], "radius": 1}},
                                 {"at": 1, "move_sphere": {"sphere": 1, "to": [0, 0, 0], "duration": 1}}]})")
                .find("field 'events[1].move_sphere.sphere': must be in [0, 0] (there are 1 spheres by then), got 1"),
            std::string::npos);
}

}  // namespace
}  // namespace clothsim::viewer

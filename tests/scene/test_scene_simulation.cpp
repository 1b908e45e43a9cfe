// Tests of scene/scene_simulation.h: make_simulation() is the scene's model, initial state and
// settings; a Simulation moved (as make_unique_simulation() moves one) goes on as it would have;
// every parameter the registry marks live reaches the simulation through apply_live_parameters().
#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

#include "scene/builtin_scenes.h"
#include "scene/parameters.h"
#include "scene/scene.h"
#include "scene/scene_model.h"
#include "scene/scene_simulation.h"

namespace clothsim {
namespace {

TEST(SceneSimulation, MakeSimulationIsTheScenesModelStateAndSettings) {
  SceneSpec spec = builtin_scene("paper-fig5");
  spec.threads = 1;
  spec.integrator.relative_tolerance = 1e-5;
  const Simulation simulation = make_simulation(spec);
  const ClothModel model = build_model(spec);
  EXPECT_EQ(simulation.model().particle_count(), model.particle_count());
  EXPECT_EQ(simulation.model().particle_rest_position, model.particle_rest_position);
  EXPECT_EQ(simulation.state().position, build_initial_state(model, spec).position);
  EXPECT_EQ(simulation.settings().integrator.relative_tolerance, 1e-5);
  EXPECT_EQ(simulation.threads(), 1);
}

// A scene that sets no time step runs with the method's own: implicit Euler, made for frame-sized
// steps, takes the frame step (a sheet of cotton from Python took 12 s for 1 s at 1 ms against
// 2.25 s at the frame step), the others 1 ms; a step the scene sets is kept. The run takes those
// steps: an implicit-Euler sheet falling freely for 0.1 s at 30 frames per second lands on each
// frame in one step.
TEST(SceneSimulation, AnUnsetTimeStepIsTheMethodsOwn) {
  SceneSpec spec = scene_from_paper_args("9,9,1,4,1,1400,200,80,5,1", "test");
  EXPECT_EQ(spec.integrator.time_step, 0.0);
  EXPECT_EQ(scene_integrator(spec).time_step, kDefaultTimeStep);
  spec.integrator.kind = IntegratorKind::rk4;
  EXPECT_EQ(scene_integrator(spec).time_step, kDefaultTimeStep);
  spec.integrator.kind = IntegratorKind::implicit_euler;
  spec.output.fps = 30;
  EXPECT_EQ(scene_integrator(spec).time_step, 1.0 / 30.0);
  spec.threads = 1;
  Simulation simulation = make_simulation(spec);
  EXPECT_EQ(simulation.settings().integrator.time_step, 1.0 / 30.0);
  ASSERT_TRUE(simulation.advance_to(3.0 / 30.0));
  EXPECT_EQ(simulation.integrator_stats().accepted_steps, 3u);
  // The built-in implicit-Euler scenes keep the steps they set.
  EXPECT_EQ(scene_integrator(builtin_scene("tear-pull")).time_step, 1e-3);
  EXPECT_EQ(scene_integrator(builtin_scene("cotton-drape")).time_step, 1.0 / 60.0);
  spec.integrator.time_step = 2e-3;
  EXPECT_EQ(scene_integrator(spec).time_step, 2e-3);
}

// The integrator keeps pointers into what the Simulation owns (the model, the collision stage's
// resting contacts, which implicit Euler holds within its solve): a moved simulation must go on
// exactly as the original would have. A sheet resting on a floor with implicit Euler uses both.
TEST(SceneSimulation, AMovedSimulationGoesOnBitForBit) {
  SceneSpec spec = builtin_scene("tablecloth");
  spec.threads = 1;
  spec.integrator.kind = IntegratorKind::implicit_euler;
  spec.integrator.time_step = 1.0 / 120.0;
  Simulation staying = make_simulation(spec);
  Simulation moving = make_simulation(spec);
  ASSERT_TRUE(staying.advance_to(0.2));
  ASSERT_TRUE(moving.advance_to(0.2));
  const std::unique_ptr<Simulation> moved = std::make_unique<Simulation>(std::move(moving));
  ASSERT_TRUE(staying.advance_to(0.4));
  ASSERT_TRUE(moved->advance_to(0.4));
  EXPECT_GT(moved->contact_statistics().contact_steps, 0u) << "the sheet touches the table";
  EXPECT_EQ(moved->state().position, staying.state().position);
  EXPECT_EQ(moved->state().velocity, staying.state().velocity);
}

// What a live edit can change in a simulation, to see that it did.
struct Observed {
  std::vector<double> connector_stiffness, connector_damping, radial_stiffness, radial_damping, mass;
  Vec3 gravity;
  double air_drag = 0.0;
  IntegratorSettings integrator;

  explicit Observed(const Simulation& simulation)
      : connector_stiffness(simulation.model().connector_stiffness),
        connector_damping(simulation.model().connector_damping),
        radial_stiffness(simulation.model().radial_stiffness),
        radial_damping(simulation.model().radial_damping),
        mass(simulation.model().particle_mass),
        gravity(simulation.model().environment.gravity),
        air_drag(simulation.model().environment.air_drag),
        integrator(simulation.settings().integrator) {}

  bool operator==(const Observed& other) const {
    const IntegratorSettings& a = integrator;
    const IntegratorSettings& b = other.integrator;
    return connector_stiffness == other.connector_stiffness && connector_damping == other.connector_damping &&
           radial_stiffness == other.radial_stiffness && radial_damping == other.radial_damping && mass == other.mass &&
           gravity == other.gravity && air_drag == other.air_drag && a.kind == b.kind &&
           a.relative_tolerance == b.relative_tolerance && a.absolute_tolerance == b.absolute_tolerance &&
           a.time_step == b.time_step && a.min_step == b.min_step && a.max_step == b.max_step && a.safety == b.safety &&
           a.max_growth == b.max_growth && a.max_shrink == b.max_shrink;
  }
};

// Another valid value of a live key, as --set text.
std::string other_value(std::string_view key, const SceneSpec& spec) {
  if (key == "integrator.method") return "rk4";
  if (key == "environment.gravity") return "0,-4.9,0";
  const ScalarParameter* parameter = find_scalar_parameter(key);
  EXPECT_NE(parameter, nullptr) << key;
  const double value = parameter->get(spec);
  // Within every live key's range: halfway towards the range's lower end, or up from 0.
  const double other = value > 0.0 ? 0.5 * value : 0.25;
  EXPECT_TRUE(is_allowed(parameter->type, parameter->range, other)) << key;
  return format_number(other);
}

TEST(SceneSimulation, EveryLiveParameterReachesTheSimulation) {
  ASSERT_FALSE(live_parameter_keys().empty());
  for (std::string_view key : live_parameter_keys()) {
    SceneSpec current = builtin_scene("paper-fig5");
    current.integrator.max_step = 0.01;  // room below it for min_step and time_step
    Simulation simulation = make_simulation(current);
    const Observed before(simulation);
    SceneSpec edited = current;
    set_scene_field(edited, key, other_value(key, current), "test");
    apply_live_parameters(current, edited, simulation);
    EXPECT_FALSE(Observed(simulation) == before) << key << " is marked live but apply_live_parameters ignores it";
  }
  EXPECT_TRUE(is_live_parameter("springs.opposite.damping"));
  EXPECT_FALSE(is_live_parameter("lattice.rows"));
  EXPECT_NE(live_parameter_list().find("integrator.method"), std::string::npos);
}

}  // namespace
}  // namespace clothsim

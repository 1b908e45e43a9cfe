// The diagnosis of a step-size underflow names the spring behind the largest error
// (sim/step_diagnosis.h): a radial spring at a kink of its angle (0 or 180 degrees, away from its
// rest angle) first, else the spring furthest from its rest.
#include <gtest/gtest.h>

#include <algorithm>
#include <numbers>
#include <string>
#include <vector>

#include "scene/builtin_scenes.h"
#include "scene/scene_model.h"
#include "scene/scene_simulation.h"
#include "sim/step_diagnosis.h"

namespace clothsim {
namespace {

SceneSpec small_sheet() {
  SceneSpec spec = builtin_scene("paper-fig5");
  spec.lattice.rows = 3;
  spec.lattice.cols = 3;
  spec.anchors.clear();
  return spec;
}

TEST(StepDiagnosis, AFlatSheetAtRestIsAtNoKink) {
  const ClothModel model = build_model(small_sheet());
  // The opposite springs of a flat sheet sit at 180 degrees, their rest: a smooth minimum there.
  const StepLimit limit = find_step_limit(model, model.particle_rest_position, 4);
  EXPECT_FALSE(limit.at_kink);
  // The stiffest spring at the centre is a damped opposite one: on a flat sheet of spacing L the
  // gradient of its angle has lengths 1/L at each arm and 2/L at the centre, so its damping rate
  // is c (1 + 1 + 4) / (m L^2).
  ASSERT_EQ(limit.kind, StepLimit::Kind::radial);
  EXPECT_EQ(model.radial_kind[limit.element], RadialKind::opposite);
  const double spacing = model.connector_rest_length[0];
  EXPECT_NEAR(limit.rate, 6.0 * model.radial_damping[limit.element] / (model.particle_mass[4] * spacing * spacing),
              1e-9 * limit.rate);
}

TEST(StepDiagnosis, AnAdjacentSpringFoldedFlatIsNamedAtItsKink) {
  const ClothModel model = build_model(small_sheet());
  std::vector<Vec3> position = model.particle_rest_position;
  // Particle 1 (row 0, col 1) turned to lie 0.3 degrees off the line through the centre 4 and its
  // east neighbour 5: the adjacent springs of the centre with arm 1 are at 0.3 and 179.7 degrees.
  const Vec3 centre = position[4];
  const Vec3 east = position[5] - centre;
  const Vec3 south = position[7] - centre;
  const double small = 0.3 * std::numbers::pi / 180.0;
  position[1] = centre - std::cos(small) * east + std::sin(small) * (norm(east) / norm(south)) * south;
  const StepLimit limit = find_step_limit(model, position, 4);
  ASSERT_EQ(limit.kind, StepLimit::Kind::radial);
  EXPECT_TRUE(limit.at_kink);
  EXPECT_EQ(model.radial_kind[limit.element], RadialKind::adjacent);
  EXPECT_NEAR(std::abs(limit.angle - limit.kink_angle), small, 1e-9);
  const std::string text = describe_step_limit(model, limit, position);
  EXPECT_NE(text.find("adjacent radial spring"), std::string::npos) << text;
  EXPECT_NE(text.find("0.3 degrees from its kink"), std::string::npos) << text;
  EXPECT_NE(text.find("particle 1 (row 0, col 1)"), std::string::npos) << text;
}

TEST(StepDiagnosis, AStretchedConnectorIsNamedWithItsStrain) {
  SceneSpec spec = small_sheet();
  spec.lattice.cols = 2;
  spec.lattice.rows = 1;
  const ClothModel model = build_model(spec);  // one connector, no radial springs
  std::vector<Vec3> position = model.particle_rest_position;
  position[1] = position[0] + 1.25 * (position[1] - position[0]);
  const StepLimit limit = find_step_limit(model, position, 1);
  ASSERT_EQ(limit.kind, StepLimit::Kind::connector);
  EXPECT_NEAR(limit.strain, 0.25, 1e-12);
  const std::string text = describe_step_limit(model, limit, position);
  EXPECT_NE(text.find("connector 0 between particle 0 (row 0, col 0) and particle 1"), std::string::npos) << text;
  EXPECT_NE(text.find("strain 25 %"), std::string::npos) << text;
}

// A connector collapsing to a point (a particle passing through its neighbour, as the paper's
// hanging sheets do after 28 s) is named wherever the largest error is.
TEST(StepDiagnosis, ACollapsingConnectorIsNamedWhereverTheErrorIs) {
  const ClothModel model = build_model(small_sheet());
  std::vector<Vec3> position = model.particle_rest_position;
  position[5] = position[4] + 0.003 * (position[5] - position[4]);
  const StepLimit limit = find_step_limit(model, position, 0);
  ASSERT_EQ(limit.kind, StepLimit::Kind::connector);
  EXPECT_TRUE(limit.collapsed);
  const auto [a, b] = model.connector_particles[limit.element];
  EXPECT_EQ(std::min(a, b), 4u);
  EXPECT_EQ(std::max(a, b), 5u);
  const std::string text = describe_step_limit(model, limit, position);
  EXPECT_NE(text.find("has collapsed to"), std::string::npos) << text;
  EXPECT_NE(text.find("0.3 % of its rest length"), std::string::npos) << text;
}

// A scene made too stiff for its step floor: the run stops and its diagnosis names a spring.
TEST(StepDiagnosis, AnUnderflowNamesTheSpringAtTheWorstParticle) {
  SceneSpec spec = builtin_scene("paper-fig5");
  spec.integrator.min_step = 0.01;  // RKF45 needs about 0.6 ms on the paper's material
  spec.integrator.max_step = 0.05;
  Simulation simulation = make_simulation(spec);
  ASSERT_FALSE(simulation.advance_to(1.0));
  ASSERT_TRUE(simulation.failure().has_value());
  const std::string& message = simulation.failure()->message;
  EXPECT_NE(message.find("step size underflow"), std::string::npos) << message;
  EXPECT_TRUE(message.find("radial spring") != std::string::npos || message.find("connector") != std::string::npos)
      << message;
}

}  // namespace
}  // namespace clothsim

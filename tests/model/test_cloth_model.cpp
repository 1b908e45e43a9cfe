// Lattice topology and layout as the paper and docs/model.md define them.
#include <gtest/gtest.h>

#include <limits>
#include <numbers>
#include <vector>

#include "core/error.h"
#include "model/cloth_model.h"
#include "model/gather_table.h"
#include "model/initial_conditions.h"
#include "model/model_edits.h"

namespace clothsim {
namespace {

LatticeDef lattice(int rows, int cols) {
  LatticeDef def;
  def.rows = rows;
  def.cols = cols;
  def.spacing = 0.5;
  return def;
}

TEST(Lattice, ParticlePositionsAndIndices) {
  const ClothModel model = build_lattice(lattice(3, 4), Environment{}, {});
  ASSERT_EQ(model.particle_count(), 12u);
  // Particle (i, j) has index i*cols + j and starts at ((j-(cols-1)/2) L, 0, (i-(rows-1)/2) L).
  EXPECT_EQ(model.particle_rest_position[lattice_index(4, 0, 0)], (Vec3{-0.75, 0, -0.5}));
  EXPECT_EQ(model.particle_rest_position[lattice_index(4, 2, 3)], (Vec3{0.75, 0, 0.5}));
  EXPECT_EQ(model.particle_rest_position[lattice_index(4, 1, 2)], (Vec3{0.25, 0, 0}));
  EXPECT_EQ(model.describe_particle(6), "particle 6 (row 1, col 2)");
}

TEST(Lattice, SpringCountsFollowThePapersRule) {
  for (auto [rows, cols] : {std::pair{2, 2}, {3, 3}, {5, 8}, {21, 21}, {1, 5}}) {
    const ClothModel model = build_lattice(lattice(rows, cols), Environment{}, {});
    EXPECT_EQ(model.connector_count(), static_cast<std::size_t>(rows * (cols - 1) + cols * (rows - 1)));
    // Per particle: 4 adjacent + 2 opposite inside, 2 + 1 on an edge, 1 + 0 at a corner.
    std::size_t adjacent = 0, opposite = 0;
    for (int i = 0; i < rows; ++i) {
      for (int j = 0; j < cols; ++j) {
        const int horizontal = (j > 0) + (j + 1 < cols);
        const int vertical = (i > 0) + (i + 1 < rows);
        adjacent += static_cast<std::size_t>(horizontal * vertical);
        opposite += static_cast<std::size_t>((horizontal == 2) + (vertical == 2));
      }
    }
    std::size_t counted_adjacent = 0;
    for (RadialKind kind : model.radial_kind) counted_adjacent += kind == RadialKind::adjacent;
    EXPECT_EQ(counted_adjacent, adjacent) << rows << "x" << cols;
    EXPECT_EQ(model.radial_count() - counted_adjacent, opposite) << rows << "x" << cols;
  }
}

TEST(Lattice, RadialSpringsJoinConnectorsOfTheirCentreAtTheRestAngle) {
  const ClothModel model = build_lattice(lattice(4, 5), Environment{}, {});
  for (std::size_t r = 0; r < model.radial_count(); ++r) {
    const auto [centre, b, c] = model.radial_particles[r];
    const auto [c1, c2] = model.radial_connectors[r];
    const auto touches = [&](std::uint32_t connector, std::uint32_t p, std::uint32_t q) {
      const auto [x, y] = model.connector_particles[connector];
      return (x == p && y == q) || (x == q && y == p);
    };
    EXPECT_TRUE(touches(c1, centre, b));
    EXPECT_TRUE(touches(c2, centre, c));
    const Vec3 eb = model.particle_rest_position[b] - model.particle_rest_position[centre];
    const Vec3 ec = model.particle_rest_position[c] - model.particle_rest_position[centre];
    const double angle = std::atan2(norm(cross(eb, ec)), dot(eb, ec));
    EXPECT_NEAR(angle, model.radial_rest_angle[r], 1e-15);
  }
}

TEST(Lattice, GatherTableListsEachSlotOnceInAscendingOrder) {
  const ClothModel model = build_lattice(lattice(5, 6), Environment{}, {});
  GatherTable gather;
  gather.build(model);
  EXPECT_TRUE(gather.built_for(model));
  EXPECT_EQ(gather.bytes(), GatherTable::bytes_for(lattice_counts(5, 6)));
  std::vector<int> seen(model.force_slot_count(), 0);
  for (std::size_t p = 0; p < model.particle_count(); ++p) {
    for (std::uint32_t k = gather.offset[p]; k < gather.offset[p + 1]; ++k) {
      ++seen[gather.slot[k]];
      if (k > gather.offset[p]) {
        EXPECT_LT(gather.slot[k - 1], gather.slot[k]);
      }
      // Slot k of the table belongs to an element that joins particle p.
      const std::size_t slot = gather.slot[k];
      const std::uint32_t owner =
          slot < model.radial_slot_base()
              ? model.connector_particles[slot / 2][slot % 2]
              : model.radial_particles[(slot - model.radial_slot_base()) / 3][(slot - model.radial_slot_base()) % 3];
      EXPECT_EQ(owner, p);
    }
  }
  for (int count : seen) EXPECT_EQ(count, 1);
}

TEST(Lattice, AnchorsAreValidated) {
  const Anchor outside{100, {}};
  EXPECT_THROW(build_lattice(lattice(3, 3), Environment{}, {&outside, 1}), InputError);
  const Anchor twice[2] = {{4, {}}, {4, {}}};
  EXPECT_THROW(build_lattice(lattice(3, 3), Environment{}, twice), InputError);
  const Anchor centre{4, {}};
  const ClothModel model = build_lattice(lattice(3, 3), Environment{}, {&centre, 1});
  EXPECT_TRUE(model.is_anchored(4));
  EXPECT_EQ(model.particle_inverse_mass[4], 0.0);
  EXPECT_FALSE(model.is_anchored(3));
}

TEST(AnchorPath, VelocityAndAccelerationAreDerivativesOfPosition) {
  AnchorPath path;
  path.kind = AnchorPathKind::sinusoid;
  path.origin = {1, 2, 3};
  path.amplitude = {0.5, -0.2, 0.1};
  path.frequency = 1.7;
  path.phase = 0.4;
  EXPECT_EQ(path.position(0.0), path.origin);
  // Central differences err by about h^2/6 omega^3 |A| (1e-8 here) on velocity and
  // h^2/6 omega^4 |A| (1e-7) on acceleration.
  const double h = 1e-5;
  for (double t : {0.0, 0.3, 1.1}) {
    const Vec3 v = (path.position(t + h) - path.position(t - h)) / (2 * h);
    const Vec3 a = (path.velocity_at(t + h) - path.velocity_at(t - h)) / (2 * h);
    EXPECT_NEAR(norm(v - path.velocity_at(t)), 0.0, 5e-8);
    EXPECT_NEAR(norm(a - path.acceleration(t)), 0.0, 5e-7);
  }
  path.kind = AnchorPathKind::linear;
  path.velocity = {0, 1, 0};
  EXPECT_EQ(path.position(2.0), (Vec3{1, 4, 3}));
}

TEST(InitialConditions, SpinAndPerturbationAreReproducible) {
  const Anchor corner{0, AnchorPath::fixed_at({-0.5, 0.0, -0.5})};  // particle 0 where it starts
  const ClothModel model = build_lattice(lattice(3, 3), Environment{}, {&corner, 1});
  InitialConditions initial;
  initial.angular_velocity = {0, 2, 0};
  ClothState spun = make_rest_state(model);
  apply_initial_conditions(model, initial, spun);
  // v = omega x r about the centre (particle 4 at the origin): particle 5 at (0.5, 0, 0) moves
  // along -z.
  EXPECT_EQ(spun.velocity[5], (Vec3{0, 0, -1}));
  EXPECT_EQ(spun.velocity[0], Vec3{});  // anchored: keeps its path velocity

  initial.position_noise = 0.01;
  initial.seed = 42;
  ClothState a = make_rest_state(model), b = make_rest_state(model);
  apply_initial_conditions(model, initial, a);
  apply_initial_conditions(model, initial, b);
  EXPECT_EQ(a.position, b.position);
  EXPECT_NE(a.position[1], model.particle_rest_position[1]);
  EXPECT_LE(std::abs(a.position[1].y), 0.01);
  EXPECT_EQ(a.position[0], model.particle_rest_position[0]);
}

TEST(AnchorPath, DrivenPathMovesInAStraightLineAndStopsAtItsTarget) {
  AnchorPath path;
  path.kind = AnchorPathKind::driven;
  path.origin = {1, 2, 3};
  path.velocity = {0.5, 0.0, -1.0};
  path.start_time = 2.0;
  path.end_time = 4.0;
  EXPECT_EQ(path.position(2.0), path.origin);
  EXPECT_EQ(path.position(3.0), (Vec3{1.5, 2.0, 2.0}));
  EXPECT_EQ(path.position(4.0), (Vec3{2.0, 2.0, 1.0}));
  EXPECT_EQ(path.position(9.0), (Vec3{2.0, 2.0, 1.0}));  // held at the target
  // Moving up to and including the arrival (the limit from inside the last step), at rest after.
  EXPECT_EQ(path.velocity_at(4.0), path.velocity);
  EXPECT_EQ(path.velocity_at(4.0 + 1e-9), Vec3{});
  EXPECT_EQ(path.acceleration(3.0), Vec3{});
  // A held path (no velocity) is exactly its origin at any time.
  path.velocity = {};
  path.end_time = std::numeric_limits<double>::infinity();
  EXPECT_EQ(path.position(1e9), path.origin);
}

TEST(ModelEdits, SpringFamilyEditTouchesOnlyThatFamily) {
  ClothModel model = build_lattice(lattice(4, 4), Environment{}, {});
  const ClothModel before = model;
  set_spring_family(model, SpringFamily::adjacent, {7.0, 0.5});
  for (std::size_t r = 0; r < model.radial_count(); ++r) {
    if (model.radial_kind[r] == RadialKind::adjacent) {
      EXPECT_EQ(model.radial_stiffness[r], 7.0);
      EXPECT_EQ(model.radial_damping[r], 0.5);
    } else {
      EXPECT_EQ(model.radial_stiffness[r], before.radial_stiffness[r]);
      EXPECT_EQ(model.radial_damping[r], before.radial_damping[r]);
    }
  }
  EXPECT_EQ(model.connector_stiffness, before.connector_stiffness);
  set_spring_family(model, SpringFamily::connector, {9.0, 0.25});
  EXPECT_EQ(model.connector_stiffness, std::vector<double>(model.connector_count(), 9.0));
  EXPECT_EQ(model.connector_damping, std::vector<double>(model.connector_count(), 0.25));
}

TEST(ModelEdits, MassEditKeepsAnchoredParticlesImmovable) {
  const Anchor centre{4, {}};
  ClothModel model = build_lattice(lattice(3, 3), Environment{}, {&centre, 1});
  set_particle_mass(model, 0.25);
  for (std::size_t p = 0; p < model.particle_count(); ++p) {
    EXPECT_EQ(model.particle_mass[p], 0.25);
    EXPECT_EQ(model.particle_inverse_mass[p], p == 4 ? 0.0 : 4.0);
  }
}

TEST(ModelEdits, AddingAndRemovingAnchorsKeepsTheIndexConsistent) {
  const Anchor centre{4, {}};
  ClothModel model = build_lattice(lattice(3, 3), Environment{}, {&centre, 1});
  set_anchor(model, 0, AnchorPath::fixed_at({1, 1, 1}));
  set_anchor(model, 8, AnchorPath::fixed_at({2, 2, 2}));
  ASSERT_EQ(model.anchor_count(), 3u);
  set_anchor(model, 0, AnchorPath::fixed_at({3, 3, 3}));  // replaces the path, no new anchor
  ASSERT_EQ(model.anchor_count(), 3u);
  EXPECT_EQ(model.anchors[static_cast<std::size_t>(model.particle_anchor[0])].path.origin, (Vec3{3, 3, 3}));
  EXPECT_EQ(model.particle_inverse_mass[8], 0.0);

  EXPECT_TRUE(remove_anchor(model, 4));  // the first anchor: the last one moves into its place
  EXPECT_FALSE(remove_anchor(model, 4));
  EXPECT_FALSE(model.is_anchored(4));
  EXPECT_EQ(model.particle_inverse_mass[4], 1.0 / model.particle_mass[4]);
  ASSERT_EQ(model.anchor_count(), 2u);
  for (std::size_t a = 0; a < model.anchor_count(); ++a) {
    EXPECT_EQ(model.particle_anchor[model.anchors[a].particle], static_cast<std::int32_t>(a));
  }
  EXPECT_EQ(model.anchors[static_cast<std::size_t>(model.particle_anchor[8])].path.origin, (Vec3{2, 2, 2}));
  EXPECT_TRUE(remove_anchor(model, 8));
  EXPECT_TRUE(remove_anchor(model, 0));
  EXPECT_EQ(model.anchor_count(), 0u);
  EXPECT_EQ(model.particle_anchor, std::vector<std::int32_t>(9, -1));
}

}  // namespace
}  // namespace clothsim

namespace clothsim {
namespace {

// Keyframes: exact positions and velocities against hand values; keys hold before the first and
// after the last; at a key the velocity is the outgoing segment's.
TEST(AnchorPath, KeyframesAreExactAndHoldOutsideTheKeys) {
  AnchorPath path;
  path.kind = AnchorPathKind::keyframes;
  path.origin = {1.0, 0.0, -1.0};
  path.keys = {{1.0, {0.0, 0.0, 0.0}}, {2.0, {2.0, 4.0, 0.0}}, {2.5, {2.0, 4.0, 1.0}}};
  EXPECT_EQ(path.position(0.0), (Vec3{1.0, 0.0, -1.0}));  // before the first key: the first
  EXPECT_EQ(path.position(1.0), (Vec3{1.0, 0.0, -1.0}));
  EXPECT_EQ(path.position(1.5), (Vec3{2.0, 2.0, -1.0}));
  EXPECT_EQ(path.position(1.75), (Vec3{2.5, 3.0, -1.0}));
  EXPECT_EQ(path.position(2.0), (Vec3{3.0, 4.0, -1.0}));
  EXPECT_EQ(path.position(2.25), (Vec3{3.0, 4.0, -0.5}));
  EXPECT_EQ(path.position(9.0), (Vec3{3.0, 4.0, 0.0}));  // after the last: the last
  EXPECT_EQ(path.velocity_at(0.5), (Vec3{}));
  EXPECT_EQ(path.velocity_at(1.0), (Vec3{2.0, 4.0, 0.0}));  // at a key: the segment starting there
  EXPECT_EQ(path.velocity_at(1.5), (Vec3{2.0, 4.0, 0.0}));
  EXPECT_EQ(path.velocity_at(2.0), (Vec3{0.0, 0.0, 2.0}));
  EXPECT_EQ(path.velocity_at(2.5), (Vec3{}));  // at the last key: holding
  EXPECT_EQ(path.acceleration(1.5), (Vec3{}));
  EXPECT_EQ(path.next_key_after(0.0), 1.0);
  EXPECT_EQ(path.next_key_after(1.0), 2.0);
  EXPECT_EQ(path.next_key_after(2.2), 2.5);
  EXPECT_EQ(path.next_key_after(2.5), std::numeric_limits<double>::infinity());
  AnchorPath still;
  EXPECT_EQ(still.next_key_after(0.0), std::numeric_limits<double>::infinity());
}

}  // namespace
}  // namespace clothsim

// The collision passes' energy bookkeeping (collision/contact_energy.h) against the whole sheet's
// energy: summed over the particles a pass changed and the springs touching them, the change is
// compute_energy's change of the whole sheet, and the same for any thread count.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "collision/contact_energy.h"
#include "forces/forces.h"
#include "model/cloth_model.h"

namespace clothsim {
namespace {

TEST(ContactEnergy, TheChangeOverWhatMovedIsTheWholeSheetsChange) {
  LatticeDef def;
  def.rows = 70;
  def.cols = 90;  // 6,300 particles: several blocks of the parallel sums and selections
  def.spacing = 0.02;
  def.particle_mass = 0.01;
  def.connector = {50.0, 0.1};
  def.adjacent = {0.3, 0.0};
  def.opposite = {0.2, 0.0};
  const ClothModel model = build_lattice(def, Environment{}, {});
  std::mt19937 random(5);
  std::normal_distribution<double> noise(0.0, 1.0);
  ClothState before = make_rest_state(model);
  for (std::size_t p = 0; p < model.particle_count(); ++p) {
    before.position[p] += 0.004 * Vec3{noise(random), noise(random), noise(random)};
    before.velocity[p] = 0.3 * Vec3{noise(random), noise(random), noise(random)};
  }
  // A pass moves a third of the particles, in patches and alone.
  ClothState after = before;
  std::vector<std::uint8_t> changed(model.particle_count(), 0);
  std::bernoulli_distribution moved(1.0 / 3.0);
  for (std::size_t p = 0; p < model.particle_count(); ++p) {
    if (!moved(random)) continue;
    changed[p] = 1;
    after.position[p] += 0.003 * Vec3{noise(random), noise(random), noise(random)};
    after.velocity[p] += 0.5 * Vec3{noise(random), noise(random), noise(random)};
  }
  for (const ForceTerms terms : {kAllForceTerms, ForceTerms{kConnectorSprings | kGravity}}) {
    const double expected = compute_energy(model, after, terms).total() - compute_energy(model, before, terms).total();
    double serial = 0.0;
    for (int threads : {1, 2, 3, 4}) {
      ContactEnergy energy;
      energy.collect(model, changed, threads);
      ASSERT_EQ(energy.particles().size(), static_cast<std::size_t>(std::count(changed.begin(), changed.end(), 1)));
      const double change = energy.energy(model, after.position, after.velocity, terms, threads) -
                            energy.energy(model, before.position, before.velocity, terms, threads);
      EXPECT_NEAR(change, expected, 1e-12 * std::abs(compute_energy(model, before, terms).total()) + 1e-13)
          << threads << " threads";
      if (threads == 1) serial = change;
      EXPECT_EQ(change, serial) << threads << " threads: the same bits";
      // Collecting again (the next step) from the marks the last collect left.
      energy.collect(model, changed, threads);
      EXPECT_EQ(energy.energy(model, after.position, after.velocity, terms, threads) -
                    energy.energy(model, before.position, before.velocity, terms, threads),
                change);
    }
  }
}

}  // namespace
}  // namespace clothsim

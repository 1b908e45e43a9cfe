// Builds the paper's Figure 5 sheet in code, anchors its centre, lets it fall for a few seconds
// and prints its energy once per simulated second. The smallest useful clothsim program:
//
//   cmake --build build/release --target hanging_sheet && ./build/release/examples/hanging_sheet
#include <cstdio>

#include "forces/forces.h"
#include "model/cloth_model.h"
#include "sim/simulation.h"

int main() {
  using namespace clothsim;

  // The paper's argument vector [11, 11, 1, 4, 1, 1400, 200, 80, 5, 1], field by field.
  LatticeDef sheet;
  sheet.rows = 11;
  sheet.cols = 11;
  sheet.particle_mass = 1.0;         // kg
  sheet.adjacent = {4.0, 1.0};       // N m/rad, N m s/rad
  sheet.opposite = {1400.0, 200.0};  // N m/rad, N m s/rad
  sheet.connector = {80.0, 5.0};     // N/m, N s/m
  sheet.spacing = 1.0;               // m

  const std::uint32_t centre = lattice_index(sheet.cols, sheet.rows / 2, sheet.cols / 2);
  const Anchor anchor{centre, AnchorPath::fixed_at({0, 0, 0})};  // where the centre particle starts
  ClothModel model = build_lattice(sheet, Environment{}, {&anchor, 1});
  ClothState state = make_rest_state(model);

  SimulationSettings settings;  // RKF45, rtol = atol = 1e-6
  Simulation simulation(std::move(model), std::move(state), settings);

  std::printf("%6s %12s %12s %12s %12s %12s\n", "t [s]", "kinetic", "gravity", "connector", "radial", "total [J]");
  for (int second = 0; second <= 5; ++second) {
    if (!simulation.advance_to(second)) {
      std::fprintf(stderr, "simulation failed %s\n", simulation.failure()->message.c_str());
      return 1;
    }
    const EnergyReport e = simulation.energy();
    std::printf("%6d %12.4f %12.4f %12.4f %12.4f %12.4f\n", second, e.kinetic, e.gravitational, e.connector,
                e.radial_adjacent + e.radial_opposite, e.total());
  }
  const IntegratorStats& stats = simulation.integrator_stats();
  std::printf("%llu steps accepted, %llu rejected, %llu force evaluations\n",
              static_cast<unsigned long long>(stats.accepted_steps),
              static_cast<unsigned long long>(stats.rejected_steps),
              static_cast<unsigned long long>(stats.force_evaluations));
  return 0;
}

// The material mapping: each deformation of the lattice (uniform stretch, uniform shear, uniform
// cylindrical bending) stores the continuum sheet's energy per unit area, up to the lattice's
// boundary, on 32 x 32 and 64 x 64 lattices of the same 1 m sheet; so behaviour changes little
// under refinement. Plus the cotton values and the input checks.
#include "model/material.h"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/error.h"
#include "forces/forces.h"

namespace clothsim {
namespace {

// Energies of one deformation of an n x n lattice of a 1 m sheet, as energy per patch area
// (n^2 L^2, the area the particle masses stand for), J/m^2.
struct Densities {
  double connector = 0.0;
  double adjacent = 0.0;
  double opposite = 0.0;
};

template <typename Deform>
Densities energy_densities(int n, Deform&& deform) {
  LatticeDef lattice;
  lattice.rows = lattice.cols = n;
  apply_material(cotton_material(), 1.0 / (n - 1), lattice);
  const ClothModel model = build_lattice(lattice, Environment{}, {});
  std::vector<Vec3> position(model.particle_count());
  for (std::size_t p = 0; p < position.size(); ++p) position[p] = deform(model.particle_rest_position[p]);
  EnergyReport radial;
  add_radial_energy(model, position, radial);
  const double area = n * n * lattice.spacing * lattice.spacing;
  return {connector_energy(model, position) / area, radial.radial_adjacent / area, radial.radial_opposite / area};
}

// The relative error of the lattice's energy density against the continuum's, at 32 and 64.
void expect_refinement_consistent(const char* what, double continuum, double lattice32, double lattice64) {
  const double error32 = std::abs(lattice32 / continuum - 1.0);
  const double error64 = std::abs(lattice64 / continuum - 1.0);
  EXPECT_LT(error32, 2.5 / 32) << what;  // boundary particles miss springs: O(1/n)
  EXPECT_LT(error64, 2.5 / 64) << what;
  EXPECT_LT(error64, error32) << what;
  EXPECT_LT(std::abs(lattice64 / lattice32 - 1.0), 0.05) << what << ": 32 -> 64 changes the energy by under 5 %";
}

TEST(Material, StretchEnergyPerAreaMatchesTheContinuum) {
  const MaterialDef cotton = cotton_material();
  const double strain = 0.01;
  const auto stretch = [&](const Vec3& x) { return Vec3{(1 + strain) * x.x, x.y, x.z}; };
  const Densities d32 = energy_densities(32, stretch);
  const Densities d64 = energy_densities(64, stretch);
  expect_refinement_consistent("stretch", 0.5 * cotton.stretch_stiffness * strain * strain, d32.connector,
                               d64.connector);
  EXPECT_LT(d64.adjacent + d64.opposite, 1e-12);  // a pure stretch turns no radial spring
}

TEST(Material, ShearEnergyPerAreaMatchesTheContinuum) {
  const MaterialDef cotton = cotton_material();
  const double shear = 0.05;  // rad: the angle between the lattice directions changes by this
  const auto shear_map = [&](const Vec3& x) { return Vec3{x.x + std::tan(shear) * x.z, x.y, x.z}; };
  const Densities d32 = energy_densities(32, shear_map);
  const Densities d64 = energy_densities(64, shear_map);
  expect_refinement_consistent("shear", 0.5 * cotton.shear_stiffness * shear * shear, d32.adjacent, d64.adjacent);
}

TEST(Material, BendingEnergyPerAreaMatchesTheContinuum) {
  const MaterialDef cotton = cotton_material();
  const double curvature = 2.0;  // 1/m: the sheet rolled onto a cylinder of radius 0.5 m
  const auto roll = [&](const Vec3& x) {
    const double angle = curvature * x.x;
    return Vec3{std::sin(angle) / curvature, (1 - std::cos(angle)) / curvature, x.z};
  };
  const Densities d32 = energy_densities(32, roll);
  const Densities d64 = energy_densities(64, roll);
  expect_refinement_consistent("bending", 0.5 * cotton.bending_rigidity * curvature * curvature, d32.opposite,
                               d64.opposite);
}

TEST(Material, MassPerAreaIsTheArealDensity) {
  const MaterialDef cotton = cotton_material();
  for (int n : {32, 64}) {
    LatticeDef lattice;
    lattice.rows = lattice.cols = n;
    apply_material(cotton, 1.0 / (n - 1), lattice);
    EXPECT_DOUBLE_EQ(lattice.particle_mass / (lattice.spacing * lattice.spacing), cotton.areal_density);
    // Stretch and bending constants do not depend on the spacing; shear scales with its square.
    EXPECT_EQ(lattice.connector.stiffness, cotton.stretch_stiffness);
    EXPECT_EQ(lattice.opposite.stiffness, cotton.bending_rigidity);
    EXPECT_DOUBLE_EQ(lattice.adjacent.stiffness, cotton.shear_stiffness * lattice.spacing * lattice.spacing / 4);
    EXPECT_DOUBLE_EQ(lattice.connector.damping, cotton.damping_time * lattice.connector.stiffness);
  }
}

TEST(Material, CottonHasKesValuesInSiUnits) {
  const MaterialDef cotton = cotton_material();
  EXPECT_EQ(cotton.areal_density, 0.13);                 // 13 mg/cm^2
  EXPECT_NEAR(cotton.stretch_stiffness, 12258.3, 0.1);   // 500 gf/cm at 4 % strain
  EXPECT_NEAR(cotton.shear_stiffness, 44.95, 0.01);      // 0.8 gf/(cm deg)
  EXPECT_NEAR(cotton.bending_rigidity, 7.845e-6, 1e-9);  // 0.08 gf cm^2/cm
}

TEST(Material, BadInputIsAnInputErrorNamingTheField) {
  LatticeDef lattice;
  EXPECT_THROW(apply_material(cotton_material(), 0.0, lattice), InputError);
  MaterialDef broken = cotton_material();
  broken.shear_stiffness = -1.0;
  try {
    apply_material(broken, 0.01, lattice, "test");
    FAIL() << "no error";
  } catch (const InputError& error) {
    EXPECT_EQ(error.field(), "shear_stiffness");
  }
}

}  // namespace
}  // namespace clothsim

namespace clothsim {
namespace {

// The presets carry the values docs/materials.md tabulates, and apply_material maps them onto the
// documented spring constants and limits.
TEST(MaterialPresets, ValuesAndMapping) {
  EXPECT_EQ(material_preset_names(), "cotton, silk, denim, paper, plastic-film");
  EXPECT_EQ(find_material_preset("wool"), nullptr);
  const MaterialDef& paper = *find_material_preset("paper");
  EXPECT_EQ(paper.areal_density, 0.08);
  EXPECT_NEAR(paper.stretch_stiffness, 3.795e5, 1e2);
  EXPECT_NEAR(paper.shear_stiffness, 1.471e5, 1e2);
  EXPECT_NEAR(paper.bending_rigidity, 3.162e-4, 1e-7);
  EXPECT_EQ(paper.break_strain, 0.02);
  EXPECT_EQ(paper.yield_strain, 0.005);
  EXPECT_NEAR(paper.opposite_yield_angle, 20.0 * std::numbers::pi / 180.0, 1e-15);
  const MaterialDef& film = *find_material_preset("plastic-film");
  EXPECT_NEAR(film.areal_density, 0.023, 1e-15);
  EXPECT_NEAR(film.stretch_stiffness, 5000.0, 1e-9);
  EXPECT_NEAR(film.shear_stiffness, 1785.714, 1e-3);
  EXPECT_NEAR(film.bending_rigidity, 3.1002e-7, 1e-11);
  EXPECT_EQ(film.yield_strain, 0.05);
  EXPECT_EQ(film.break_strain, 4.0);
  EXPECT_NEAR(find_material_preset("silk")->stretch_stiffness, 6129.16, 0.01);
  EXPECT_NEAR(find_material_preset("denim")->shear_stiffness, 122.49, 0.01);
  EXPECT_EQ(find_material_preset("cotton")->break_strain, SpringLimits::kNever);
  EXPECT_EQ(cotton_material(), *find_material_preset("cotton"));

  LatticeDef lattice;
  lattice.limits.variation_seed = 9;
  apply_material(paper, 0.01, lattice);
  EXPECT_DOUBLE_EQ(lattice.particle_mass, 0.08 * 1e-4);
  EXPECT_EQ(lattice.connector.stiffness, paper.stretch_stiffness);
  EXPECT_DOUBLE_EQ(lattice.adjacent.stiffness, paper.shear_stiffness * 1e-4 / 4.0);
  EXPECT_EQ(lattice.opposite.stiffness, paper.bending_rigidity);
  EXPECT_EQ(lattice.limits, material_limits(paper, 9));
}

TEST(MaterialPresets, LimitChecks) {
  MaterialDef material = cotton_material();
  material.break_strain = 0.01;
  material.yield_strain = 0.02;
  LatticeDef lattice;
  EXPECT_THROW(apply_material(material, 0.01, lattice), InputError);
  material.yield_strain = 0.005;
  material.break_strain_variation = 1.0;
  EXPECT_THROW(apply_material(material, 0.01, lattice), InputError);
}

}  // namespace
}  // namespace clothsim

#include "model/material.h"

#include <cmath>
#include <numbers>
#include <string>
#include <utility>

#include "core/error.h"

namespace clothsim {

MaterialDef cotton_material() {
  // KES-F values of a cotton shirting (docs/materials.md): W = 13 mg/cm^2, extension EMT = 4 % at
  // 500 gf/cm, shear rigidity G = 0.8 gf/(cm deg), bending rigidity B = 0.08 gf cm^2/cm.
  constexpr double gram_force = 9.80665e-3;  // N
  constexpr double degree = std::numbers::pi / 180.0;
  MaterialDef cotton;
  cotton.name = "cotton";
  cotton.areal_density = 0.13;
  cotton.stretch_stiffness = (500.0 * gram_force / 1e-2) / 0.04;       // N/m, secant to 500 gf/cm
  cotton.shear_stiffness = (0.8 * gram_force / 1e-2) / degree;         // N/m per rad
  cotton.bending_rigidity = 0.08 * gram_force * 1e-4 / 1e-2;           // N m
  cotton.damping_time = 1e-3;                                          // s, a modelling choice
  return cotton;
}

void apply_material(const MaterialDef& material, double spacing, LatticeDef& lattice, const std::string& source) {
  if (!(spacing > 0.0) || !std::isfinite(spacing)) {
    throw InputError(source, "spacing", "must be a positive length in m");
  }
  if (!(material.areal_density > 0.0) || !std::isfinite(material.areal_density)) {
    throw InputError(source, "areal_density", "must be positive (kg/m^2)");
  }
  const std::pair<const char*, double> non_negative[] = {{"stretch_stiffness", material.stretch_stiffness},
                                                         {"shear_stiffness", material.shear_stiffness},
                                                         {"bending_rigidity", material.bending_rigidity},
                                                         {"damping_time", material.damping_time}};
  for (const auto& [field, value] : non_negative) {
    if (!(value >= 0.0) || !std::isfinite(value)) {
      throw InputError(source, field, "must be finite and non-negative, got " + std::to_string(value));
    }
  }
  const double beta = material.damping_time;
  lattice.spacing = spacing;
  lattice.particle_mass = material.areal_density * spacing * spacing;
  const double connector = material.stretch_stiffness;
  const double adjacent = material.shear_stiffness * spacing * spacing / 4.0;
  const double opposite = material.bending_rigidity;
  lattice.connector = {connector, beta * connector};
  lattice.adjacent = {adjacent, beta * adjacent};
  lattice.opposite = {opposite, beta * opposite};
  lattice.adjacent_rest_angle = std::numbers::pi / 2.0;
  lattice.opposite_rest_angle = std::numbers::pi;
}

}  // namespace clothsim

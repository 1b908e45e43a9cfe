#include "model/material.h"

#include <array>
#include <cmath>
#include <numbers>
#include <string>
#include <utility>

#include "core/error.h"

namespace clothsim {
namespace {

constexpr double kGramForce = 9.80665e-3;  // N
constexpr double kDegree = std::numbers::pi / 180.0;
constexpr double kNever = SpringLimits::kNever;

// The Kawabata (KES-F) quantities of a woven fabric in the units the system reports: W in mg/cm^2,
// EMT the strain (as a fraction) at 500 gf/cm, G in gf/(cm deg), B in gf cm^2/cm.
MaterialDef from_kawabata(std::string name, double weight, double extension_at_500, double shear, double bending) {
  MaterialDef fabric;
  fabric.name = std::move(name);
  fabric.areal_density = weight / 100.0;                                      // mg/cm^2 -> kg/m^2
  fabric.stretch_stiffness = (500.0 * kGramForce / 1e-2) / extension_at_500;  // N/m, secant to 500 gf/cm
  fabric.shear_stiffness = (shear * kGramForce / 1e-2) / kDegree;             // N/m per rad
  fabric.bending_rigidity = bending * kGramForce * 1e-4 / 1e-2;               // N m
  fabric.damping_time = 1e-3;                                                 // s, a modelling choice
  return fabric;
}

// An isotropic plate of Young's modulus E (Pa), Poisson's ratio nu and thickness t (m):
// Y = E t, G = E t / (2 (1 + nu)), B = E t^3 / (12 (1 - nu^2)).
void set_plate_stiffness(MaterialDef& sheet, double young, double poisson, double thickness) {
  sheet.stretch_stiffness = young * thickness;
  sheet.shear_stiffness = young * thickness / (2.0 * (1.0 + poisson));
  sheet.bending_rigidity = young * thickness * thickness * thickness / (12.0 * (1.0 - poisson * poisson));
}

std::array<MaterialDef, 5> make_presets() {
  // Woven fabrics (docs/materials.md): representative KES-F values. Under everyday loads cloth
  // neither tears nor keeps a stretch or a fold in this model: its limits stay +inf.
  MaterialDef cotton = from_kawabata("cotton", 13.0, 0.04, 0.8, 0.08);   // shirting, plain weave
  MaterialDef silk = from_kawabata("silk", 5.0, 0.08, 0.4, 0.03);        // thin dress silk (habutae)
  MaterialDef denim = from_kawabata("denim", 40.7, 0.055, 2.18, 0.172);  // 12 oz/yd^2 twill

  // Office paper, 80 g/m^2, 0.1 mm: tensile stiffness the geometric mean of machine and cross
  // direction (index 7.5 and 3 kN m/g), shear after Baum et al. (G = sqrt(E_md E_cd) / 2.58),
  // bending as a plate. Elastic to about 0.5 % strain, then plastic with a tangent modulus near a
  // quarter of the initial one (hardening 1/3), breaking near 2 %; folds crease.
  MaterialDef paper;
  paper.name = "paper";
  paper.areal_density = 0.080;
  const double paper_thickness = 1e-4;
  paper.stretch_stiffness = std::sqrt(7.5e3 * 3.0e3) * 80.0;  // N m/g times g/m^2 = N/m
  paper.shear_stiffness = paper.stretch_stiffness / 2.58;
  paper.bending_rigidity = paper.stretch_stiffness * paper_thickness * paper_thickness / 12.0;
  paper.damping_time = 1e-3;
  paper.break_strain = 0.02;
  paper.break_strain_variation = 0.1;
  paper.yield_strain = 0.005;
  paper.hardening = 1.0 / 3.0;
  paper.opposite_yield_angle = 20.0 / 180.0 * std::numbers::pi;  // as scene/ converts 20 degrees, exactly

  // Low-density polyethylene packaging film, 25 um: E 0.2 GPa, nu 0.4, density 920 kg/m^3; yields
  // near 5 % strain and draws to several times its length before breaking (400 %).
  MaterialDef film;
  film.name = "plastic-film";
  const double film_thickness = 25e-6;
  film.areal_density = 920.0 * film_thickness;
  set_plate_stiffness(film, 0.2e9, 0.4, film_thickness);
  film.damping_time = 1e-3;
  film.break_strain = 4.0;
  film.break_strain_variation = 0.1;
  film.yield_strain = 0.05;
  film.hardening = 0.0;
  return {cotton, silk, denim, paper, film};
}

const std::array<MaterialDef, 5>& presets() {
  static const std::array<MaterialDef, 5> table = make_presets();
  return table;
}

[[noreturn]] void bad_value(const std::string& source, const char* field, double value, const std::string& allowed) {
  throw InputError(source, field, "must be " + allowed + ", got " + std::to_string(value));
}

// A limit is +inf (never) or a number in its range.
void check_limits(const MaterialDef& material, const std::string& source) {
  const auto positive_or_never = [&](const char* field, double value) {
    if (value == kNever) return;
    if (!(value > 0.0) || !std::isfinite(value)) bad_value(source, field, value, "positive, or +inf (never)");
  };
  const auto angle_or_never = [&](const char* field, double value) {
    if (value == kNever) return;
    if (!(value >= 0.0 && value <= std::numbers::pi)) bad_value(source, field, value, "in [0, pi] rad, or +inf");
  };
  positive_or_never("break_strain", material.break_strain);
  positive_or_never("yield_strain", material.yield_strain);
  if (!(material.break_strain_variation >= 0.0 && material.break_strain_variation < 1.0)) {
    bad_value(source, "break_strain_variation", material.break_strain_variation, "in [0, 1)");
  }
  if (!(material.hardening >= 0.0) || !std::isfinite(material.hardening)) {
    bad_value(source, "hardening", material.hardening, "finite and non-negative");
  }
  angle_or_never("adjacent_yield_angle", material.adjacent_yield_angle);
  angle_or_never("opposite_yield_angle", material.opposite_yield_angle);
  if (yields_after_breaking(material.yield_strain, material.break_strain)) {
    throw InputError(source, "yield_strain",
                     "must be <= break_strain (" + std::to_string(material.break_strain) + "), got " +
                         std::to_string(material.yield_strain) + ": the sheet would tear before it yields");
  }
}

}  // namespace

std::span<const MaterialDef> material_presets() { return presets(); }

const MaterialDef* find_material_preset(std::string_view name) {
  for (const MaterialDef& material : presets()) {
    if (material.name == name) return &material;
  }
  return nullptr;
}

std::string material_preset_names() {
  std::string text;
  for (const MaterialDef& material : presets()) text += (text.empty() ? "" : ", ") + material.name;
  return text;
}

MaterialDef cotton_material() {
  // KES-F values of a cotton shirting (docs/materials.md): W = 13 mg/cm^2, extension EMT = 4 % at
  // 500 gf/cm, shear rigidity G = 0.8 gf/(cm deg), bending rigidity B = 0.08 gf cm^2/cm.
  return presets()[0];
}

SpringLimits material_limits(const MaterialDef& material, std::uint64_t seed) {
  SpringLimits limits;
  limits.break_strain = material.break_strain;
  limits.break_strain_variation = material.break_strain_variation;
  limits.variation_seed = seed;
  limits.yield_strain = material.yield_strain;
  limits.hardening = material.hardening;
  limits.adjacent_yield_angle = material.adjacent_yield_angle;
  limits.opposite_yield_angle = material.opposite_yield_angle;
  return limits;
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
  check_limits(material, source);
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
  lattice.limits = material_limits(material, lattice.limits.variation_seed);
}

}  // namespace clothsim

// Materials in physical per-area units, and their mapping onto the lattice's per-spring constants.
//
// A woven fabric is characterised by its areal density and three stiffnesses per unit width,
// which are what the Kawabata Evaluation System (KES-F) and similar tests measure: stretch (force
// per unit width per unit strain), shear (force per unit length per radian of shear angle) and
// bending (moment per unit width per unit curvature). material_lattice() turns them into the
// constants of a square lattice of spacing L so that each deformation stores the same energy per
// unit area as the continuum sheet, whatever L is (docs/materials.md derives every line):
//
//   particle mass               m     = rho L^2           (each particle stands for an L x L patch)
//   connector stiffness         k_c   = Y                 (a strip of width L carries Y eps L over an
//                                                          extension eps L; independent of L)
//   adjacent radial stiffness   k_adj = G L^2 / 4         (4 springs per particle, each turned by the
//                                                          shear angle gamma: 4 (1/2) k gamma^2 = (1/2) G gamma^2 L^2)
//   opposite radial stiffness   k_opp = B                 (one spring per particle and direction, bent
//                                                          by kappa L: (1/2) k (kappa L)^2 = (1/2) B kappa^2 L^2)
//   damping                     c     = damping_time * k  for every spring (stiffness-proportional,
//                                                          Rayleigh damping: modal damping ratio
//                                                          damping_time * omega / 2 in every mode)
//
// The lattice has no Poisson effect (a square grid of springs has Poisson's ratio 0) and the
// stretch and shear responses are linear: a fabric's initial, nearly linear range, which is the
// range of draping under its own weight. Rejected: fitting the springs to a measured drape (the
// mapping would then hold for one lattice only).
#pragma once

#include <span>
#include <string>
#include <string_view>

#include "model/cloth_model.h"

namespace clothsim {

struct MaterialDef {
  std::string name{};              // preset name, or what a scene calls its own material
  double areal_density = 0.0;      // rho, kg/m^2
  double stretch_stiffness = 0.0;  // Y, N/m: tension per unit width per unit strain (E times thickness)
  double shear_stiffness = 0.0;    // G, N/m per rad: shear force per unit length per radian of shear
  double bending_rigidity = 0.0;   // B, N m: bending moment per unit width per unit curvature
  double damping_time = 0.0;       // s: every spring's damping is damping_time times its stiffness
  // Where the sheet changes for good (model/spring_limits.h; +inf: never). Strains are
  // dimensionless and scale-free; the yield angles are per radial spring, rad: a crease is a kink
  // at one line of springs whatever the spacing, so its angle is what a fold keeps
  // (docs/materials.md discusses what this means for smooth bends).
  double break_strain = SpringLimits::kNever;          // > 0: a connector breaks beyond it
  double break_strain_variation = 0.0;                 // [0, 1): relative spread of the break strain
  double yield_strain = SpringLimits::kNever;          // > 0, <= break_strain: stretches for good beyond it
  double hardening = 0.0;                              // >= 0: yield strain growth per unit plastic strain
  double adjacent_yield_angle = SpringLimits::kNever;  // rad, [0, pi]: in-plane shear that stays
  double opposite_yield_angle = SpringLimits::kNever;  // rad, [0, pi]: folds that stay

  bool operator==(const MaterialDef&) const = default;
};

// The presets, in a fixed order: cotton, silk, denim, paper, plastic-film. docs/materials.md
// gives every value's source and unit conversion.
std::span<const MaterialDef> material_presets();
// nullptr for an unknown name.
const MaterialDef* find_material_preset(std::string_view name);
// "cotton, silk, denim, paper, plastic-film".
std::string material_preset_names();

// A cotton shirting fabric (plain weave, about 130 g/m^2) from KES-F data.
MaterialDef cotton_material();

// The spring limits of `material` with `seed` as the seed of the break-strain variation.
SpringLimits material_limits(const MaterialDef& material, std::uint64_t seed);

// Sets the spacing, particle mass, spring constants, rest angles and spring limits of `lattice`
// (keeping rows, cols and the limits' variation seed) for `material` at connector rest length
// `spacing` (m). Throws InputError naming `source` and the field for a non-positive spacing or
// density, a negative stiffness, or a limit out of its range (yield strain above break strain
// included).
void apply_material(const MaterialDef& material, double spacing, LatticeDef& lattice,
                    const std::string& source = "material");

}  // namespace clothsim

// The implicit Euler scenes the device's tests hold against the CPU (test_device_implicit_euler.cpp,
// test_device_multigrid.cpp), on lattices small enough for lavapipe.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <span>

#include "core/vec3.h"
#include "scene/builtin_scenes.h"
#include "scene/scene.h"
#include "scene/validate_scene.h"

namespace clothsim::testing {

inline const BackendSettings kCpu{Backend::cpu, 0, std::nullopt};
inline const BackendSettings kVulkan{Backend::vulkan, 0, std::nullopt};

// cotton-drape on a rows x cols lattice (the same 1 m sheet of cotton, hung by two corners), on
// `backend`; `two_level` false gives the CPU the device's block Jacobi alone. The V-cycle's fine
// level smooths single particles (the default solves lines: test_device_multigrid.cpp holds both).
inline SceneSpec cotton(int rows, int cols, const BackendSettings& backend, bool two_level) {
  SceneSpec spec = builtin_scene("cotton-drape");
  spec.lattice.rows = rows;
  spec.lattice.cols = cols;
  spec.lattice.spacing = 1.0 / (cols - 1);
  parse_anchor_preset("edge-corners", spec.lattice, spec.anchors);
  spec.backend = backend;
  spec.integrator.cg_two_level = two_level;
  spec.integrator.cg_line_smoother = false;
  return spec;
}
inline SceneSpec cotton(int side, const BackendSettings& backend, bool two_level) {
  return cotton(side, side, backend, two_level);
}

// tablecloth on 15 x 15 (the same 1 m of cotton on the same table); `two_level` and the smoother
// as above.
inline SceneSpec table_scene(const BackendSettings& backend, bool two_level = false) {
  SceneSpec spec = builtin_scene("tablecloth");
  spec.lattice.rows = spec.lattice.cols = 15;
  spec.lattice.spacing = 1.0 / 14.0;
  set_scene_field(spec, "material", "cotton", "--set");
  spec.integrator.cg_two_level = two_level;
  spec.integrator.cg_line_smoother = false;
  spec.backend = backend;
  return spec;
}

// Nothing inside table_scene's table: the particles over its top (y = -0.05) rest on it, more than 50.
inline void expect_resting_on_the_table(std::span<const Vec3> positions) {
  std::size_t on_top = 0;
  for (const Vec3& x : positions) {
    if (std::abs(x.x) > 0.34 || std::abs(x.z) > 0.34) continue;
    EXPECT_GT(x.y, -0.05 - 1e-6);
    ++on_top;
  }
  EXPECT_GT(on_top, 50u);
}

}  // namespace clothsim::testing

// What the viewer's session tests share: the frame time they advance by and a small scene.
#pragma once

#include "scene/scene.h"

namespace clothsim::viewer::fixtures {

inline constexpr double kFrameTime = 1.0 / 60.0;

// The paper's material on a 5 x 5 lattice with the centre anchored at the origin.
inline SceneSpec small_scene() {
  SceneSpec scene = scene_from_paper_args("5,5,1,4,1,1400,200,80,5,1", "test");
  scene.threads = 1;
  return scene;
}

}  // namespace clothsim::viewer::fixtures

// Fuzz target: the OBJ files of mesh colliders (src/scene/colliders_json.h, parse_obj_mesh, the
// text half of read_obj_mesh), as a scene's {"type": "mesh", "file": ...} reads them. The input
// is the file's text.
//
// An accepted mesh is prepared (normals, pseudonormals, hierarchy) and must answer distance
// queries: signed_distance() through the hierarchy at a few points agrees with the brute-force
// search over every triangle, as the collision code relies on.
#include <cmath>
#include <cstdio>

#include "fuzz_target.h"
#include "model/collider.h"
#include "scene/colliders_json.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace clothsim;
  fuzz::accept_input_error([&] {
    const auto mesh = scene_json::parse_obj_mesh(fuzz::as_text(data, size), "fuzz.obj", 1.0, Vec3{}, "fuzz.json",
                                                 "colliders[0].file");
    FUZZ_CHECK(!mesh->triangle.empty());
    Collider collider;
    collider.shape = ColliderShape::mesh;
    collider.mesh = mesh;
    for (const Vec3& x : {Vec3{0.0, 0.0, 0.0}, Vec3{0.5, 1.0, -0.25}, mesh->vertex.front() + Vec3{0.1, 0.2, 0.3}}) {
      const SurfaceDistance fast = signed_distance(collider, x, 0.0);
      const SurfaceDistance slow = mesh_distance_brute_force(*mesh, x);
      // The sign may differ where two triangles are equally near; the distance may not.
      const bool agree =
          std::isnan(fast.distance) ? std::isnan(slow.distance) : std::abs(fast.distance) == std::abs(slow.distance);
      if (!agree) {
        std::fprintf(stderr, "at (%.17g, %.17g, %.17g): hierarchy %.17g, every triangle %.17g\n", x.x, x.y, x.z,
                     fast.distance, slow.distance);
      }
      FUZZ_CHECK(agree);
    }
  });
  return 0;
}

// Triangles the renderer builds on the CPU: the unit sphere of the anchor markers, and the
// colliders at their current positions (spheres and capsules tessellated, boxes and meshes with
// flat faces, planes as a large square around the sheet). Plain float arrays, ready for a vertex
// buffer (gl_objects.h); nothing here needs OpenGL.
#pragma once

#include <cstdint>
#include <vector>

#include "core/vec3.h"
#include "model/collider.h"

namespace clothsim::render {

// v / |v|, or `fallback` when v is (nearly) zero or not finite.
Vec3 unit_or(const Vec3& v, const Vec3& fallback);

// A UV sphere of unit radius: positions (= normals) and triangle indices, counter-clockwise seen
// from outside.
void make_sphere(int slices, int stacks, std::vector<float>& vertices, std::vector<std::uint32_t>& indices);

// Appends the triangles of `collider` translated by `shift`: position and normal per vertex (6
// floats), three vertices per triangle, counter-clockwise seen from outside. Planes become a
// square of half-width `plane_extent` centred on the point of the plane nearest `focus` (the
// sheet's centre).
void append_collider(const Collider& collider, const Vec3& shift, const Vec3& focus, double plane_extent,
                     std::vector<float>& out);

// An upward horizontal plane: the floor, drawn instead of the ground grid.
bool is_floor(const Collider& collider);

}  // namespace clothsim::render

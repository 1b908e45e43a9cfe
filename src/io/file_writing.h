// What the file writers of io/ share: the error they throw, and the mesh of the sheet that the
// mesh writers (io/obj.h, io/gltf.h) write.
#pragma once

#include <cstring>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>

#include "core/vec3.h"
#include "model/cloth_model.h"
#include "model/sheet_mesh.h"

namespace clothsim {

// "path: what: reason" with the system's reason for `error_number` (an errno), or "path: what"
// when it is 0.
inline std::runtime_error io_error(const std::string& path, const std::string& what, int error_number) {
  std::string text = path + ": " + what;
  if (error_number != 0) text += std::string(": ") + std::strerror(error_number);
  return std::runtime_error(text);
}

// The particle-mode mesh (model/sheet_mesh.h) of the sheet at `position`, which must have
// particle_count() entries: otherwise throws io_error naming `path` and `writer`.
inline SheetMesh sheet_mesh_to_write(const std::string& path, std::string_view writer, const ClothModel& model,
                                     std::span<const Vec3> position) {
  const std::size_t n = model.particle_count();
  if (position.size() != n) {
    throw io_error(path,
                   std::string(writer) + ": " + std::to_string(position.size()) + " positions for a model of " +
                       std::to_string(n) + " particles",
                   0);
  }
  SheetMesh mesh;
  build_sheet_mesh(model, position, SheetMeshMode::particles, mesh);
  return mesh;
}

}  // namespace clothsim

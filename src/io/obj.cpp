// The OBJ writer; the conventions are in obj.h, the mesh in model/sheet_mesh.h.
//
// The file is written straight to `path` through stdio with fprintf: OBJ is text, one short line
// per element, and a 1000 x 1000 sheet (5M lines) takes about a second. Errors are collected
// with ferror/fclose at the end rather than checked per line (stdio's error flag is sticky); the
// message quotes errno as left by the failing call, which is the reason in practice (ENOSPC).
#include "io/obj.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <vector>

#include "core/assert.h"
#include "io/file_writing.h"

namespace clothsim {
namespace {

struct FileCloser {
  void operator()(std::FILE* file) const { std::fclose(file); }
};

// Writes `text` as OBJ comment lines, one per line of text.
void write_comment(std::FILE* file, std::string_view text) {
  while (true) {
    const std::size_t end = text.find('\n');
    const std::string_view line = text.substr(0, end);
    std::fprintf(file, "# %.*s\n", static_cast<int>(line.size()), line.data());
    if (end == std::string_view::npos) break;
    text.remove_prefix(end + 1);
  }
}

}  // namespace

void write_obj(const std::string& path, const ClothModel& model, std::span<const Vec3> position,
               std::string_view comment) {
  write_obj_mesh(path, model, sheet_mesh_to_write(path, "write_obj", model, position), comment);
}

void write_obj_mesh(const std::string& path, const ClothModel& model, const SheetMesh& mesh, std::string_view comment) {
  const std::size_t n = model.particle_count();
  std::unique_ptr<std::FILE, FileCloser> file(std::fopen(path.c_str(), "w"));
  if (file == nullptr) throw io_error(path, "cannot create file", errno);
  std::FILE* out = file.get();
  errno = 0;

  std::fprintf(out, "# clothsim sheet: %d x %d particles (rows x cols), spacing %.9g m, positions in m\n", model.rows,
               model.cols, model.spacing);
  if (mesh.vertex_count() > n) {
    std::fprintf(out, "# torn along %zu broken connectors: %zu vertices, the first %zu are the particles\n",
                 model.broken_connector_count, mesh.vertex_count(), n);
  }
  if (!comment.empty()) write_comment(out, comment);
  std::fprintf(out, "o clothsim_sheet\n");
  for (const Vec3& p : mesh.vertex_position) std::fprintf(out, "v %.9g %.9g %.9g\n", p.x, p.y, p.z);
  // Texture coordinates span [0, 1] across the lattice; a 1-wide axis maps to 0. A split vertex
  // takes the lattice coordinates of where it sits at rest.
  const double u_step = model.cols > 1 ? 1.0 / (model.cols - 1) : 0.0;
  const double v_step = model.rows > 1 ? 1.0 / (model.rows - 1) : 0.0;
  for (const SheetVertexSource& source : mesh.vertex_source) {
    const auto [row, col] = sheet_vertex_lattice_coordinate(model, source);
    std::fprintf(out, "vt %.9g %.9g\n", col * u_step, row * v_step);
  }

  if (model.rows == 1 || model.cols == 1) {
    // A 1-wide lattice is a chain of particles: a polyline through them in index order, broken
    // where a connector is.
    std::vector<std::uint8_t> joined(n, 0);  // joined[p]: particles p and p+1 share an intact connector
    for (std::size_t e = 0; e < model.connector_count(); ++e) {
      const auto [a, b] = model.connector_particles[e];
      if (model.connector_live[e] != 0 && std::max(a, b) == std::min(a, b) + 1) joined[std::min(a, b)] = 1;
    }
    std::fprintf(out, "l 1/1");
    for (std::size_t p = 2; p <= n; ++p) {
      if (joined[p - 2] == 0) std::fprintf(out, "\nl");
      std::fprintf(out, " %zu/%zu", p, p);
    }
    std::fprintf(out, "\n");
  } else {
    for (const Vec3& normal : mesh.vertex_normal) {
      std::fprintf(out, "vn %.9g %.9g %.9g\n", normal.x, normal.y, normal.z);
    }
    std::fprintf(out, "s 1\n");
    for (const auto& triangle : mesh.triangle_vertices) {
      // OBJ indices are 1-based; v, vt and vn share the vertex's index.
      const std::uint32_t a = triangle[0] + 1;
      const std::uint32_t b = triangle[1] + 1;
      const std::uint32_t c = triangle[2] + 1;
      std::fprintf(out, "f %u/%u/%u %u/%u/%u %u/%u/%u\n", a, a, a, b, b, b, c, c, c);
    }
  }

  const bool write_failed = std::ferror(out) != 0;
  const int write_error = errno;
  errno = 0;
  const bool closed = std::fclose(file.release()) == 0;
  if (write_failed) throw io_error(path, "write failed", write_error);
  if (!closed) throw io_error(path, "close failed", errno);
}

}  // namespace clothsim

// The run report: a run folder's data gathered into the page web/report.html (run_report.h).
#include "run/run_report.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <limits>
#include <span>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/error.h"
#include "core/input_file.h"
#include "io/npy.h"
#include "model/cloth_model.h"
#include "model/model_edits.h"
#include "model/sheet_mesh.h"
#include "run/report_assets.h"
#include "run/run_folders.h"
#include "run/run_scene.h"
#include "run/run_writer.h"
#include "scene/scene.h"
#include "scene/scene_model.h"

namespace clothsim {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

std::string base64(std::span<const std::uint8_t> bytes) {
  static constexpr char kDigits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string text;
  text.reserve((bytes.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const std::uint32_t b0 = bytes[i];
    const std::uint32_t b1 = i + 1 < bytes.size() ? bytes[i + 1] : 0u;
    const std::uint32_t b2 = i + 2 < bytes.size() ? bytes[i + 2] : 0u;
    const std::uint32_t triple = (b0 << 16) | (b1 << 8) | b2;
    text += kDigits[(triple >> 18) & 63];
    text += kDigits[(triple >> 12) & 63];
    text += i + 1 < bytes.size() ? kDigits[(triple >> 6) & 63] : '=';
    text += i + 2 < bytes.size() ? kDigits[triple & 63] : '=';
  }
  return text;
}

template <typename T>
std::string base64_of(const std::vector<T>& values) {
  return base64({reinterpret_cast<const std::uint8_t*>(values.data()), values.size() * sizeof(T)});
}

json vec3_json(const Vec3& v) { return json::array({v.x, v.y, v.z}); }

// A file of the run folder, which must be there.
fs::path run_file(const fs::path& folder, std::string_view name) {
  fs::path path = folder / name;
  std::error_code error;
  if (!fs::is_regular_file(path, error)) {
    throw InputError(folder.string(), std::string(name),
                     "is missing: not a run folder, or a run that wrote no frame (clothsim report reads the "
                     "folder a run wrote)");
  }
  return path;
}

// The frames the player holds: all of them where their vertex data fits kReportVertexBytes,
// otherwise every stride-th and the last.
std::vector<std::size_t> player_frames(std::size_t frames, std::size_t particles, std::size_t& stride) {
  const std::size_t per_frame = std::max<std::size_t>(1, particles * 3 * sizeof(float));
  const std::size_t fit = std::max<std::size_t>(2, kReportVertexBytes / per_frame);
  stride = frames <= fit ? 1 : (frames - 1 + fit - 2) / (fit - 1);
  std::vector<std::size_t> chosen;
  for (std::size_t k = 0; k < frames; k += stride) chosen.push_back(k);
  if (!chosen.empty() && chosen.back() != frames - 1) chosen.push_back(frames - 1);
  return chosen;
}

std::string_view shape_name(ColliderShape shape) {
  switch (shape) {
    case ColliderShape::plane: return "plane";
    case ColliderShape::sphere: return "sphere";
    case ColliderShape::box: return "box";
    case ColliderShape::capsule: return "capsule";
    case ColliderShape::mesh: return "mesh";
  }
  return "plane";
}

// A collider's shape at rest and its offset at each of the player's frames.
json collider_json(const Collider& collider, const std::vector<double>& times) {
  json out{{"shape", shape_name(collider.shape)}};
  switch (collider.shape) {
    case ColliderShape::plane:
      out["point"] = vec3_json(collider.point);
      out["normal"] = vec3_json(collider.normal);
      break;
    case ColliderShape::sphere:
      out["center"] = vec3_json(collider.center);
      out["radius"] = collider.radius;
      break;
    case ColliderShape::box:
      out["center"] = vec3_json(collider.center);
      out["half_extents"] = vec3_json(collider.half_extents);
      break;
    case ColliderShape::capsule:
      out["a"] = vec3_json(collider.a);
      out["b"] = vec3_json(collider.b);
      out["radius"] = collider.radius;
      break;
    case ColliderShape::mesh: {
      std::vector<float> vertices;
      for (const Vec3& v : collider.mesh->vertex) push_vec3(vertices, v);
      std::vector<std::uint32_t> triangles;
      for (const auto& t : collider.mesh->triangle) triangles.insert(triangles.end(), t.begin(), t.end());
      out["vertices"] = base64_of(vertices);
      out["triangles"] = base64_of(triangles);
      break;
    }
  }
  std::vector<float> offsets;
  for (double t : times) push_vec3(offsets, collider_offset(collider, t));
  out["offsets"] = base64_of(offsets);
  return out;
}

// A float64 array of one value per connector of the run folder.
std::vector<double> connector_array(const fs::path& folder, std::string_view name, const ClothModel& model) {
  const std::string path = run_file(folder, name).string();
  NpyArray array;
  try {
    array = read_npy(path);
  } catch (const std::runtime_error& error) {
    throw InputError(path, "", error.what());
  }
  if (array.data.size() != model.connector_count()) {
    throw InputError(path, "",
                     "holds " + std::to_string(array.data.size()) + " values for the " +
                         std::to_string(model.connector_count()) + " connectors of the folder's scene.json");
  }
  return std::move(array.data);
}

// The player's frames: the mesh of each (build_sheet_mesh in particle mode, as final.obj and the
// run's pictures), its topology replayed from the connectors' break times.
json frames_json(const fs::path& folder, const SceneSpec& spec, const json& summary) {
  ClothModel model = build_model(spec);
  const std::size_t particles = model.particle_count();
  const std::size_t frames = summary.value("frames", std::size_t{0});
  if (frames == 0) throw InputError(folder.string(), "summary.json", "records no frame: the run wrote none");
  // Each connector's break time and, for the split vertices of a torn mesh (half a rest length
  // along a broken connector), its rest length as it broke, which is its rest length at the end.
  const std::vector<double> break_time = connector_array(folder, RunWriter::kBreakTimeFile, model);
  const std::vector<double> rest_length = connector_array(folder, RunWriter::kRestLengthFile, model);

  std::size_t stride = 1;
  const std::vector<std::size_t> chosen = player_frames(frames, particles, stride);
  const std::string positions_file = run_file(folder, RunWriter::kPositionsFile).string();
  const int fps = spec.output.fps;
  std::vector<Vec3> position(particles);
  std::vector<float> vertices;
  std::vector<std::uint64_t> offsets;
  std::vector<std::uint64_t> counts;
  std::vector<double> times;
  json epochs = json::array();
  SheetMesh mesh;
  std::uint64_t topology = std::numeric_limits<std::uint64_t>::max();
  for (std::size_t i = 0; i < chosen.size(); ++i) {
    const double t = frame_time(chosen[i], fps);
    for (std::uint32_t c = 0; c < break_time.size(); ++c) {
      if (break_time[c] <= t && model.connector_live[c] != 0) {
        break_connector(model, c, break_time[c]);
        set_connector_rest_length(model, c, rest_length[c]);
      }
    }
    read_npy_frame(positions_file, chosen[i], position);
    build_sheet_mesh(model, position, SheetMeshMode::particles, mesh);
    if (mesh.topology_version != topology) {
      topology = mesh.topology_version;
      std::vector<std::uint32_t> triangles;
      for (const auto& triangle : mesh.triangle_vertices)
        triangles.insert(triangles.end(), triangle.begin(), triangle.end());
      epochs.push_back({{"first", i}, {"triangles", base64_of(triangles)}});
    }
    offsets.push_back(vertices.size());
    counts.push_back(mesh.vertex_count());
    for (const Vec3& v : mesh.vertex_position) push_vec3(vertices, v);
    times.push_back(t);
  }

  json anchors = json::array();
  for (const Anchor& anchor : model.anchors) {
    anchors.push_back({{"particle", anchor.particle},
                       {"release_time", std::isfinite(anchor.release_time) ? json(anchor.release_time) : json()}});
  }
  json colliders = json::array();
  for (const Collider& collider : model.colliders) colliders.push_back(collider_json(collider, times));

  return {
      {"total_frames", frames},    {"frames", chosen},        {"frame_stride", stride},           {"times", times},
      {"vertex_offsets", offsets}, {"vertex_counts", counts}, {"positions", base64_of(vertices)}, {"epochs", epochs},
      {"anchors", anchors},        {"colliders", colliders},  {"spacing", model.spacing}};
}

// JSON inside a <script> element: "</" would end the element early.
std::string script_safe(std::string text) {
  for (std::size_t at = text.find("</"); at != std::string::npos; at = text.find("</", at + 3)) {
    text.replace(at, 2, "<\\/");
  }
  return text;
}

std::string escape_html(std::string_view text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string data_url(std::string_view script) {
  return "data:text/javascript;base64," + base64({reinterpret_cast<const std::uint8_t*>(script.data()), script.size()});
}

std::string_view asset(std::string_view name) {
  const std::string_view text = report_asset(name);
  if (text.empty()) {
    throw OutputError(
        "this clothsim was built without the run report: three.js was not found at build time "
        "(web/node_modules; scripts/install-deps.sh installs it with npm ci), so '" +
        std::string(name) + "' is missing");
  }
  return text;
}

// The page: web/report.html with its four marked lines replaced.
std::string page(const std::string& title, const std::string& data_json) {
  std::string html(asset("report.html"));
  const json import_map = {{"imports",
                            {{"three", data_url(asset("three.module.min.js"))},
                             {"three/addons/controls/OrbitControls.js", data_url(asset("OrbitControls.js"))}}}};
  const std::array<std::pair<std::string_view, std::string>, 4> parts = {{
      {"<!--CLOTHSIM_TITLE-->", "<title>" + escape_html(title) + "</title>"},
      {"<!--CLOTHSIM_IMPORTMAP-->", "<script type=\"importmap\">" + import_map.dump() + "</script>"},
      {"<!--CLOTHSIM_DATA-->",
       "<script type=\"application/json\" id=\"run-data\">" + script_safe(data_json) + "</script>"},
      {"<!--CLOTHSIM_APP-->",
       "<script type=\"module\">\n" + script_safe(std::string(asset("report.js"))) + "</script>"},
  }};
  for (const auto& [mark, text] : parts) {
    const std::size_t at = html.find(mark);
    if (at == std::string::npos) throw OutputError("web/report.html lacks " + std::string(mark));
    html.replace(at, mark.size(), text);
  }
  return html;
}

}  // namespace

bool report_available() { return !report_asset("three.module.min.js").empty(); }

fs::path write_run_report(const fs::path& folder) {
  const SceneSpec spec = load_scene_file(run_file(folder, RunWriter::kSceneFile).string());
  const std::string summary_path = run_file(folder, RunWriter::kSummaryFile).string();
  const json summary = json::parse(read_input_file(summary_path), nullptr, false);
  if (!summary.is_object()) throw InputError(summary_path, "", "is not a JSON object");
  json data = frames_json(folder, spec, summary);
  data["name"] = spec.name;
  data["description"] = spec.description;
  data["fps"] = spec.output.fps;
  data["summary"] = summary;
  data["energy_csv"] = read_input_file(run_file(folder, RunWriter::kEnergyFile).string());
  fs::path path = folder / kReportFile;
  write_text_atomically(path, page("clothsim: " + spec.name, data.dump()));
  return path;
}

fs::path write_sweep_report(const fs::path& out) {
  const std::string index = read_input_file(run_file(out, "index.csv").string());
  std::istringstream lines(index);
  std::string line;
  std::string table = "<table>\n";
  bool header = true;
  while (std::getline(lines, line)) {
    // index.csv quotes no cell that holds a comma but a parameter's value; split at top level.
    std::vector<std::string> cells;
    std::string cell;
    bool quoted = false;
    for (char c : line) {
      if (c == '"')
        quoted = !quoted;
      else if (c == ',' && !quoted)
        cells.push_back(std::exchange(cell, {}));
      else
        cell += c;
    }
    cells.push_back(cell);
    table += "<tr>";
    for (std::size_t i = 0; i < cells.size(); ++i) {
      const std::string tag = header ? "th" : "td";
      std::string content = escape_html(cells[i]);
      std::error_code error;
      if (!header && i == 1 && fs::exists(out / cells[i] / kReportFile, error)) {
        content = "<a href=\"" + escape_html(cells[i]) + "/" + std::string(kReportFile) + "\">" + content + "</a>";
      }
      table += "<" + tag + ">" + content + "</" + tag + ">";
    }
    table += "</tr>\n";
    header = false;
  }
  table += "</table>\n";
  const std::string html =
      "<!doctype html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>clothsim sweep: " +
      escape_html(out.filename().string()) +
      "</title>\n<style>body{font:14px/1.4 system-ui,sans-serif;margin:20px;color:#1d2733}"
      "table{border-collapse:collapse;font-size:13px}th,td{border:1px solid #d6dde4;padding:3px 6px;"
      "text-align:right}th{background:#eef2f5}</style>\n</head>\n<body>\n<h1>clothsim sweep: " +
      escape_html(out.filename().string()) +
      "</h1>\n<p>One row per run, from index.csv; a run's folder links to its report where the run wrote one "
      "(clothsim run --report).</p>\n" +
      table + "</body>\n</html>\n";
  fs::path path = out / kReportFile;
  write_text_atomically(path, html);
  return path;
}

}  // namespace clothsim

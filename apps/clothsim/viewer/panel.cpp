#include "viewer/panel.h"

#include <imgui.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <span>
#include <vector>

#include "core/error.h"
#include "scene/parameters.h"
#include "scene/scene.h"
#include "scene/validate_scene.h"

namespace clothsim::viewer {
namespace {

constexpr float kPlotHeight = 130.0f;
const ImVec4 kWarningColour{0.85f, 0.05f, 0.05f, 1.0f};
constexpr ImU32 kKineticColour = IM_COL32(220, 90, 20, 255);
constexpr ImU32 kPotentialColour = IM_COL32(30, 110, 200, 255);
constexpr ImU32 kTotalColour = IM_COL32(20, 20, 20, 255);

void tooltip(std::string_view description, std::string_view unit) {
  if (!ImGui::IsItemHovered()) return;
  std::string text(description);
  if (!unit.empty()) text += " (" + std::string(unit) + ")";
  ImGui::SetTooltip("%s", text.c_str());
}

// A slider for the registry parameter `key` on `edited`; true when the value changed.
bool parameter_slider(const char* label, std::string_view key, SceneSpec& edited) {
  const ScalarParameter* parameter = find_scalar_parameter(key);
  if (parameter == nullptr) return false;
  double value = parameter->get(edited);
  const ValueRange& range = parameter->range;
  double low = range.min;
  double high = range.max;
  // Log scale where the range spans decades; an open lower end of 0 starts a little above it.
  const bool logarithmic = high > 1000.0 * std::max(low, 1e-300) || (low == 0.0 && high > 10.0);
  if (logarithmic && low == 0.0 && !range.min_inclusive) low = high * 1e-15;
  ImGuiSliderFlags flags = ImGuiSliderFlags_AlwaysClamp;
  if (logarithmic) flags |= ImGuiSliderFlags_Logarithmic;
  ImGui::PushID(label);
  const bool changed = ImGui::SliderScalar(label, ImGuiDataType_Double, &value, &low, &high, "%.4g", flags);
  tooltip(parameter->description, parameter->unit);
  ImGui::PopID();
  if (changed && range.contains(value)) {
    parameter->set(edited, value);
    return true;
  }
  return false;
}

bool gravity_editor(SceneSpec& edited) {
  const VectorParameter* gravity = find_vector_parameter("environment.gravity");
  std::array<double, 3> value = {edited.environment.gravity.x, edited.environment.gravity.y,
                                 edited.environment.gravity.z};
  const double low = gravity->component_range.min;
  const double high = gravity->component_range.max;
  const bool changed = ImGui::DragScalarN("gravity", ImGuiDataType_Double, value.data(), 3, 0.05f, &low, &high, "%.3g",
                                          ImGuiSliderFlags_AlwaysClamp);
  tooltip(gravity->description, gravity->unit);
  if (changed) gravity->set(edited, {value[0], value[1], value[2]});
  return changed;
}

bool integrator_editor(SceneSpec& edited) {
  bool changed = false;
  // A scene that sets no step (0) shows the step it runs with; the simulation's settings stay the
  // same (scene_integrator() resolves both alike).
  if (edited.integrator.time_step == 0.0) edited.integrator.time_step = scene_integrator(edited).time_step;
  constexpr std::array<IntegratorKind, 3> kKinds = {IntegratorKind::rkf45, IntegratorKind::rk4,
                                                    IntegratorKind::symplectic_euler};
  const std::string current(to_string(edited.integrator.kind));
  if (ImGui::BeginCombo("method", current.c_str())) {
    for (IntegratorKind kind : kKinds) {
      const std::string name(to_string(kind));
      if (ImGui::Selectable(name.c_str(), kind == edited.integrator.kind) && kind != edited.integrator.kind) {
        edited.integrator.kind = kind;
        changed = true;
      }
    }
    ImGui::EndCombo();
  }
  if (edited.integrator.kind == IntegratorKind::rkf45) {
    changed |= parameter_slider("rtol", "integrator.relative_tolerance", edited);
    changed |= parameter_slider("atol", "integrator.absolute_tolerance", edited);
    changed |= parameter_slider("first step", "integrator.time_step", edited);
    changed |= parameter_slider("min step", "integrator.min_step", edited);
    changed |= parameter_slider("max step", "integrator.max_step", edited);
    changed |= parameter_slider("safety", "integrator.safety", edited);
    changed |= parameter_slider("max growth", "integrator.max_growth", edited);
    changed |= parameter_slider("max shrink", "integrator.max_shrink", edited);
  } else {
    changed |= parameter_slider("time step", "integrator.time_step", edited);
  }
  return changed;
}

// Kinetic, potential and total energy over the history, as three lines on one scale.
void energy_plot(const std::deque<EnergySample>& history) {
  const float width = ImGui::GetContentRegionAvail().x;
  const ImVec2 origin = ImGui::GetCursorScreenPos();
  ImGui::InvisibleButton("energy plot", ImVec2(width, kPlotHeight));
  ImDrawList* draw = ImGui::GetWindowDrawList();
  const ImVec2 corner(origin.x + width, origin.y + kPlotHeight);
  draw->AddRectFilled(origin, corner, IM_COL32(255, 255, 255, 255));
  draw->AddRect(origin, corner, IM_COL32(160, 160, 160, 255));
  if (history.size() < 2) {
    ImGui::TextDisabled("(the plot starts when time moves)");
    return;
  }
  double low = history.front().total;
  double high = low;
  for (const EnergySample& sample : history) {
    low = std::min({low, sample.kinetic, sample.potential, sample.total});
    high = std::max({high, sample.kinetic, sample.potential, sample.total});
  }
  if (high - low < 1e-12) {
    low -= 0.5;
    high += 0.5;
  }
  const double start = history.front().time;
  const double span = std::max(history.back().time - start, 1e-9);
  const float margin = 4.0f;
  const auto point = [&](double time, double energy) {
    return ImVec2(origin.x + margin + static_cast<float>((time - start) / span) * (width - 2 * margin),
                  corner.y - margin - static_cast<float>((energy - low) / (high - low)) * (kPlotHeight - 2 * margin));
  };
  if (low < 0.0 && high > 0.0) {
    draw->AddLine(point(start, 0.0), point(start + span, 0.0), IM_COL32(200, 200, 200, 255));
  }
  std::vector<ImVec2> line(history.size());
  const auto polyline = [&](double EnergySample::*member, ImU32 colour) {
    std::size_t i = 0;
    for (const EnergySample& sample : history) line[i++] = point(sample.time, sample.*member);
    draw->AddPolyline(line.data(), static_cast<int>(line.size()), colour, 0, 1.5f);
  };
  polyline(&EnergySample::potential, kPotentialColour);
  polyline(&EnergySample::kinetic, kKineticColour);
  polyline(&EnergySample::total, kTotalColour);
  char label[64];
  std::snprintf(label, sizeof label, "%.4g J", high);
  draw->AddText(ImVec2(origin.x + margin, origin.y + 1), IM_COL32(90, 90, 90, 255), label);
  std::snprintf(label, sizeof label, "%.4g J", low);
  draw->AddText(ImVec2(origin.x + margin, corner.y - ImGui::GetTextLineHeight() - 1), IM_COL32(90, 90, 90, 255), label);
  std::snprintf(label, sizeof label, "last %.3g s", span);
  const float label_width = ImGui::CalcTextSize(label).x;
  draw->AddText(ImVec2(corner.x - margin - label_width, origin.y + 1), IM_COL32(90, 90, 90, 255), label);

  const EnergySample& last = history.back();
  ImGui::TextColored(ImGui::ColorConvertU32ToFloat4(kKineticColour), "kinetic %.4g J", last.kinetic);
  ImGui::SameLine();
  ImGui::TextColored(ImGui::ColorConvertU32ToFloat4(kPotentialColour), "potential %.4g J", last.potential);
  ImGui::TextColored(ImGui::ColorConvertU32ToFloat4(kTotalColour), "total %.6g J", last.total);
}

void run_section(PanelState& state, Session& session, const FramePacer& pacer) {
  const Simulation& simulation = session.simulation();
  if (ImGui::Button(session.playing() ? "Pause" : "Play")) session.set_playing(!session.playing());
  ImGui::SameLine();
  if (ImGui::Button("Step")) {
    session.set_playing(false);
    state.step_requested = true;
  }
  ImGui::SameLine();
  if (ImGui::Button("Reset")) state.reset_requested = true;
  ImGui::SameLine();
  if (ImGui::Button("Screenshot")) state.screenshot_requested = true;
  ImGui::SameLine();
  if (ImGui::Button("Frame")) state.frame_requested = true;

  const IntegratorStats stats = simulation.integrator_stats();
  ImGui::Text("t = %.3f s   %.0f fps   step %.3g s", session.time(), pacer.frames_per_second(), stats.last_step);
  if (simulation.failure()) {
    ImGui::PushTextWrapPos(0.0f);
    ImGui::TextColored(kWarningColour, "simulation failed %s (Reset to start again)",
                       simulation.failure()->message.c_str());
    ImGui::PopTextWrapPos();
  } else if (!session.playing()) {
    ImGui::TextDisabled("paused");
  } else if (pacer.behind()) {
    ImGui::TextColored(kWarningColour, "simulation behind real time: %.2fx", pacer.real_time_ratio());
  } else {
    ImGui::Text("real time: %.2fx", pacer.real_time_ratio());
  }
  if (!state.status.empty()) ImGui::TextDisabled("%s", state.status.c_str());
}

void parameters_section(PanelState& state, Session& session) {
  SceneSpec edited = session.scene();
  bool changed = false;
  if (ImGui::CollapsingHeader("Springs", ImGuiTreeNodeFlags_DefaultOpen)) {
    ImGui::TextDisabled("connector (stretch)");
    changed |= parameter_slider("k connector", "springs.connector.stiffness", edited);
    changed |= parameter_slider("c connector", "springs.connector.damping", edited);
    ImGui::TextDisabled("adjacent radial (90 degrees)");
    changed |= parameter_slider("k adjacent", "springs.adjacent.stiffness", edited);
    changed |= parameter_slider("c adjacent", "springs.adjacent.damping", edited);
    ImGui::TextDisabled("opposite radial (180 degrees)");
    changed |= parameter_slider("k opposite", "springs.opposite.stiffness", edited);
    changed |= parameter_slider("c opposite", "springs.opposite.damping", edited);
  }
  if (ImGui::CollapsingHeader("Environment and mass", ImGuiTreeNodeFlags_DefaultOpen)) {
    changed |= gravity_editor(edited);
    changed |= parameter_slider("air drag", "environment.air_drag", edited);
    changed |= parameter_slider("particle mass", "lattice.particle_mass", edited);
  }
  if (ImGui::CollapsingHeader("Integrator")) changed |= integrator_editor(edited);
  if (changed) {
    try {
      validate_scene(edited, "panel");
      session.set_live_parameters(edited);
      state.edit_error.clear();
    } catch (const InputError& error) {
      state.edit_error = error.what();
    }
  }
  if (!state.edit_error.empty()) {
    ImGui::PushTextWrapPos(0.0f);
    ImGui::TextColored(kWarningColour, "%s", state.edit_error.c_str());
    ImGui::PopTextWrapPos();
  }
}

// A limit that may be +infinity ("never"): a checkbox that turns it on (at `on_value`) or off,
// and, when on, a slider over [low, high] (log-scaled when `logarithmic`), shown in `scale` units
// (180/pi for degrees). True when the value changed.
bool limit_editor(const char* label, double& value, double on_value, double low, double high, bool logarithmic,
                  double scale, const char* tooltip_text) {
  bool enabled = value != SpringLimits::kNever;
  bool changed = false;
  ImGui::PushID(label);
  if (ImGui::Checkbox("##on", &enabled)) {
    value = enabled ? on_value : SpringLimits::kNever;
    changed = true;
  }
  tooltip(tooltip_text, "");
  ImGui::SameLine();
  if (enabled) {
    double shown = value * scale;
    const double shown_low = low * scale;
    const double shown_high = high * scale;
    ImGuiSliderFlags flags = ImGuiSliderFlags_AlwaysClamp;
    if (logarithmic) flags |= ImGuiSliderFlags_Logarithmic;
    if (ImGui::SliderScalar(label, ImGuiDataType_Double, &shown, &shown_low, &shown_high, "%.4g", flags)) {
      value = shown / scale;
      changed = true;
    }
  } else {
    ImGui::TextDisabled("%s: never", label);
  }
  tooltip(tooltip_text, "");
  ImGui::PopID();
  return changed;
}

// Where the sheet tears, stretches for good and creases (model/spring_limits.h), edited live, and
// what it has done so far.
void tearing_section(PanelState& state, Session& session) {
  if (!ImGui::CollapsingHeader("Tearing and plasticity")) return;
  SpringLimits limits = session.spring_limits();
  constexpr double kDegree = 180.0 / std::numbers::pi;
  bool changed = false;
  changed |= limit_editor("break strain", limits.break_strain, 0.3, 1e-3, 10.0, true, 1.0,
                          "a connector breaks when l / L0 - 1 exceeds this (dimensionless)");
  // A clamped slider for a dimensionless companion of a limit.
  const auto slider = [&changed](const char* label, double& value, double low, double high, const char* help) {
    if (ImGui::SliderScalar(label, ImGuiDataType_Double, &value, &low, &high, "%.3g", ImGuiSliderFlags_AlwaysClamp)) {
      changed = true;
    }
    tooltip(help, "");
  };
  if (limits.break_strain != SpringLimits::kNever) {
    slider("variation", limits.break_strain_variation, 0.0, 0.99,
           "relative spread of the break strain over the springs, in [0, 1)");
  }
  changed |= limit_editor("yield strain", limits.yield_strain, 0.05, 1e-4, 10.0, true, 1.0,
                          "a connector stretched beyond this keeps the excess (dimensionless)");
  if (limits.yield_strain != SpringLimits::kNever) {
    slider("hardening", limits.hardening, 0.0, 10.0,
           "growth of the yield strain per unit of plastic strain (dimensionless)");
  }
  changed |= limit_editor("shear yield", limits.adjacent_yield_angle, 20.0 / kDegree, 0.0, std::numbers::pi, false,
                          kDegree, "in-plane shear beyond this angle stays (adjacent radial springs, degrees)");
  changed |= limit_editor("fold yield", limits.opposite_yield_angle, 20.0 / kDegree, 0.0, std::numbers::pi, false,
                          kDegree, "folds beyond this angle stay (opposite radial springs, degrees)");
  if (changed) {
    state.limits_error = check_spring_limits(limits);
    if (state.limits_error.empty()) session.set_spring_limits(limits);
  }
  if (!state.limits_error.empty()) ImGui::TextColored(kWarningColour, "%s", state.limits_error.c_str());
  const ModelChanges sheet = session.simulation().model_changes();
  const EnergyBalance balance = session.simulation().energy_balance();
  ImGui::TextDisabled("broken: %zu connectors, %zu radial springs", sheet.broken_connectors, sheet.broken_radials);
  ImGui::TextDisabled("max plastic strain %.3g, max rest angle change %.3g deg", sheet.max_plastic_strain,
                      sheet.max_rest_angle_change * kDegree);
  ImGui::TextDisabled("plastic work %.4g J, fracture work %.4g J", balance.plastic_work, balance.fracture_work);
  ImGui::TextDisabled("ctrl+drag across the sheet to cut it");
}

// A fifth of the sheet's largest extent now: a sphere that visibly pushes it, whatever its size.
double default_sphere_radius(std::span<const Vec3> positions) {
  Vec3 low = positions.empty() ? Vec3{} : positions.front();
  Vec3 high = low;
  for (const Vec3& p : positions) {
    low = {std::min(low.x, p.x), std::min(low.y, p.y), std::min(low.z, p.z)};
    high = {std::max(high.x, p.x), std::max(high.y, p.y), std::max(high.z, p.z)};
  }
  const double extent = std::max({high.x - low.x, high.y - low.y, high.z - low.z});
  return std::isfinite(extent) && extent > 0.0 ? 0.2 * extent : 0.1;
}

// Self-collision on and off, spheres added and how many particles touch an obstacle.
void collisions_section(PanelState& state, Session& session) {
  const Simulation& simulation = session.simulation();
  if (!ImGui::CollapsingHeader("Collisions", ImGuiTreeNodeFlags_DefaultOpen)) return;
  bool self = session.self_collision();
  if (ImGui::Checkbox("self-collision (C)", &self)) {
    try {
      session.set_self_collision(self);
      state.status = self ? "self-collision on" : "self-collision off";
    } catch (const InputError& error) {
      state.status = error.what();
    }
  }
  tooltip("the sheet keeps collision.thickness from itself; switched between two steps", "");
  if (state.sphere_radius <= 0.0) state.sphere_radius = default_sphere_radius(simulation.state().position);
  if (ImGui::Button("Add sphere")) state.add_sphere_requested = true;
  tooltip("a sphere beside the sheet, in view; drag it into the sheet with the mouse", "");
  ImGui::SameLine();
  const double low = 1e-3;
  const double high = 10.0;
  ImGui::SliderScalar("radius", ImGuiDataType_Double, &state.sphere_radius, &low, &high, "%.3g m",
                      ImGuiSliderFlags_AlwaysClamp | ImGuiSliderFlags_Logarithmic);
  ImGui::TextDisabled("%zu obstacles, %zu spheres; %zu particles in contact", simulation.model().colliders.size(),
                      session.spheres().size(), simulation.contact_statistics().contacts);
  ImGui::TextDisabled("left drag on a sphere (alt: behind the sheet) moves it");
}

void display_section(PanelState& state) {
  if (!ImGui::CollapsingHeader("Display")) return;
  render::RenderOptions& options = state.render;
  ImGui::Checkbox("sheet", &options.show_sheet);
  ImGui::SameLine();
  ImGui::Checkbox("anchors", &options.show_anchors);
  ImGui::SameLine();
  ImGui::Checkbox("ground", &options.show_ground);
  ImGui::SameLine();
  ImGui::Checkbox("colliders", &options.show_colliders);
  ImGui::Checkbox("wireframe", &options.show_wireframe);
  ImGui::SameLine();
  ImGui::Checkbox("connectors", &options.show_connectors);
  ImGui::SameLine();
  ImGui::Checkbox("radials", &options.show_radials);
  bool cell_centres = options.mesh_mode == SheetMeshMode::cell_centres;
  if (ImGui::Checkbox("paper's mesh (vertices at cell centres)", &cell_centres)) {
    options.mesh_mode = cell_centres ? SheetMeshMode::cell_centres : SheetMeshMode::particles;
  }
}

void help_section() {
  if (!ImGui::CollapsingHeader("Controls")) return;
  ImGui::TextUnformatted(
      "left drag: orbit; on a particle: drag it\n"
      "right drag / middle drag: pan   wheel: zoom\n"
      "right click or shift+click a particle: pin/unpin\n"
      "ctrl+left drag: cut the sheet along the drag\n"
      "left drag on a sphere (alt: behind the sheet): move it\n"
      "space: play/pause   N: step one frame   R: reset\n"
      "S: screenshot   F: frame the sheet   H: hide panel\n"
      "C: self-collision on/off\n"
      "arrows: orbit (shift: pan)   +/-: zoom   Q/Esc: quit");
}

}  // namespace

void draw_panel(PanelState& state, Session& session, const FramePacer& pacer) {
  if (!state.visible) return;
  const ImGuiIO& io = ImGui::GetIO();
  const auto width = static_cast<float>(kPanelWidth);
  ImGui::SetNextWindowPos(ImVec2(io.DisplaySize.x - width - 8.0f, 8.0f), ImGuiCond_Always);
  ImGui::SetNextWindowSizeConstraints(ImVec2(width, 0.0f), ImVec2(width, io.DisplaySize.y - 16.0f));
  ImGui::SetNextWindowBgAlpha(0.92f);
  const std::string title = "clothsim: " + session.scene().name;
  if (ImGui::Begin(title.c_str(), nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
    ImGui::PushItemWidth(-110.0f);
    run_section(state, session, pacer);
    if (ImGui::CollapsingHeader("Energy", ImGuiTreeNodeFlags_DefaultOpen)) {
      energy_plot(session.energy_history());
      const EnergyBalance balance = session.simulation().energy_balance();
      ImGui::TextDisabled("balance error %.3g J (edits %.4g J)", balance.error(), balance.edit_work);
    }
    parameters_section(state, session);
    tearing_section(state, session);
    collisions_section(state, session);
    display_section(state);
    help_section();
    ImGui::PopItemWidth();
  }
  ImGui::End();
}

}  // namespace clothsim::viewer

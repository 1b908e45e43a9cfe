// The viewer's Dear ImGui panel: run controls and readouts, the live parameters, the energy plot
// and the display options.
//
// Every parameter widget is made from the parameter registry (scene/parameters.h): its label is
// the registry key, its range the registry's range (log-scaled where the range spans more than
// three decades), its tooltip the registry's description and unit. Edits go to a copy of the
// session's scene, are checked with validate_scene(), and reach the simulation through
// Session::set_live_parameters(), between steps. An edit that breaks a cross-field rule is shown
// in red and not applied. The spring limits (tearing, yielding, creasing) are not scene keys yet:
// their section edits Session::spring_limits() directly, checked by check_spring_limits(). The
// collisions section switches self-collision (Session::set_self_collision) and asks the window to
// add a sphere, which it places in view.
#pragma once

#include <string>

#include "render/render_options.h"
#include "viewer/frame_pacer.h"
#include "viewer/session.h"

namespace clothsim::viewer {

// Width of the panel, pixels (the camera frames the sheet beside it).
inline constexpr double kPanelWidth = 360.0;

struct PanelState {
  bool visible = true;
  // Requests the window carries out at the right moment of its frame.
  bool step_requested = false;
  bool reset_requested = false;
  bool screenshot_requested = false;
  bool frame_requested = false;
  bool add_sphere_requested = false;
  double sphere_radius = 0.0;    // m, of the next sphere added; 0: not chosen yet (the panel picks one)
  render::RenderOptions render;  // display options edited in the panel
  std::string status;            // the last action's message ("saved shot.png")
  std::string edit_error;        // why the last parameter edit was refused
  std::string limits_error;      // why the last edit of the spring limits was refused
};

// Draws the panel inside an ImGui frame (between ImGui::NewFrame and ImGui::Render).
void draw_panel(PanelState& state, Session& session, const FramePacer& pacer);

}  // namespace clothsim::viewer

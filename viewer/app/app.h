// viewer/app/app.h: the viewer's state between frames (session, camera, what the panels set) and
// its per-frame steps; main.cpp runs them in a window or once into a screenshot.
#pragma once

#include <string>
#include <vector>

#include "viewer/app/renderer.h"
#include "viewer/core/camera.h"
#include "viewer/core/session.h"

namespace mimetic::viewer {

struct FrameStats {
  double evaluate_ms = 0.0, overlay_ms = 0.0, upload_ms = 0.0, draw_ms = 0.0;
};

struct App {
  explicit App(unsigned threads) : session(threads) {}

  Session session;
  OrbitCamera camera;
  Renderer renderer;
  // Shading (docs/model.md §12).
  float melanin = 0.f, hemoglobin = 0.f;
  float light_azimuth = -35.f, light_elevation = 30.f;  // degrees, camera space
  bool wireframe = false, show_surface = true, show_gizmos = true;
  Overlay overlay = Overlay::kNone;
  // Muscles panel.
  int selected_muscle = -1;
  bool link_sides = true;
  // Clip playback.
  bool playing = false, loop = true;
  float clip_time = 0.f, speed = 1.f, fps = 30.f;
  bool pose_from_clip = false;  // the clip drives the pose (play or scrub)
  // Hover.
  bool hover_valid = false;
  uint32_t hover_vertex = 0;
  float hover_value = 0.f;
  std::vector<uint32_t> hover_muscles;
  // Text fields of the Files panel.
  char rig_field[512] = "", clip_field[512] = "", library_field[512] = "";

  bool dirty = true;  // the pose or the overlay changed: evaluate again
  FrameStats stats;
  std::vector<uint32_t> point_vertex;  // point -> one of its vertices (gizmo points)

  // After a successful rig load: mesh into the renderer, camera framed, fields filled.
  void OnRigLoaded();
  // Evaluate (when dirty), upload, gizmos; timings into stats.
  void Update();
  void UpdateGizmos();
  DrawParams MakeDrawParams(float aspect) const;
  // The pick under pixel (x, y) of a width x height view.
  void Hover(float x, float y, float width, float height);
};

// The ImGui panels (viewer/app/panels.cpp): Files, Scene, Muscles, Expressions, Clip,
// Messages, Stats, the legend and the hover tooltip.
void DrawPanels(App* app, float width, float height);

}  // namespace mimetic::viewer

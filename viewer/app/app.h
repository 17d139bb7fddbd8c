// viewer/app/app.h: the viewer's state between frames (session, camera, what the panels set) and
// its per-frame steps; main.cpp runs them in a window or once into a screenshot.
#pragma once

#include <string>
#include <vector>

#include "viewer/app/renderer.h"
#include "viewer/core/camera.h"
#include "viewer/core/map_job.h"
#include "viewer/core/session.h"
#include "viewer/core/uv_scale.h"

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
  bool hover_seen = false;  // hover_vertex is a vertex the cursor was over (kept off the mesh)
  float hover_value = 0.f;
  std::vector<uint32_t> hover_muscles;
  // Text fields of the Files panel.
  char rig_field[512] = "", clip_field[512] = "", library_field[512] = "";
  char fine_field[512] = "";

  // Authoring (docs/viewer.md "Authoring").
  int active_channel = -1;        // the timeline row Ins adds a key to (a spec channel)
  bool dragging_keys = false;     // the selected keys follow the mouse; one command on release
  float drag_dt = 0.f, drag_dv = 0.f;
  int new_channel = 0;            // the "add channel" combo: muscles, jaw, expressions
  int interp_choice = 1;          // step, linear, cubic
  char expr_name[128] = "";       // the Expressions panel's name field
  int expr_target = -1;           // the expression a confirmation popup is about
  char rename_field[128] = "";
  std::vector<float> pose_before;  // the pose when a slider drag started
  float jaw_before = 0.f;
  double autosave_seconds = 60.0, last_autosave = 0.0;
  bool offer_recovery = false;    // the start found .autosave files (a popup asks)
  bool close_requested = false;   // the window's close button with unsaved changes
  bool quit_requested = false;    // Ctrl+Q: closes the window as its close button does
  bool close_confirmed = false;
  int pending_load = 0;           // 1 rig, 2 library, 3 clip: asked to discard unsaved edits

  // Rig editors (viewer/app/panels_rig.cpp; docs/viewer.md "Editing the rig").
  bool show_muscle_editor = false, show_uv_curves = false, show_directions = false;
  int selected_curve = -1;              // the UV view's curve (spec index)
  int drag_curve = -1, drag_point = -1;  // a control point being dragged
  float uv_center[2] = {0.5f, 0.5f}, uv_zoom = 0.f;  // uv_zoom 0: frame the curves first
  unsigned uv_texture = 0;              // the UV triangles drawn once (GL texture name)
  bool uv_texture_stale = true;         // a new rig's mesh: draw them again
  UvScaleGrid uv_scale;                 // mesh units per uv (the curves' widths), with it
  int direction_field = 0;
  int new_direction_vertex = 0;
  float new_direction[4] = {1.f, 0.f, 0.f, 0.5f};  // x y z, magnitude
  int map_size = 1024;
  uint64_t gizmo_key = ~0ull;           // the rig version and toggles the gizmos were made for
  MapJob maps;
  std::string last_rig_error;           // the last refused rig edit (said once in Messages)

  // A slider drag of the pose: remember the pose it started from; at the end, one SetPose
  // command from there to the pose the drag left.
  void BeginPoseEdit();
  void EndPoseEdit();
  // After any edit (or undo): evaluate again, and the pose from the clip when it drives it.
  void OnEdited();
  void Undo();
  void Redo();
  bool unsaved() const {
    return session.clip_dirty() || session.library_dirty() || session.rig_dirty();
  }

  // --ui-trace FILE (docs/viewer.md "Tested by driving the UI"): the screen rectangles of the
  // widgets the UI tests drive, collected during a frame (TraceItem) and written after it
  // (WriteUiTrace), with numbers the tests need (the UV editor's pixels per uv).
  struct TraceRect {
    std::string name;
    float x0, y0, x1, y1;
  };
  std::string ui_trace_path;
  std::vector<TraceRect> ui_trace;
  std::vector<std::pair<std::string, double>> ui_trace_values;
  uint64_t ui_frame = 0;

  bool dirty = true;  // the pose or the overlay changed: evaluate again
  FrameStats stats;
  std::vector<uint32_t> point_vertex;  // point -> one of its vertices (gizmo points)

  // After a successful rig load: mesh into the renderer, camera framed, fields filled.
  void OnRigLoaded();
  // Loads the fine-scale maps of DIR into the session and the renderer (false: messages).
  bool LoadFineMaps(const std::string& dir);
  // After a rebuild of the edited rig was swapped in (Session::PollRigRebuild): the mesh into
  // the renderer again (refinement may have changed it); camera, selection and pose stay.
  void OnRigRebuilt();
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
// The rig editors (viewer/app/panels_rig.cpp): Muscle editor, UV curve wrinkles, Directions;
// RigFilesRow is the Files panel's rig line (Save rig, the rebuild's progress bar, the editors'
// toggles). ReleaseRigPanels frees their GL texture.
void DrawRigPanels(App* app, float width, float height);
void RigFilesRow(App* app);
void ReleaseRigPanels(App* app);
// Ctrl+Z / Ctrl+Shift+Z / Ctrl+Y, Ctrl+S, Ctrl+C / Ctrl+V, Ins, Del (not while a text field
// has the keyboard).
void HandleEditShortcuts(App* app);
// --ui-trace: TraceItem records the last ImGui item's rectangle as `name` (nothing without
// --ui-trace); TraceValue a number; WriteUiTrace writes the frame's records to the trace file
// (atomically) as {"frame": N, "window": [x, y], "items": {name: [x0, y0, x1, y1]},
// "values": {name: v}} and starts the next frame's.
void TraceItem(App* app, const std::string& name);
void TraceValue(App* app, const std::string& name, double value);
void WriteUiTrace(App* app, int window_x, int window_y);

}  // namespace mimetic::viewer

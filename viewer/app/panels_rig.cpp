// viewer/app/panels_rig.cpp: the rig editors (docs/viewer.md "Editing the rig"): the Muscle
// editor (the selected muscle's parameters), the UV curve wrinkles view (control points dragged
// in texture space, depth, width and profile) and the fine-scale Directions (vectors at
// vertices, Regenerate maps off the UI thread). Every change is one command of
// viewer/core/rig_edit.h; a drag is merged into one undo step (Session::EditMerged). The rig is
// rebuilt off the UI thread; the Files panel's rig line shows its progress bar while it runs.
#include <GL/glcorearb.h>
#include <GLFW/glfw3.h>
#include <imgui.h>
#include <imgui_internal.h>  // SetItemUsingMouseWheel (1.86 keeps it internal)

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>

#include "core/file_util.h"
#include "viewer/app/app.h"
#include "viewer/core/rig_edit.h"

namespace mimetic::viewer {
namespace {

constexpr float kDegrees = float(180.0 / std::numbers::pi);

std::string Num(float f) {
  char buf[64];
  const auto res = std::to_chars(buf, buf + sizeof buf, f);
  return std::string(buf, res.ptr);
}

// A refused edit: its message once in Messages (a drag past a bound would repeat it).
void Refused(App* app, const std::string& error) {
  if (error.empty() || error == app->last_rig_error) return;
  app->last_rig_error = error;
  Diagnostics d;
  d.Error("", error);
  app->session.AddMessages(d, "");
}

// Issues `command` (built from the spec; nullptr: refused with `error`), merged with the
// previous one of the same drag `tag`.
void Issue(App* app, CommandPtr command, const std::string& error, const std::string& tag) {
  if (!command) return Refused(app, error);
  std::string why;
  if (app->session.EditMerged(std::move(command), tag, &why)) {
    app->last_rig_error.clear();
  } else {
    app->last_rig_error = why;  // Session::Edit put it in Messages already
  }
}

// After the widget that issued the edits: its release ends the merge.
void EndOfWidget(App* app) {
  if (ImGui::IsItemDeactivated()) app->session.EndMerge();
}


// The rebuild's state: a progress bar with BuildRig's stage and the time it has run.
void RebuildStatus(App* app) {
  Session& s = app->session;
  if (s.rig_rebuilding()) {
    char text[96];
    std::snprintf(text, sizeof text, "rebuilding the rig: %s, %.1f s (showing the last one)",
                  s.rig_rebuild_stage(), s.rig_rebuild_ms() / 1000.0);
    ImGui::ProgressBar(s.rig_rebuild_progress(), ImVec2(-1, 0), text);
  } else if (s.rig_stale()) {
    ImGui::TextColored(ImVec4(1.f, 0.45f, 0.4f, 1.f), "the edited rig did not build (Messages); showing the last good one");
  }
}

// --- Muscle editor. ------------------------------------------------------------------------
void MuscleValue(App* app, uint32_t m, const char* label, const std::string& param, float value,
                 float speed, float lo, float hi, const char* format = "%.3f") {
  float v = value;
  if (ImGui::DragFloat(label, &v, speed, lo, hi, format) && v != value) {
    std::string error;
    CommandPtr c = MakeMuscleValueEdit(*app->session.rig_spec(), m, param, {v}, &error);
    Issue(app, std::move(c), error, "muscle:" + std::to_string(m) + ":" + param);
  }
  EndOfWidget(app);
}

void MusclePoint(App* app, uint32_t m, const char* label, const std::string& param, int line,
                 float3 p, float speed) {
  float v[3] = {p.x, p.y, p.z};
  if (ImGui::DragFloat3(label, v, speed, 0.f, 0.f, "%.2f") &&
      (v[0] != p.x || v[1] != p.y || v[2] != p.z)) {
    std::vector<float> values;
    if (line >= 0) values.push_back(float(line));
    values.insert(values.end(), v, v + 3);
    std::string error;
    CommandPtr c = MakeMuscleValueEdit(*app->session.rig_spec(), m, param, values, &error);
    Issue(app, std::move(c), error,
          "muscle:" + std::to_string(m) + ":" + param + std::to_string(line));
  }
  EndOfWidget(app);
}

void MuscleChoice(App* app, const MuscleSpec& muscle, const char* label, const std::string& param,
                  const char* const* names, int count, int current) {
  int choice = current;
  if (ImGui::Combo(label, &choice, names, count) && choice != current) {
    std::string error;
    CommandPtr c = MakeMuscleEdit(*app->session.rig_spec(), muscle.name, param, {names[choice]}, &error);
    Issue(app, std::move(c), error, "");
  }
}

// Opens one of the rig editors' windows (opaque; `pos` and `size` on first use) and returns
// the rig's spec, or nullptr with the window closed again when it is folded or there is nothing
// to edit (no rig, or a compiled .mrig, which keeps no `what`: the message says so).
const RigSpec* BeginRigEditor(App* app, const char* title, bool* open, ImVec2 pos, ImVec2 size,
                              const char* what) {
  ImGui::SetNextWindowPos(pos, ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(size, ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowBgAlpha(1.f);
  if (!ImGui::Begin(title, open)) {
    ImGui::End();
    return nullptr;
  }
  const RigSpec* spec = app->session.rig_spec();
  if (!spec) {
    if (app->session.has_rig())
      ImGui::TextWrapped("a compiled .mrig keeps no %s: open its .rig.json", what);
    else
      ImGui::TextWrapped("no rig loaded");
    ImGui::End();
  }
  return spec;
}

void MuscleEditorPanel(App* app, float width, float height) {
  // Over the Clip panel's place (bottom centre).
  const RigSpec* spec = BeginRigEditor(
      app, "Muscle editor", &app->show_muscle_editor, ImVec2(345, std::max(10.f, height - 310)),
      ImVec2(std::max(300.f, std::min(600.f, width - 690.f)), 300), "muscle parameters");
  if (!spec) return;
  Session& s = app->session;
  if (app->selected_muscle < 0 || size_t(app->selected_muscle) >= spec->muscles.size()) {
    ImGui::TextWrapped("select a muscle (the round button before its slider in Muscles)");
    return ImGui::End();
  }
  const uint32_t m = uint32_t(app->selected_muscle);
  const MuscleSpec& muscle = spec->muscles[m];
  const bool linear = muscle.type == MuscleType::kLinear;
  ImGui::Text("%s  (%s, muscles[%u])", muscle.name.c_str(), linear ? "linear" : "sheet", m);
  RebuildStatus(app);
  // Steps of the drags: a thousandth of the mesh's size for lengths and points.
  const float3 lo = s.bounds_lo(), hi = s.bounds_hi();
  const float size = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z, 1e-3f});
  const float step = size * 1e-3f;
  ImGui::PushItemWidth(-150);
  MuscleValue(app, m, "strength", "strength", muscle.strength, step, 0.f, 10.f * size);
  static const char* const kFalloffs[] = {"waters", "smooth"};
  static const char* const kMotions[] = {"chord", "tangent"};
  MuscleChoice(app, muscle, "fall-off", "falloff", kFalloffs, 2, muscle.falloff == MuscleFalloff::kSmooth);
  MuscleChoice(app, muscle, "motion", "motion", kMotions, 2, muscle.motion == MuscleMotion::kTangent);
  if (muscle.motion == MuscleMotion::kTangent)  // the ball its normals are averaged over
    MuscleValue(app, m, "normal radius", "tangent_radius", muscle.tangent_radius, step, 0.f, size);
  if (linear) {
    MusclePoint(app, m, "attachment", "attachment", -1, muscle.linear.attachment, step);
    MusclePoint(app, m, "insertion", "insertion", -1, muscle.linear.insertion, step);
    MuscleValue(app, m, "zone angle (deg)", "zone_angle", muscle.linear.zone_angle * kDegrees,
                0.1f, 0.1f, 179.9f, "%.2f");
    // The drags stop at the rule between them (Rs < Rf), so a drag does not run into it.
    MuscleValue(app, m, "fall-off start Rs", "falloff_start", muscle.linear.falloff_start, step,
                step, std::max(step, muscle.linear.falloff_end - step));
    MuscleValue(app, m, "fall-off end Rf", "falloff_end", muscle.linear.falloff_end, step,
                muscle.linear.falloff_start + step, 10.f * size);
  } else {
    MusclePoint(app, m, "attachment 0", "attachment", 0, muscle.sheet.attachment[0], step);
    MusclePoint(app, m, "attachment 1", "attachment", 1, muscle.sheet.attachment[1], step);
    MusclePoint(app, m, "insertion 0", "insertion", 0, muscle.sheet.insertion[0], step);
    MusclePoint(app, m, "insertion 1", "insertion", 1, muscle.sheet.insertion[1], step);
    MuscleValue(app, m, "length Ls", "length", muscle.sheet.length, step,
                muscle.sheet.falloff_start + step, 10.f * size);
    MuscleValue(app, m, "width Ws", "width", muscle.sheet.width, step, step, 10.f * size);
    MuscleValue(app, m, "fall-off start Rs", "falloff_start", muscle.sheet.falloff_start, step,
                step, std::max(step, muscle.sheet.length - step));
  }
  ImGui::Separator();
  bool has = m < spec->muscle_wrinkles.size() && spec->muscle_wrinkles[m].has_value();
  const MuscleWrinkleSpec wrinkles = has ? *spec->muscle_wrinkles[m] : MuscleWrinkleSpec{};
  const MuscleWrinkleSpec* w = has ? &wrinkles : nullptr;
  if (ImGui::Checkbox("wrinkle block", &has)) {
    std::string error;
    Issue(app, MakeMuscleEdit(*spec, muscle.name, "wrinkles", {has ? "on" : "none"}, &error), error, "");
  }
  if (w) {
    MuscleValue(app, m, "lambda_w", "wrinkles.lambda_w", w->lambda_w, 0.002f, 0.f, 0.999f);
    int count = w->count;
    if (ImGui::DragInt("count", &count, 0.05f, 1, 50) && count != w->count) {
      std::string error;
      Issue(app, MakeMuscleValueEdit(*spec, m, "wrinkles.count", {float(count)}, &error), error,
            "muscle:" + std::to_string(m) + ":count");
    }
    EndOfWidget(app);
    MuscleValue(app, m, "depth k0", "wrinkles.depth", w->depth, step * 0.1f, 0.f, size);
    MuscleValue(app, m, "shape alpha", "wrinkles.shape", w->shape, 0.005f, -10.f, 10.f);
    if (linear)
      MuscleValue(app, m, "phi_c (deg)", "wrinkles.phi_c", w->phi_c * kDegrees, 0.1f, 0.f, 179.f, "%.2f");
    else
      MuscleValue(app, m, "h_c", "wrinkles.h_c", w->h_c, step, 0.f, 10.f * size);
    MuscleValue(app, m, "gate (activation)", "wrinkles.gate", w->gate, 0.005f, 0.f, 1.f);
    if (ImGui::IsItemHovered())
      ImGui::SetTooltip("the muscle's activation at which its wrinkles reach full depth; 0: no "
                        "gate, they follow the skin's compression alone (docs/model.md §6)");
  }
  ImGui::PopItemWidth();
  ImGui::End();
}

// --- UV curve wrinkles. --------------------------------------------------------------------
constexpr int kUvTextureSize = 2048;

// The mesh's uv triangles drawn once into a texture (white lines, alpha = coverage): drawing
// the 67k triangles of a head through the draw list every frame would cost more than a frame.
void MakeUvTexture(App* app) {
  app->uv_texture_stale = false;
  const MeshData& mesh = app->session.loaded().mesh;
  app->uv_scale = MakeUvScaleGrid(mesh);
  if (mesh.uvs.empty()) return;
  const int n = kUvTextureSize;
  std::vector<uint8_t> alpha(size_t(n) * n, 0);
  const auto plot = [&](int x, int y) {
    if (x < 0 || y < 0 || x >= n || y >= n) return;
    uint8_t& a = alpha[size_t(y) * n + size_t(x)];
    a = uint8_t(std::min(255, a + 160));
  };
  const auto line = [&](float2 a, float2 b) {
    const float ax = a.x * n, ay = a.y * n, bx = b.x * n, by = b.y * n;
    const int steps = int(std::ceil(std::max(std::fabs(bx - ax), std::fabs(by - ay)))) + 1;
    if (steps > 4 * n) return;  // a uv far outside [0, 1]
    for (int i = 0; i <= steps; ++i) {
      const float t = float(i) / float(steps);
      plot(int(ax + (bx - ax) * t), int(ay + (by - ay) * t));
    }
  };
  for (size_t t = 0; t + 2 < mesh.indices.size(); t += 3) {
    const float2 a = mesh.uvs[mesh.indices[t]], b = mesh.uvs[mesh.indices[t + 1]],
                 c = mesh.uvs[mesh.indices[t + 2]];
    line(a, b);
    line(b, c);
    line(c, a);
  }
  std::vector<uint8_t> rgba(alpha.size() * 4);
  for (size_t i = 0; i < alpha.size(); ++i) {
    rgba[4 * i] = rgba[4 * i + 1] = rgba[4 * i + 2] = 255;
    rgba[4 * i + 3] = alpha[i];
  }
  GLuint tex = app->uv_texture;
  if (!tex) glGenTextures(1, &tex);
  glBindTexture(GL_TEXTURE_2D, tex);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
  glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
  glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
  glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, n, n, 0, GL_RGBA, GL_UNSIGNED_BYTE, rgba.data());
  glGenerateMipmap(GL_TEXTURE_2D);
  glBindTexture(GL_TEXTURE_2D, 0);
  app->uv_texture = tex;
}

float2 Bezier(const float2 c[4], float t) {
  const float u = 1.f - t;
  const float b0 = u * u * u, b1 = 3.f * u * u * t, b2 = 3.f * u * t * t, b3 = t * t * t;
  return {b0 * c[0].x + b1 * c[1].x + b2 * c[2].x + b3 * c[3].x,
          b0 * c[0].y + b1 * c[1].y + b2 * c[2].y + b3 * c[3].y};
}

// Frames the curves' control points (or the whole [0, 1] square without curves).
void FrameCurves(App* app, const RigSpec& spec, float aspect) {
  float lo[2] = {1e9f, 1e9f}, hi[2] = {-1e9f, -1e9f};
  for (const NamedCurveWrinkle& c : spec.curve_wrinkles)
    for (const float2& p : c.spec.control) {
      lo[0] = std::min(lo[0], p.x), lo[1] = std::min(lo[1], p.y);
      hi[0] = std::max(hi[0], p.x), hi[1] = std::max(hi[1], p.y);
    }
  if (spec.curve_wrinkles.empty()) lo[0] = lo[1] = 0.f, hi[0] = hi[1] = 1.f;
  app->uv_center[0] = 0.5f * (lo[0] + hi[0]);
  app->uv_center[1] = 0.5f * (lo[1] + hi[1]);
  const float extent = std::max({(hi[0] - lo[0]) / std::max(aspect, 0.1f), hi[1] - lo[1], 0.02f});
  app->uv_zoom = 1.f / (1.45f * extent);  // room for the names
}

void CurveValue(App* app, uint32_t c, const char* label, const std::string& param, float value,
                float speed, float lo, float hi) {
  float v = value;
  if (ImGui::DragFloat(label, &v, speed, lo, hi, "%.3f") && v != value) {
    const RigSpec& spec = *app->session.rig_spec();
    std::string error;
    CommandPtr cmd = MakeCurveEdit(spec, spec.curve_wrinkles[c].name, param, {Num(v)}, &error);
    Issue(app, std::move(cmd), error, "curve:" + std::to_string(c) + ":" + param);
  }
  EndOfWidget(app);
}

void CurveChoice(App* app, uint32_t c, const char* label, const std::string& param,
                 const char* const* names, int count, int current) {
  int choice = current;
  if (ImGui::Combo(label, &choice, names, count) && choice != current) {
    const RigSpec& spec = *app->session.rig_spec();
    std::string error;
    Issue(app, MakeCurveEdit(spec, spec.curve_wrinkles[c].name, param, {names[choice]}, &error),
          error, "");
  }
}

void UvCurvesPanel(App* app, float width, float height) {
  const RigSpec* spec = BeginRigEditor(
      app, "UV curve wrinkles", &app->show_uv_curves, ImVec2(345, 10),
      ImVec2(std::max(300.f, std::min(600.f, width - 690.f)), height - 20), "curve wrinkles to edit");
  if (!spec) return;
  Session& s = app->session;
  if (app->uv_texture_stale) MakeUvTexture(app);
  if (app->selected_curve < 0 && !spec->curve_wrinkles.empty()) app->selected_curve = 0;
  // The rebuild's status takes one row whether it shows or not: the canvas below (and with it
  // the pixels-to-uv mapping) must not move when a drag's first edit starts a rebuild, or the
  // dragged point would leave the pointer (ViewerUiDrive.DraggingAUvControlPoint...).
  const float status_y = ImGui::GetCursorPosY();
  RebuildStatus(app);
  ImGui::SetCursorPosY(status_y + ImGui::GetFrameHeightWithSpacing());
  const ImVec2 avail = ImGui::GetContentRegionAvail();
  const bool has_selection = app->selected_curve >= 0 && size_t(app->selected_curve) < spec->curve_wrinkles.size();
  const ImVec2 canvas(std::max(100.f, avail.x), std::max(100.f, avail.y - (has_selection ? 205.f : 60.f)));
  if (app->uv_zoom <= 0.f) FrameCurves(app, *spec, canvas.x / canvas.y);
  const ImVec2 origin = ImGui::GetCursorScreenPos();
  const float scale = app->uv_zoom * canvas.y;  // pixels per uv unit
  const auto to_screen = [&](float2 uv) {
    return ImVec2(origin.x + 0.5f * canvas.x + (uv.x - app->uv_center[0]) * scale,
                  origin.y + 0.5f * canvas.y + (uv.y - app->uv_center[1]) * scale);
  };
  const auto to_uv = [&](ImVec2 p) {
    return float2{app->uv_center[0] + (p.x - origin.x - 0.5f * canvas.x) / scale,
                  app->uv_center[1] + (p.y - origin.y - 0.5f * canvas.y) / scale};
  };
  ImGui::InvisibleButton("uv", canvas, ImGuiButtonFlags_MouseButtonLeft | ImGuiButtonFlags_MouseButtonRight);
  ImGui::SetItemUsingMouseWheel();  // the wheel zooms the view, it does not scroll the window
  TraceItem(app, "uv/canvas");
  TraceValue(app, "uv/pixels-per-uv", scale);
  const bool hovered = ImGui::IsItemHovered();
  ImDrawList* dl = ImGui::GetWindowDrawList();
  const ImVec2 end(origin.x + canvas.x, origin.y + canvas.y);
  dl->AddRectFilled(origin, end, IM_COL32(18, 20, 26, 255));
  dl->PushClipRect(origin, end, true);
  if (app->uv_texture)
    dl->AddImage(reinterpret_cast<ImTextureID>(intptr_t(app->uv_texture)), to_screen({0.f, 0.f}),
                 to_screen({1.f, 1.f}), ImVec2(0, 0), ImVec2(1, 1), IM_COL32(150, 160, 180, 110));
  dl->AddRect(to_screen({0.f, 0.f}), to_screen({1.f, 1.f}), IM_COL32(90, 90, 110, 255));
  // The curves: the Bezier, its control polygon, the control points.
  const ImVec2 mouse = ImGui::GetIO().MousePos;
  int near_curve = -1, near_point = -1;
  float near_d = 8.f;
  for (size_t c = 0; c < spec->curve_wrinkles.size(); ++c) {
    const CurveWrinkleSpec& cw = spec->curve_wrinkles[c].spec;
    const bool sel = int(c) == app->selected_curve;
    ImVec2 pts[49], left[49], right[49];
    bool band = app->uv_scale.whole > 0.f && cw.width > 0.f;
    for (int i = 0; i <= 48; ++i) {
      const float t = float(i) / 48.f;
      const float2 p = Bezier(cw.control, t);
      pts[i] = to_screen(p);
      // The furrow's width: mesh units -> uv by the local texture-to-mesh scale (the one the
      // curve-wrinkle builder uses, viewer/core/uv_scale.h), across the curve's uv tangent.
      const float2 d0 = Bezier(cw.control, std::max(0.f, t - 1e-3f)), d1 = Bezier(cw.control, std::min(1.f, t + 1e-3f));
      const float2 d{d1.x - d0.x, d1.y - d0.y};
      const float len = std::hypot(d.x, d.y), scale = app->uv_scale.At(p);
      if (!(len > 0.f) || !(scale > 0.f)) {
        band = false;
        continue;
      }
      const float half = 0.5f * cw.width / scale;
      const float2 n{-d.y / len * half, d.x / len * half};
      left[i] = to_screen({p.x + n.x, p.y + n.y});
      right[i] = to_screen({p.x - n.x, p.y - n.y});
    }
    if (band) {
      const ImU32 fill = sel ? IM_COL32(255, 220, 80, 60) : IM_COL32(240, 130, 70, 40);
      for (int i = 0; i < 48; ++i) {
        dl->AddQuadFilled(left[i], left[i + 1], right[i + 1], right[i], fill);
      }
      const ImU32 edge = sel ? IM_COL32(255, 220, 80, 170) : IM_COL32(240, 130, 70, 120);
      dl->AddPolyline(left, 49, edge, ImDrawFlags_None, 1.f);
      dl->AddPolyline(right, 49, edge, ImDrawFlags_None, 1.f);
    }
    dl->AddPolyline(pts, 49, sel ? IM_COL32(255, 220, 80, 255) : IM_COL32(240, 130, 70, 230),
                    ImDrawFlags_None, sel ? 2.f : 1.5f);
    for (int k = 0; k < 3; ++k)
      dl->AddLine(to_screen(cw.control[k]), to_screen(cw.control[k + 1]), IM_COL32(150, 150, 170, sel ? 200 : 90));
    for (int k = 0; k < 4; ++k) {
      const ImVec2 p = to_screen(cw.control[k]);
      if (!app->ui_trace_path.empty())
        app->ui_trace.push_back({"uv/point/" + spec->curve_wrinkles[c].name + "/" + std::to_string(k), p.x, p.y, p.x, p.y});
      const bool end_point = k == 0 || k == 3;
      dl->AddCircleFilled(p, sel ? 5.f : 3.5f, end_point ? IM_COL32(255, 255, 255, 230) : IM_COL32(120, 200, 255, 230));
      const float d = std::hypot(p.x - mouse.x, p.y - mouse.y);
      if (d < near_d || (d == near_d && sel)) near_d = d, near_curve = int(c), near_point = k;
    }
    if (sel || spec->curve_wrinkles.size() <= 16)
      dl->AddText(ImVec2(pts[48].x + 4, pts[48].y - 6), IM_COL32(220, 220, 230, sel ? 255 : 150),
                  spec->curve_wrinkles[c].name.c_str());
  }
  dl->PopClipRect();
  // Mouse: left drags a control point (one command per drag), a click on a curve selects it;
  // right drag pans, the wheel zooms about the pointer.
  ImGuiIO& io = ImGui::GetIO();
  if (hovered && ImGui::IsMouseClicked(ImGuiMouseButton_Left)) {
    app->drag_curve = near_curve;
    app->drag_point = near_point;
    if (near_curve >= 0) {
      app->selected_curve = near_curve;
    } else {
      float best = 6.f;
      for (size_t c = 0; c < spec->curve_wrinkles.size(); ++c)
        for (int i = 0; i <= 48; ++i) {
          const ImVec2 p = to_screen(Bezier(spec->curve_wrinkles[c].spec.control, float(i) / 48.f));
          const float d = std::hypot(p.x - mouse.x, p.y - mouse.y);
          if (d < best) best = d, app->selected_curve = int(c);
        }
    }
  }
  if (app->drag_curve >= 0 && ImGui::IsMouseDown(ImGuiMouseButton_Left) &&
      (io.MouseDelta.x != 0.f || io.MouseDelta.y != 0.f)) {
    std::string error;
    CommandPtr c = MakeCurvePointEdit(*spec, uint32_t(app->drag_curve), app->drag_point, to_uv(mouse), &error);
    Issue(app, std::move(c), error, "uv:" + std::to_string(app->drag_curve) + ":" + std::to_string(app->drag_point));
  }
  if (app->drag_curve >= 0 && !ImGui::IsMouseDown(ImGuiMouseButton_Left)) {
    app->drag_curve = app->drag_point = -1;
    s.EndMerge();
  }
  if (hovered && ImGui::IsMouseDragging(ImGuiMouseButton_Right)) {
    app->uv_center[0] -= io.MouseDelta.x / scale;
    app->uv_center[1] -= io.MouseDelta.y / scale;
  }
  if (hovered && io.MouseWheel != 0.f) {
    const float2 at = to_uv(mouse);
    const float f = std::pow(1.2f, io.MouseWheel);
    app->uv_zoom = std::clamp(app->uv_zoom * f, 0.2f, 2000.f);
    app->uv_center[0] = at.x - (at.x - app->uv_center[0]) / f;
    app->uv_center[1] = at.y - (at.y - app->uv_center[1]) / f;
  }
  if (hovered) {
    const float2 at = to_uv(mouse);
    ImGui::Text("u %.4f  v %.4f", at.x, at.y);
  } else {
    ImGui::TextDisabled("drag a control point; right drag pans, the wheel zooms");
  }
  ImGui::SameLine();
  if (ImGui::SmallButton("Frame curves")) FrameCurves(app, *spec, canvas.x / canvas.y);
  if (!has_selection) {
    ImGui::TextDisabled("click a curve to edit its depth, width and profile");
    return ImGui::End();
  }
  const uint32_t c = uint32_t(app->selected_curve);
  const CurveWrinkleSpec& cw = spec->curve_wrinkles[c].spec;
  ImGui::Text("%s  (curve_wrinkles[%u])", spec->curve_wrinkles[c].name.c_str(), c);
  ImGui::PushItemWidth(-170);
  const float3 lo = s.bounds_lo(), hi = s.bounds_hi();
  const float size = std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z, 1e-3f});
  CurveValue(app, c, "depth (mesh units)", "depth", cw.depth, size * 1e-4f, size * 1e-5f, size);
  CurveValue(app, c, "width (mesh units)", "width", cw.width, size * 1e-4f, size * 1e-4f, size);
  static const char* const kProfiles[] = {"bando", "yang_zhang", "yang_zhang_exact"};
  static const char* const kModulations[] = {"directional", "area"};
  CurveChoice(app, c, "profile", "profile", kProfiles, 3, int(cw.profile));
  CurveChoice(app, c, "modulation", "modulation", kModulations, 2, int(cw.modulation));
  CurveValue(app, c, "rest amplitude", "rest_amplitude", cw.rest_amplitude, 0.002f, 0.f, 1.f);
  for (int k = 0; k < 4; ++k) {
    float v[2] = {cw.control[k].x, cw.control[k].y};
    char label[32];
    std::snprintf(label, sizeof label, "control %d (u, v)", k);
    if (ImGui::DragFloat2(label, v, 0.0005f, 0.f, 0.f, "%.4f") &&
        (v[0] != cw.control[k].x || v[1] != cw.control[k].y)) {
      std::string error;
      Issue(app, MakeCurvePointEdit(*spec, c, k, {v[0], v[1]}, &error), error,
            "uv:" + std::to_string(c) + ":" + std::to_string(k));
    }
    EndOfWidget(app);
  }
  ImGui::PopItemWidth();
  ImGui::End();
}

// --- Fine-scale direction vectors. ---------------------------------------------------------
void DirectionEdit(App* app, const std::string& field, uint32_t vertex, std::vector<std::string> args,
                   const std::string& tag) {
  Session& s = app->session;
  std::string error;
  CommandPtr c = MakeDirectionEdit(*s.rig_spec(), s.mesh_vertex_count(), field, vertex, args, &error);
  Issue(app, std::move(c), error, tag);
}

void DirectionsPanel(App* app, float width, float height) {
  const RigSpec* spec = BeginRigEditor(
      app, "Fine-scale directions", &app->show_directions,
      ImVec2(std::max(10.f, width - 540), std::max(10.f, height - 430)), ImVec2(530, 420),
      "direction fields");
  if (!spec) return;
  Session& s = app->session;
  if (!spec->fine_scale) {
    ImGui::TextWrapped("the rig has no fine_scale block (docs/rig-format.md)");
    return ImGui::End();
  }
  RebuildStatus(app);
  const FineScaleSpec& fs = *spec->fine_scale;
  const char* names[2] = {fs.fields[0].name.c_str(), fs.fields[1].name.c_str()};
  ImGui::Combo("field", &app->direction_field, names, 2);
  const DirectionFieldSpec& field = fs.fields[app->direction_field];
  const float max_mag = MaxMagnitude(fs.parameters);
  if (ImGui::BeginTable("vectors", 4, ImGuiTableFlags_RowBg | ImGuiTableFlags_BordersInnerV |
                                          ImGuiTableFlags_ScrollY,
                        ImVec2(0, std::max(80.f, ImGui::GetContentRegionAvail().y - 120.f)))) {
    ImGui::TableSetupColumn("vertex", ImGuiTableColumnFlags_WidthFixed, 60.f);
    ImGui::TableSetupColumn("direction (unit)");
    ImGui::TableSetupColumn("magnitude", ImGuiTableColumnFlags_WidthFixed, 90.f);
    ImGui::TableSetupColumn("", ImGuiTableColumnFlags_WidthFixed, 50.f);
    ImGui::TableHeadersRow();
    for (size_t i = 0; i < field.anchors.size(); ++i) {
      const DirectionAnchor& a = field.anchors[i];
      const float mag = Length(a.vector);
      float dir[3] = {0.f, 0.f, 0.f};
      if (mag > 0.f) dir[0] = a.vector.x / mag, dir[1] = a.vector.y / mag, dir[2] = a.vector.z / mag;
      ImGui::PushID(int(i));
      ImGui::TableNextRow();
      ImGui::TableSetColumnIndex(0);
      ImGui::Text("%u", a.vertex);
      const std::string tag = "dir:" + std::to_string(app->direction_field) + ":" + std::to_string(a.vertex);
      ImGui::TableSetColumnIndex(1);
      ImGui::SetNextItemWidth(-1);
      float d[3] = {dir[0], dir[1], dir[2]};
      if (ImGui::DragFloat3("##dir", d, 0.005f, -1.f, 1.f, "%.3f") &&
          (d[0] != dir[0] || d[1] != dir[1] || d[2] != dir[2]))
        DirectionEdit(app, field.name, a.vertex, {Num(d[0]), Num(d[1]), Num(d[2]), Num(mag)}, tag);
      EndOfWidget(app);
      ImGui::TableSetColumnIndex(2);
      ImGui::SetNextItemWidth(-1);
      float m = mag;
      if (ImGui::DragFloat("##mag", &m, 0.002f, 0.001f, max_mag, "%.3f") && m != mag)
        DirectionEdit(app, field.name, a.vertex, {Num(dir[0]), Num(dir[1]), Num(dir[2]), Num(m)}, tag);
      EndOfWidget(app);
      ImGui::TableSetColumnIndex(3);
      if (ImGui::SmallButton("delete")) DirectionEdit(app, field.name, a.vertex, {"delete"}, "");
      ImGui::PopID();
    }
    ImGui::EndTable();
  }
  // A new vector (or the one at that vertex replaced). The first output vertices of a rig are
  // the file's, in order (refinement adds after them), so a hovered vertex below the file's
  // count is a file vertex.
  if (app->hover_seen && app->hover_vertex < s.mesh_vertex_count()) {
    char label[64];
    std::snprintf(label, sizeof label, "Use the last hovered vertex (%u)", app->hover_vertex);
    if (ImGui::SmallButton(label)) app->new_direction_vertex = int(app->hover_vertex);
  }
  ImGui::SetNextItemWidth(90);
  ImGui::InputInt("##vertex", &app->new_direction_vertex);
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("a vertex of the mesh file (0 to %zu)", s.mesh_vertex_count() - 1);
  ImGui::SameLine();
  ImGui::SetNextItemWidth(180);
  ImGui::DragFloat3("##newdir", app->new_direction, 0.01f, -1.f, 1.f, "%.2f");
  ImGui::SameLine();
  ImGui::SetNextItemWidth(60);
  ImGui::DragFloat("##newmag", &app->new_direction[3], 0.005f, 0.001f, max_mag, "%.3f");
  ImGui::SameLine();
  if (ImGui::Button("Add / set")) {
    if (app->new_direction_vertex < 0) {
      Refused(app, "direction: vertex " + std::to_string(app->new_direction_vertex) + " is not a vertex number");
    } else {
      DirectionEdit(app, field.name, uint32_t(app->new_direction_vertex),
                    {Num(app->new_direction[0]), Num(app->new_direction[1]), Num(app->new_direction[2]),
                     Num(app->new_direction[3])}, "");
    }
  }
  ImGui::Separator();
  // The maps (`mimetic texture`'s code) off the UI thread, into MAPS/ beside the rig file.
  static const char* const kSizes[] = {"256", "512", "1024", "2048"};
  int size_index = app->map_size <= 256 ? 0 : app->map_size <= 512 ? 1 : app->map_size <= 1024 ? 2 : 3;
  ImGui::SetNextItemWidth(80);
  if (ImGui::Combo("size", &size_index, kSizes, 4)) app->map_size = 256 << size_index;
  ImGui::SameLine();
  const std::string out_dir = JoinPath(DirectoryOf(s.rig_path()), "maps");
  ImGui::BeginDisabled(app->maps.busy());
  if (ImGui::Button("Regenerate maps")) {
    std::string error;
    if (!app->maps.Start(*spec, s.rig(), s.mesh_vertex_count(), out_dir, app->map_size, 1, &error))
      Refused(app, "Regenerate maps: " + error);
  }
  ImGui::EndDisabled();
  if (app->maps.busy()) {
    ImGui::SameLine();
    ImGui::ProgressBar(app->maps.progress(), ImVec2(-1, 0));
  } else {
    ImGui::TextDisabled("into %s/ (fine_height_1/2, fine_height, fine_normal .png)", out_dir.c_str());
  }
  bool ok = false;
  Diagnostics diag;
  std::vector<std::string> written;
  if (app->maps.Take(&ok, &diag, &written)) {
    std::string files;
    for (const std::string& w : written) files += (files.empty() ? "" : ", ") + w;
    s.AddMessages(diag, ok ? "maps written: " + files : "the maps were not made");
    if (ok) app->LoadFineMaps(out_dir);  // drawn at once (docs/viewer.md "Fine scale")
  }
  ImGui::End();
}

}  // namespace

void RigFilesRow(App* app) {
  Session& s = app->session;
  if (!s.has_rig()) return;
  ImGui::Separator();
  ImGui::BeginDisabled(!s.rig_spec());
  if (ImGui::Button("Save rig")) s.SaveRigFile(app->rig_field);
  TraceItem(app, "files/save-rig");
  ImGui::EndDisabled();
  ImGui::SameLine();
  ImGui::TextColored(s.rig_dirty() ? ImVec4(1.f, 0.8f, 0.3f, 1.f) : ImVec4(0.6f, 0.8f, 0.6f, 1.f), "rig: %s",
                     !s.rig_spec() ? "not editable (.mrig)" : s.rig_dirty() ? "unsaved changes" : "saved");
  ImGui::Checkbox("muscle editor (E)", &app->show_muscle_editor);
  ImGui::Checkbox("UV curves (U)", &app->show_uv_curves);
  ImGui::SameLine();
  ImGui::Checkbox("directions (D)", &app->show_directions);
  RebuildStatus(app);
}

void DrawRigPanels(App* app, float width, float height) {
  // E, U, D open and close the editors (not while a text field or a widget has the keyboard).
  if (!ImGui::GetIO().WantCaptureKeyboard && !ImGui::GetIO().KeyCtrl) {
    if (ImGui::IsKeyPressed(GLFW_KEY_E, false)) app->show_muscle_editor = !app->show_muscle_editor;
    if (ImGui::IsKeyPressed(GLFW_KEY_U, false)) app->show_uv_curves = !app->show_uv_curves;
    if (ImGui::IsKeyPressed(GLFW_KEY_D, false)) app->show_directions = !app->show_directions;
  }
  // The direction vectors' gizmos follow the edits and the editor's toggle.
  const uint64_t key = app->session.history().version(kEditRig) * 4 + (app->show_directions ? 2 : 0) +
                       (app->show_gizmos ? 1 : 0);
  if (app->session.has_rig() && key != app->gizmo_key) {
    app->gizmo_key = key;
    app->UpdateGizmos();
  }
  if (app->show_muscle_editor) MuscleEditorPanel(app, width, height);
  if (app->show_uv_curves) UvCurvesPanel(app, width, height);
  if (app->show_directions) DirectionsPanel(app, width, height);
}

void ReleaseRigPanels(App* app) {
  if (app->uv_texture) {
    GLuint tex = app->uv_texture;
    glDeleteTextures(1, &tex);
    app->uv_texture = 0;
  }
  app->uv_texture_stale = true;
}

}  // namespace mimetic::viewer

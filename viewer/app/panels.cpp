// viewer/app/panels.cpp: the ImGui 1.86 panels (docs/viewer.md "Panels"). Widgets edit the App
// and set `dirty` when the pose or the overlay changes.
#include <GLFW/glfw3.h>
#include <imgui.h>

#include <algorithm>
#include <cstdio>

#include "viewer/app/app.h"
#include "viewer/core/scene_query.h"

namespace mimetic::viewer {
namespace {

ImVec4 Color(const float3& c) { return ImVec4(c.x, c.y, c.z, 1.f); }

void FilesPanel(App* app) {
  ImGui::SetNextWindowPos(ImVec2(10, 10), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(330, 0), ImGuiCond_FirstUseEver);
  ImGui::Begin("Files");
  Session& s = app->session;
  ImGui::InputText("rig", app->rig_field, sizeof app->rig_field);
  ImGui::SameLine();
  if (ImGui::Button("Load##rig") && s.LoadRigFile(app->rig_field)) app->OnRigLoaded();
  ImGui::InputText("library", app->library_field, sizeof app->library_field);
  ImGui::SameLine();
  if (ImGui::Button("Load##lib")) s.LoadLibraryFile(app->library_field);
  ImGui::InputText("clip", app->clip_field, sizeof app->clip_field);
  ImGui::SameLine();
  if (ImGui::Button("Load##clip") && s.LoadClipFile(app->clip_field)) {
    app->clip_time = 0.f;
    app->pose_from_clip = true;
    app->dirty = true;
  }
  ImGui::End();
}

void ScenePanel(App* app) {
  ImGui::SetNextWindowPos(ImVec2(10, 130), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(330, 0), ImGuiCond_FirstUseEver);
  ImGui::Begin("Scene");
  const float3 lo = app->session.bounds_lo(), hi = app->session.bounds_hi();
  if (ImGui::Button("Frame all (F)")) app->camera.Frame({lo.x, lo.y, lo.z}, {hi.x, hi.y, hi.z});
  ImGui::SameLine();
  if (ImGui::Button("Front (1)")) app->camera.SetPreset(ViewPreset::kFront);
  ImGui::SameLine();
  if (ImGui::Button("Side (2)")) app->camera.SetPreset(ViewPreset::kSide);
  ImGui::SameLine();
  if (ImGui::Button("3/4 (3)")) app->camera.SetPreset(ViewPreset::kThreeQuarter);
  ImGui::SliderFloat("melanin m", &app->melanin, 0.f, 1.f);
  ImGui::SliderFloat("hemoglobin h", &app->hemoglobin, 0.f, 1.f);
  ImGui::SliderFloat("light azimuth", &app->light_azimuth, -180.f, 180.f, "%.0f deg");
  ImGui::SliderFloat("light elevation", &app->light_elevation, -89.f, 89.f, "%.0f deg");
  ImGui::Checkbox("surface", &app->show_surface);
  ImGui::SameLine();
  ImGui::Checkbox("wireframe (W)", &app->wireframe);
  ImGui::SameLine();
  if (ImGui::Checkbox("gizmos", &app->show_gizmos)) app->dirty = true;
  if (app->session.has_rig()) {
    ImGui::Separator();
    ImGui::TextUnformatted("layers");
    Session& s = app->session;
    const Rig& rig = s.rig();
    bool changed = ImGui::Checkbox("muscles", &s.muscles_enabled);
    if (!rig.jaw().empty()) changed |= ImGui::Checkbox("jaw", &s.jaw_enabled);
    if (rig.layers().thickness) changed |= ImGui::Checkbox("thickness", &s.layers.thickness);
    if (rig.layers().muscle_wrinkles)
      changed |= ImGui::Checkbox("muscle wrinkles", &s.layers.muscle_wrinkles);
    if (rig.layers().curve_wrinkles)
      changed |= ImGui::Checkbox("curve wrinkles", &s.layers.curve_wrinkles);
    changed |= ImGui::Checkbox("fold limiter", &s.limit_folds);
    ImGui::TextDisabled("fine scale: not in this rig format yet");
    if (changed) app->dirty = true;
  }
  ImGui::Separator();
  const char* names[kOverlayCount];
  for (int i = 0; i < kOverlayCount; ++i) names[i] = OverlayLabel(Overlay(i));
  int current = int(app->overlay);
  if (ImGui::Combo("overlay", &current, names, kOverlayCount)) {
    app->overlay = Overlay(current);
    app->dirty = true;
  }
  if (app->overlay != Overlay::kNone) {
    const OverlayField& f = app->session.overlay_field();
    for (const LegendEntry& e : OverlayLegend(f, 5)) {
      ImGui::ColorButton("##legend", Color(e.color), ImGuiColorEditFlags_NoTooltip, ImVec2(28, 14));
      ImGui::SameLine();
      ImGui::Text("%.4g", e.value);
    }
    ImGui::Text("data: min %.4g  max %.4g", f.min_value, f.max_value);
  }
  ImGui::End();
}

void MusclesPanel(App* app, float height) {
  ImGui::SetNextWindowPos(ImVec2(10, 570), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(330, std::max(150.f, height - 580)), ImGuiCond_FirstUseEver);
  ImGui::Begin("Muscles");
  Session& s = app->session;
  if (!s.has_rig()) {
    ImGui::TextUnformatted("no rig loaded");
    ImGui::End();
    return;
  }
  const Rig& rig = s.rig();
  if (app->selected_muscle >= 0)
    ImGui::Text("gizmos: %s", rig.muscle_names()[size_t(app->selected_muscle)].c_str());
  if (app->selected_muscle >= 0 && s.loaded().spec.muscles.empty())
    ImGui::TextDisabled("(a .mrig keeps no attachment or zone: wrinkling region only)");
  ImGui::Checkbox("link left/right", &app->link_sides);
  ImGui::SameLine();
  if (ImGui::Button("Reset")) {
    s.ResetPose();
    app->pose_from_clip = false;
    app->dirty = true;
  }
  if (!rig.jaw().empty() && ImGui::SliderFloat("jaw", &s.jaw, 0.f, 1.f)) {
    app->pose_from_clip = false;
    app->dirty = true;
  }
  ImGui::PushItemWidth(120);
  for (const MuscleGroup& g : GroupMuscles(rig.muscle_names())) {
    if (!ImGui::CollapsingHeader(g.region.c_str(), ImGuiTreeNodeFlags_DefaultOpen)) continue;
    for (uint32_t m : g.muscles) {
      ImGui::PushID(int(m));
      const bool selected = app->selected_muscle == int(m);
      if (ImGui::RadioButton("##sel", selected)) {
        app->selected_muscle = selected ? -1 : int(m);
        app->UpdateGizmos();
      }
      ImGui::SameLine();
      if (ImGui::SliderFloat(rig.muscle_names()[m].c_str(), &s.activations[m], 0.f, 1.f)) {
        if (app->link_sides)
          if (const int other = MirrorMuscle(rig.muscle_names(), m); other >= 0)
            s.activations[size_t(other)] = s.activations[m];
        app->pose_from_clip = false;
        app->dirty = true;
      }
      ImGui::PopID();
    }
  }
  ImGui::PopItemWidth();
  ImGui::End();
}

void ExpressionsPanel(App* app, float width) {
  ImGui::SetNextWindowPos(ImVec2(width - 330, 10), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(320, 300), ImGuiCond_FirstUseEver);
  ImGui::Begin("Expressions");
  ImGui::PushItemWidth(150);
  Session& s = app->session;
  ImGui::TextWrapped("%s", s.library_path().empty() ? "no library" : s.library_path().c_str());
  bool changed = false;
  for (size_t e = 0; e < s.library().size(); ++e) {
    ImGui::PushID(int(e));
    if (ImGui::SmallButton("apply")) {
      std::fill(s.expression_weights.begin(), s.expression_weights.end(), 0.f);
      s.expression_weights[e] = 1.f;
      changed = true;
    }
    ImGui::SameLine();
    changed |= ImGui::SliderFloat(s.library()[e].name.c_str(), &s.expression_weights[e], 0.f, 1.f);
    if (ImGui::IsItemHovered() && !s.library()[e].description.empty())
      ImGui::SetTooltip("%s", s.library()[e].description.c_str());
    ImGui::PopID();
  }
  if (changed && s.has_rig()) {
    s.ApplyExpressionBlend();
    app->pose_from_clip = false;
    app->dirty = true;
  }
  ImGui::PopItemWidth();
  ImGui::End();
}

void ClipPanel(App* app, float width, float height) {
  ImGui::SetNextWindowPos(ImVec2(350, height - 130), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(width - 700, 120), ImGuiCond_FirstUseEver);
  ImGui::Begin("Clip");
  Session& s = app->session;
  if (!s.has_clip()) {
    ImGui::TextUnformatted("no clip: open one in Files (or --clip CLIP)");
    ImGui::End();
    return;
  }
  const CompiledClip& clip = s.clip();
  ImGui::Text("%s  (%.2f s, %u channels)", s.clip_path().c_str(), clip.duration(), clip.channel_count());
  if (ImGui::Button(app->playing ? "Pause (space)" : "Play (space)")) {
    app->playing = !app->playing;
    app->pose_from_clip = true;
  }
  ImGui::SameLine();
  ImGui::Checkbox("loop", &app->loop);
  ImGui::SameLine();
  ImGui::SetNextItemWidth(90);
  ImGui::SliderFloat("fps", &app->fps, 1.f, 120.f, "%.0f");
  ImGui::SameLine();
  ImGui::SetNextItemWidth(90);
  ImGui::SliderFloat("speed", &app->speed, 0.1f, 2.f, "%.2fx");
  if (ImGui::SliderFloat("time", &app->clip_time, 0.f, std::max(clip.duration(), 1e-3f), "%.3f s")) {
    app->pose_from_clip = true;
    app->dirty = true;
  }
  // The timeline: one row per channel, its keys as dots, the playhead as a line.
  const float duration = std::max(clip.duration(), 1e-3f);
  ImDrawList* draw = ImGui::GetWindowDrawList();
  const float label_w = 180.f, row_h = 16.f;
  ImGui::BeginChild("timeline", ImVec2(0, 0), false);
  const ImVec2 origin = ImGui::GetCursorScreenPos();
  const float track_w = std::max(ImGui::GetContentRegionAvail().x - label_w - 8.f, 50.f);
  draw = ImGui::GetWindowDrawList();
  const auto& rows = s.timeline();
  for (size_t c = 0; c < rows.size(); ++c) {
    const float y = origin.y + float(c) * row_h;
    draw->AddText(ImVec2(origin.x, y), IM_COL32(220, 220, 220, 255), rows[c].label.c_str());
    const float x0 = origin.x + label_w;
    draw->AddRectFilled(ImVec2(x0, y + 2), ImVec2(x0 + track_w, y + row_h - 2), IM_COL32(60, 60, 70, 255));
    for (size_t k = 0; k < rows[c].key_times.size(); ++k) {
      const float x = x0 + track_w * rows[c].key_times[k] / duration;
      const float v = rows[c].key_values[k];
      draw->AddCircleFilled(ImVec2(x, y + row_h * 0.5f), 4.f,
                            IM_COL32(int(255 * v), 180, int(255 * (1 - v)), 255));
    }
  }
  const float px = origin.x + label_w + track_w * app->clip_time / duration;
  draw->AddLine(ImVec2(px, origin.y), ImVec2(px, origin.y + row_h * float(rows.size())),
                IM_COL32(255, 80, 80, 255), 2.f);
  // Scrubbing: click or drag on the tracks.
  ImGui::SetCursorScreenPos(ImVec2(origin.x + label_w, origin.y));
  ImGui::InvisibleButton("scrub", ImVec2(track_w, std::max(row_h * float(rows.size()), row_h)));
  if (ImGui::IsItemActive()) {
    const float t = (ImGui::GetIO().MousePos.x - origin.x - label_w) / track_w * duration;
    app->clip_time = std::clamp(t, 0.f, duration);
    app->pose_from_clip = true;
    app->dirty = true;
  }
  ImGui::EndChild();
  ImGui::End();
}

void MessagesPanel(App* app, float width, float height) {
  Session& s = app->session;
  if (s.messages().empty()) return;
  ImGui::SetNextWindowPos(ImVec2(width - 520, height - 200), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(510, 190), ImGuiCond_FirstUseEver);
  ImGui::Begin("Messages");
  if (ImGui::Button("Clear")) s.ClearMessages();
  for (const Message& m : s.messages())
    ImGui::TextColored(m.error ? ImVec4(1.f, 0.45f, 0.4f, 1.f) : ImVec4(1.f, 0.85f, 0.4f, 1.f),
                       "%s %s", m.error ? "error:" : "warning:", m.text.c_str());
  ImGui::End();
}

void StatsOverlay(App* app, float width) {
  ImGui::SetNextWindowPos(ImVec2(width - 330, 320), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowBgAlpha(0.6f);
  ImGui::Begin("Stats", nullptr, ImGuiWindowFlags_AlwaysAutoResize);
  const FrameStats& st = app->stats;
  Session& s = app->session;
  ImGui::Text("evaluate %.2f ms (%u threads)", st.evaluate_ms, s.threads());
  if (app->overlay != Overlay::kNone) ImGui::Text("overlay  %.2f ms", st.overlay_ms);
  ImGui::Text("upload   %.2f ms", st.upload_ms);
  ImGui::Text("draw     %.2f ms", st.draw_ms);
  ImGui::Text("eval + upload %.2f ms (target 4)", st.evaluate_ms + st.upload_ms);
  if (s.has_rig()) {
    ImGui::Text("vertices %u  triangles %u", s.rig().vertex_count(), s.rig().triangle_count());
    std::string layers;
    for (const std::string& n : s.ActiveLayerNames()) layers += (layers.empty() ? "" : ", ") + n;
    ImGui::TextWrapped("active layers: %s", layers.c_str());
  }
  ImGui::End();
}

void HoverTooltip(App* app) {
  if (!app->hover_valid || ImGui::GetIO().WantCaptureMouse) return;
  const Rig& rig = app->session.rig();
  ImGui::BeginTooltip();
  ImGui::Text("vertex %u", app->hover_vertex);
  if (app->overlay != Overlay::kNone)
    ImGui::Text("%s: %.4g", OverlayLabel(app->overlay), app->hover_value);
  if (app->hover_muscles.empty()) ImGui::TextUnformatted("no muscle reaches this point");
  for (uint32_t m : app->hover_muscles) ImGui::BulletText("%s", rig.muscle_names()[m].c_str());
  ImGui::EndTooltip();
}

}  // namespace

void DrawPanels(App* app, float width, float height) {
  FilesPanel(app);
  ScenePanel(app);
  MusclesPanel(app, height);
  ExpressionsPanel(app, width);
  ClipPanel(app, width, height);
  MessagesPanel(app, width, height);
  StatsOverlay(app, width);
  HoverTooltip(app);
}

}  // namespace mimetic::viewer

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

// Loads the file of the Files panel's field `which` (1 rig, 2 library, 3 clip).
void LoadField(App* app, int which) {
  Session& s = app->session;
  if (which == 1) s.StartRigLoad(app->rig_field);  // adopted by the frame loop's PollRigLoad
  if (which == 2 && s.LoadLibraryFile(app->library_field)) app->OnEdited();
  if (which == 3 && s.LoadClipFile(app->clip_field)) {
    app->clip_time = 0.f;
    app->pose_from_clip = true;
    app->active_channel = -1;
    app->OnEdited();
  }
}

// Load, unless it would drop unsaved edits: then the "Discard unsaved changes?" popup asks.
void AskLoad(App* app, int which) {
  const Session& s = app->session;
  const bool loses = which == 1   ? app->unsaved()
                     : which == 2 ? s.library_dirty()
                                  : s.clip_dirty();
  if (loses) app->pending_load = which;
  else LoadField(app, which);
}

void FilesPanel(App* app) {
  ImGui::SetNextWindowPos(ImVec2(10, 10), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(330, 0), ImGuiCond_FirstUseEver);
  ImGui::Begin("Files");
  if (!app->ui_trace_path.empty()) {  // the window itself (its title bar brings it to the front)
    const ImVec2 lo = ImGui::GetWindowPos(), size = ImGui::GetWindowSize();
    app->ui_trace.push_back({"window/Files", lo.x, lo.y, lo.x + size.x, lo.y + size.y});
  }
  Session& s = app->session;
  ImGui::InputText("rig", app->rig_field, sizeof app->rig_field);
  ImGui::SameLine();
  if (ImGui::Button("Load##rig")) AskLoad(app, 1);
  if (s.rig_loading())
    ImGui::TextColored(ImVec4(0.5f, 0.8f, 1.f, 1.f), "loading %s... (%s)", s.rig_loading_path().c_str(),
                       s.has_rig() ? "showing the last rig" : "no rig yet");
  ImGui::InputText("library", app->library_field, sizeof app->library_field);
  ImGui::SameLine();
  if (ImGui::Button("Load##lib")) AskLoad(app, 2);
  TraceItem(app, "files/load-library");
  ImGui::InputText("clip", app->clip_field, sizeof app->clip_field);
  ImGui::SameLine();
  if (ImGui::Button("Load##clip")) AskLoad(app, 3);
  // Saving to the paths in the fields (atomic; a failure lands in Messages, edits kept).
  if (ImGui::Button("Save clip (Ctrl+S)")) s.SaveClipFile(app->clip_field);
  ImGui::SameLine();
  if (ImGui::Button("Save library")) s.SaveLibraryFile(app->library_field);
  TraceItem(app, "files/save-library");
  ImGui::SameLine();
  if (ImGui::Button("New clip") && s.has_rig()) {
    if (s.clip_dirty()) app->pending_load = 4;
    else if (s.NewClip(app->clip_field)) app->OnEdited();
  }
  ImGui::TextColored(s.clip_dirty() ? ImVec4(1.f, 0.8f, 0.3f, 1.f) : ImVec4(0.6f, 0.8f, 0.6f, 1.f),
                     "clip: %s", !s.has_clip_spec() ? "not editable" : s.clip_dirty() ? "unsaved changes" : "saved");
  ImGui::SameLine();
  ImGui::TextColored(s.library_dirty() ? ImVec4(1.f, 0.8f, 0.3f, 1.f) : ImVec4(0.6f, 0.8f, 0.6f, 1.f),
                     "  library: %s", s.library_dirty() ? "unsaved changes" : "saved");
  // Edit: undo and redo of every command (edit.h), with what they would undo.
  const EditHistory& h = s.history();
  ImGui::BeginDisabled(!h.CanUndo());
  if (ImGui::Button("Undo (Ctrl+Z)")) app->Undo();
  TraceItem(app, "files/undo");
  ImGui::EndDisabled();
  ImGui::SameLine();
  ImGui::BeginDisabled(!h.CanRedo());
  if (ImGui::Button("Redo (Ctrl+Y)")) app->Redo();
  ImGui::EndDisabled();
  if (h.CanUndo()) ImGui::TextDisabled("undo: %s", h.UndoText().c_str());
  RigFilesRow(app);
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
    // Fine scale: the maps of a `mimetic texture` run, bump-mapped and scaled per vertex.
    if (s.has_fine_maps()) {
      changed |= ImGui::Checkbox("fine scale", &s.fine_enabled);
      ImGui::SameLine();
      ImGui::SetNextItemWidth(90.f);
      changed |= ImGui::DragFloat("depth", &s.fine_depth, 0.005f, 0.f, 10.f, "%.3f");
    } else {
      ImGui::TextDisabled(rig.fine_scale().empty() ? "fine scale: maps only (no fields in the rig)"
                                                   : "fine scale: no maps loaded");
    }
    ImGui::SetNextItemWidth(160.f);
    ImGui::InputText("##fine", app->fine_field, sizeof app->fine_field);
    ImGui::SameLine();
    if (ImGui::Button("Load maps")) changed |= app->LoadFineMaps(app->fine_field);
    if (ImGui::IsItemHovered())
      ImGui::SetTooltip("the folder of fine_height_1.png and fine_height_2.png (mimetic texture RIG --out DIR)");
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
    app->BeginPoseEdit();
    s.ResetPose();
    app->EndPoseEdit();
    app->pose_from_clip = false;
  }
  if (!rig.jaw().empty()) {
    if (ImGui::SliderFloat("jaw", &s.jaw, 0.f, 1.f)) {
      app->pose_from_clip = false;
      app->dirty = true;
    }
    if (ImGui::IsItemActivated()) app->BeginPoseEdit();
    if (ImGui::IsItemDeactivatedAfterEdit()) app->EndPoseEdit();
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
      const float frame_w = ImGui::CalcItemWidth();  // the slider's frame, without its label
      const bool moved = ImGui::SliderFloat(rig.muscle_names()[m].c_str(), &s.activations[m], 0.f, 1.f);
      if (!app->ui_trace_path.empty()) {
        const ImVec2 lo = ImGui::GetItemRectMin(), hi = ImGui::GetItemRectMax();
        app->ui_trace.push_back({"muscle/" + rig.muscle_names()[m], lo.x, lo.y, lo.x + frame_w, hi.y});
      }
      if (moved) {
        if (app->link_sides)
          if (const int other = MirrorMuscle(rig.muscle_names(), m); other >= 0)
            s.activations[size_t(other)] = s.activations[m];
        app->pose_from_clip = false;
        app->dirty = true;
      }
      // The drag is one command (undo gives back the pose before it).
      if (ImGui::IsItemActivated()) app->BeginPoseEdit();
      if (ImGui::IsItemDeactivatedAfterEdit()) app->EndPoseEdit();
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
  ImGui::TextWrapped("%s%s", s.library_path().empty() ? "no library" : s.library_path().c_str(),
                     s.library_dirty() ? " (unsaved)" : "");
  // Save the pose as a new expression (an existing name asks to overwrite it).
  ImGui::InputText("##name", app->expr_name, sizeof app->expr_name);
  TraceItem(app, "expr/name");
  TraceValue(app, "library/expressions", double(s.library().size()));
  ImGui::SameLine();
  int open_modal = 0;  // 1 overwrite, 2 rename, 3 delete: opened at the window's level below
  const bool save_pose = ImGui::Button("Save pose as");
  TraceItem(app, "expr/save-pose-as");
  if (save_pose && app->expr_name[0] != '\0' && s.has_rig()) {
    app->expr_target = -1;
    for (size_t e = 0; e < s.library().size(); ++e)
      if (s.library()[e].name == app->expr_name) app->expr_target = int(e);
    if (app->expr_target >= 0) open_modal = 1;
    else if (s.Edit(MakeSaveExpression(app->expr_name))) app->OnEdited();
  }
  bool changed = false;
  for (size_t e = 0; e < s.library().size(); ++e) {
    ImGui::PushID(int(e));
    if (ImGui::SmallButton("apply")) {
      app->BeginPoseEdit();
      std::fill(s.expression_weights.begin(), s.expression_weights.end(), 0.f);
      s.expression_weights[e] = 1.f;
      s.ApplyExpressionBlend();
      app->EndPoseEdit();
      app->pose_from_clip = false;
    }
    ImGui::SameLine();
    if (ImGui::SmallButton("...")) ImGui::OpenPopup("expr_menu");
    if (ImGui::BeginPopup("expr_menu")) {
      if (ImGui::MenuItem("Overwrite with the pose")) app->expr_target = int(e), open_modal = 1;
      if (ImGui::MenuItem("Rename")) {
        app->expr_target = int(e), open_modal = 2;
        std::snprintf(app->rename_field, sizeof app->rename_field, "%s", s.library()[e].name.c_str());
      }
      if (ImGui::MenuItem("Delete")) app->expr_target = int(e), open_modal = 3;
      ImGui::EndPopup();
    }
    ImGui::SameLine();
    changed |= ImGui::SliderFloat(s.library()[e].name.c_str(), &s.expression_weights[e], 0.f, 1.f);
    if (ImGui::IsItemActivated()) app->BeginPoseEdit();
    const bool released = ImGui::IsItemDeactivatedAfterEdit();
    if (ImGui::IsItemHovered() && !s.library()[e].description.empty())
      ImGui::SetTooltip("%s", s.library()[e].description.c_str());
    ImGui::PopID();
    if (released && s.has_rig()) {
      s.ApplyExpressionBlend();
      app->EndPoseEdit();
    }
  }
  if (changed && s.has_rig()) {
    s.ApplyExpressionBlend();
    app->pose_from_clip = false;
    app->dirty = true;
  }
  if (open_modal == 1) ImGui::OpenPopup("Overwrite expression?");
  if (open_modal == 2) ImGui::OpenPopup("Rename expression");
  if (open_modal == 3) ImGui::OpenPopup("Delete expression?");
  const bool valid = app->expr_target >= 0 && size_t(app->expr_target) < s.library().size();
  const std::string name = valid ? s.library()[size_t(app->expr_target)].name : "";
  if (ImGui::BeginPopupModal("Overwrite expression?", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
    ImGui::Text("Replace the activations of '%s' with the current pose?", name.c_str());
    if (ImGui::Button("Overwrite") && valid) {
      if (s.Edit(MakeOverwriteExpression(name))) app->OnEdited();
      ImGui::CloseCurrentPopup();
    }
    ImGui::SameLine();
    if (ImGui::Button("Cancel")) ImGui::CloseCurrentPopup();
    ImGui::EndPopup();
  }
  if (ImGui::BeginPopupModal("Rename expression", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
    ImGui::Text("Rename '%s' (and the clip's channels of it) to", name.c_str());
    ImGui::InputText("##rename", app->rename_field, sizeof app->rename_field);
    if (ImGui::Button("Rename") && valid) {
      if (s.Edit(MakeRenameExpression(name, app->rename_field))) app->OnEdited();
      ImGui::CloseCurrentPopup();
    }
    ImGui::SameLine();
    if (ImGui::Button("Cancel")) ImGui::CloseCurrentPopup();
    ImGui::EndPopup();
  }
  if (ImGui::BeginPopupModal("Delete expression?", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
    ImGui::Text("Delete '%s' from the library? (Undo brings it back.)", name.c_str());
    if (ImGui::Button("Delete") && valid) {
      if (s.Edit(MakeDeleteExpression(name))) app->OnEdited();
      ImGui::CloseCurrentPopup();
    }
    ImGui::SameLine();
    if (ImGui::Button("Cancel")) ImGui::CloseCurrentPopup();
    ImGui::EndPopup();
  }
  ImGui::PopItemWidth();
  ImGui::End();
}

// The channels a key can be added to: every muscle, the jaw (a rig with one), every expression.
std::vector<ChannelId> ChannelChoices(const Session& s) {
  std::vector<ChannelId> out;
  if (!s.has_rig()) return out;
  for (const std::string& m : s.rig().muscle_names()) out.push_back({ClipChannelKind::kMuscle, m});
  if (!s.rig().jaw().empty()) out.push_back({ClipChannelKind::kMuscle, kJawInputName});
  for (const Expression& e : s.library()) out.push_back({ClipChannelKind::kExpression, e.name});
  return out;
}

// The pose's value of a channel's target (the key Ins adds takes it).
float CurrentValue(const Session& s, const ChannelId& id) {
  if (id.kind == ClipChannelKind::kExpression) {
    for (size_t e = 0; e < s.library().size() && e < s.expression_weights.size(); ++e)
      if (s.library()[e].name == id.target) return s.expression_weights[e];
    return 0.f;
  }
  if (id.target == kJawInputName && s.rig().FindMuscle(id.target) < 0) return s.jaw;
  int m = s.rig().FindMuscle(id.target);
  if (m < 0) m = s.rig().FindMuscle(id.target + "_L");
  return m >= 0 && size_t(m) < s.activations.size() ? std::clamp(s.activations[size_t(m)], 0.f, 1.f) : 0.f;
}

// Ins: a key at the playhead on the active row (or the "add channel" choice).
void AddKeyAtPlayhead(App* app) {
  Session& s = app->session;
  if (!s.has_clip_spec()) return;
  ChannelId id;
  if (app->active_channel >= 0 && size_t(app->active_channel) < s.clip_spec().channels.size()) {
    const ClipChannelSpec& c = s.clip_spec().channels[size_t(app->active_channel)];
    id = {c.kind, c.target};
  } else {
    const std::vector<ChannelId> choices = ChannelChoices(s);
    if (app->new_channel < 0 || size_t(app->new_channel) >= choices.size()) return;
    id = choices[size_t(app->new_channel)];
  }
  if (s.Edit(MakeAddKey(id, app->clip_time, CurrentValue(s, id), KeyInterp(app->interp_choice)))) {
    s.selection.clear();
    app->active_channel = FindChannel(s.clip_spec(), id);
    app->OnEdited();
  }
}

void DeleteSelection(App* app) {
  Session& s = app->session;
  if (s.selection.empty()) return;
  if (s.Edit(MakeDeleteKeys(s.selection))) {
    s.selection.clear();
    app->OnEdited();
  }
}

void PasteAtPlayhead(App* app) {
  Session& s = app->session;
  if (s.clipboard.empty() || !s.has_clip_spec()) return;
  if (s.Edit(MakePasteKeys(s.clipboard, app->clip_time))) {
    s.selection.clear();
    app->OnEdited();
  }
}

bool Selected(const Session& s, uint32_t c, uint32_t k) {
  return std::find(s.selection.begin(), s.selection.end(), KeyRef{c, k}) != s.selection.end();
}

void ClipPanel(App* app, float width, float height) {
  ImGui::SetNextWindowPos(ImVec2(350, height - 250), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(width - 700, 240), ImGuiCond_FirstUseEver);
  ImGui::Begin("Clip");
  Session& s = app->session;
  if (!s.has_clip() && !s.has_clip_spec()) {
    ImGui::TextUnformatted("no clip: open one in Files (or --clip CLIP), or New clip");
    ImGui::End();
    return;
  }
  const bool editable = s.has_clip_spec();
  const float clip_duration = s.has_clip() ? s.clip().duration() : ClipDuration(s.clip_spec());
  ImGui::Text("%s%s  (%.2f s, %zu channels)", s.clip_path().c_str(), s.clip_dirty() ? " *" : "",
              clip_duration, editable ? s.clip_spec().channels.size() : size_t(s.clip().channel_count()));
  if (ImGui::Button(app->playing ? "Pause (space)" : "Play (space)") && s.has_clip()) {
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
  ImGui::SameLine();
  ImGui::SetNextItemWidth(200);
  // The track spans a little past the clip's end so keys can be added and dragged there.
  const float duration = std::max(clip_duration * 1.25f, 1.f);
  if (ImGui::SliderFloat("time", &app->clip_time, 0.f, duration, "%.3f s")) {
    app->pose_from_clip = true;
    app->dirty = true;
  }
  if (editable) {
    // Key editing: a channel to add to, the interpolation of new and selected keys.
    const std::vector<ChannelId> choices = ChannelChoices(s);
    std::vector<std::string> labels;
    for (const ChannelId& id : choices) labels.push_back(ChannelIdText(id));
    ImGui::SetNextItemWidth(200);
    const char* preview = app->new_channel >= 0 && size_t(app->new_channel) < labels.size()
                              ? labels[size_t(app->new_channel)].c_str() : "";
    if (ImGui::BeginCombo("##channel", preview)) {
      for (size_t i = 0; i < labels.size(); ++i)
        if (ImGui::Selectable(labels[i].c_str(), int(i) == app->new_channel)) {
          app->new_channel = int(i);
          app->active_channel = -1;
        }
      ImGui::EndCombo();
    }
    ImGui::SameLine();
    if (ImGui::Button("Add key (Ins)")) AddKeyAtPlayhead(app);
    ImGui::SameLine();
    const char* interps[] = {"step", "linear", "cubic"};
    ImGui::SetNextItemWidth(90);
    if (ImGui::Combo("interp", &app->interp_choice, interps, 3) && !s.selection.empty() &&
        s.Edit(MakeSetInterp(s.selection, KeyInterp(app->interp_choice))))
      app->OnEdited();
    ImGui::SameLine();
    ImGui::BeginDisabled(s.selection.empty());
    if (ImGui::Button("Delete (Del)")) DeleteSelection(app);
    ImGui::SameLine();
    if (ImGui::Button("Copy (Ctrl+C)")) s.clipboard = CopyKeys(s.clip_spec(), s.selection);
    ImGui::EndDisabled();
    ImGui::SameLine();
    ImGui::BeginDisabled(s.clipboard.empty());
    if (ImGui::Button("Paste (Ctrl+V)")) PasteAtPlayhead(app);
    ImGui::EndDisabled();
    ImGui::SameLine();
    if (s.selection.size() == 1) {
      const KeyRef r = s.selection[0];
      const ClipKeySpec& k = s.clip_spec().channels[r.channel].keys[r.key];
      ImGui::Text("key %.3f s = %.3f (%s)", k.t, k.v, InterpName(k.interp));
    } else {
      ImGui::Text("%zu keys selected", s.selection.size());
    }
  }
  // The timeline: one row per channel (the spec's when editable), keys at their value's height,
  // the curve between them, the playhead.
  struct Row {
    std::string label;
    std::vector<ClipKeySpec> keys;
  };
  std::vector<Row> rows;
  if (editable) {
    for (const ClipChannelSpec& c : s.clip_spec().channels)
      rows.push_back({ChannelIdText({c.kind, c.target}), c.keys});
  } else {
    for (const TimelineChannel& c : s.timeline()) {
      Row r{c.label, {}};
      for (size_t k = 0; k < c.key_times.size(); ++k) r.keys.push_back({c.key_times[k], c.key_values[k]});
      rows.push_back(std::move(r));
    }
  }
  const float label_w = 190.f, row_h = 26.f;
  ImGui::BeginChild("timeline", ImVec2(0, 0), false);
  const ImVec2 origin = ImGui::GetCursorScreenPos();
  const float track_w = std::max(ImGui::GetContentRegionAvail().x - label_w - 8.f, 50.f);
  ImDrawList* draw = ImGui::GetWindowDrawList();
  const float x0 = origin.x + label_w;
  auto key_pos = [&](size_t c, const ClipKeySpec& k, bool moved) {
    const float t = moved ? k.t + app->drag_dt : k.t;
    const float v = moved ? std::clamp(k.v + app->drag_dv, 0.f, 1.f) : k.v;
    return ImVec2(x0 + track_w * t / duration, origin.y + float(c) * row_h + row_h - 4.f - v * (row_h - 8.f));
  };
  for (size_t c = 0; c < rows.size(); ++c) {
    const float y = origin.y + float(c) * row_h;
    const bool active = editable && int(c) == app->active_channel;
    draw->AddText(ImVec2(origin.x, y + 5), active ? IM_COL32(255, 230, 120, 255) : IM_COL32(220, 220, 220, 255),
                  rows[c].label.c_str());
    draw->AddRectFilled(ImVec2(x0, y + 2), ImVec2(x0 + track_w, y + row_h - 2),
                        active ? IM_COL32(70, 70, 90, 255) : IM_COL32(55, 55, 65, 255));
    const float end_x = x0 + track_w * clip_duration / duration;
    draw->AddLine(ImVec2(end_x, y + 2), ImVec2(end_x, y + row_h - 2), IM_COL32(120, 120, 130, 255));
    const auto& keys = rows[c].keys;
    for (size_t k = 0; k < keys.size(); ++k) {
      const bool sel = editable && Selected(s, uint32_t(c), uint32_t(k));
      const ImVec2 p = key_pos(c, keys[k], sel && app->dragging_keys);
      if (k + 1 < keys.size()) {
        const bool next_sel = editable && Selected(s, uint32_t(c), uint32_t(k + 1));
        const ImVec2 q = key_pos(c, keys[k + 1], next_sel && app->dragging_keys);
        if (keys[k].interp == KeyInterp::kStep) {
          draw->AddLine(p, ImVec2(q.x, p.y), IM_COL32(150, 200, 255, 200));
          draw->AddLine(ImVec2(q.x, p.y), q, IM_COL32(150, 200, 255, 200));
        } else {
          draw->AddLine(p, q, keys[k].interp == KeyInterp::kCubic ? IM_COL32(150, 255, 170, 200)
                                                                  : IM_COL32(150, 200, 255, 200));
        }
      }
      const float v = keys[k].v;
      draw->AddCircleFilled(p, 4.5f, IM_COL32(int(255 * v), 180, int(255 * (1 - v)), 255));
      if (sel) draw->AddCircle(p, 7.f, IM_COL32(255, 255, 255, 255), 0, 2.f);
    }
  }
  const float px = x0 + track_w * app->clip_time / duration;
  draw->AddLine(ImVec2(px, origin.y), ImVec2(px, origin.y + row_h * float(rows.size())),
                IM_COL32(255, 80, 80, 255), 2.f);
  // Mouse: click a key to select it (shift: add or remove), drag the selection in time and
  // value (one command on release); click a track to scrub and make its row the active one.
  ImGui::SetCursorScreenPos(ImVec2(x0, origin.y));
  ImGui::InvisibleButton("tracks", ImVec2(track_w, std::max(row_h * float(rows.size()), row_h)));
  const ImGuiIO& io = ImGui::GetIO();
  if (ImGui::IsItemActivated()) {
    int hit_c = -1, hit_k = -1;
    float best = 7.f * 7.f;
    for (size_t c = 0; c < rows.size(); ++c)
      for (size_t k = 0; k < rows[c].keys.size(); ++k) {
        const ImVec2 p = key_pos(c, rows[c].keys[k], false);
        const float d = (p.x - io.MousePos.x) * (p.x - io.MousePos.x) + (p.y - io.MousePos.y) * (p.y - io.MousePos.y);
        if (d < best) best = d, hit_c = int(c), hit_k = int(k);
      }
    const int row = int((io.MousePos.y - origin.y) / row_h);
    if (editable && row >= 0 && size_t(row) < rows.size()) app->active_channel = row;
    if (editable && hit_c >= 0) {
      const KeyRef r{uint32_t(hit_c), uint32_t(hit_k)};
      const auto it = std::find(s.selection.begin(), s.selection.end(), r);
      if (io.KeyShift) {
        if (it == s.selection.end()) s.selection.push_back(r);
        else s.selection.erase(it);
      } else if (it == s.selection.end()) {
        s.selection = {r};
      }
      app->dragging_keys = !s.selection.empty();
      app->drag_dt = app->drag_dv = 0.f;
    } else if (!io.KeyShift) {
      s.selection.clear();
    }
  }
  if (ImGui::IsItemActive()) {
    if (app->dragging_keys) {
      const ImVec2 d = ImGui::GetMouseDragDelta(0, 0.f);
      app->drag_dt = d.x / track_w * duration;
      app->drag_dv = -d.y / (row_h - 8.f);
    } else {
      const float t = (io.MousePos.x - x0) / track_w * duration;
      app->clip_time = std::clamp(t, 0.f, duration);
      app->pose_from_clip = true;
      app->dirty = true;
    }
  }
  if (ImGui::IsItemDeactivated() && app->dragging_keys) {
    app->dragging_keys = false;
    if ((app->drag_dt != 0.f || app->drag_dv != 0.f) &&
        s.Edit(MakeMoveKeys(s.selection, app->drag_dt, app->drag_dv)))
      app->OnEdited();
    app->drag_dt = app->drag_dv = 0.f;
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

// The popups that guard unsaved work: a load that would drop edits, the window's close, and
// the autosaves found at the start.
void SafetyPopups(App* app) {
  Session& s = app->session;
  if (app->pending_load) ImGui::OpenPopup("Discard unsaved changes?");
  if (ImGui::BeginPopupModal("Discard unsaved changes?", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
    ImGui::TextUnformatted(app->pending_load == 2 ? "The library has unsaved changes."
                           : app->pending_load == 1 && s.rig_dirty()
                               ? "The rig (or the clip or the library) has unsaved changes."
                           : app->pending_load == 1 && s.library_dirty()
                               ? "The clip or the library has unsaved changes."
                               : "The clip has unsaved changes.");
    const bool discard = ImGui::Button("Discard them");
    TraceItem(app, "discard/discard");
    if (discard) {
      if (app->pending_load == 4) {
        if (s.NewClip(app->clip_field)) app->OnEdited();
      } else {
        LoadField(app, app->pending_load);
      }
      app->pending_load = 0;
      ImGui::CloseCurrentPopup();
    }
    ImGui::SameLine();
    const bool cancel = ImGui::Button("Cancel");
    TraceItem(app, "discard/cancel");
    if (cancel) {
      app->pending_load = 0;
      ImGui::CloseCurrentPopup();
    }
    ImGui::EndPopup();
  }
  if (app->close_requested) ImGui::OpenPopup("Quit with unsaved changes?");
  if (ImGui::BeginPopupModal("Quit with unsaved changes?", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
    if (s.clip_dirty()) ImGui::Text("clip %s: unsaved changes", s.clip_path().c_str());
    if (s.library_dirty()) ImGui::Text("library %s: unsaved changes", s.library_path().c_str());
    if (s.rig_dirty()) ImGui::Text("rig %s: unsaved changes", s.rig_path().c_str());
    const bool save_and_quit = ImGui::Button("Save and quit");
    TraceItem(app, "quit/save-and-quit");
    if (save_and_quit) {
      const bool ok = (!s.clip_dirty() || s.SaveClipFile()) && (!s.library_dirty() || s.SaveLibraryFile()) &&
                      (!s.rig_dirty() || s.SaveRigFile());
      app->close_requested = false;
      app->close_confirmed = ok;  // a failed save stays open, its message in Messages
      ImGui::CloseCurrentPopup();
    }
    ImGui::SameLine();
    const bool quit = ImGui::Button("Quit without saving");
    TraceItem(app, "quit/without-saving");
    if (quit) {
      app->close_requested = false;
      app->close_confirmed = true;
      ImGui::CloseCurrentPopup();
    }
    ImGui::SameLine();
    if (ImGui::Button("Cancel")) {
      app->close_requested = false;
      ImGui::CloseCurrentPopup();
    }
    ImGui::EndPopup();
  }
  if (app->offer_recovery) ImGui::OpenPopup("Recover unsaved work?");
  if (ImGui::BeginPopupModal("Recover unsaved work?", nullptr, ImGuiWindowFlags_AlwaysAutoResize)) {
    ImGui::TextUnformatted("Edits that were never saved were autosaved to:");
    for (const std::string& p : s.PendingAutosaves()) ImGui::BulletText("%s", p.c_str());
    if (ImGui::Button("Recover")) {
      s.RecoverAutosaves();
      app->OnEdited();
      app->offer_recovery = false;
      ImGui::CloseCurrentPopup();
    }
    ImGui::SameLine();
    if (ImGui::Button("Discard them")) {
      s.DiscardAutosaves();
      app->offer_recovery = false;
      ImGui::CloseCurrentPopup();
    }
    ImGui::SameLine();
    if (ImGui::Button("Later")) {
      app->offer_recovery = false;
      ImGui::CloseCurrentPopup();
    }
    ImGui::EndPopup();
  }
}

}  // namespace

void HandleEditShortcuts(App* app) {
  const ImGuiIO& io = ImGui::GetIO();
  if (io.WantTextInput) return;
  Session& s = app->session;
  const bool ctrl = io.KeyCtrl;
  if (ctrl && ImGui::IsKeyPressed(GLFW_KEY_Z, false)) {
    if (io.KeyShift) app->Redo();
    else app->Undo();
  }
  if (ctrl && ImGui::IsKeyPressed(GLFW_KEY_Y, false)) app->Redo();
  if (ctrl && ImGui::IsKeyPressed(GLFW_KEY_Q, false)) app->quit_requested = true;
  if (ctrl && ImGui::IsKeyPressed(GLFW_KEY_S, false) && s.has_clip_spec()) s.SaveClipFile(app->clip_field);
  if (!s.has_clip_spec()) return;
  if (ctrl && ImGui::IsKeyPressed(GLFW_KEY_C, false) && !s.selection.empty())
    s.clipboard = CopyKeys(s.clip_spec(), s.selection);
  if (ctrl && ImGui::IsKeyPressed(GLFW_KEY_V, false)) PasteAtPlayhead(app);
  if (ImGui::IsKeyPressed(GLFW_KEY_INSERT, false)) AddKeyAtPlayhead(app);
  if (ImGui::IsKeyPressed(GLFW_KEY_DELETE, false)) DeleteSelection(app);
}

void TraceItem(App* app, const std::string& name) {
  if (app->ui_trace_path.empty()) return;
  const ImVec2 lo = ImGui::GetItemRectMin(), hi = ImGui::GetItemRectMax();
  app->ui_trace.push_back({name, lo.x, lo.y, hi.x, hi.y});
}

void TraceValue(App* app, const std::string& name, double value) {
  if (!app->ui_trace_path.empty()) app->ui_trace_values.emplace_back(name, value);
}

namespace {
std::string JsonString(const std::string& text) {
  std::string out = "\"";
  for (char c : text) {
    if (c == '"' || c == '\\') out += '\\';
    if (static_cast<unsigned char>(c) >= 0x20) out += c;
  }
  return out + "\"";
}
}  // namespace

void WriteUiTrace(App* app, int window_x, int window_y) {
  if (app->ui_trace_path.empty()) return;
  char number[64];
  std::string body = "\"window\": [" + std::to_string(window_x) + ", " + std::to_string(window_y) +
                     "],\n \"items\": {";
  for (size_t i = 0; i < app->ui_trace.size(); ++i) {
    const App::TraceRect& r = app->ui_trace[i];
    std::snprintf(number, sizeof number, "[%.2f, %.2f, %.2f, %.2f]", r.x0, r.y0, r.x1, r.y1);
    body += (i ? ",\n  " : "\n  ") + JsonString(r.name) + ": " + number;
  }
  body += "},\n \"values\": {";
  for (size_t i = 0; i < app->ui_trace_values.size(); ++i) {
    std::snprintf(number, sizeof number, "%.9g", app->ui_trace_values[i].second);
    body += (i ? ",\n  " : "\n  ") + JsonString(app->ui_trace_values[i].first) + ": " + number;
  }
  body += "}}\n";
  app->ui_trace.clear();
  app->ui_trace_values.clear();
  ++app->ui_frame;
  // Every frame (the tests wait for a frame number to pass), through a temporary file and a
  // rename, so a reader never sees half a trace.
  const std::string text = "{\"frame\": " + std::to_string(app->ui_frame) + ",\n " + body;
  const std::string tmp = app->ui_trace_path + ".tmp";
  FILE* f = std::fopen(tmp.c_str(), "wb");
  if (!f) return;
  const bool ok = std::fwrite(text.data(), 1, text.size(), f) == text.size();
  if (std::fclose(f) == 0 && ok) std::rename(tmp.c_str(), app->ui_trace_path.c_str());
}

void DrawPanels(App* app, float width, float height) {
  FilesPanel(app);
  ScenePanel(app);
  MusclesPanel(app, height);
  ExpressionsPanel(app, width);
  ClipPanel(app, width, height);
  MessagesPanel(app, width, height);
  StatsOverlay(app, width);
  DrawRigPanels(app, width, height);
  HoverTooltip(app);
  SafetyPopups(app);
}

}  // namespace mimetic::viewer

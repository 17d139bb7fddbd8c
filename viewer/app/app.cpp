// viewer/app/app.cpp: see app.h.
#include "viewer/app/app.h"

#include "content/sample_head.h"

#include <GL/glcorearb.h>

#include <algorithm>
#include <cmath>
#include <cstring>

#include "viewer/core/scene_query.h"
#include "viewer/core/skin_shading.h"

namespace mimetic::viewer {

void App::OnRigLoaded() {
  const Rig& rig = session.rig();
  renderer.SetMesh(rig.vertex_indices(), rig.vertex_count(), rig.vertex_uvs());
  // The mesh file's other meshes, unposed; "eyes" in the eyeballs' colours, others as skin.
  const MeshData others = MergeForDrawing(MeshData{}, session.companions());
  std::vector<float3> colors;
  for (const NamedMeshData& m : session.companions().others)
    for (size_t k = 0; k < m.mesh.vertex_count(); ++k)
      colors.push_back(m.name == "eyes" && k < m.mesh.normals.size() ? SampleHeadEyeColor(m.mesh.normals[k])
                                                                     : float3{0.97f, 0.87f, 0.67f});
  renderer.SetStaticMesh(others, colors);  // draws nothing when a part lacks normals
  const float3 lo = session.bounds_lo(), hi = session.bounds_hi();
  camera.Frame({lo.x, lo.y, lo.z}, {hi.x, hi.y, hi.z});
  point_vertex.assign(rig.point_count(), 0);
  for (uint32_t v = rig.vertex_count(); v-- > 0;) point_vertex[rig.vertex_points()[v]] = v;
  selected_muscle = -1;
  selected_curve = drag_curve = drag_point = -1;
  uv_zoom = 0.f;
  uv_texture_stale = true;
  hover_valid = hover_seen = false;
  gizmo_key = ~0ull;
  std::snprintf(rig_field, sizeof rig_field, "%s", session.rig_path().c_str());
  dirty = true;
}

bool App::LoadFineMaps(const std::string& dir) {
  if (!session.LoadFineMaps(dir)) return false;
  renderer.SetFineMaps(session.fine_height(0), session.fine_height(1));
  std::snprintf(fine_field, sizeof fine_field, "%s", dir.c_str());
  dirty = true;
  return true;
}

void App::OnRigRebuilt() {
  const Rig& rig = session.rig();
  renderer.SetMesh(rig.vertex_indices(), rig.vertex_count(), rig.vertex_uvs());
  point_vertex.assign(rig.point_count(), 0);
  for (uint32_t v = rig.vertex_count(); v-- > 0;) point_vertex[rig.vertex_points()[v]] = v;
  hover_valid = false;
  UpdateGizmos();  // the selected muscle's geometry may have been edited
  dirty = true;
}

void App::BeginPoseEdit() {
  pose_before = session.activations;
  jaw_before = session.jaw;
}

void App::EndPoseEdit() {
  if (pose_before.size() != session.activations.size()) return;
  std::vector<float> pose = session.activations;
  const float jaw = session.jaw;
  session.activations = pose_before;
  session.jaw = jaw_before;
  if (pose != pose_before || jaw != jaw_before) session.Edit(MakeSetPose(std::move(pose), jaw));
  dirty = true;
}

void App::OnEdited() {
  if (session.last_touched() & kEditPose) pose_from_clip = false;  // the pose is the edit
  if (pose_from_clip && session.has_clip()) session.SampleClip(clip_time);
  dirty = true;
}

void App::Undo() {
  if (session.Undo()) OnEdited();
}

void App::Redo() {
  if (session.Redo()) OnEdited();
}

void App::Update() {
  if (!session.has_rig()) return;
  if (dirty) {
    if (!session.Evaluate(overlay)) {
      session.AddMessages({}, "evaluation failed (the job did not validate); showing the last frame");
    }
    stats.evaluate_ms = session.evaluate_ms();
    stats.overlay_ms = overlay == Overlay::kNone ? 0.0 : session.overlay_ms();
    auto start = std::chrono::steady_clock::now();
    renderer.UploadFrame(session.positions(), session.normals());
    if (session.fine_active()) renderer.UploadFineAmplitudes(session.fine_amplitudes());
    if (overlay != Overlay::kNone) {
      std::vector<float3> colors;
      OverlayColors(session.overlay_field(), &colors);
      renderer.UploadColors(colors);
    }
    glFinish();  // the upload's real cost, not just the queued copy
    stats.upload_ms = MillisecondsSince(start);
    UpdateGizmos();
    dirty = false;
  }
}

void App::UpdateGizmos() {
  std::vector<float3> lines, line_colors, points, point_colors;
  const Rig& rig = session.rig();
  const LoadedRig& loaded = session.loaded();
  if (show_gizmos && selected_muscle >= 0 && uint32_t(selected_muscle) < rig.muscle_count()) {
    const uint32_t m = uint32_t(selected_muscle);
    const float3 yellow{1.f, 0.85f, 0.1f}, cyan{0.2f, 0.9f, 1.f}, magenta{1.f, 0.3f, 0.9f};
    auto line = [&](float3 a, float3 b, float3 c) {
      lines.push_back(a);
      lines.push_back(b);
      line_colors.push_back(c);
      line_colors.push_back(c);
    };
    if (m < loaded.spec.muscles.size()) {  // a .rig.json keeps the muscle geometry; a .mrig not
      const MuscleSpec& spec = loaded.spec.muscles[m];
      if (spec.type == MuscleType::kLinear) {
        const LinearMuscleSpec& l = spec.linear;
        line(l.attachment, l.insertion, yellow);  // attachment -> insertion
        // The zone: a cone of half-angle Omega about the axis, out to the fall-off end Rf.
        const float3 axis = NormalizeOr(l.insertion - l.attachment, float3{0.f, 0.f, 1.f});
        const float3 side = NormalizeOr(Cross(axis, float3{0.f, 1.f, 0.f}), float3{1.f, 0.f, 0.f});
        const float3 up = Cross(side, axis);
        const int n = 24;
        for (float radius : {l.falloff_start, l.falloff_end}) {
          const float along = radius * std::cos(l.zone_angle), across = radius * std::sin(l.zone_angle);
          float3 prev{};
          for (int i = 0; i <= n; ++i) {
            const float a = 6.2831853f * float(i) / float(n);
            const float3 p = l.attachment + along * axis + across * (std::cos(a) * side + std::sin(a) * up);
            if (i > 0) line(prev, p, cyan);
            if (i % 6 == 0 && radius == l.falloff_end) line(l.attachment, p, cyan);
            prev = p;
          }
        }
      } else {
        const SheetMuscleSpec& s = spec.sheet;
        line(s.attachment[0], s.attachment[1], yellow);
        line(s.insertion[0], s.insertion[1], yellow);
        line(s.attachment[0], s.insertion[0], cyan);
        line(s.attachment[1], s.insertion[1], cyan);
      }
    }
    const std::vector<float3>& pos = session.positions();
    for (const RigMuscleWrinkles& w : rig.muscle_wrinkles()) {
      if (w.muscle != m) continue;
      // At most about kMaxRegionDots dots, evenly taken: the region stays readable as a
      // stipple over the skin instead of a solid patch.
      constexpr size_t kMaxRegionDots = 1200;
      const size_t step = std::max<size_t>(1, (w.points.size() + kMaxRegionDots - 1) / kMaxRegionDots);
      for (size_t i = 0; i < w.points.size(); i += step) {
        const uint32_t p = w.points[i];
        if (p < point_vertex.size() && point_vertex[p] < pos.size()) {
          points.push_back(pos[point_vertex[p]]);
          point_colors.push_back(magenta);
        }
      }
    }
  }
  // The fine-scale direction vectors while their editor is open: a line from each anchor's
  // vertex (rest) along its vector, a tenth of the mesh's size at magnitude 1; green for the
  // first field, orange for the second; a dot at the vertex.
  const RigSpec* edited = session.rig_spec();
  if (show_gizmos && show_directions && edited && edited->fine_scale) {
    const float3 lo = session.bounds_lo(), hi = session.bounds_hi();
    const float scale = 0.1f * std::max({hi.x - lo.x, hi.y - lo.y, hi.z - lo.z});
    const std::vector<float3>& rest = session.rest_positions();
    const float3 colors[2] = {{0.3f, 1.f, 0.4f}, {1.f, 0.6f, 0.2f}};
    for (int f = 0; f < 2; ++f)
      for (const DirectionAnchor& a : edited->fine_scale->fields[f].anchors) {
        if (a.vertex >= rest.size()) continue;  // output vertex a.vertex is file vertex a.vertex
        lines.push_back(rest[a.vertex]);
        lines.push_back(rest[a.vertex] + scale * a.vector);
        line_colors.push_back(colors[f]);
        line_colors.push_back(colors[f]);
        points.push_back(rest[a.vertex]);
        point_colors.push_back(colors[f]);
      }
  }
  renderer.SetGizmos(lines, line_colors, points, point_colors);
}

DrawParams App::MakeDrawParams(float aspect) const {
  DrawParams p;
  p.view = camera.View();
  p.projection = camera.Projection(aspect);
  p.albedo = SkinAlbedo(melanin, hemoglobin);
  p.light_camera = LightDirection(light_azimuth, light_elevation);
  const SkinLighting lighting;
  p.ambient = lighting.ambient;
  p.light = lighting.light;
  p.specular = lighting.specular;
  p.exponent = lighting.exponent;
  p.overlay = overlay != Overlay::kNone;
  p.wireframe = wireframe;
  p.surface = show_surface;
  p.fine = session.fine_active();
  p.fine_depth = session.fine_depth;
  return p;
}

void App::Hover(float x, float y, float width, float height) {
  hover_valid = false;
  if (!session.has_rig()) return;
  const Ray ray = camera.PixelRay(x, y, width, height);
  PickHit hit;
  const std::vector<float3>& pos = session.positions();
  if (!PickTriangle(pos, session.rig().vertex_indices(), {ray.origin.x, ray.origin.y, ray.origin.z},
                    {ray.direction.x, ray.direction.y, ray.direction.z}, &hit))
    return;
  hover_valid = true;
  hover_vertex = hit.nearest;
  hover_seen = true;
  hover_muscles = MusclesReachingPoint(session.rig(), session.rig().vertex_points()[hit.nearest]);
  const uint32_t* t = &session.rig().vertex_indices()[3 * size_t(hit.triangle)];
  hover_value = InterpolateValue(session.overlay_field(), t[0], t[1], t[2], hit.u, hit.w);
}

}  // namespace mimetic::viewer

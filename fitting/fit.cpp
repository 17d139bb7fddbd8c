// fitting/fit.cpp: place a landmark-relative muscle template on a head (docs/fitting.md).
#include "fitting/fit.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "geometry/bounds.h"

namespace mimetic {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

float Comp(float3 v, int axis) { return axis == 0 ? v.x : (axis == 1 ? v.y : v.z); }

std::string Vec(float3 v) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "(%.4g, %.4g, %.4g)", double(v.x), double(v.y), double(v.z));
  return buf;
}

const std::vector<std::pair<std::string, double>>& UnitsInMm() {
  static const std::vector<std::pair<std::string, double>> units = {
      {"mm", 1.0}, {"cm", 10.0}, {"dm", 100.0}, {"m", 1000.0}, {"in", 25.4}};
  return units;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// FaceFrame

float3 FaceFrame::ToWorld(float3 l) const {
  return origin + (x * l.x + y * l.y + z * l.z) * scale;
}
float3 FaceFrame::ToLocal(float3 w) const {
  const float3 d = (w - origin) / scale;
  return {Dot(d, x), Dot(d, y), Dot(d, z)};
}
float3 FaceFrame::DirectionToWorld(float3 l) const { return x * l.x + y * l.y + z * l.z; }

bool ComputeFaceFrame(const std::vector<float3>& lm, FaceFrame* out, Diagnostics* diag) {
  if (lm.size() != size_t(kTemplateLandmarkCount)) {
    diag->Error("landmarks", "expected 68 landmarks (iBUG order), got " + std::to_string(lm.size()));
    return false;
  }
  bool ok = true;
  for (size_t i = 0; i < lm.size(); ++i) {
    if (!IsFinite(lm[i])) {
      diag->Error("landmarks[" + std::to_string(i) + "]", "expected a finite position, got " + Vec(lm[i]));
      ok = false;
    }
  }
  if (!ok) return false;
  const float3 eye = lm[45] - lm[36];
  const float s = Length(eye);
  const float3 up = lm[27] - lm[8];
  const float up_len = Length(up);
  // Scale-free degeneracy thresholds: relative to the landmarks' extent.
  const BoundingBox box = ComputeBounds(lm);
  const float extent = Length(box.Hi() - box.Lo());
  if (!(s > 1e-6f * extent) || !(s > 0.f)) {
    diag->Error("landmarks[36], landmarks[45]",
                "the outer eye corners coincide (distance " + std::to_string(s) +
                    "); expected two distinct points to define the face's x axis and scale");
    return false;
  }
  FaceFrame f;
  f.x = eye / s;
  const float3 y = up - f.x * Dot(up, f.x);
  const float y_len = Length(y);
  if (!(up_len > 0.f) || !(y_len > 0.05f * up_len)) {
    diag->Error("landmarks[8], landmarks[27]",
                "the chin (8) and the nose bridge (27) do not span an up direction across the "
                "eye-corner line; expected a chin below the eyes");
    return false;
  }
  f.y = y / y_len;
  f.z = Cross(f.x, f.y);
  f.origin = lm[27];
  f.scale = s;
  *out = f;
  return true;
}

std::string GuessUnits(float s) {
  if (!(s > 0.f) || !std::isfinite(s)) return "";
  std::string best;
  double best_err = 1e30;
  for (const auto& [name, mm] : UnitsInMm()) {
    const double err = std::fabs(std::log(double(s) * mm / 90.0));
    if (err < best_err) best_err = err, best = name;
  }
  return best;
}


bool ResolveLandmarks(const Landmarks& landmarks, const MeshData& head, std::vector<float3>* out,
                      Diagnostics* diag) {
  const size_t n = size_t(kTemplateLandmarkCount);
  if (!landmarks.vertex_indices.empty()) {
    if (landmarks.vertex_indices.size() != n) {
      diag->Error("landmarks.vertices", "expected 68 vertex indices (iBUG order), got " +
                                            std::to_string(landmarks.vertex_indices.size()));
      return false;
    }
    bool ok = true;
    out->assign(n, {});
    for (size_t i = 0; i < n; ++i) {
      const int64_t v = landmarks.vertex_indices[i];
      if (v < 0 || uint64_t(v) >= head.vertex_count()) {
        diag->Error("landmarks.vertices[" + std::to_string(i) + "]",
                    "vertex index " + std::to_string(v) + " is out of range; expected 0.." +
                        std::to_string(head.vertex_count()) + " - 1 (a vertex of " +
                        (head.source.empty() ? std::string("the head mesh") : head.source) + ")");
        ok = false;
        continue;
      }
      (*out)[i] = head.positions[size_t(v)];
    }
    return ok;
  }
  if (landmarks.points.size() != n) {
    diag->Error("landmarks.points", "expected 68 landmarks (iBUG order), got " +
                                        std::to_string(landmarks.points.size()));
    return false;
  }
  *out = landmarks.points;
  return true;
}

// ---------------------------------------------------------------------------------------------
// Landmark sanity

namespace {

std::string Num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

// The largest distance from a landmark to the surface, and which landmark.
float WorstDistance(const std::vector<float3>& lm, const SurfaceQuery& query, int* worst) {
  float d = 0.f;
  *worst = 0;
  for (size_t i = 0; i < lm.size(); ++i) {
    const SurfaceQuery::Hit h = query.Nearest(lm[i]);
    const float t = h.found ? h.t : kInf;
    if (!(t <= d)) d = t, *worst = int(i);
  }
  return d;
}

}  // namespace

bool CheckLandmarksOnHead(const std::vector<float3>& lm, const MeshData& head,
                          const SurfaceQuery& query, Diagnostics* diag) {
  if (lm.size() != size_t(kTemplateLandmarkCount)) return true;  // ComputeFaceFrame says so
  const BoundingBox box = ComputeBounds(head.positions);
  const float diagonal = Length(box.Hi() - box.Lo());
  const float3 centre = (box.Hi() + box.Lo()) * 0.5f;
  const float tol = kLandmarkSurfaceTolerance * diagonal;
  int worst = 0;
  const float off = WorstDistance(lm, query, &worst);
  const std::string mesh_name = head.source.empty() ? std::string("the mesh") : head.source;
  if (!(off <= tol)) {
    auto fits = [&](auto&& transform) {
      std::vector<float3> t(lm.size());
      for (size_t i = 0; i < lm.size(); ++i) t[i] = transform(lm[i]);
      int w = 0;
      return WorstDistance(t, query, &w) <= tol;
    };
    // Another unit: landmarks at f times the mesh's coordinates.
    static const double kFactors[] = {10, 100, 1000, 25.4, 2.54, 0.1, 0.01, 0.001, 1 / 25.4, 1 / 2.54};
    for (double f : kFactors) {
      if (!fits([&](float3 p) { return p * float(1.0 / f); })) continue;
      diag->Error("landmarks",
                  "landmarks are about " + Num(f) + "x the mesh size: another unit? " +
                      (f > 1 ? "divided by " + Num(f) : "multiplied by " + Num(1 / f)) +
                      " they lie on " + mesh_name + "; give the landmarks in the mesh's units "
                      "(landmark " + std::to_string(worst) + ", " + Ibug68Name(worst) + ", is " +
                      Num(off) + " from the surface, " + Num(100.0 * off / diagonal) +
                      "% of the mesh's size)");
      return false;
    }
    // Upside down or mirrored coordinates (image rows grow downward; another handedness).
    for (int axis = 1; axis >= 0; --axis)
      for (int about = 0; about < 2; ++about) {
        const float c = about ? (axis ? centre.y : centre.x) : 0.f;
        const bool ok = fits([&](float3 p) {
          if (axis) p.y = 2.f * c - p.y;
          else p.x = 2.f * c - p.x;
          return p;
        });
        if (!ok) continue;
        const std::string coord = axis ? "y" : "x";
        const std::string mirror = (about ? coord + " mirrored about the mesh's centre (" +
                                                coord + " = " + Num(c) + ")"
                                          : coord + " negated");
        diag->Error("landmarks",
                    std::string(axis ? "landmarks look upside down: " : "landmarks look mirrored left/right: ") +
                        "with " + mirror + " they lie on " + mesh_name + ", as they are they do not "
                        "(landmark " + std::to_string(worst) + ", " + Ibug68Name(worst) + ", is " +
                        Num(off) + " from the surface); " +
                        (axis ? "flip y of the landmarks (image coordinates grow downward; the mesh's +y is up)"
                              : "mirror x of the landmarks (the subject's right is at -x: docs/landmarks-format.md, Sides)"));
        return false;
      }
    diag->Error("landmarks",
                "landmark " + std::to_string(worst) + " (" + Ibug68Name(worst) + ") is " + Num(off) +
                    " from the surface of " + mesh_name + ", " + Num(100.0 * off / diagonal) +
                    "% of the mesh's size (bounding-box diagonal " + Num(diagonal) +
                    "); expected every landmark on the surface (within " +
                    Num(100.0 * kLandmarkSurfaceTolerance) + "%): are these the landmarks of this "
                    "mesh, in its units and placement?");
    return false;
  }

  // Does the frame's z point out of the face? Count the landmarks seen first along -z from in
  // front of the face, and along +z from behind it.
  FaceFrame frame;
  Diagnostics ignored;
  if (!ComputeFaceFrame(lm, &frame, &ignored)) return true;  // the caller reports the frame
  const float reach = 2.f * diagonal + 4.f * frame.scale;
  const float seen = std::max(0.1f * frame.scale, 0.01f * diagonal);
  int front = 0, back = 0;
  double normal_sum = 0;
  for (const float3& p : lm) {
    const SurfaceQuery::Hit f = query.Raycast(p + frame.z * reach, -frame.z);
    const SurfaceQuery::Hit b = query.Raycast(p - frame.z * reach, frame.z);
    front += f.found && Length(f.point - p) <= seen;
    back += b.found && Length(b.point - p) <= seen;
    const SurfaceQuery::Hit n = query.Nearest(p);
    if (n.found) normal_sum += Dot(query.NormalAt(n.triangle, n.point), frame.z);
  }
  const int count = int(lm.size());
  bool inward = false;
  std::string evidence;
  if (back > front + count / 4) {
    inward = true;
    evidence = "seen along -z of the frame, from in front of the face, only " + std::to_string(front) +
               " of 68 landmarks are not hidden behind other surface; seen from behind, " +
               std::to_string(back) + " are";
  } else if (std::abs(back - front) <= count / 4 && normal_sum < 0) {
    inward = true;  // open at the back: the mesh's winding says where out is
    evidence = "the mesh's outward normals at the landmarks point against the frame's z (mean "
               "cosine " + Num(normal_sum / count) + ")";
  }
  if (!inward) {
    if (frame.y.y < -0.5f && frame.x.x < -0.5f)
      diag->Warning("landmarks", "the landmarks' up (chin 8 to nose bridge 27) runs along -y of " +
                                     mesh_name + " and their left along -x: the head, or the "
                                     "landmarks, are upside down (rotated 180 degrees)");
    return true;
  }
  const std::string frame_says = "the face frame they give points into the head (" + evidence + ")";
  if (frame.y.y < 0.f && std::fabs(frame.y.y) > std::fabs(frame.x.x) * 0.5f) {
    diag->Error("landmarks", "landmarks look upside down: the chin (8) is above the nose bridge "
                             "(27) along the mesh's y (" + Num(lm[8].y) + " > " + Num(lm[27].y) +
                             "), and " + frame_says + "; flip the landmarks top to bottom "
                             "(image coordinates grow downward; the mesh's +y is up)");
    return false;
  }
  diag->Error("landmarks",
              "landmarks look mirrored left/right: the subject's left outer eye corner (45) is "
              "on the subject's right of the face, and " + frame_says + "; swap the left and "
              "right landmarks (iBUG \"right\" is the subject's right, at -x for a head facing "
              "+z: docs/landmarks-format.md, Sides) or mirror their x");
  return false;
}

// ---------------------------------------------------------------------------------------------
// FitTemplate

namespace {

struct Placer {
  const FaceFrame& frame;
  const std::vector<float3>& lm;
  const SurfaceQuery& query;
  float reach;  // ray start distance in front of the face, mesh units
  Diagnostics* diag;
  FitReport* report;

  bool Place(const TemplatePoint& tp, const std::string& muscle, const std::string& role,
             const std::string& where, float3* out, SurfaceQuery::Hit* hit_out = nullptr) {
    float3 base{0, 0, 0};
    for (size_t i = 0; i < tp.landmarks.size(); ++i) base += lm[size_t(tp.landmarks[i])] * tp.weights[i];
    const float3 p = base + frame.DirectionToWorld({tp.offset.x, tp.offset.y, 0.f}) * frame.scale;
    PlacedPoint placed;
    placed.muscle = muscle;
    placed.role = role;
    placed.landmark_point = p;
    placed.depth = tp.depth * frame.scale;
    SurfaceQuery::Hit hit = query.Raycast(p + frame.z * reach, -frame.z);
    float3 outward;
    if (hit.found) {
      outward = hit.normal;  // faces the ray origin, in front of the face
    } else {
      hit = query.Nearest(p);
      placed.ray_hit = false;
      if (!hit.found || hit.t > kMaxOffMeshDistance * frame.scale) {
        diag->Error(where, "found no surface: the ray along -z of the face frame from " + Vec(p) +
                               " missed the mesh and the nearest surface point is " +
                               (hit.found ? std::to_string(hit.t / frame.scale) + " s away"
                                          : std::string("missing")) +
                               "; expected a point over the face (check the landmarks and offset)");
        return false;
      }
      outward = hit.normal;
      if (Dot(outward, frame.z) < 0.f) outward = -outward;  // toward the viewer
      diag->Warning(where, "the ray along -z of the face frame missed the mesh; used the nearest "
                           "surface point, " + std::to_string(hit.t / frame.scale) + " s away");
    }
    placed.surface = hit.point;
    placed.position = hit.point - outward * placed.depth;
    *out = placed.position;
    if (hit_out) *hit_out = hit;
    if (report) report->points.push_back(placed);
    return true;
  }
};

}  // namespace

float LargestMiss(const FitReport& report, std::string* where) {
  float worst = 0.f;
  if (where) where->clear();
  for (const PlacedPoint& p : report.points) {
    if (p.ray_hit) continue;
    const float d = Length(p.landmark_point - p.surface) / report.frame.scale;
    if (d > worst) {
      worst = d;
      if (where) *where = p.muscle + " " + p.role;
    }
  }
  return worst;
}

void PlaceJaw(const TemplateJaw& tj, const std::vector<float3>& lm, const FaceFrame& frame,
              JawSpec* out) {
  const float s = frame.scale;
  JawSpec jaw;
  for (int side = 0; side < 2; ++side) {
    float3 mean{};
    for (size_t k = 0; k < tj.landmarks.size(); ++k) {
      const int l = side == 0 ? tj.landmarks[k] : IbugMirrorLandmark(tj.landmarks[k]);
      mean += lm[size_t(l)] * tj.weights[k];
    }
    const float3 off{side == 0 ? tj.offset.x : -tj.offset.x, tj.offset.y, tj.offset.z};
    jaw.condyles[side] = mean + frame.DirectionToWorld(off) * s;
  }
  jaw.range_deg = tj.range_deg;
  jaw.translation = frame.DirectionToWorld(tj.translation) * s;
  jaw.mouth = (lm[62] + lm[66]) * 0.5f;
  jaw.mouth_width = Length(lm[54] - lm[48]);
  jaw.lip_blend_deg = tj.lip_blend_deg;
  jaw.cheek_blend_deg = tj.cheek_blend_deg;
  jaw.cheek_drop_deg = tj.cheek_drop_deg;
  jaw.corner_fade = tj.corner_fade;
  jaw.thickness_fade = tj.thickness_fade;
  jaw.back[0] = tj.back[0];
  jaw.back[1] = tj.back[1];
  jaw.neck_deg[0] = tj.neck_deg[0];
  jaw.neck_deg[1] = tj.neck_deg[1];
  *out = std::move(jaw);
}

bool FitTemplate(const MuscleTemplate& tmpl, const MeshData& head, const Landmarks& landmarks,
                 const std::string& units, RigSpec* out, Diagnostics* diag, FitReport* report,
                 const SurfaceQuery* head_query) {
  bool units_ok = false;
  for (const auto& u : UnitsInMm()) units_ok = units_ok || u.first == units;
  if (!units_ok) {
    diag->Error("units", "unknown unit \"" + units + "\"; expected \"mm\", \"cm\", \"dm\", \"m\" or \"in\"");
    return false;
  }
  if (head.vertex_count() == 0 || head.triangle_count() == 0) {
    diag->Error(head.source, "the head mesh is empty; expected triangles");
    return false;
  }
  std::vector<float3> lm;
  if (!ResolveLandmarks(landmarks, head, &lm, diag)) return false;
  FaceFrame frame;
  if (!ComputeFaceFrame(lm, &frame, diag)) return false;

  const BoundingBox box = ComputeBounds(head.positions);
  std::optional<SurfaceQuery> own_query;
  if (!head_query) head_query = &own_query.emplace(head);
  const SurfaceQuery& query = *head_query;
  if (!CheckLandmarksOnHead(lm, head, query, diag)) return false;
  FitReport local_report;
  Placer placer{frame, lm, query, 2.f * Length(box.Hi() - box.Lo()) + 4.f * frame.scale, diag,
                report ? &local_report : nullptr};
  local_report.frame = frame;
  local_report.units = units;

  RigSpec spec;
  spec.units = units;
  spec.refinement.falloff_error = tmpl.falloff_error;  // docs/model.md §11
  // What ties the per-vertex thickness and the curves' texture coordinates to this mesh.
  spec.mesh_fingerprint = ComputeMeshFingerprint(head);
  const float s = frame.scale;
  bool ok = true;
  for (size_t i = 0; i < tmpl.muscles.size(); ++i) {
    const TemplateMuscle& tm = tmpl.muscles[i];
    const std::string path = "muscles[" + std::to_string(i) + "] (" + tm.name + ")";
    MuscleSpec m;
    m.name = tm.name;
    m.type = tm.type;
    m.strength = tm.strength * s;
    m.falloff = tm.falloff;
    m.motion = tm.motion;
    m.tangent_radius = tm.tangent_radius * s;
    if (tm.type == MuscleType::kLinear) {
      bool placed = placer.Place(tm.attachment[0], tm.name, "attachment", path + ".attachment", &m.linear.attachment);
      placed &= placer.Place(tm.insertion[0], tm.name, "insertion", path + ".insertion", &m.linear.insertion);
      if (placed && !(Length(m.linear.insertion - m.linear.attachment) > 1e-4f * s)) {
        diag->Error(path, "attachment and insertion land on the same point " + Vec(m.linear.insertion) +
                              "; expected distinct points (a muscle needs a direction)");
        placed = false;
      }
      ok &= placed;
      m.linear.zone_angle = tm.zone_angle_deg * kPi / 180.f;
      m.linear.falloff_start = tm.falloff_start * s;
      m.linear.falloff_end = tm.falloff_end * s;
    } else {
      bool placed = true;
      for (int k = 0; k < 2; ++k) {
        const std::string idx = "[" + std::to_string(k) + "]";
        placed &= placer.Place(tm.attachment[k], tm.name, "attachment" + idx, path + ".attachment" + idx,
                               &m.sheet.attachment[k]);
        placed &= placer.Place(tm.insertion[k], tm.name, "insertion" + idx, path + ".insertion" + idx,
                               &m.sheet.insertion[k]);
      }
      const float3 ac = (m.sheet.attachment[0] + m.sheet.attachment[1]) * 0.5f;
      const float3 ic = (m.sheet.insertion[0] + m.sheet.insertion[1]) * 0.5f;
      if (placed && !(Length(ic - ac) > 1e-4f * s)) {
        diag->Error(path, "the attachment and insertion lines have the same midpoint " + Vec(ac) +
                              "; expected distinct lines (the sheet's fibre needs a direction)");
        placed = false;
      }
      ok &= placed;
      m.sheet.length = tm.length * s;
      m.sheet.width = tm.width * s;
      m.sheet.falloff_start = tm.falloff_start * s;
    }
    spec.muscles.push_back(m);
    if (tm.wrinkles) {
      // docs/model.md §6: the block as written, lengths from units of s to mesh units.
      MuscleWrinkleSpec w = *tm.wrinkles;
      w.depth *= s;
      w.h_c *= s;
      const WrinkleMuscleGeometry g = WrinkleGeometryOf(m);
      ok &= ValidateMuscleWrinkleSpec(w, g, path + ".wrinkles", diag);
      spec.muscle_wrinkles.resize(tmpl.muscles.size());
      spec.muscle_wrinkles[i] = w;
    }
  }
  // Curve wrinkles (docs/model.md §7-8): control points on the skin -> texture coordinates.
  const bool has_uvs = !head.uvs.empty() && head.uvs.size() == head.vertex_count();
  if (!tmpl.curve_wrinkles.empty() && !has_uvs) {
    diag->Error("curve_wrinkles", "the head mesh " + head.source + " has no texture coordinates; "
                                  "curve wrinkles are drawn in texture space and need them");
    ok = false;
  }
  for (size_t i = 0; i < tmpl.curve_wrinkles.size() && has_uvs; ++i) {
    const TemplateCurveWrinkle& tc = tmpl.curve_wrinkles[i];
    const std::string path = "curve_wrinkles[" + std::to_string(i) + "] (" + tc.name + ")";
    NamedCurveWrinkle c;
    c.name = tc.name;
    c.spec.depth = tc.depth * s;
    c.spec.width = tc.width * s;
    c.spec.profile = tc.profile;
    c.spec.modulation = tc.modulation;
    c.spec.rest_amplitude = tc.rest_amplitude;
    bool placed = true;
    for (int k = 0; k < 4; ++k) {
      const std::string role = "control[" + std::to_string(k) + "]";
      float3 position;
      SurfaceQuery::Hit hit;
      if (!placer.Place(tc.control[k], tc.name, role, path + "." + role, &position, &hit)) {
        placed = false;
        continue;
      }
      // The uv of the hit: barycentric in the hit triangle (its own corners' uvs, so a point
      // next to a seam takes one side's chart).
      const uint32_t* tri = &head.indices[3 * size_t(hit.triangle)];
      const float3 bary = hit.bary;
      const float2 ua = head.uvs[tri[0]], ub = head.uvs[tri[1]], uc = head.uvs[tri[2]];
      c.spec.control[k] = {ua.x * bary.x + ub.x * bary.y + uc.x * bary.z,
                           ua.y * bary.x + ub.y * bary.y + uc.y * bary.z};
    }
    if (placed) {
      float2 lo = c.spec.control[0], hi = lo;
      for (const float2& uv : c.spec.control) {
        lo = {std::fmin(lo.x, uv.x), std::fmin(lo.y, uv.y)};
        hi = {std::fmax(hi.x, uv.x), std::fmax(hi.y, uv.y)};
      }
      if (hi.x - lo.x > 0.5f || hi.y - lo.y > 0.5f) {
        std::string uvs;
        for (const float2& uv : c.spec.control) {
          char buf[48];
          std::snprintf(buf, sizeof buf, "%s(%.3g, %.3g)", uvs.empty() ? "" : ", ", double(uv.x),
                        double(uv.y));
          uvs += buf;
        }
        diag->Error(path, "the control points land at texture coordinates " + uvs +
                              ", more than 0.5 apart: the curve would cross a UV seam; expected "
                              "a curve inside one UV chart (move it or split it)");
        placed = false;
      }
    }
    if (placed) placed = ValidateCurveWrinkleSpec(c.spec, path, diag);
    ok &= placed;
    if (placed && report) {
      PlacedCurve pc;
      pc.name = c.name;
      for (int k = 0; k < 4; ++k) pc.uv[k] = c.spec.control[k];
      local_report.curves.push_back(pc);
    }
    spec.curve_wrinkles.push_back(c);
  }
  // Skin thickness per vertex (docs/model.md §4), template units of s -> mesh units.
  spec.thickness.kind = ThicknessSpec::Kind::kPerVertex;
  spec.thickness.per_vertex.resize(head.vertex_count());
  for (size_t v = 0; v < head.vertex_count(); ++v)
    spec.thickness.per_vertex[v] =
        EvaluateTemplateThickness(tmpl.thickness, frame.ToLocal(head.positions[v])) * s;
  // Tension regions (docs/tension.md): each template region's mask per vertex, in the face frame.
  for (const TemplateTensionRegion& g : tmpl.tension_regions) {
    TensionRegionSpec region;
    region.name = g.name;
    region.reference = g.reference;
    region.weights.resize(head.vertex_count());
    for (size_t v = 0; v < head.vertex_count(); ++v)
      region.weights[v] =
          EvaluateTensionRegion(g, tmpl.thickness.front, frame.ToLocal(head.positions[v]));
    spec.tension_regions.push_back(std::move(region));
  }
  // Fine-scale direction fields (docs/model.md §20): each template vector on the forward-facing
  // head vertex nearest to its face-frame (x, y), its direction turned into mesh axes.
  if (tmpl.fine_scale) {
    FineScaleSpec fs;
    fs.rest_amplitude = tmpl.fine_scale->rest_amplitude;
    std::vector<float3> local(head.vertex_count());
    for (size_t v = 0; v < head.vertex_count(); ++v) local[v] = frame.ToLocal(head.positions[v]);
    for (int i = 0; i < 2; ++i) {
      fs.fields[i].name = tmpl.fine_scale->field_names[i];
      for (const TemplateDirectionAnchor& a : tmpl.fine_scale->fields[i]) {
        size_t best = head.vertex_count();
        float best_d = 0.f;
        for (size_t v = 0; v < head.vertex_count(); ++v) {
          const float* front = tmpl.thickness.front;
          const float u = (local[v].z - front[0]) / (front[1] - front[0]);
          if (!(u >= 0.5f)) continue;  // the front fade's smoothstep is 1/2 at u = 1/2
          const float dx = local[v].x - a.at.x, dy = local[v].y - a.at.y, d = dx * dx + dy * dy;
          if (best == head.vertex_count() || d < best_d) best = v, best_d = d;
        }
        if (best == head.vertex_count()) {
          diag->Error("fine_scale." + fs.fields[i].name + "." + a.name,
                      "no forward-facing head vertex to place the direction vector on");
          ok = false;
          continue;
        }
        DirectionAnchor anchor;
        anchor.vertex = uint32_t(best);
        anchor.vector = NormalizeOr(frame.DirectionToWorld(a.direction), float3{}) * a.magnitude;
        fs.fields[i].anchors.push_back(anchor);
      }
    }
    spec.fine_scale = std::move(fs);
  }
  // The jaw (docs/model.md §18): condyles from the landmarks (the right one as the template
  // says, the left one mirrored), the mouth point on the inner lip midline (62, 66), the mouth
  // width between the outer corners (48, 54); the region parameters as they are.
  if (tmpl.jaw) {
    JawSpec jaw;
    PlaceJaw(*tmpl.jaw, lm, frame, &jaw);
    JawFrame jf;
    if (!MakeJawFrame(jaw, &jf)) {
      diag->Error("jaw.condyle", "the placed condyles coincide or the mouth lies on their axis; "
                                 "expected condyles on either side of the head, behind the mouth");
      ok = false;
    } else if (Dot(jf.axis, frame.x) <= 0.f) {
      diag->Error("jaw.condyle", "the placed right condyle lies on the subject's left of the "
                                 "left one; expected an offset dx that keeps it on the right "
                                 "(landmark 0's side)");
      ok = false;
    }
    spec.jaw = std::move(jaw);
  }
  if (!ok) return false;
  spec.file = out->file;
  spec.mesh_path = out->mesh_path;
  spec.mesh_name = out->mesh_name;
  *out = std::move(spec);
  if (report) *report = std::move(local_report);
  return true;
}

// ---------------------------------------------------------------------------------------------
// Thickness map in texture space

bool RasterizeThicknessMap(const MeshData& mesh, const std::vector<float>& values, int size,
                           float blur_sigma_px, std::vector<uint8_t>* gray, float* max_value,
                           Diagnostics* diag) {
  bool ok = true;
  if (mesh.uvs.size() != mesh.vertex_count() || mesh.uvs.empty()) {
    diag->Error(mesh.source, "a thickness map needs texture coordinates and the mesh has none");
    ok = false;
  }
  if (values.size() != mesh.vertex_count()) {
    diag->Error("thickness", "expected one value per vertex (" + std::to_string(mesh.vertex_count()) +
                                 "), got " + std::to_string(values.size()));
    ok = false;
  }
  if (size < 8 || size > 8192) {
    diag->Error("size", "expected an image size in [8, 8192], got " + std::to_string(size));
    ok = false;
  }
  if (!ok) return false;
  float vmax = 0.f;
  for (float v : values) vmax = std::fmax(vmax, v);
  // Round the white level up to two significant digits so the rig file reads well.
  if (vmax > 0.f) {
    const float p = std::pow(10.f, std::floor(std::log10(vmax)) - 1.f);
    vmax = std::ceil(vmax / p - 1e-4f) * p;
  } else {
    vmax = 1.f;
  }
  const int n = size;
  std::vector<float> img(size_t(n) * n, 0.f), cover(size_t(n) * n, 0.f);
  for (size_t t = 0; t < mesh.triangle_count(); ++t) {
    const uint32_t ia = mesh.indices[3 * t], ib = mesh.indices[3 * t + 1], ic = mesh.indices[3 * t + 2];
    // Pixel centres at (i + 0.5) / n; the bilinear sampler in rig_builder reads u * (n - 1),
    // so rasterise in that convention: pixel i is at u = i / (n - 1).
    auto px = [&](uint32_t v) {
      return float2{mesh.uvs[v].x * float(n - 1), mesh.uvs[v].y * float(n - 1)};
    };
    const float2 a = px(ia), b = px(ib), c = px(ic);
    const float area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    if (!(std::fabs(area) > 1e-12f)) continue;
    const int x0 = std::max(0, int(std::floor(std::fmin(a.x, std::fmin(b.x, c.x)))));
    const int x1 = std::min(n - 1, int(std::ceil(std::fmax(a.x, std::fmax(b.x, c.x)))));
    const int y0 = std::max(0, int(std::floor(std::fmin(a.y, std::fmin(b.y, c.y)))));
    const int y1 = std::min(n - 1, int(std::ceil(std::fmax(a.y, std::fmax(b.y, c.y)))));
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        const float fx = float(x), fy = float(y);
        const float w0 = ((b.x - fx) * (c.y - fy) - (b.y - fy) * (c.x - fx)) / area;
        const float w1 = ((c.x - fx) * (a.y - fy) - (c.y - fy) * (a.x - fx)) / area;
        const float w2 = 1.f - w0 - w1;
        const float eps = -1e-3f;
        if (w0 < eps || w1 < eps || w2 < eps) continue;
        const size_t i = size_t(y) * n + x;
        img[i] += w0 * values[ia] + w1 * values[ib] + w2 * values[ic];
        cover[i] += 1.f;
      }
    }
  }
  for (size_t i = 0; i < img.size(); ++i)
    if (cover[i] > 0.f) img[i] /= cover[i], cover[i] = 1.f;
  // Fill uncovered pixels from covered neighbours (repeated dilation), so that bilinear
  // sampling at a chart's border never mixes in black.
  for (int pass = 0; pass < n; ++pass) {
    bool changed = false;
    std::vector<float> next = img, next_cover = cover;
    for (int y = 0; y < n; ++y) {
      for (int x = 0; x < n; ++x) {
        const size_t i = size_t(y) * n + x;
        if (cover[i] > 0.f) continue;
        float sum = 0.f, cnt = 0.f;
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const int xx = x + dx, yy = y + dy;
            if (xx < 0 || yy < 0 || xx >= n || yy >= n) continue;
            const size_t j = size_t(yy) * n + xx;
            if (cover[j] > 0.f) sum += img[j], cnt += 1.f;
          }
        if (cnt > 0.f) next[i] = sum / cnt, next_cover[i] = 1.f, changed = true;
      }
    }
    img.swap(next);
    cover.swap(next_cover);
    if (!changed) break;
  }
  // Separable Gaussian blur (Bando 2003 §6: "a Gaussian filter so that the thickness changes
  // continuously").
  if (blur_sigma_px > 0.f) {
    const int r = int(std::ceil(3.f * blur_sigma_px));
    std::vector<float> k(size_t(2 * r + 1));
    float ksum = 0.f;
    for (int i = -r; i <= r; ++i) ksum += k[size_t(i + r)] = std::exp(-0.5f * float(i * i) / (blur_sigma_px * blur_sigma_px));
    for (float& w : k) w /= ksum;
    std::vector<float> tmp(img.size());
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        float acc = 0.f;
        for (int i = -r; i <= r; ++i) acc += k[size_t(i + r)] * img[size_t(y) * n + std::clamp(x + i, 0, n - 1)];
        tmp[size_t(y) * n + x] = acc;
      }
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x) {
        float acc = 0.f;
        for (int i = -r; i <= r; ++i) acc += k[size_t(i + r)] * tmp[size_t(std::clamp(y + i, 0, n - 1)) * n + x];
        img[size_t(y) * n + x] = acc;
      }
  }
  gray->resize(img.size());
  for (size_t i = 0; i < img.size(); ++i)
    (*gray)[i] = uint8_t(std::lround(ClampOrLow(img[i] / vmax, 0.f, 1.f) * 255.f));
  *max_value = vmax;
  return true;
}


// ---------------------------------------------------------------------------------------------
// Landmark transfer (docs/landmarks-format.md, "Heads without landmarks")

namespace {

struct MidlineFeatures {
  float3 nose_tip, nasion;
  bool ok = false;
};

// The frontmost midline silhouette, sampled in 200 height bins: nose tip = its most forward
// point; nasion = its deepest point between 5% and 30% of the mesh height above the tip.
MidlineFeatures FindMidlineFeatures(const MeshData& m) {
  MidlineFeatures f;
  const BoundingBox box = ComputeBounds(m.positions);
  const float3 lo = box.Lo(), hi = box.Hi();
  const float width = hi.x - lo.x, height = hi.y - lo.y;
  const float cx = 0.5f * (lo.x + hi.x);
  const int bins = 200;
  std::vector<int> best(bins, -1);
  for (size_t v = 0; v < m.vertex_count(); ++v) {
    const float3 p = m.positions[v];
    if (std::fabs(p.x - cx) > 0.01f * width) continue;
    const int b = std::clamp(int((p.y - lo.y) / height * bins), 0, bins - 1);
    if (best[b] < 0 || p.z > m.positions[size_t(best[b])].z) best[b] = int(v);
  }
  int tip = -1;
  for (int b = 0; b < bins; ++b)
    if (best[b] >= 0 && (tip < 0 || m.positions[size_t(best[b])].z > m.positions[size_t(tip)].z)) tip = best[b];
  if (tip < 0) return f;
  f.nose_tip = m.positions[size_t(tip)];
  int nasion = -1;
  for (int b = 0; b < bins; ++b) {
    if (best[b] < 0) continue;
    const float3 p = m.positions[size_t(best[b])];
    if (p.y < f.nose_tip.y + 0.05f * height || p.y > f.nose_tip.y + 0.3f * height) continue;
    if (nasion < 0 || p.z < m.positions[size_t(nasion)].z) nasion = best[b];
  }
  if (nasion < 0) return f;
  f.nasion = m.positions[size_t(nasion)];
  f.ok = Length(f.nasion - f.nose_tip) > 0.f;
  return f;
}

}  // namespace

bool TransferLandmarks(const MeshData& source, const std::vector<float3>& source_landmarks,
                       const MeshData& target, std::vector<uint32_t>* target_vertices,
                       Diagnostics* diag) {
  if (source.triangle_count() == 0 || target.triangle_count() == 0) {
    diag->Error("", "landmark transfer needs two non-empty meshes");
    return false;
  }
  FaceFrame frame;
  if (!ComputeFaceFrame(source_landmarks, &frame, diag)) return false;
  const MidlineFeatures fs = FindMidlineFeatures(source), ft = FindMidlineFeatures(target);
  if (!fs.ok || !ft.ok) {
    diag->Error(fs.ok ? target.source : source.source,
                "found no nose tip and nasion on the midline (x = centre of the bounding box); "
                "expected a head facing +Z with +Y up");
    return false;
  }
  // 1. Initial similarity: the nose tips coincide, the tip-nasion distances match.
  float scale[3];
  scale[0] = scale[1] = scale[2] = Length(ft.nasion - ft.nose_tip) / Length(fs.nasion - fs.nose_tip);
  float3 shift = ft.nose_tip - fs.nose_tip * scale[0];
  auto apply = [&](float3 p) { return float3{p.x * scale[0], p.y * scale[1], p.z * scale[2]} + shift; };
  // 2. Refine with a per-axis scale and a translation (iterated closest points) over the
  // source's face: x within the jaw contour, y from below the chin to above the brows, in
  // front of the ears.
  std::vector<float3> samples;
  for (const float3& p : source.positions) {
    const float3 l = frame.ToLocal(p);
    if (std::fabs(l.x) < 0.75f && l.y > -1.3f && l.y < 0.6f && l.z > -0.45f) samples.push_back(p);
  }
  const SurfaceQuery query(target);
  for (int iter = 0; iter < 30 && samples.size() >= 16; ++iter) {
    std::vector<std::pair<float3, float3>> pairs;
    std::vector<float> dist;
    for (const float3& p : samples) {
      const SurfaceQuery::Hit h = query.Nearest(apply(p));
      pairs.push_back({p, h.point});
      dist.push_back(h.t);
    }
    std::vector<float> sorted = dist;
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
    const float cutoff = 3.f * sorted[sorted.size() / 2] + 1e-6f;
    double mp[3] = {0, 0, 0}, mq[3] = {0, 0, 0}, n = 0;
    for (size_t i = 0; i < pairs.size(); ++i) {
      if (dist[i] > cutoff) continue;
      for (int a = 0; a < 3; ++a) mp[a] += Comp(pairs[i].first, a), mq[a] += Comp(pairs[i].second, a);
      n += 1;
    }
    if (n < 8) break;
    for (int a = 0; a < 3; ++a) mp[a] /= n, mq[a] /= n;
    double num[3] = {0, 0, 0}, den[3] = {0, 0, 0};
    for (size_t i = 0; i < pairs.size(); ++i) {
      if (dist[i] > cutoff) continue;
      for (int a = 0; a < 3; ++a) {
        const double dp = Comp(pairs[i].first, a) - mp[a], dq = Comp(pairs[i].second, a) - mq[a];
        num[a] += dp * dq;
        den[a] += dp * dp;
      }
    }
    for (int a = 0; a < 3; ++a)
      if (den[a] > 0 && num[a] > 0) scale[a] = float(num[a] / den[a]);
    shift = {float(mq[0] - scale[0] * mp[0]), float(mq[1] - scale[1] * mp[1]),
             float(mq[2] - scale[2] * mp[2])};
  }
  // 3. Each landmark: the nearest target surface point, then the nearest target vertex.
  target_vertices->assign(source_landmarks.size(), 0);
  for (size_t l = 0; l < source_landmarks.size(); ++l) {
    const SurfaceQuery::Hit h = query.Nearest(apply(source_landmarks[l]));
    float best = kInf;
    for (size_t v = 0; v < target.vertex_count(); ++v) {
      const float d = LengthSquared(target.positions[v] - h.point);
      if (d < best) best = d, (*target_vertices)[l] = uint32_t(v);
    }
  }
  return true;
}

}  // namespace mimetic

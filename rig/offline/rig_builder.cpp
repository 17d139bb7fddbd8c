#include "rig/offline/rig_builder.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <string>
#include <unordered_map>

#include "muscles/offline/muscle_builder.h"
#include "muscles/offline/waters.h"
#include "geometry/normals.h"
#include "geometry/bounds.h"
#include "geometry/orientation.h"
#include "geometry/refine.h"
#include "geometry/refine_estimate.h"
#include "geometry/topology.h"
#include "geometry/weld.h"
#include "rig/runtime/evaluate_job.h"
#include "rig/runtime/normals_job.h"
#include "wrinkles/offline/bezier.h"
#include "wrinkles/offline/wrinkle_builder.h"

namespace mimetic {
namespace {

bool ResolveThickness(const ThicknessSpec& spec, const MeshData& mesh, const WeldedMesh& welded,
                      std::vector<float>* out, Diagnostics* diag) {
  const size_t points = welded.points.size();
  out->assign(points, 0.f);
  switch (spec.kind) {
    case ThicknessSpec::Kind::kConstant:
      out->assign(points, spec.value);
      return true;
    case ThicknessSpec::Kind::kPerVertex: {
      if (spec.per_vertex.size() != mesh.vertex_count()) {
        diag->Error("thickness.values",
                    "expected one value per mesh vertex (" + std::to_string(mesh.vertex_count()) +
                        "), got " + std::to_string(spec.per_vertex.size()));
        return false;
      }
      std::vector<uint32_t> count(points, 0);
      for (size_t v = 0; v < mesh.vertex_count(); ++v) {
        (*out)[welded.point_of_vertex[v]] += spec.per_vertex[v];
        ++count[welded.point_of_vertex[v]];
      }
      for (size_t p = 0; p < points; ++p) (*out)[p] /= float(count[p] ? count[p] : 1);
      return true;
    }
    case ThicknessSpec::Kind::kImage: {
      if (mesh.uvs.size() != mesh.vertex_count()) {
        diag->Error("thickness", "a thickness image needs texture coordinates, and mesh '" +
                                     mesh.source + "' has none");
        return false;
      }
      if (spec.image.empty()) {  // io's LoadRig decodes it (io/rig_loader.h)
        diag->Error("thickness.path", "thickness image '" + spec.image_path +
                                          "' was not decoded (load the rig with LoadRig, or fill "
                                          "ThicknessSpec::image before BuildRig)");
        return false;
      }
      const std::vector<uint8_t>& gray = spec.image.pixels;
      const int width = spec.image.width, height = spec.image.height;
      // Gray level in [0, 1] at every file vertex (002 §6), then min + (max - min) * g.
      std::vector<float> level;
      if (!SampleThicknessMap(gray, width, height, 1.f, mesh.uvs, "thickness", &level, diag))
        return false;
      std::vector<uint32_t> count(points, 0);
      for (size_t v = 0; v < mesh.vertex_count(); ++v) {
        (*out)[welded.point_of_vertex[v]] += spec.min + (spec.max - spec.min) * level[v];
        ++count[welded.point_of_vertex[v]];
      }
      for (size_t p = 0; p < points; ++p) (*out)[p] /= float(count[p] ? count[p] : 1);
      return true;
    }
  }
  return false;
}


// The nearest point of segment [a, b] to x, as a distance.
float SegmentDistance(float3 x, float3 a, float3 b) {
  const float3 ab = b - a;
  const float len2 = Dot(ab, ab);
  const float t = len2 > 0.f ? std::fmin(std::fmax(Dot(x - a, ab) / len2, 0.f), 1.f) : 0.f;
  return Length(x - (a + ab * t));
}

// docs/model.md §18: the jaw's hinge, range and per-point weights (explicit per file vertex,
// averaged over a point's vertices, or the region function of the rest position and normal). Only points
// with w > 0 are listed.
bool CompileJaw(const RigSpec& spec, const MeshData& mesh, const WeldedMesh& welded,
                RigData* rig, Diagnostics* diag) {
  if (!spec.jaw) return true;
  const JawSpec& jaw = *spec.jaw;
  JawFrame frame;
  if (!MakeJawFrame(jaw, &frame)) {
    diag->Error("jaw", Length(jaw.condyles[1] - jaw.condyles[0]) > 0.f
                           ? "the mouth point lies on the hinge axis through the condyles; "
                             "expected jaw.mouth in front of the condyles"
                           : "the two condyles coincide; expected two distinct points (the "
                             "subject's right, then left condyle)");
    return false;
  }
  if (!IsFinite(jaw.translation) || Length(jaw.translation) > frame.reach) {
    char buf[160];
    std::snprintf(buf, sizeof buf, "is %g long; expected a glide no longer than the hinge-to-mouth "
                  "distance (%g mesh units)", double(Length(jaw.translation)), double(frame.reach));
    diag->Error("jaw.translation", buf);
    return false;
  }
  const uint32_t points = uint32_t(welded.points.size());
  std::vector<float> w(points, 0.f);
  if (!jaw.weights.empty()) {
    if (jaw.weights.size() != mesh.vertex_count()) {
      diag->Error("jaw.weights", "expected one value per mesh vertex (" +
                                     std::to_string(mesh.vertex_count()) + "), got " +
                                     std::to_string(jaw.weights.size()));
      return false;
    }
    std::vector<uint32_t> count(points, 0);
    for (size_t v = 0; v < mesh.vertex_count(); ++v) {
      w[welded.point_of_vertex[v]] += jaw.weights[v];
      ++count[welded.point_of_vertex[v]];
    }
    for (uint32_t p = 0; p < points; ++p) w[p] = std::min(w[p] / float(count[p] ? count[p] : 1), 1.f);
  } else {
    VertexNormalOptions no;
    no.fallback = {};  // a point without a normal takes no side on the lip line
    const std::vector<float3> normals = ComputeVertexNormals(welded.points, welded.triangles, no);
    for (uint32_t p = 0; p < points; ++p)
      w[p] = JawRegionWeight(jaw, frame, welded.points[p], normals[p]);
  }
  // The lips carry no fat: thickness fades in from the edge of the slit between them.
  if (jaw.thickness_fade > 0.f && jaw.mouth_width > 0.f && !rig->point_thickness.empty()) {
    const float fade = jaw.thickness_fade * jaw.mouth_width;
    const std::vector<float> d = MouthEdgeDistances(jaw, welded.points, welded.triangles, fade);
    for (size_t p = 0; p < d.size() && p < rig->point_thickness.size(); ++p)
      rig->point_thickness[p] *= Smoothstep(0.f, fade, d[p]);
  }
  RigJaw& out = rig->jaw;
  out.pivot = frame.pivot;
  out.axis = frame.axis;
  out.range = float(double(jaw.range_deg) * 3.14159265358979323846 / 180.0);
  out.translation = jaw.translation;
  for (uint32_t p = 0; p < points; ++p)
    if (w[p] > 0.f) {
      out.points.push_back(p);
      out.weights.push_back(w[p]);
    }
  if (out.points.empty())
    diag->Warning("jaw", "no vertex of the mesh has a jaw weight above 0: check the mouth point "
                         "and the condyles against the mesh's units and placement");
  return true;
}

// The points a muscle or the jaw moves themselves (1), before their neighbours are added
// (MovingPoints below; CompileEyes).
std::vector<uint8_t> MovedByMuscleOrJaw(const RigData& rig) {
  const uint32_t points = rig.point_count();
  std::vector<uint8_t> moved(points, 0);
  for (uint32_t p = 0; p < points; ++p)
    moved[p] = rig.muscles.offsets[p + 1] > rig.muscles.offsets[p];
  for (uint32_t p : rig.jaw.points) moved[p] = 1;  // the jaw turns them (docs/model.md §18)
  return moved;
}

// docs/model.md §24: the points a muscle or the jaw moves that lie in the band over an
// eyeball, each with its nearest eyeball (largest weight; the first on a tie), its rest
// distance from that eyeball's centre and its weight EyeSlideWeight; their thickness is
// scaled by 1 - weight.
bool CompileEyes(const RigSpec& spec, RigData* rig, Diagnostics* diag) {
  if (!spec.eyes) return true;
  const EyesSpec& eyes = *spec.eyes;
  RigEyes& out = rig->eyes;
  for (const EyeSphere& s : eyes.spheres) out.centers.push_back(s.center);
  const uint32_t points = rig->point_count();
  const std::vector<uint8_t> moved = MovedByMuscleOrJaw(*rig);
  for (uint32_t p = 0; p < points; ++p) {
    if (!moved[p]) continue;
    const float3 x = rig->rest_points[p];
    float best = 0.f, radius = 0.f;
    uint32_t eye = 0;
    for (uint32_t e = 0; e < eyes.spheres.size(); ++e) {
      const float r = Length(x - eyes.spheres[e].center);
      const float w = EyeSlideWeight(r - eyes.spheres[e].radius, eyes.band);
      if (w > best) best = w, radius = r, eye = e;
    }
    if (best > 0.f && radius > 0.f) {
      // The lids' skin lies on the globe without subcutaneous fat: no thickness to bulge
      // where it slides (docs/model.md §24).
      if (p < rig->point_thickness.size()) rig->point_thickness[p] *= 1.f - best;
      out.points.push_back(p);
      out.eyes.push_back(eye);
      out.radii.push_back(radius);
      out.weights.push_back(best);
    }
  }
  if (out.points.empty())
    diag->Warning("eyes", "no vertex that a muscle or the jaw moves lies within eyes.band of an "
                          "eyeball: check the spheres and the band against the mesh's units "
                          "and placement");
  return true;
}

// docs/tension.md: each tension region's weights checked (one per mesh vertex, in [0, 1]) and
// averaged onto the welded points (as per-vertex thickness is); the rig keeps the points with a
// weight above 0, ascending.
bool CheckTensionRegionWeights(const RigSpec& spec, size_t vertex_count, Diagnostics* diag) {
  bool ok = true;
  for (size_t i = 0; i < spec.tension_regions.size(); ++i) {
    const TensionRegionSpec& g = spec.tension_regions[i];
    const std::string where =
        "tension_regions[" + std::to_string(i) + "] (" + g.name + ")";
    if (g.weights.size() != vertex_count) {
      diag->Error(where + ".weights", "expected one value per mesh vertex (" +
                                          std::to_string(vertex_count) + "), got " +
                                          std::to_string(g.weights.size()));
      ok = false;
      continue;
    }
    for (size_t v = 0; v < g.weights.size(); ++v) {
      if (!(g.weights[v] >= 0.f && g.weights[v] <= 1.f)) {
        diag->Error(where + ".weights[" + std::to_string(v) + "]",
                    "is " + std::to_string(g.weights[v]) + "; expected a number in [0, 1]");
        ok = false;
        break;
      }
    }
    if (!(g.reference > 0.f) || !std::isfinite(g.reference)) {
      diag->Error(where + ".reference", "is " + std::to_string(g.reference) +
                                            "; expected a finite number > 0");
      ok = false;
    }
    if (g.name.empty()) {
      diag->Error(where + ".name", "is empty; expected a region name");
      ok = false;
    }
    for (size_t k = 0; k < i; ++k)
      if (spec.tension_regions[k].name == g.name) {
        diag->Error(where + ".name", "repeats tension_regions[" + std::to_string(k) +
                                         "]; expected a name unique among the regions");
        ok = false;
      }
  }
  return ok;
}

bool ResolveTensionRegions(const RigSpec& spec, const MeshData& mesh, const WeldedMesh& welded,
                           RigData* rig, Diagnostics* diag) {
  RigTensionRegions& out = rig->tension_regions;
  out = RigTensionRegions();
  if (spec.tension_regions.empty()) return true;
  if (!CheckTensionRegionWeights(spec, mesh.vertex_count(), diag)) return false;
  const size_t points = welded.points.size();
  std::vector<float> sum(points);
  std::vector<uint32_t> count(points);
  out.offsets.push_back(0);
  for (const TensionRegionSpec& g : spec.tension_regions) {
    std::fill(sum.begin(), sum.end(), 0.f);
    std::fill(count.begin(), count.end(), 0u);
    for (size_t v = 0; v < mesh.vertex_count(); ++v) {
      sum[welded.point_of_vertex[v]] += g.weights[v];
      ++count[welded.point_of_vertex[v]];
    }
    for (uint32_t p = 0; p < points; ++p) {
      const float w = count[p] ? std::min(sum[p] / float(count[p]), 1.f) : 0.f;
      if (w > 0.f) {
        out.points.push_back(p);
        out.weights.push_back(w);
      }
    }
    out.names.push_back(g.name);
    out.references.push_back(g.reference);
    out.offsets.push_back(uint32_t(out.points.size()));
  }
  return true;
}

// docs/model.md §4-8: rest areas, muscle wrinkling regions, curve-wrinkle distances and probes.
bool CompileSkinLayers(const RigSpec& spec, const MeshData& mesh,
                       const std::vector<uint32_t>& file_triangle, RigData* rig,
                       Diagnostics* diag) {
  bool ok = true;
  bool any_thickness = false;
  for (float h : rig->point_thickness) any_thickness |= h > 0.f;
  rig->layers.thickness = spec.layers.thickness && any_thickness;

  if (spec.layers.muscle_wrinkles && !spec.muscle_wrinkles.empty()) {
    const CsrTable neighbors = BuildPointNeighbors(rig->triangles, rig->point_count());
    for (size_t m = 0; m < spec.muscles.size() && m < spec.muscle_wrinkles.size(); ++m) {
      if (!spec.muscle_wrinkles[m]) continue;
      MuscleWrinkleTable table;
      const std::string where = "muscles[" + std::to_string(m) + "].wrinkles";
      if (!BuildMuscleWrinkleTable(*spec.muscle_wrinkles[m], WrinkleGeometryOf(spec.muscles[m]),
                                   rig->rest_points, neighbors, where, &table, diag)) {
        ok = false;
        continue;
      }
      if (table.points.empty()) continue;
      RigMuscleWrinkles w;
      w.muscle = uint32_t(m);
      w.points = std::move(table.points);
      w.phase = std::move(table.phase);
      w.attenuation = std::move(table.attenuation);
      w.edge_offsets = std::move(table.edge_offsets);
      w.edge_neighbors = std::move(table.edge_neighbors);
      w.edge_rest_lengths = std::move(table.edge_rest_lengths);
      w.edge_weights = std::move(table.edge_weights);
      w.half_cycle = table.half_cycle;
      w.furrow_depth = table.furrow_depth;
      w.shape = table.shape;
      w.gate = spec.muscle_wrinkles[m]->gate;
      w.profile.resize(w.points.size());
      for (size_t i = 0; i < w.points.size(); ++i)
        w.profile[i] = MuscleWrinkleProfile(w.phase[i], w.half_cycle, w.furrow_depth, w.shape,
                                            w.attenuation[i]);
      rig->muscle_wrinkles.push_back(std::move(w));
    }
  }
  rig->layers.muscle_wrinkles = !rig->muscle_wrinkles.empty();

  if (spec.layers.curve_wrinkles && !spec.curve_wrinkles.empty()) {
    if (mesh.uvs.size() != mesh.vertex_count()) {
      diag->Error("curve_wrinkles", "curve wrinkles are drawn in texture space, and mesh '" +
                                        mesh.source + "' has no texture coordinates");
      ok = false;
    } else {
      // Texture coordinates of each internal triangle's corners, from its file triangle.
      std::vector<float2> corner_uvs(mesh.indices.size());
      for (size_t t = 0; t < file_triangle.size(); ++t)
        for (int k = 0; k < 3; ++k)
          corner_uvs[3 * t + k] = mesh.uvs[mesh.indices[3 * size_t(file_triangle[t]) + k]];
      std::vector<CurveWrinkleSpec> specs;
      for (const NamedCurveWrinkle& c : spec.curve_wrinkles) specs.push_back(c.spec);
      CurveWrinkleTable table;
      if (BuildCurveWrinkleTable(specs, rig->rest_points, rig->triangles, corner_uvs,
                                 "curve_wrinkles", &table, diag)) {
        RigCurveWrinkles& c = rig->curve_wrinkles;
        for (const NamedCurveWrinkle& n : spec.curve_wrinkles) c.names.push_back(n.name);
        c.wrinkles = std::move(table.wrinkles);
        c.points = std::move(table.points);
        c.offsets = std::move(table.offsets);
        c.entries = std::move(table.entries);
        c.probes = std::move(table.probes);
      } else {
        ok = false;
      }
    }
  }
  rig->layers.curve_wrinkles = !rig->curve_wrinkles.entries.empty();

  // (A rig with tension regions keeps the rest areas too: EvaluateJob measures r for them.)
  if (rig->layers.thickness || rig->layers.muscle_wrinkles || rig->layers.curve_wrinkles ||
      !spec.tension_regions.empty()) {
    rig->rest_triangle_areas.resize(rig->triangle_count());
    for (uint32_t t = 0; t < rig->triangle_count(); ++t)
      rig->rest_triangle_areas[t] = TriangleRestArea(rig->rest_points[rig->triangles[3 * t]],
                                                     rig->rest_points[rig->triangles[3 * t + 1]],
                                                     rig->rest_points[rig->triangles[3 * t + 2]]);
  }
  return ok;
}

// docs/model.md §11: the input's slivers (TriangleShape under kSliverShape, as the crease meter
// leaves out), each as a ball of radius L (its longest edge) about its centroid, which holds its
// edges' midpoints and its neighbours'. Fall-off refinement stays out of them: splitting a sliver
// keeps its height while its new points move with the muscle field instead of along its edge,
// so a sliver 0.07 mm high and 17 mm long (the sample head's submental pinch) turns over under
// motions that leave it whole alone.
class SliverBalls {
 public:
  explicit SliverBalls(const MeshData& mesh) {
    for (size_t t = 0; t < mesh.triangle_count(); ++t) {
      const float3 a = mesh.positions[mesh.indices[3 * t]], b = mesh.positions[mesh.indices[3 * t + 1]],
                   c = mesh.positions[mesh.indices[3 * t + 2]];
      if (!(TriangleShape(a, b, c) < kSliverShape)) continue;
      const double l = std::max({double(Length(b - a)), double(Length(c - b)), double(Length(a - c))});
      if (!(l > 0.0)) continue;
      balls_.push_back({(a + b + c) * (1.f / 3.f), l});
      cell_ = std::max(cell_, l);
    }
    for (uint32_t i = 0; i < balls_.size(); ++i) grid_[Key(balls_[i].center, 0, 0, 0)].push_back(i);
  }
  bool Holds(float3 p) const {
    if (balls_.empty()) return false;
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          const auto it = grid_.find(Key(p, dx, dy, dz));
          if (it == grid_.end()) continue;
          for (uint32_t i : it->second) {
            const float3 d = p - balls_[i].center;
            if (double(d.x) * d.x + double(d.y) * d.y + double(d.z) * d.z <= balls_[i].r * balls_[i].r)
              return true;
          }
        }
    return false;
  }

 private:
  struct Ball {
    float3 center;
    double r;
  };
  uint64_t Key(float3 p, int dx, int dy, int dz) const {
    // Clamped, so that a tiny sliver's cell cannot overflow (far cells then share keys: more
    // balls to test, never a wrong answer).
    auto c = [&](float v, int d) {
      const double q = std::clamp(std::floor(double(v) / cell_), -1e6, 1e6);
      return uint64_t(int64_t(q) + d) & 0x1FFFFF;
    };
    return c(p.x, dx) << 42 | c(p.y, dy) << 21 | c(p.z, dz);
  }
  std::vector<Ball> balls_;
  double cell_ = 0.0;
  std::unordered_map<uint64_t, std::vector<uint32_t>> grid_;
};

// docs/model.md §11: the target edge length at a surface place, the smallest over the wrinkles
// whose support holds it (fraction x width: u for a muscle wrinkle, whose furrows are u wide,
// w or a0 for a curve wrinkle), +infinity elsewhere. A curve's support is measured in texture
// space with the texture-to-mesh scale of the triangles around it, and widened by their
// longest edge so that sampling at centroids and edge midpoints cannot miss a narrow one
// (local, so that a coarse back of the head does not widen a crow's foot).
EdgeLengthField MakeRefinementField(const RigSpec& spec, const MeshData& mesh) {
  const float fraction = spec.refinement.edge_fraction;
  struct MuscleRegion {
    MuscleWrinkleSpec spec;
    WrinkleMuscleGeometry geometry;
    float target;
    // A ball around the region's origin that holds S_w (001 eq. 3 / 14), with a margin: a
    // sample outside it is outside the region, so SampleMuscleWrinkleRegion need not run.
    // Linear: l = |v| cos(phi) <= R with phi <= the zone angle, so |v| <= R / cos(angle)
    // (no ball past 89 degrees); sheet: l <= Ls and h <= Ws / 2.
    float3 center;
    double reach2;
  };
  struct Curve {
    CurveWrinkleSpec spec;
    float2 lo, hi;  // the control polygon's texture bounding box (holds the curve)
    float uv_reach, uv_scale, target;  // reach in texture units; scale: mesh units per uv unit
  };
  std::vector<MuscleRegion> regions;
  std::vector<Curve> curves;
  auto sq = [](double v) { return v * v; };
  if (spec.layers.muscle_wrinkles) {
    for (size_t m = 0; m < spec.muscles.size() && m < spec.muscle_wrinkles.size(); ++m) {
      if (!spec.muscle_wrinkles[m]) continue;
      MuscleRegion r{*spec.muscle_wrinkles[m], WrinkleGeometryOf(spec.muscles[m]), 0.f, {},
                     std::numeric_limits<double>::infinity()};
      r.target = fraction * SampleMuscleWrinkleRegion(r.spec, r.geometry, {}).half_cycle;
      const WrinkleMuscleGeometry& g = r.geometry;
      if (g.kind == WrinkleMuscleKind::kLinear) {
        r.center = g.attachment;
        const double c = std::cos(double(g.zone_angle));
        constexpr double kLimit = 89.0 * 3.14159265358979323846 / 180.0;  // radians
        if (c >= std::cos(kLimit)) r.reach2 = sq(double(g.radius) / c);
      } else {
        r.center = (g.attachment_line[0] + g.attachment_line[1]) * 0.5f;
        r.reach2 = sq(double(g.length)) + sq(0.5 * g.width);
      }
      r.reach2 = r.reach2 * 1.001 + 1e-12;
      regions.push_back(r);
    }
  }
  const bool has_uvs = mesh.uvs.size() == mesh.vertex_count();
  if (spec.layers.curve_wrinkles && has_uvs) {
    for (const NamedCurveWrinkle& c : spec.curve_wrinkles) {
      // Triangles with a corner in the curve's texture bounding box (a Bezier lies in its
      // control polygon's hull), grown until they hold the support: their scale and edges.
      float2 lo = c.spec.control[0], hi = c.spec.control[0];
      for (const float2& q : c.spec.control) {
        lo = {std::min(lo.x, q.x), std::min(lo.y, q.y)};
        hi = {std::max(hi.x, q.x), std::max(hi.y, q.y)};
      }
      // **choice**: refine the profile's core, not its whole tail: for Bando, 4 w (beyond it
      // |S| < 3 e^-4 d = 0.055 d and S varies slowly, which the unrefined mesh follows);
      // the displacement itself still reaches CurveWrinkleSupport (8 w).
      const float support = c.spec.profile == CurveWrinkleProfile::kBando
                                ? 4.f * c.spec.width
                                : CurveWrinkleSupport(c.spec);
      double area3 = 0, area2 = 0, longest = 0;
      float grow = 0.f;
      for (int round = 0; round < 2; ++round) {
        area3 = area2 = longest = 0;
        for (size_t t = 0; t < mesh.triangle_count(); ++t) {
          const uint32_t* i = &mesh.indices[3 * t];
          bool inside = false;
          for (int k = 0; k < 3; ++k) {
            const float2 q = mesh.uvs[i[k]];
            inside |= q.x >= lo.x - grow && q.x <= hi.x + grow && q.y >= lo.y - grow && q.y <= hi.y + grow;
          }
          if (!inside) continue;
          const float3 a = mesh.positions[i[0]], b = mesh.positions[i[1]], d = mesh.positions[i[2]];
          area3 += 0.5 * Length(Cross(b - a, d - a));
          const float2 p = mesh.uvs[i[0]], q = mesh.uvs[i[1]], r = mesh.uvs[i[2]];
          area2 += 0.5 * std::fabs(double(q.x - p.x) * (r.y - p.y) - double(q.y - p.y) * (r.x - p.x));
          longest = std::max({longest, double(Length(b - a)), double(Length(d - b)), double(Length(a - d))});
        }
        if (!(area2 > 0)) break;
        grow = float((support + longest) / std::sqrt(area3 / area2));  // texture units
      }
      if (!(area2 > 0)) continue;
      const float uv_scale = float(std::sqrt(area3 / area2));
      curves.push_back({c.spec, lo, hi, float((support + longest) / uv_scale), uv_scale,
                        fraction * c.spec.width});
    }
  }
  // Fall-offs (docs/model.md §11): every muscle, when asked for; h = sqrt(8 E / c) keeps the
  // linear interpolation of its profile within E of its peak. Not near the input's slivers.
  std::vector<MuscleSpec> falloffs;
  const double error = spec.refinement.falloff_error;
  if (error > 0.0) falloffs = spec.muscles;
  std::shared_ptr<const SliverBalls> slivers;
  if (!falloffs.empty()) slivers = std::make_shared<const SliverBalls>(mesh);
  std::vector<MuscleBall> balls;  // where each fall-off bends at all
  for (const MuscleSpec& m : falloffs) balls.push_back(MuscleFalloffCurvatureBall(m));
  return [regions, curves, falloffs, balls, error, slivers](float3 position, float2 uv) {
    float target = std::numeric_limits<float>::infinity();
    double largest = 0.0;
    for (size_t k = 0; k < falloffs.size(); ++k)
      if (balls[k].Holds(position)) largest = std::max(largest, MuscleFalloffCurvature(falloffs[k], position));
    if (largest > 0.0 && !slivers->Holds(position))
      target = float(std::sqrt(8.0 * error / largest));
    for (const MuscleRegion& r : regions) {
      if (!(r.target > 0.f) || r.target >= target) continue;
      const float3 v = position - r.center;
      if (double(v.x) * v.x + double(v.y) * v.y + double(v.z) * v.z > r.reach2) continue;
      if (SampleMuscleWrinkleRegion(r.spec, r.geometry, position).inside) target = r.target;
    }
    for (const Curve& c : curves) {
      if (!(c.target > 0.f) || c.target >= target) continue;
      // Distance to the box bounds the distance to the curve from below: a cheap reject.
      const float dx = std::max({c.lo.x - uv.x, 0.f, uv.x - c.hi.x});
      const float dy = std::max({c.lo.y - uv.y, 0.f, uv.y - c.hi.y});
      if (dx * dx + dy * dy > c.uv_reach * c.uv_reach) continue;
      const BezierReach near = ClassifyBezierReach(c.spec.control, uv, c.uv_reach);
      if (near == BezierReach::kWithin ||
          (near == BezierReach::kUnsure &&
           ClosestPointOnBezier(c.spec.control, uv).distance <= c.uv_reach))
        target = c.target;
    }
    return target;
  };
}

std::string Short(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

double MmPerUnit(const std::string& units) {
  if (units == "cm") return 10.0;
  if (units == "dm") return 100.0;
  if (units == "m") return 1000.0;
  if (units == "in") return 25.4;
  return 1.0;
}

// Issue 11: finite but absurd values (coordinates at 1e38, a thickness or wrinkle depth of
// 3e38) are errors naming the key, checked against the mesh's size.
bool ValidateMagnitudes(const RigSpec& spec, const MeshData& mesh, Diagnostics* diag) {
  const size_t errors_before = diag->ErrorCount();
  const std::string units = spec.units.empty() ? "mm" : spec.units;
  const double max_coordinate = kMaxCoordinateMm / MmPerUnit(units);
  const std::string mesh_name = mesh.source.empty() ? "the mesh" : mesh.source;
  {
    size_t far = 0, first = 0;
    for (size_t v = 0; v < mesh.vertex_count(); ++v) {
      const float3 p = mesh.positions[v];
      const double c[3] = {p.x, p.y, p.z};
      if (!std::isfinite(c[0]) || !std::isfinite(c[1]) || !std::isfinite(c[2])) continue;  // weld's
      if (std::max({std::fabs(c[0]), std::fabs(c[1]), std::fabs(c[2])}) > max_coordinate) {
        if (far++ == 0) first = v;
      }
    }
    if (far > 0) {
      const float3 p = mesh.positions[first];
      diag->Error(mesh_name, std::to_string(far) + " vertices have a coordinate beyond " +
                                 Short(max_coordinate) + " " + units + " (" +
                                 Short(kMaxCoordinateMm / 1e6) + " km; first: vertex " +
                                 std::to_string(first) + " at (" + Short(p.x) + ", " + Short(p.y) +
                                 ", " + Short(p.z) + ")); expected a head-sized mesh in " + units);
      return false;
    }
  }
  const BoundingBox box = ComputeBounds(mesh.positions);
  const double size = box.Diagonal();
  if (!(size > 0.0) || !std::isfinite(size)) return true;  // WeldMesh reports the mesh
  const double centre[3] = {0.5 * (box.lo[0] + box.hi[0]), 0.5 * (box.lo[1] + box.hi[1]),
                            0.5 * (box.lo[2] + box.hi[2])};
  const double limit = kMaxLengthFactor * size;
  const std::string about = "more than " + Short(kMaxLengthFactor) + " times the mesh's size "
                            "(bounding-box diagonal " + Short(size) + " " + units + ")";
  auto length = [&](const std::string& where, float value) {
    if (double(value) <= limit) return;
    diag->Error(where, "is " + Short(value) + " " + units + ", " + about +
                           "; expected a length at most " + Short(limit) + " " + units);
  };
  auto point = [&](const std::string& where, float3 p) {
    const double d = std::hypot(double(p.x) - centre[0], double(p.y) - centre[1],
                                double(p.z) - centre[2]);
    if (d <= limit && std::max({std::fabs(p.x), std::fabs(p.y), std::fabs(p.z)}) <= max_coordinate)
      return;
    diag->Error(where, "(" + Short(p.x) + ", " + Short(p.y) + ", " + Short(p.z) + ") is " +
                           Short(d) + " " + units + " from the mesh's centre, " + about +
                           "; expected a point near the mesh, in its units and frame");
  };
  const ThicknessSpec& t = spec.thickness;
  switch (t.kind) {
    case ThicknessSpec::Kind::kConstant: length("thickness.value", t.value); break;
    case ThicknessSpec::Kind::kPerVertex: {
      CappedErrors capped(diag, "thickness.values", "thickness values too large");
      for (size_t v = 0; v < t.per_vertex.size(); ++v)
        if (double(t.per_vertex[v]) > limit)
          capped.Add("thickness.values[" + std::to_string(v) + "]",
                     "is " + Short(t.per_vertex[v]) + " " + units + ", " + about +
                         "; expected a length at most " + Short(limit) + " " + units);
      break;
    }
    case ThicknessSpec::Kind::kImage:
      length("thickness.min", t.min);
      length("thickness.max", t.max);
      break;
  }
  for (size_t m = 0; m < spec.muscles.size(); ++m) {
    const MuscleSpec& ms = spec.muscles[m];
    const std::string at = "muscles[" + std::to_string(m) + "]";
    length(at + ".strength", ms.strength);
    if (ms.type == MuscleType::kLinear) {
      point(at + ".attachment", ms.linear.attachment);
      point(at + ".insertion", ms.linear.insertion);
      length(at + ".falloff_start", ms.linear.falloff_start);
      length(at + ".falloff_end", ms.linear.falloff_end);
    } else {
      for (int k = 0; k < 2; ++k) {
        point(at + ".attachment[" + std::to_string(k) + "]", ms.sheet.attachment[k]);
        point(at + ".insertion[" + std::to_string(k) + "]", ms.sheet.insertion[k]);
      }
      length(at + ".length", ms.sheet.length);
      length(at + ".width", ms.sheet.width);
      length(at + ".falloff_start", ms.sheet.falloff_start);
    }
    if (m < spec.muscle_wrinkles.size() && spec.muscle_wrinkles[m]) {
      length(at + ".wrinkles.depth", spec.muscle_wrinkles[m]->depth);
      length(at + ".wrinkles.h_c", spec.muscle_wrinkles[m]->h_c);
    }
  }
  for (size_t c = 0; c < spec.curve_wrinkles.size(); ++c) {
    const std::string at = "curve_wrinkles[" + std::to_string(c) + "]";
    length(at + ".depth", spec.curve_wrinkles[c].spec.depth);
    length(at + ".width", spec.curve_wrinkles[c].spec.width);
  }
  if (spec.jaw) {
    point("jaw.condyles[0]", spec.jaw->condyles[0]);
    point("jaw.condyles[1]", spec.jaw->condyles[1]);
    if (spec.jaw->weights.empty()) {
      point("jaw.mouth", spec.jaw->mouth);
      length("jaw.mouth_width", spec.jaw->mouth_width);
    }
  }
  return diag->ErrorCount() == errors_before;
}

// Issue 11: a wrinkle count near 2^31, a curve width of 0.01 mm or an edge_fraction of 1e-30
// drove refinement to millions of triangles and tens of seconds. Estimate first; refuse when
// the estimate passes the stated growth, naming the key that asks for the smallest edges (each
// wrinkle's estimate alone; refinement.edge_fraction when the default 0.25 would fit).
bool CheckRefinementGrowth(const RigSpec& spec, const MeshData& mesh,
                           const EdgeLengthField& field, const RefineOptions& options,
                           Diagnostics* diag) {
  const double input = double(mesh.triangle_count());
  const double limit = std::min(std::max(kMaxRefinementGrowth * input, kMinRefinementLimit),
                                double(options.max_triangles));
  const double estimate = EstimateRefinedTriangles(mesh, field, options);
  if (estimate <= limit) return true;
  // Which wrinkle: each alone.
  std::string where = "refinement", detail;
  double worst = -1;
  RigSpec alone = spec;
  alone.curve_wrinkles.clear();
  alone.muscle_wrinkles.assign(spec.muscle_wrinkles.size(), std::nullopt);
  alone.refinement.falloff_error = 0.f;
  if (spec.refinement.falloff_error > 0.f) {
    alone.refinement.falloff_error = spec.refinement.falloff_error;
    worst = EstimateRefinedTriangles(mesh, MakeRefinementField(alone, mesh), options);
    alone.refinement.falloff_error = 0.f;
    where = "refinement.falloff_error";
    detail = "refinement.falloff_error " + Short(spec.refinement.falloff_error) +
             " (where the muscles' fall-offs bend) alone would give about " + Short(worst) +
             " triangles";
  }
  if (spec.layers.muscle_wrinkles)
    for (size_t m = 0; m < spec.muscles.size() && m < spec.muscle_wrinkles.size(); ++m) {
      if (!spec.muscle_wrinkles[m]) continue;
      alone.muscle_wrinkles[m] = spec.muscle_wrinkles[m];
      const double e = EstimateRefinedTriangles(mesh, MakeRefinementField(alone, mesh), options);
      alone.muscle_wrinkles[m].reset();
      if (e <= worst) continue;
      worst = e;
      const MuscleWrinkleSpec& w = *spec.muscle_wrinkles[m];
      const float u = SampleMuscleWrinkleRegion(w, WrinkleGeometryOf(spec.muscles[m]), {}).half_cycle;
      where = "muscles[" + std::to_string(m) + "].wrinkles.count";
      detail = "muscles[" + std::to_string(m) + "].wrinkles (" + spec.muscles[m].name + ", count " +
               std::to_string(w.count) + ") makes furrows " + Short(u) + " wide, refined to edges of " +
               Short(spec.refinement.edge_fraction * u) + ", and alone would give about " +
               Short(e) + " triangles";
    }
  alone.muscle_wrinkles.assign(spec.muscle_wrinkles.size(), std::nullopt);
  if (spec.layers.curve_wrinkles)
    for (size_t c = 0; c < spec.curve_wrinkles.size(); ++c) {
      alone.curve_wrinkles = {spec.curve_wrinkles[c]};
      const double e = EstimateRefinedTriangles(mesh, MakeRefinementField(alone, mesh), options);
      if (e <= worst) continue;
      worst = e;
      const float w = spec.curve_wrinkles[c].spec.width;
      where = "curve_wrinkles[" + std::to_string(c) + "].width";
      detail = "curve_wrinkles[" + std::to_string(c) + "] (" + spec.curve_wrinkles[c].name +
               ", width " + Short(w) + ") is refined to edges of " +
               Short(spec.refinement.edge_fraction * w) + " and alone would give about " +
               Short(e) + " triangles";
    }
  if (spec.refinement.edge_fraction < kDefaultRefineWidthFraction) {
    RigSpec usual = spec;
    usual.refinement.edge_fraction = kDefaultRefineWidthFraction;
    if (EstimateRefinedTriangles(mesh, MakeRefinementField(usual, mesh), options) <= limit) {
      where = "refinement.edge_fraction";
      detail = "refinement.edge_fraction " + Short(spec.refinement.edge_fraction) +
               " asks for edges that short; the default " + Short(kDefaultRefineWidthFraction) +
               " would stay within the limit";
    }
  }
  diag->Error(where, std::string(spec.refinement.falloff_error > 0.f
                                     ? "refinement where wrinkles act and fall-offs bend"
                                     : "refinement where wrinkles act") +
                         " would grow the mesh from " +
                         std::to_string(mesh.triangle_count()) + " to about " + Short(estimate) +
                         " triangles, more than the limit of " + Short(limit) + " (" +
                         Short(kMaxRefinementGrowth) + "x the mesh's triangles, at least " +
                         Short(kMinRefinementLimit) + ", at most " +
                         Short(double(options.max_triangles)) + "; docs/model.md §11)" +
                         (detail.empty() ? "" : ": " + detail) +
                         "; use fewer or wider wrinkles, a larger refinement.edge_fraction or "
                         "refinement.falloff_error, or "
                         "\"refinement\": {\"enabled\": false}");
  return false;
}

bool NeedsRefinement(const RigSpec& spec) {
  if (!spec.refinement.enabled) return false;
  bool any = spec.layers.curve_wrinkles && !spec.curve_wrinkles.empty();
  any |= spec.refinement.falloff_error > 0.f && !spec.muscles.empty();
  if (spec.layers.muscle_wrinkles)
    for (const auto& w : spec.muscle_wrinkles) any |= w.has_value();
  return any;
}

// Everything after welding: `welded` may be reordered (points and triangles); file_triangle[t]
// is the file triangle of internal triangle t. The output's vertex layout and index buffer
// stay the file's own.
bool BuildOnWelded(const RigSpec& spec, const MeshData& mesh, const WeldedMesh& welded,
                   const std::vector<uint32_t>& file_triangle, RigData* out,
                   Diagnostics* diag) {
  RigData rig;
  rig.rest_points = welded.points;
  rig.triangles = welded.triangles;
  rig.vertex_points = welded.point_of_vertex;
  rig.vertex_indices = mesh.indices;
  rig.vertex_uvs = mesh.uvs;

  // Point -> triangle adjacency (CSR, ascending triangle order per point).
  CsrTable adjacency = BuildPointTriangles(rig.triangles, rig.point_count());
  rig.point_triangle_offsets = std::move(adjacency.offsets);
  rig.point_triangles = std::move(adjacency.items);

  bool ok = ResolveThickness(spec.thickness, mesh, welded, &rig.point_thickness, diag);

  for (const MuscleSpec& m : spec.muscles) rig.muscle_names.push_back(m.name);
  // The welded rest surface's normals (a point per position, so seams agree), averaged over
  // each tangent muscle's own radius (geometry/normal_field.h).
  NormalField rest_normals{span<const float3>(rig.rest_points), span<const uint32_t>(rig.triangles)};
  rig.muscles = BuildMuscleTable(spec.muscles, rig.rest_points, &rest_normals);
  const std::vector<uint32_t> influenced = CountInfluencedPoints(rig.muscles);
  for (uint32_t m = 0; m < rig.muscle_count(); ++m) {
    if (influenced[m] == 0 && spec.muscles[m].strength > 0.f)
      diag->Warning("muscles[" + std::to_string(m) + "] (" + spec.muscles[m].name + ")",
                    "reaches no vertex of the mesh: check its position and fall-off radii "
                    "against the mesh's units and placement");
  }
  ok = CompileSkinLayers(spec, mesh, file_triangle, &rig, diag) && ok;
  ok = CompileJaw(spec, mesh, welded, &rig, diag) && ok;
  ok = CompileEyes(spec, &rig, diag) && ok;
  ok = ResolveTensionRegions(spec, mesh, welded, &rig, diag) && ok;
  if (!ok) return false;
  *out = std::move(rig);
  return true;
}

// THE definition of which points a frame can move (every per-frame range, and so every table
// Rig::Build derives, follows from it): points a muscle moves, points sharing a triangle with
// one (their area ratio, hence their thickness displacement, changes), and wrinkle rows. A
// stage that moves points (the jaw) adds its points here. 2 = can move, 0 = not (ActiveOrder
// adds 1 = normal can change).
std::vector<uint8_t> MovingPoints(const RigData& rig) {
  const uint32_t points = rig.point_count(), tris = rig.triangle_count();
  const std::vector<uint8_t> moved = MovedByMuscleOrJaw(rig);
  std::vector<uint8_t> level(points, 0);
  // A moved point is active even when no triangle uses it (a stray vertex of a scan that a
  // muscle reaches: it moves with its displacement and is drawn by nothing).
  for (uint32_t p = 0; p < points; ++p)
    if (moved[p]) level[p] = 2;
  for (const RigMuscleWrinkles& w : rig.muscle_wrinkles)
    for (uint32_t p : w.points) level[p] = 2;
  for (uint32_t p : rig.curve_wrinkles.points) level[p] = 2;
  for (uint32_t t = 0; t < tris; ++t) {
    const uint32_t* c = &rig.triangles[3 * t];
    if (moved[c[0]] || moved[c[1]] || moved[c[2]]) level[c[0]] = level[c[1]] = level[c[2]] = 2;
  }
  return level;
}

RigActiveRanges ActiveOrder(const RigData& rig, const WeldedMesh& welded, WeldedMesh* out,
                            std::vector<uint32_t>* file_triangle) {
  const uint32_t points = rig.point_count(), tris = rig.triangle_count();
  std::vector<uint8_t> level = MovingPoints(rig);  // 2 active, 1 normal, 0 static
  std::vector<uint8_t> touches_active(tris, 0);
  for (uint32_t t = 0; t < tris; ++t) {
    const uint32_t* c = &rig.triangles[3 * t];
    touches_active[t] = level[c[0]] == 2 || level[c[1]] == 2 || level[c[2]] == 2;
  }
  for (uint32_t t = 0; t < tris; ++t) {
    if (!touches_active[t]) continue;
    for (int k = 0; k < 3; ++k) {
      uint8_t& l = level[rig.triangles[3 * t + k]];
      if (l == 0) l = 1;
    }
  }
  RigActiveRanges counts;
  std::vector<uint32_t> new_index(points);
  std::vector<uint32_t> order;
  order.reserve(points);
  for (int want = 2; want >= 0; --want)
    for (uint32_t p = 0; p < points; ++p)
      if (level[p] == want) new_index[p] = uint32_t(order.size()), order.push_back(p);
  for (uint32_t p = 0; p < points; ++p) {
    counts.points += level[p] == 2;
    counts.normal_points += level[p] >= 1;
  }
  out->points.resize(points);
  for (uint32_t i = 0; i < points; ++i) out->points[i] = welded.points[order[i]];
  out->point_of_vertex.resize(welded.point_of_vertex.size());
  for (size_t v = 0; v < welded.point_of_vertex.size(); ++v)
    out->point_of_vertex[v] = new_index[welded.point_of_vertex[v]];
  file_triangle->clear();
  out->triangles.clear();
  for (int want = 1; want >= 0; --want) {
    for (uint32_t t = 0; t < tris; ++t) {
      if (touches_active[t] != want) continue;
      file_triangle->push_back(t);
      for (int k = 0; k < 3; ++k) out->triangles.push_back(new_index[welded.triangles[3 * t + k]]);
    }
    if (want == 1) counts.triangles = uint32_t(file_triangle->size());
  }
  return counts;
}

}  // namespace

bool MakeFineScaleRigMesh(const FineScaleSpec& spec, const RigData& rig,
                          size_t file_vertex_count, FineScaleRigMesh* out, Diagnostics* diag) {
  if (!ValidateFineScaleSpec(spec, file_vertex_count, "fine_scale", diag)) return false;
  out->points = rig.rest_points;
  out->triangles.resize(rig.vertex_indices.size());
  for (size_t i = 0; i < rig.vertex_indices.size(); ++i)
    out->triangles[i] = rig.vertex_points[rig.vertex_indices[i]];
  out->corner_uvs.clear();
  if (rig.vertex_uvs.size() == rig.vertex_points.size() && !rig.vertex_uvs.empty()) {
    out->corner_uvs.resize(rig.vertex_indices.size());
    for (size_t i = 0; i < rig.vertex_indices.size(); ++i)
      out->corner_uvs[i] = rig.vertex_uvs[rig.vertex_indices[i]];
  }
  for (int f = 0; f < 2; ++f) {
    out->anchor_points[f].clear();
    for (const DirectionAnchor& a : spec.fields[f].anchors)
      out->anchor_points[f].push_back(rig.vertex_points[a.vertex]);
  }
  return true;
}

namespace {

// docs/model.md §23: the fine-scale probes of the points that can see a moving point
// ([0, normal_points)): per field, the shrinkage probe across the field's texture direction.
bool CompileFineScale(const FineScaleSpec& spec, size_t file_vertex_count, RigData* data,
                      Diagnostics* diag) {
  FineScaleRigMesh m;
  if (!MakeFineScaleRigMesh(spec, *data, file_vertex_count, &m, diag)) return false;
  std::vector<float2> uvs;
  if (!MakeTextureSpace(m.view(), spec.projection, spec.minimize_distortion, "fine_scale", &uvs,
                        diag))
    return false;
  const CsrTable pt = BuildPointTriangles(m.triangles, data->point_count());
  std::vector<float3> fields[2];
  if (!InterpolateSpecFields(spec, m.view(), m.anchor_points, fields, diag)) return false;
  const uint32_t rows = data->active.normal_points;
  RigFineScale& out = data->fine_scale;
  out.rest_amplitude = spec.rest_amplitude;
  out.probes.assign(2 * size_t(rows), ShrinkageProbe{});
  for (uint32_t p = 0; p < rows; ++p)
    for (int f = 0; f < 2; ++f) {
      const float2 d = TextureDirectionAt(m.view(), uvs, pt.offsets, pt.items, fields[f], p);
      ShrinkageProbe& probe = out.probes[2 * size_t(p) + f];
      if (d.x == 0.f && d.y == 0.f) {  // no field here: s = 0
        probe.point = p;
        continue;
      }
      probe = BuildShrinkageProbe(p, float2{-d.y, d.x}, data->rest_points, m.triangles, uvs, pt);
    }
  return true;
}

}  // namespace

// The sparse tension regions of `spec` (TensionRegionSpec::vertices) made dense for a mesh of
// `vertex_count` vertices into *out (a copy of spec); false, with a message, for a bad index list.
bool DenseTensionRegions(const RigSpec& spec, size_t vertex_count, RigSpec* out,
                         Diagnostics* diag) {
  *out = spec;
  bool ok = true;
  for (size_t i = 0; i < out->tension_regions.size(); ++i) {
    TensionRegionSpec& g = out->tension_regions[i];
    if (!g.sparse) continue;
    const std::string where = "tension_regions[" + std::to_string(i) + "] (" + g.name + ")";
    if (g.weights.size() != g.vertices.size()) {
      diag->Error(where + ".weights", "expected one value per entry of vertices (" +
                                          std::to_string(g.vertices.size()) + "), got " +
                                          std::to_string(g.weights.size()));
      ok = false;
      continue;
    }
    std::vector<float> dense(vertex_count, 0.f);
    for (size_t k = 0; k < g.vertices.size(); ++k) {
      const uint32_t v = g.vertices[k];
      if (v >= vertex_count || (k > 0 && v <= g.vertices[k - 1])) {
        diag->Error(where + ".vertices[" + std::to_string(k) + "]",
                    "is " + std::to_string(v) + "; expected ascending vertex indices below the "
                    "mesh's " + std::to_string(vertex_count) + " vertices");
        ok = false;
        break;
      }
      dense[v] = g.weights[k];
    }
    g.weights = std::move(dense);
    g.vertices.clear();
    g.sparse = false;
  }
  return ok;
}

// BuildOptions::progress: each stage's share of BuildRig on the sample head (its default rig,
// measured with the progress hook's own time stamps, 1.36 s in all on one core: checks 18 ms,
// refining 331, welding 44, each muscle pass 237-240, ordering 4, fine scale 434; the rest,
// "tables", is Rig::Build, 46 ms).
constexpr float kShareChecks = 0.013f, kShareRefine = 0.245f, kShareWeld = 0.033f,
                kSharePass = 0.175f, kShareOrder = 0.003f, kShareFine = 0.32f;

bool BuildRig(const RigSpec& spec_original, const MeshData& file_mesh_in,
              const BuildOptions& options, Rig* out, Diagnostics* diag) {
  auto stage = [&](float done, const char* name) {
    if (options.progress) options.progress(done, name);
  };
  stage(0.f, "checks");
  RigSpec dense_spec;
  const bool sparse = std::any_of(spec_original.tension_regions.begin(),
                                  spec_original.tension_regions.end(),
                                  [](const TensionRegionSpec& g) { return g.sparse; });
  if (sparse && !DenseTensionRegions(spec_original, file_mesh_in.vertex_count(), &dense_spec, diag))
    return false;
  const RigSpec& spec_in = sparse ? dense_spec : spec_original;
  if (options.check_magnitudes && !ValidateMagnitudes(spec_in, file_mesh_in, diag)) return false;
  // The mesh the per-vertex and texture-space data were made for (geometry/fingerprint.h).
  {
    const bool per_vertex = spec_in.thickness.kind == ThicknessSpec::Kind::kPerVertex;
    const bool image = spec_in.thickness.kind == ThicknessSpec::Kind::kImage;
    const bool curves = !spec_in.curve_wrinkles.empty();
    const bool fine = spec_in.fine_scale.has_value();
    if (!spec_in.mesh_fingerprint.empty() && (per_vertex || image || curves || fine)) {
      const std::string why =
          FingerprintMismatch(spec_in.mesh_fingerprint, file_mesh_in, image || curves || fine);
      if (!why.empty()) {
        std::string data = per_vertex ? "per-vertex thickness" : (image ? "thickness image" : "");
        if (curves) data += std::string(data.empty() ? "" : " and ") + "curve wrinkles";
        if (fine) data += std::string(data.empty() ? "" : " and ") + "fine-scale fields";
        const std::string mesh_name = file_mesh_in.source.empty() ? "the mesh" : file_mesh_in.source;
        diag->Error("mesh.fingerprint",
                    "'" + mesh_name + "' is not the mesh this rig's " + data + " (" +
                        (per_vertex ? "one value per vertex" : "texture space") +
                        ") was made for: " + why + "; refit the rig on this mesh (mimetic fit "
                        "TEMPLATE --mesh " + mesh_name + " --landmarks LANDMARKS --out RIG, "
                        "docs/fitting.md), or point mesh.path at the mesh it was fitted to");
        return false;
      }
    }
  }
  // Consistent winding first (geometry/orientation.h): a minority of reversed triangles is
  // turned round with a warning, so that the posed normals point one way; the output's index
  // buffer is the corrected one.
  MeshData reoriented;
  const MeshData* file_ptr = &file_mesh_in;
  {
    std::vector<uint32_t> fixed;
    if (!MakeWindingConsistent(file_mesh_in, options.weld_tolerance, file_mesh_in.source, &fixed,
                               diag))
      return false;
    if (!fixed.empty()) {
      reoriented = file_mesh_in;
      reoriented.indices = std::move(fixed);
      file_ptr = &reoriented;
    }
  }
  const MeshData& file_mesh = *file_ptr;
  // Refine where wrinkles act (docs/model.md §11); everything below runs on the refined layout.
  const MeshData* mesh_ptr = &file_mesh;
  const RigSpec* spec_ptr = &spec_in;
  RefineResult refined;
  RigSpec carried;
  if (NeedsRefinement(spec_in)) {
    stage(kShareChecks, "refining");
    if (spec_in.thickness.kind == ThicknessSpec::Kind::kPerVertex &&
        spec_in.thickness.per_vertex.size() != file_mesh.vertex_count()) {
      diag->Error("thickness.values",
                  "expected one value per mesh vertex (" + std::to_string(file_mesh.vertex_count()) +
                      "), got " + std::to_string(spec_in.thickness.per_vertex.size()));
      return false;
    }
    RefineOptions refine_options;
    refine_options.weld_tolerance = options.weld_tolerance;
    const EdgeLengthField field = MakeRefinementField(spec_in, file_mesh);
    if (!CheckRefinementGrowth(spec_in, file_mesh, field, refine_options, diag)) return false;
    Diagnostics refine_diag;
    const bool refined_ok = RefineMesh(file_mesh, field, refine_options, &refined, &refine_diag);
    diag->Append(refine_diag, file_mesh.source);
    if (!refined_ok) return false;
    mesh_ptr = &refined.mesh;
    if (spec_in.jaw && !spec_in.jaw->weights.empty() &&
        spec_in.jaw->weights.size() != file_mesh.vertex_count()) {
      diag->Error("jaw.weights",
                  "expected one value per mesh vertex (" + std::to_string(file_mesh.vertex_count()) +
                      "), got " + std::to_string(spec_in.jaw->weights.size()));
      return false;
    }
    if (!CheckTensionRegionWeights(spec_in, file_mesh.vertex_count(), diag)) return false;
    const bool carry_thickness = spec_in.thickness.kind == ThicknessSpec::Kind::kPerVertex;
    const bool carry_jaw = spec_in.jaw && !spec_in.jaw->weights.empty();
    const bool carry_regions = !spec_in.tension_regions.empty();
    if (carry_thickness || carry_jaw || carry_regions) {
      carried = spec_in;
      if (carry_thickness)
        carried.thickness.per_vertex = CarryAttribute(refined, spec_in.thickness.per_vertex);
      if (carry_jaw) carried.jaw->weights = CarryAttribute(refined, spec_in.jaw->weights);
      for (TensionRegionSpec& g : carried.tension_regions)
        g.weights = CarryAttribute(refined, g.weights);
      spec_ptr = &carried;
    }
  }
  const MeshData& mesh = *mesh_ptr;
  const RigSpec& spec = *spec_ptr;

  float done = kShareChecks + kShareRefine;
  stage(done, "welding");
  WeldedMesh welded;
  Diagnostics weld_diag;
  const bool welded_ok = WeldMesh(mesh, options.weld_tolerance, &welded, &weld_diag);
  diag->Append(weld_diag, mesh.source);
  if (!welded_ok) return false;

  // Pass 1 finds what can move; pass 2 builds on points and triangles reordered so that the
  // per-frame stages run over leading ranges only (see ActiveOrder).
  const std::vector<uint32_t> identity = [&] {
    std::vector<uint32_t> v(welded.triangles.size() / 3);
    for (uint32_t t = 0; t < v.size(); ++t) v[t] = t;
    return v;
  }();
  RigData first;
  stage(done += kShareWeld, "muscles");
  if (!BuildOnWelded(spec, mesh, welded, identity, &first, diag)) return false;
  stage(done += kSharePass, "ordering");
  WeldedMesh ordered;
  std::vector<uint32_t> file_triangle;
  RigData data;
  Diagnostics repeat;  // the same diagnostics again: already reported
  const RigActiveRanges active = ActiveOrder(first, welded, &ordered, &file_triangle);
  stage(done += kShareOrder, "muscles (ordered)");
  if (!BuildOnWelded(spec, mesh, ordered, file_triangle, &data, &repeat)) {
    diag->Append(repeat);
    return false;
  }
  data.active = active;
  stage(done += kSharePass, "fine scale");
  if (spec.fine_scale && options.fine_scale_probes &&
      !CompileFineScale(*spec.fine_scale, file_mesh.vertex_count(), &data, diag))
    return false;
  // The runtime derives its tables and checks everything once (rig/runtime/rig_tables.h).
  stage(done += kShareFine, "tables");
  Rig rig;
  if (!Rig::Build(std::move(data), &rig)) {
    diag->Error("rig", "internal error: the compiled tables failed the runtime's check");
    return false;
  }
  *out = std::move(rig);
  stage(1.f, "done");
  return true;
}

MeshData RestMesh(const Rig& rig) {
  MeshData mesh;
  mesh.source = "rig rest pose";
  mesh.positions.resize(rig.vertex_count());
  for (uint32_t v = 0; v < rig.vertex_count(); ++v)
    mesh.positions[v] = rig.rest_points()[rig.vertex_points()[v]];
  mesh.uvs = rig.vertex_uvs();
  mesh.indices = rig.vertex_indices();
  return mesh;
}

bool PosedMesh(const Rig& rig, span<const float> activations, const SkinLayers& layers,
               MeshData* out, float jaw) {
  MeshData posed = RestMesh(rig);
  posed.normals.resize(posed.positions.size());
  EvaluateContext context(rig);
  EvaluateJob job;
  job.rig = &rig;
  job.context = &context;
  job.activations = activations;
  job.jaw = jaw;
  job.out_positions = span<float>(&posed.positions[0].x, posed.positions.size() * 3);
  job.out_normals = span<float>(&posed.normals[0].x, posed.normals.size() * 3);
  job.layers = layers;
  if (posed.positions.empty() || !job.Run()) return false;
  *out = std::move(posed);
  return true;
}

namespace {

// The first output vertex whose position or normal is not finite; -1 when none.
int64_t FirstNonFinite(const MeshData& m) {
  for (size_t v = 0; v < m.positions.size(); ++v)
    if (!IsFinite(m.positions[v]) || (v < m.normals.size() && !IsFinite(m.normals[v])))
      return int64_t(v);
  return -1;
}

}  // namespace

bool CheckPosedFinite(const Rig& rig, const RigSpec& spec, span<const float> activations,
                      const SkinLayers& layers, const MeshData& posed, Diagnostics* diag) {
  const int64_t bad = FirstNonFinite(posed);
  if (bad < 0) return true;
  auto finite_with = [&](span<const float> a, const SkinLayers& l) {
    MeshData m;
    return PosedMesh(rig, a, l, &m) && FirstNonFinite(m) < 0;
  };
  auto muscle_name = [&](size_t m) {
    return "muscles[" + std::to_string(m) + "] (" +
           (m < spec.muscles.size() ? spec.muscles[m].name : rig.muscle_names()[m]) + ")";
  };
  // The active muscle that, alone at its activation, gives non-finite output; -1 when none.
  std::vector<float> one(rig.muscle_count(), 0.f);
  auto culprit = [&](const SkinLayers& l) -> int64_t {
    for (uint32_t m = 0; m < rig.muscle_count() && m < activations.size(); ++m) {
      if (activations[m] == 0.f) continue;
      std::fill(one.begin(), one.end(), 0.f);
      one[m] = activations[m];
      if (!finite_with(one, l)) return m;
    }
    return -1;
  };
  const SkinLayers none{.thickness = false, .muscle_wrinkles = false, .curve_wrinkles = false};
  const SkinLayers thick{.thickness = layers.thickness, .muscle_wrinkles = false,
                         .curve_wrinkles = false};
  const SkinLayers wrinkled{.thickness = layers.thickness,
                            .muscle_wrinkles = layers.muscle_wrinkles, .curve_wrinkles = false};
  // How far the muscles alone move the skin: a finite but absurd motion (more than
  // kMaxLengthFactor times the mesh's size) that a skin layer then overflows is the muscle's.
  const MeshData rest = RestMesh(rig);
  const double limit = kMaxLengthFactor * ComputeBounds(rest.positions).Diagonal();
  auto largest_motion = [&](span<const float> a) {
    MeshData m;
    double d = 0;
    if (!PosedMesh(rig, a, none, &m)) return d;
    for (size_t v = 0; v < m.positions.size() && v < rest.positions.size(); ++v)
      d = std::max(d, std::hypot(double(m.positions[v].x) - rest.positions[v].x,
                                 double(m.positions[v].y) - rest.positions[v].y,
                                 double(m.positions[v].z) - rest.positions[v].z));
    return d;
  };
  int64_t wild = -1;
  double wild_motion = 0;
  if (largest_motion(activations) > limit)
    for (uint32_t m = 0; m < rig.muscle_count() && m < activations.size() && wild < 0; ++m) {
      if (activations[m] == 0.f) continue;
      std::fill(one.begin(), one.end(), 0.f);
      one[m] = activations[m];
      if (const double d = largest_motion(one); d > limit) wild = m, wild_motion = d;
    }
  std::string where, what;
  if (wild >= 0 && finite_with(activations, none)) {
    where = "muscles[" + std::to_string(wild) + "]";
    what = muscle_name(size_t(wild)) + " alone moves the skin by " + Short(wild_motion) + " " +
           (spec.units.empty() ? "mm" : spec.units) + ", more than " + Short(kMaxLengthFactor) +
           " times the mesh's size, and the skin layers then overflow: check its strength";
  } else if (!finite_with(activations, none)) {
    const int64_t m = culprit(none);
    where = m >= 0 ? "muscles[" + std::to_string(m) + "]" : "muscles";
    what = m >= 0 ? "the muscles alone move it there: " + muscle_name(size_t(m)) +
                        " alone does, at activation " + Short(activations[size_t(m)]) +
                        "; check its strength and fall-off radii"
                  : "the muscles alone move it there (together, none alone): check their "
                    "strengths";
  } else if (layers.thickness && rig.layers().thickness && !finite_with(activations, thick)) {
    where = "thickness";
    what = "the thickness layer does (docs/model.md §4): check the thickness values";
  } else if (layers.muscle_wrinkles && rig.layers().muscle_wrinkles &&
             !finite_with(activations, wrinkled)) {
    const int64_t m = culprit(wrinkled);
    where = m >= 0 ? "muscles[" + std::to_string(m) + "].wrinkles" : "muscles";
    what = m >= 0 ? "the muscle wrinkles do: those of " + muscle_name(size_t(m)) +
                        "; check their depth and count"
                  : "the muscle wrinkles do (together, none alone): check their depths";
  } else if (layers.curve_wrinkles && rig.layers().curve_wrinkles) {
    // The curve wrinkles that reach the first bad vertex's point.
    const RigCurveWrinkles& c = rig.curve_wrinkles();
    const uint32_t point = size_t(bad) < rig.vertex_points().size() ? rig.vertex_points()[size_t(bad)] : 0;
    std::vector<uint32_t> reach;
    for (uint32_t row = 0; row < c.row_count(); ++row)
      if (c.points[row] == point)
        for (uint32_t k = c.offsets[row]; k < c.offsets[row + 1]; ++k)
          if (std::find(reach.begin(), reach.end(), c.entries[k].wrinkle) == reach.end())
            reach.push_back(c.entries[k].wrinkle);
    where = reach.empty() ? "curve_wrinkles" : "curve_wrinkles[" + std::to_string(reach[0]) + "]";
    what = "the curve wrinkles do";
    for (size_t i = 0; i < reach.size(); ++i)
      what += std::string(i ? ", " : ": ") + "curve_wrinkles[" + std::to_string(reach[i]) + "] (" +
              (reach[i] < c.names.size() ? c.names[reach[i]] : std::string("?")) + ")";
    what += "; check their depth and width";
  } else {
    where = "rig";
    what = "no part of the rig alone does (internal error)";
  }
  diag->Error(where, "the evaluation gives non-finite positions or normals (first: output vertex " +
                         std::to_string(bad) + "): " + what);
  return false;
}

std::vector<float> MouthEdgeDistances(const JawSpec& jaw, span<const float3> points,
                                      span<const uint32_t> triangles, float beyond) {
  EdgeTable edges;
  BuildEdgeTable(triangles, &edges);
  const std::vector<uint32_t> boundary = BoundaryEdges(edges);
  if (boundary.empty() || !(jaw.mouth_width > 0.f)) return {};
  // Union-find over the boundary's points: one set per loop (the smallest point names it).
  std::unordered_map<uint32_t, uint32_t> parent;
  auto find = [&](uint32_t a) {
    while (parent[a] != a) a = parent[a] = parent[parent[a]];
    return a;
  };
  for (uint32_t e : boundary) {
    const uint32_t a = EdgeKeyLow(edges.keys[e]), b = EdgeKeyHigh(edges.keys[e]);
    parent.emplace(a, a);
    parent.emplace(b, b);
    const uint32_t ra = find(a), rb = find(b);
    if (ra != rb) parent[std::max(ra, rb)] = std::min(ra, rb);
  }
  auto distance = [&](float3 x, uint32_t e) {
    return SegmentDistance(x, points[EdgeKeyLow(edges.keys[e])], points[EdgeKeyHigh(edges.keys[e])]);
  };
  float nearest = std::numeric_limits<float>::infinity();
  uint32_t loop = 0;
  for (uint32_t e : boundary) {  // ascending edge ids: the first of equally near loops
    const float d = distance(jaw.mouth, e);
    if (d < nearest) nearest = d, loop = find(EdgeKeyLow(edges.keys[e]));
  }
  if (!(nearest <= 0.25f * jaw.mouth_width)) return {};
  std::vector<uint32_t> mouth;
  for (uint32_t e : boundary)
    if (find(EdgeKeyLow(edges.keys[e])) == loop) mouth.push_back(e);
  // The loop's bounding box (in double, so that rounding never puts a point nearer than
  // `beyond` to the loop at `beyond` or more from the box).
  double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  for (uint32_t e : mouth)
    for (uint32_t q : {EdgeKeyLow(edges.keys[e]), EdgeKeyHigh(edges.keys[e])}) {
      const double c[3] = {points[q].x, points[q].y, points[q].z};
      for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], c[k]), hi[k] = std::max(hi[k], c[k]);
    }
  const double grow = beyond >= 0.f ? double(beyond) : HUGE_VAL;
  std::vector<float> out(points.size(), std::numeric_limits<float>::infinity());
  for (size_t p = 0; p < points.size(); ++p) {
    const double c[3] = {points[p].x, points[p].y, points[p].z};
    double gap2 = 0.0;
    for (int k = 0; k < 3; ++k) {
      const double g = std::max({lo[k] - c[k], 0.0, c[k] - hi[k]});
      gap2 += g * g;
    }
    if (gap2 >= grow * grow) continue;  // as far from every edge of the loop
    float d = std::numeric_limits<float>::infinity();
    for (uint32_t e : mouth) d = std::fmin(d, distance(points[p], e));
    out[p] = d;
  }
  return out;
}

}  // namespace mimetic

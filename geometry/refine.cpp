// geometry/refine.cpp: RefineMesh, adaptive refinement at rig compile time (docs/model.md §11).
//
// Algorithm: conforming longest-edge bisection (M.-C. Rivara, "Algorithms for refining
// triangular grids suitable for adaptive and multigrid techniques", IJNME 1984), one batch per
// pass:
//   1. mark every edge longer than its target (the field at its midpoint and at the centroids of
//      the triangles using it);
//   2. closure: a triangle with a marked edge also marks its longest edge, until nothing changes
//      (a least fixed point, so independent of the visiting order);
//   3. split each triangle with marked edges: bisect the longest edge (a, b) at m towards the
//      opposite corner c, then bisect (b, c) and (c, a) in the halves when they are marked.
//      That is 2, 3 or 4 triangles; a neighbour always splits the shared edge too (it is marked
//      for both), so there are no T-junctions. Longest-edge bisection keeps every angle >= half
//      the smallest input angle (Rosenberg & Stenger 1975), unlike repeated green splits.
// Marks are decided on welded points (weld.h), so the two file-edges of a seam edge split
// together; each file-edge gets its own midpoint vertex (own uv and normal) at the point-edge's
// midpoint position, so both sides carry identical position bits.
//
// Only triangles created in the previous pass (or still violating) are evaluated again: a
// triangle kept unchanged met its targets, and its edges have not changed since.
//
// Placement (docs/model.md §14): every pass works on the flat positions (each new point the
// exact midpoint of its point-edge), so the marks and the topology do not depend on where new
// points finally go. Each new point also records its barycentric coordinates in the input
// triangle it lies in (dyadic: the mean of its edge ends', exact in double). After the last
// pass, with RefinePlacement::kSmooth, every new point moves from its flat position onto the
// PN triangle of that input triangle (A. Vlachos, J. Peters, C. Boyd, J. L. Mitchell, "Curved
// PN Triangles", Proc. I3D 2001), written as the flat (linear) position plus the cubic
// Bernstein sum of the control points' offsets from the linear patch. A point on an input
// edge uses the edge's cubic alone, in the order of the edge's point ids, so the two
// triangles of the edge give it the same bits.
//
// OpenMesh's subdividers (OpenMesh/Tools/Subdivider: Loop, sqrt3, midpoint, LongestEdgeT) are
// not used: they split by a fixed rule or one global edge length, on one vertex per position,
// so they keep neither our UV/normal seams (split file vertices with their own uvs), nor the
// edge-length field sampled at centroids and midpoints, nor the parents and triangle origins
// CarryAttribute and the rig builder read; the results would not be the same bytes.
#include "geometry/refine.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <deque>
#include <exception>
#include <limits>
#include <string>
#include <unordered_map>

#include "geometry/bounds.h"
#include "geometry/normals.h"
#include "geometry/topology.h"
#include "geometry/weld.h"

namespace mimetic {
namespace {

constexpr uint32_t kNone = UINT32_MAX;
constexpr double kInf = std::numeric_limits<double>::infinity();
// Edges shorter than this fraction of the bounding-box diagonal are never split: their halves
// stay well above WeldMesh's default tolerance (1e-6) and zero-area threshold (1e-10 squared).
constexpr double kMinSplitFraction = 2e-4;

std::string G(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.6g", v);
  return buf;
}

float3 Midpoint(float3 a, float3 b) {
  // Exact midpoint rounded once; symmetric in (a, b).
  return {static_cast<float>((static_cast<double>(a.x) + b.x) * 0.5),
          static_cast<float>((static_cast<double>(a.y) + b.y) * 0.5),
          static_cast<float>((static_cast<double>(a.z) + b.z) * 0.5)};
}

float2 Midpoint(float2 a, float2 b) {
  return {static_cast<float>((static_cast<double>(a.x) + b.x) * 0.5),
          static_cast<float>((static_cast<double>(a.y) + b.y) * 0.5)};
}

double Distance(float3 a, float3 b) {
  const double x = static_cast<double>(a.x) - b.x, y = static_cast<double>(a.y) - b.y,
               z = static_cast<double>(a.z) - b.z;
  return std::sqrt(x * x + y * y + z * z);
}

// Where a new point lies in the input: its input triangle and barycentric coordinates there
// (corner k of the triangle is input_triangles[3 * triangle + k]).
struct PointParam {
  uint32_t triangle = kNone;
  double bary[3] = {0, 0, 0};
};

// The refinement so far: the output mesh (file-vertex layout, vertices only appended) and the
// welded points it lies on (flat positions), with each vertex's parents, each triangle's input
// triangle and each new point's place in its input triangle.
struct State {
  MeshData& mesh;
  std::vector<uint32_t>& pov;  // vertex -> point
  std::vector<float3>& points;
  std::vector<std::pair<uint32_t, uint32_t>>& parents;
  std::vector<uint32_t>& origin;
  std::vector<uint8_t> dirty;  // per triangle: its targets must be sampled (again)
  bool has_uv = false, has_normal = false;
  const std::vector<uint32_t>& input_triangles;  // 3 input points per input triangle
  size_t input_points = 0;                       // points [0, input_points) are the input's
  std::vector<PointParam> params;                // per new point (index - input_points)

  float2 uv_of(uint32_t v) const { return has_uv ? mesh.uvs[v] : float2{}; }

  // Barycentric coordinates of point p in input triangle t (p lies in its closure: a corner,
  // a point of one of its edges, or a point inside it).
  void BaryIn(uint32_t p, uint32_t t, double out[3]) const {
    const uint32_t* c = &input_triangles[3 * size_t(t)];
    out[0] = out[1] = out[2] = 0;
    if (p < input_points) {
      for (int k = 0; k < 3; ++k)
        if (c[k] == p) out[k] = 1;
      return;
    }
    const PointParam& q = params[p - input_points];
    if (q.triangle == t) {
      for (int k = 0; k < 3; ++k) out[k] = q.bary[k];
      return;
    }
    // On an edge shared with q's triangle: carry the two non-zero coordinates by point.
    const uint32_t* d = &input_triangles[3 * size_t(q.triangle)];
    for (int j = 0; j < 3; ++j) {
      if (q.bary[j] == 0) continue;
      for (int k = 0; k < 3; ++k)
        if (c[k] == d[j]) out[k] = q.bary[j];
    }
  }
};

// One pass's view of the current triangles: point-edges, their lengths, targets and marks.
struct Pass {
  std::vector<uint32_t> tri_points;  // 3 per triangle
  EdgeTable et;
  std::vector<double> length, target;
  std::vector<uint8_t> evaluated, marked;
};

// The edge-length field as refinement reads it: NaN counts (and reads as no constraint), +inf
// and <= 0 are no constraint.
struct FieldSampler {
  const EdgeLengthField& field;
  size_t nan_count = 0;
  float3 nan_at{};
  double operator()(float3 p, float2 uv) {
    const float v = field(p, uv);
    if (std::isnan(v)) {
      if (nan_count++ == 0) nan_at = p;
      return kInf;
    }
    return v > 0 ? static_cast<double>(v) : kInf;
  }
};

// Edges that miss their target: how many can split, how many are too short to, the worst.
struct Misses {
  size_t splittable = 0, too_short = 0;
  double worst_ratio = 1, worst_length = 0, worst_target = 0;
};

// Counts of normals and uvs, the field, a finite weld tolerance. Records every problem.
bool CheckInput(const MeshData& in, const EdgeLengthField& max_edge, const RefineOptions& options,
                const std::string& where, Diagnostics* diag) {
  const size_t errors_before = diag->ErrorCount();
  const size_t nv = in.positions.size();
  if (!max_edge) {
    diag->Error(where, "no edge-length field given (expected a function of position and uv)");
  }
  if (!in.normals.empty() && in.normals.size() != nv) {
    diag->Error(where, "has " + std::to_string(in.normals.size()) + " normals for " +
                           std::to_string(nv) + " vertices (expected none or one per vertex)");
  }
  if (!in.uvs.empty() && in.uvs.size() != nv) {
    diag->Error(where, "has " + std::to_string(in.uvs.size()) + " uvs for " +
                           std::to_string(nv) + " vertices (expected none or one per vertex)");
  }
  if (!std::isfinite(options.weld_tolerance)) {
    diag->Error(where, "weld tolerance " + G(options.weld_tolerance) +
                           " is not finite (expected a positive number, or <= 0 for the "
                           "default)");
  }
  return diag->ErrorCount() == errors_before;
}

// The input as it is, every vertex its own parent (nothing to refine).
void InitResult(const MeshData& in, RefineResult* out) {
  out->mesh = in;
  out->input_vertex_count = in.positions.size();
  out->parents.resize(in.positions.size());
  for (size_t v = 0; v < in.positions.size(); ++v) out->parents[v] = {uint32_t(v), uint32_t(v)};
  out->triangle_origin.resize(in.triangle_count());
  for (size_t t = 0; t < in.triangle_count(); ++t) out->triangle_origin[t] = uint32_t(t);
}

// The point-edges of the current triangles and their lengths.
void BuildPassEdges(const State& s, Pass* pass) {
  const size_t nt = s.mesh.indices.size() / 3;
  pass->tri_points.resize(nt * 3);
  for (size_t i = 0; i < nt * 3; ++i) pass->tri_points[i] = s.pov[s.mesh.indices[i]];
  BuildEdgeTable(pass->tri_points, &pass->et);
  const size_t ne = pass->et.edge_count();
  pass->length.resize(ne);
  for (size_t e = 0; e < ne; ++e) {
    const uint64_t key = pass->et.keys[e];
    pass->length[e] = Distance(s.points[EdgeKeyLow(key)], s.points[EdgeKeyHigh(key)]);
  }
}

// Targets for the edges of dirty triangles: the field at the triangle's centroid and at the
// edge's midpoint (positions on points, uvs from the triangle's own file vertices).
void SampleTargets(const State& s, FieldSampler* field, Pass* pass) {
  const size_t nt = s.mesh.indices.size() / 3, ne = pass->et.edge_count();
  pass->target.assign(ne, kInf);
  pass->evaluated.assign(ne, 0);
  for (size_t t = 0; t < nt; ++t) {
    if (!s.dirty[t]) continue;
    const uint32_t* v = &s.mesh.indices[3 * t];
    const float3 a = s.points[s.pov[v[0]]], b = s.points[s.pov[v[1]]], c = s.points[s.pov[v[2]]];
    const float3 centroid{static_cast<float>((static_cast<double>(a.x) + b.x + c.x) / 3.0),
                          static_cast<float>((static_cast<double>(a.y) + b.y + c.y) / 3.0),
                          static_cast<float>((static_cast<double>(a.z) + b.z + c.z) / 3.0)};
    const float2 ua = s.uv_of(v[0]), ub = s.uv_of(v[1]), uc = s.uv_of(v[2]);
    const float2 uv_centroid{static_cast<float>((static_cast<double>(ua.x) + ub.x + uc.x) / 3.0),
                             static_cast<float>((static_cast<double>(ua.y) + ub.y + uc.y) / 3.0)};
    const double at_centroid = (*field)(centroid, uv_centroid);
    for (int k = 0; k < 3; ++k) {
      const uint32_t e = pass->et.tri_edge[3 * t + k];
      pass->target[e] = std::min(pass->target[e], at_centroid);
      if (!pass->evaluated[e]) {
        pass->evaluated[e] = 1;
        const uint32_t va = v[k], vb = v[(k + 1) % 3];
        pass->target[e] =
            std::min(pass->target[e], (*field)(Midpoint(s.points[s.pov[va]], s.points[s.pov[vb]]),
                                               Midpoint(s.uv_of(va), s.uv_of(vb))));
      }
    }
  }
}

// Marks the edges longer than their target and at least `min_split` long; counts the rest.
Misses MarkLongEdges(double min_split, Pass* pass) {
  const size_t ne = pass->et.edge_count();
  pass->marked.assign(ne, 0);
  Misses m;
  for (size_t e = 0; e < ne; ++e) {
    if (!(pass->length[e] > pass->target[e])) continue;
    const double ratio = pass->length[e] / pass->target[e];
    if (ratio > m.worst_ratio) {
      m.worst_ratio = ratio;
      m.worst_length = pass->length[e];
      m.worst_target = pass->target[e];
    }
    if (pass->length[e] >= min_split) {
      pass->marked[e] = 1;
      ++m.splittable;
    } else {
      ++m.too_short;
    }
  }
  return m;
}

// The warning for a refinement that stopped before every edge met its target.
void WarnStopped(const std::string& where, const std::string& why, size_t passes, size_t nt,
                 const Misses& m, RefineResult* out, Diagnostics* diag) {
  out->bound_met = false;
  diag->Warning(where, "adaptive refinement (docs/model.md §11) " + why + " after " +
                           std::to_string(passes) + " passes with " + std::to_string(nt) +
                           " triangles: " + std::to_string(m.splittable + m.too_short) +
                           " edges are still longer than their target, the worst by a factor " +
                           G(m.worst_ratio) + " (length " + G(m.worst_length) + ", target " +
                           G(m.worst_target) +
                           "); expected every edge in a wrinkle support within its target");
}

// Corner k of triangle t whose edge is the triangle's longest (ties: the lower edge id).
int LongestCorner(const Pass& pass, size_t t) {
  int best = 0;
  for (int k = 1; k < 3; ++k) {
    const uint32_t e = pass.et.tri_edge[3 * t + k], b = pass.et.tri_edge[3 * t + best];
    if (pass.length[e] > pass.length[b] || (pass.length[e] == pass.length[b] && e < b)) best = k;
  }
  return best;
}

bool HasMark(const Pass& pass, size_t t) {
  return pass.marked[pass.et.tri_edge[3 * t]] || pass.marked[pass.et.tri_edge[3 * t + 1]] ||
         pass.marked[pass.et.tri_edge[3 * t + 2]];
}

// Closure: every triangle with a marked edge gets its longest edge marked (a least fixed
// point, so the visiting order does not matter).
void CloseMarks(size_t nt, Pass* pass) {
  std::deque<uint32_t> queue;
  for (size_t t = 0; t < nt; ++t) {
    if (HasMark(*pass, t)) queue.push_back(static_cast<uint32_t>(t));
  }
  while (!queue.empty()) {
    const uint32_t t = queue.front();
    queue.pop_front();
    const uint32_t e = pass->et.tri_edge[3 * t + LongestCorner(*pass, t)];
    if (pass->marked[e]) continue;
    pass->marked[e] = 1;
    for (uint32_t i = pass->et.start[e]; i < pass->et.start[e + 1]; ++i)
      queue.push_back(pass->et.corners[i] / 3);
  }
}

// The triangle count after splitting: 1 + the marked edges, per triangle.
size_t CountAfterSplit(size_t nt, const Pass& pass) {
  size_t n = 0;
  for (size_t t = 0; t < nt; ++t) {
    n += 1 + pass.marked[pass.et.tri_edge[3 * t]] + pass.marked[pass.et.tri_edge[3 * t + 1]] +
         pass.marked[pass.et.tri_edge[3 * t + 2]];
  }
  return n;
}

// Bisects the marked edges: new points in edge order, new file vertices in order of first use
// (uv the midpoint, normal the normalised sum), each split triangle into 2, 3 or 4.
void SplitMarked(const Pass& pass, size_t new_count, State* s) {
  const size_t nt = s->mesh.indices.size() / 3, ne = pass.et.edge_count();
  MeshData& mesh = s->mesh;
  std::vector<uint32_t> mid_point(ne, kNone);
  for (size_t e = 0; e < ne; ++e) {
    if (!pass.marked[e]) continue;
    mid_point[e] = static_cast<uint32_t>(s->points.size());
    const uint64_t key = pass.et.keys[e];
    const uint32_t lo = EdgeKeyLow(key), hi = EdgeKeyHigh(key);
    s->points.push_back(Midpoint(s->points[lo], s->points[hi]));
    // Its place in the input: the mean of its ends' coordinates in the input triangle of a
    // triangle using the edge (any: on an input edge the coordinates carry by point).
    PointParam param;
    param.triangle = s->origin[pass.et.corners[pass.et.start[e]] / 3];
    double ba[3], bb[3];
    s->BaryIn(lo, param.triangle, ba);
    s->BaryIn(hi, param.triangle, bb);
    for (int k = 0; k < 3; ++k) param.bary[k] = 0.5 * (ba[k] + bb[k]);
    s->params.push_back(param);
  }
  std::unordered_map<uint64_t, uint32_t> mid_vertex;
  mid_vertex.reserve(2 * (new_count - nt));
  auto midpoint_vertex = [&](uint32_t va, uint32_t vb, uint32_t e) {
    const uint64_t key = EdgeKey(va, vb);
    const auto [it, inserted] =
        mid_vertex.try_emplace(key, static_cast<uint32_t>(mesh.positions.size()));
    if (!inserted) return it->second;
    const uint32_t a = std::min(va, vb), b = std::max(va, vb);
    mesh.positions.push_back(s->points[mid_point[e]]);
    if (s->has_normal) {
      const float3 na = mesh.normals[a], nb = mesh.normals[b];
      mesh.normals.push_back(NormalizeOr(na + nb, na));
    }
    if (s->has_uv) mesh.uvs.push_back(Midpoint(mesh.uvs[a], mesh.uvs[b]));
    s->pov.push_back(mid_point[e]);
    s->parents.push_back({a, b});
    return it->second;
  };
  std::vector<uint32_t> indices, next_origin;
  std::vector<uint8_t> next_dirty;
  indices.reserve(3 * new_count);
  next_origin.reserve(new_count);
  next_dirty.reserve(new_count);
  auto emit = [&](uint32_t a, uint32_t b, uint32_t c, uint32_t from, uint8_t d) {
    indices.insert(indices.end(), {a, b, c});
    next_origin.push_back(from);
    next_dirty.push_back(d);
  };
  for (size_t t = 0; t < nt; ++t) {
    const uint32_t* v = &mesh.indices[3 * t];
    const uint32_t* e = &pass.et.tri_edge[3 * t];
    const uint32_t from = s->origin[t];
    if (!HasMark(pass, t)) {
      // Kept as it is; evaluated again only while one of its edges misses its target.
      const bool misses = pass.length[e[0]] > pass.target[e[0]] ||
                          pass.length[e[1]] > pass.target[e[1]] ||
                          pass.length[e[2]] > pass.target[e[2]];
      emit(v[0], v[1], v[2], from, misses ? 1 : 0);
      continue;
    }
    const int k = LongestCorner(pass, t);
    const uint32_t a = v[k], b = v[(k + 1) % 3], c = v[(k + 2) % 3];
    const uint32_t eab = e[k], ebc = e[(k + 1) % 3], eca = e[(k + 2) % 3];
    const uint32_t m = midpoint_vertex(a, b, eab);
    // The half (a, m, c), bisected again at the midpoint q of (c, a) when that is marked.
    if (pass.marked[eca]) {
      const uint32_t q = midpoint_vertex(c, a, eca);
      emit(a, m, q, from, 1);
      emit(q, m, c, from, 1);
    } else {
      emit(a, m, c, from, 1);
    }
    // The half (m, b, c), bisected again at the midpoint n of (b, c) when that is marked.
    if (pass.marked[ebc]) {
      const uint32_t n = midpoint_vertex(b, c, ebc);
      emit(m, b, n, from, 1);
      emit(m, n, c, from, 1);
    } else {
      emit(m, b, c, from, 1);
    }
  }
  mesh.indices = std::move(indices);
  s->origin = std::move(next_origin);
  s->dirty = std::move(next_dirty);
}

// The offset of a PN edge control point from the linear patch: b_ij - (2 P_i + P_j) / 3 =
// -((P_j - P_i) . N_i) N_i / 3 (Vlachos et al. 2001), in double.
void EdgeControlOffset(const float3& pi, const float3& pj, const float3& ni, double out[3]) {
  const double w = (double(pj.x) - pi.x) * ni.x + (double(pj.y) - pi.y) * ni.y +
                   (double(pj.z) - pi.z) * ni.z;
  out[0] = -w * ni.x / 3.0;
  out[1] = -w * ni.y / 3.0;
  out[2] = -w * ni.z / 3.0;
}

// docs/model.md §14: where the input's normals disagree sharply (a mouth corner, where the
// outer skin, the slit and the inner lip rolls meet in one point) a PN patch can bulge past its
// own triangle's plane and turn a new triangle over against the input triangle it lies in. Such
// a triangle's new points go back to their flat positions (which lie in the input triangle,
// turned its way), and the check repeats, since a point moved back is shared with other new
// triangles; it ends because every round moves at least one point back for good.
void KeepOrientation(State* s, const std::vector<float3>& flat) {
  const size_t np = s->input_points;
  std::vector<uint8_t> is_flat(flat.size(), 0);
  const std::vector<uint32_t>& idx = s->mesh.indices;
  for (bool changed = true; changed;) {
    changed = false;
    for (size_t t = 0; 3 * t < idx.size(); ++t) {
      const uint32_t a = s->pov[idx[3 * t]], b = s->pov[idx[3 * t + 1]], c = s->pov[idx[3 * t + 2]];
      if (a < np && b < np && c < np) continue;
      const uint32_t* in = &s->input_triangles[3 * size_t(s->origin[t])];
      const float3 n_in = Cross(s->points[in[1]] - s->points[in[0]], s->points[in[2]] - s->points[in[0]]);
      const float3 n = Cross(s->points[b] - s->points[a], s->points[c] - s->points[a]);
      if (double(n.x) * n_in.x + double(n.y) * n_in.y + double(n.z) * n_in.z > 0) continue;
      for (uint32_t q : {a, b, c})
        if (q >= np && !is_flat[q - np]) {
          s->points[q] = flat[q - np];
          is_flat[q - np] = 1;
          changed = true;
        }
    }
  }
}

// docs/model.md §14: moves every new point from its flat position onto the PN triangle of its
// input triangle, normals = the input's area-weighted point normals. Input points stay.
void PlaceOnPnTriangles(State* s) {
  const size_t np = s->input_points;
  const std::vector<float3> normals = ComputeVertexNormals(
      span<const float3>(s->points.data(), np), span<const uint32_t>(s->input_triangles));
  const std::vector<float3> flat(s->points.begin() + std::ptrdiff_t(np), s->points.end());
  for (size_t i = 0; i < s->params.size(); ++i) {
    const PointParam& q = s->params[i];
    const uint32_t* c = &s->input_triangles[3 * size_t(q.triangle)];
    double d[3] = {0, 0, 0};
    int zero = -1, zeros = 0;
    for (int k = 0; k < 3; ++k)
      if (q.bary[k] == 0) zero = k, ++zeros;
    if (zeros == 1) {
      // On the input edge opposite corner `zero`: the edge's cubic, ends in point-id order.
      uint32_t lo = c[(zero + 1) % 3], hi = c[(zero + 2) % 3];
      double t = q.bary[(zero + 2) % 3];  // the coordinate of hi
      if (lo > hi) std::swap(lo, hi), t = q.bary[(zero + 1) % 3];
      double a[3], b[3];
      EdgeControlOffset(s->points[lo], s->points[hi], normals[lo], a);
      EdgeControlOffset(s->points[hi], s->points[lo], normals[hi], b);
      const double wa = 3 * (1 - t) * (1 - t) * t, wb = 3 * (1 - t) * t * t;
      for (int k = 0; k < 3; ++k) d[k] = wa * a[k] + wb * b[k];
    } else {
      // Inside: the six edge control offsets and the centre's, 1.5 times their mean
      // (b111 = E + (E - V) / 2, and the linear patch's six edge points average to V).
      const double u[3] = {q.bary[0], q.bary[1], q.bary[2]};
      double centre[3] = {0, 0, 0};
      for (int i0 = 0; i0 < 3; ++i0) {
        for (int j0 : {(i0 + 1) % 3, (i0 + 2) % 3}) {
          double o[3];
          EdgeControlOffset(s->points[c[i0]], s->points[c[j0]], normals[c[i0]], o);
          const double w = 3 * u[i0] * u[i0] * u[j0];  // b_(2 at i0, 1 at j0)
          for (int k = 0; k < 3; ++k) d[k] += w * o[k], centre[k] += o[k] / 6.0;
        }
      }
      const double w111 = 6 * u[0] * u[1] * u[2];
      for (int k = 0; k < 3; ++k) d[k] += w111 * 1.5 * centre[k];
    }
    float3& p = s->points[np + i];
    p = {static_cast<float>(double(p.x) + d[0]), static_cast<float>(double(p.y) + d[1]),
         static_cast<float>(double(p.z) + d[2])};
  }
  KeepOrientation(s, flat);
  for (size_t v = 0; v < s->mesh.positions.size(); ++v)
    if (s->pov[v] >= np) s->mesh.positions[v] = s->points[s->pov[v]];
}

}  // namespace

bool RefineMesh(const MeshData& in, const EdgeLengthField& max_edge, const RefineOptions& options,
                RefineResult* out, Diagnostics* diag) {
  Diagnostics local;
  if (!diag) diag = &local;
  const std::string where = in.source.empty() ? std::string("refinement") : in.source;
  if (!out) {
    diag->Error(where, "RefineMesh: no output given (expected a RefineResult to fill)");
    return false;
  }
  *out = RefineResult{};
  const size_t errors_before = diag->ErrorCount();
  try {
    // Counts of normals and uvs, a field, a finite weld tolerance.
    if (!CheckInput(in, max_edge, options, where, diag)) return false;
    // The result starts as the input (with no triangles, that is all).
    InitResult(in, out);
    if (in.indices.empty()) return true;
    // Weld: marks are decided on points, so both sides of a seam split alike.
    WeldedMesh welded;
    if (!WeldMesh(in, options.weld_tolerance, &welded, diag)) {
      *out = RefineResult{};
      return false;
    }
    State s{out->mesh, welded.point_of_vertex, welded.points, out->parents, out->triangle_origin,
            std::vector<uint8_t>(in.triangle_count(), 1), !in.uvs.empty(), !in.normals.empty(),
            welded.triangles, welded.points.size(), {}};
    // The shortest edge that is split: 2e-4 of the bounding-box diagonal, 8 weld tolerances.
    const double bbox_diag = ComputeBounds(welded.points).Diagonal();
    const double min_split = std::max(kMinSplitFraction * bbox_diag,
                                      8.0 * EffectiveWeldTolerance(options.weld_tolerance, bbox_diag));
    FieldSampler field{max_edge};
    Pass pass;
    for (;;) {
      const size_t nt = s.mesh.indices.size() / 3;
      // 1. The point-edges of the current triangles and their lengths.
      BuildPassEdges(s, &pass);
      // 2. Targets for the edges of triangles that changed (or still miss).
      SampleTargets(s, &field, &pass);
      // 3. Mark the edges that miss their target (unless too short to split).
      const Misses misses = MarkLongEdges(min_split, &pass);
      if (misses.splittable == 0) {
        if (misses.too_short > 0) {
          WarnStopped(where,
                      "stopped at the shortest edge it splits (" + G(min_split) +
                          ", 2e-4 of the bounding-box diagonal or 8 weld tolerances)",
                      out->passes, nt, misses, out, diag);
        }
        break;
      }
      if (out->passes >= static_cast<size_t>(std::max(options.max_passes, 0))) {
        WarnStopped(where,
                    "stopped at the pass limit (max_passes " + std::to_string(options.max_passes) +
                        ")",
                    out->passes, nt, misses, out, diag);
        break;
      }
      // 4. Closure: a triangle with a marked edge has its longest edge marked.
      CloseMarks(nt, &pass);
      // 5. The triangle limit: a pass that would exceed it is not run.
      const size_t new_count = CountAfterSplit(nt, pass);
      if (new_count > options.max_triangles) {
        WarnStopped(where,
                    "stopped at the triangle limit (max_triangles " +
                        std::to_string(options.max_triangles) + "; the next pass would make " +
                        std::to_string(new_count) + ")",
                    out->passes, nt, misses, out, diag);
        break;
      }
      // 6. Split: bisect every marked edge once.
      SplitMarked(pass, new_count, &s);
      ++out->passes;
    }
    // 7. Placement: new points onto the input's smooth surface (docs/model.md §14).
    if (options.placement == RefinePlacement::kSmooth && !s.params.empty()) PlaceOnPnTriangles(&s);
    // NaN samples of the field: one warning with the first place.
    if (field.nan_count > 0) {
      diag->Warning(where, "the edge-length field returned NaN at " +
                               std::to_string(field.nan_count) + " places (first at position (" +
                               G(field.nan_at.x) + ", " + G(field.nan_at.y) + ", " +
                               G(field.nan_at.z) +
                               ")); treated as no constraint (expected a positive length, or "
                               "+inf / <= 0 for none)");
    }
  } catch (const std::exception& e) {
    diag->Error(where, std::string("internal error while refining: ") + e.what());
  } catch (...) {
    diag->Error(where, "internal error while refining");
  }
  if (diag->ErrorCount() > errors_before) {
    *out = RefineResult{};
    return false;
  }
  return true;
}

std::vector<float> CarryAttribute(const RefineResult& refined,
                                  const std::vector<float>& per_input_vertex) {
  const size_t n = refined.parents.size();
  if (per_input_vertex.size() < refined.input_vertex_count || refined.input_vertex_count > n) {
    return {};
  }
  std::vector<double> value(n);
  for (size_t v = 0; v < n; ++v) {
    const auto [a, b] = refined.parents[v];
    if (v < refined.input_vertex_count) {
      value[v] = per_input_vertex[v];
    } else if (a < v && b < v) {
      value[v] = 0.5 * (value[a] + value[b]);
    } else {
      return {};  // parents not earlier: not a RefineMesh result
    }
  }
  return std::vector<float>(value.begin(), value.end());
}

}  // namespace mimetic

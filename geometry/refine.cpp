// geometry/refine.cpp: RefineMesh, adaptive refinement at rig compile time (MODEL.md §11).
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
#include "geometry/refine.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <deque>
#include <exception>
#include <limits>
#include <string>
#include <unordered_map>

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

uint64_t EdgeKey(uint32_t a, uint32_t b) {
  return (static_cast<uint64_t>(std::min(a, b)) << 32) | std::max(a, b);
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

// Point-edges of the current triangles: ids in ascending key order, per-corner edge ids
// (corner 3t+k is edge (k, k+1) of triangle t), and the corners of each edge (CSR).
struct EdgeTable {
  std::vector<uint64_t> keys;       // #E, ascending
  std::vector<uint32_t> tri_edge;   // 3 per triangle
  std::vector<uint32_t> start;      // #E + 1
  std::vector<uint32_t> corners;    // 3 per triangle, grouped by edge, ascending within one
};

void BuildEdges(const std::vector<uint32_t>& tri_points, EdgeTable* et) {
  const size_t n = tri_points.size();
  std::vector<std::pair<uint64_t, uint32_t>> uses(n);
  for (size_t c = 0; c < n; ++c) {
    const size_t t = c / 3, k = c % 3;
    uses[c] = {EdgeKey(tri_points[c], tri_points[3 * t + (k + 1) % 3]), static_cast<uint32_t>(c)};
  }
  std::sort(uses.begin(), uses.end());
  et->keys.clear();
  et->start.clear();
  et->tri_edge.assign(n, kNone);
  et->corners.resize(n);
  for (size_t i = 0; i < n; ++i) {
    if (i == 0 || uses[i].first != uses[i - 1].first) {
      et->keys.push_back(uses[i].first);
      et->start.push_back(static_cast<uint32_t>(i));
    }
    et->tri_edge[uses[i].second] = static_cast<uint32_t>(et->keys.size() - 1);
    et->corners[i] = uses[i].second;
  }
  et->start.push_back(static_cast<uint32_t>(n));
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
    if (diag->ErrorCount() > errors_before) return false;

    out->input_vertex_count = nv;
    if (in.indices.empty()) {
      // Nothing to refine (and nothing to weld): the result is the input.
      out->mesh = in;
      out->parents.resize(nv);
      for (size_t v = 0; v < nv; ++v) out->parents[v] = {uint32_t(v), uint32_t(v)};
      return true;
    }
    WeldedMesh welded;
    if (!WeldMesh(in, options.weld_tolerance, &welded, diag)) return false;

    // Working state. Vertices are only appended, so input vertex indices never change.
    MeshData& mesh = out->mesh;
    mesh = in;
    std::vector<uint32_t>& pov = welded.point_of_vertex;
    std::vector<float3>& points = welded.points;
    std::vector<std::pair<uint32_t, uint32_t>>& parents = out->parents;
    parents.resize(nv);
    for (size_t v = 0; v < nv; ++v) parents[v] = {uint32_t(v), uint32_t(v)};
    std::vector<uint32_t>& origin = out->triangle_origin;
    origin.resize(in.triangle_count());
    for (size_t t = 0; t < origin.size(); ++t) origin[t] = static_cast<uint32_t>(t);
    std::vector<uint8_t> dirty(origin.size(), 1);
    const bool has_uv = !mesh.uvs.empty(), has_normal = !mesh.normals.empty();

    double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
    for (size_t p = 0; p < points.size(); ++p) {
      const double c[3] = {points[p].x, points[p].y, points[p].z};
      for (int k = 0; k < 3; ++k) {
        if (p == 0 || c[k] < lo[k]) lo[k] = c[k];
        if (p == 0 || c[k] > hi[k]) hi[k] = c[k];
      }
    }
    const double bbox_diag = std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) +
                                       (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                                       (hi[2] - lo[2]) * (hi[2] - lo[2]));
    const double tol = options.weld_tolerance > 0 ? options.weld_tolerance : 1e-6 * bbox_diag;
    const double min_split = std::max(kMinSplitFraction * bbox_diag, 8.0 * tol);

    size_t nan_count = 0;
    float3 nan_at{};
    auto evaluate = [&](float3 p, float2 uv) -> double {
      const float v = max_edge(p, uv);
      if (std::isnan(v)) {
        if (nan_count++ == 0) nan_at = p;
        return kInf;
      }
      return v > 0 ? static_cast<double>(v) : kInf;  // +inf and <= 0: no constraint
    };
    auto uv_of = [&](uint32_t v) { return has_uv ? mesh.uvs[v] : float2{}; };

    EdgeTable et;
    std::vector<uint32_t> tri_points;
    std::vector<double> length, target;
    std::vector<uint8_t> evaluated, marked;
    for (;;) {
      const size_t nt = mesh.indices.size() / 3;
      tri_points.resize(nt * 3);
      for (size_t i = 0; i < nt * 3; ++i) tri_points[i] = pov[mesh.indices[i]];
      BuildEdges(tri_points, &et);
      const size_t ne = et.keys.size();
      length.resize(ne);
      for (size_t e = 0; e < ne; ++e) {
        length[e] = Distance(points[et.keys[e] >> 32], points[et.keys[e] & 0xffffffffu]);
      }

      // 1. Targets for the edges of dirty triangles, and the edges that miss them.
      target.assign(ne, kInf);
      evaluated.assign(ne, 0);
      for (size_t t = 0; t < nt; ++t) {
        if (!dirty[t]) continue;
        const uint32_t* v = &mesh.indices[3 * t];
        const float3 a = points[pov[v[0]]], b = points[pov[v[1]]], c = points[pov[v[2]]];
        const float3 centroid{
            static_cast<float>((static_cast<double>(a.x) + b.x + c.x) / 3.0),
            static_cast<float>((static_cast<double>(a.y) + b.y + c.y) / 3.0),
            static_cast<float>((static_cast<double>(a.z) + b.z + c.z) / 3.0)};
        const float2 ua = uv_of(v[0]), ub = uv_of(v[1]), uc = uv_of(v[2]);
        const float2 uv_centroid{
            static_cast<float>((static_cast<double>(ua.x) + ub.x + uc.x) / 3.0),
            static_cast<float>((static_cast<double>(ua.y) + ub.y + uc.y) / 3.0)};
        const double at_centroid = evaluate(centroid, uv_centroid);
        for (int k = 0; k < 3; ++k) {
          const uint32_t e = et.tri_edge[3 * t + k];
          target[e] = std::min(target[e], at_centroid);
          if (!evaluated[e]) {
            evaluated[e] = 1;
            const uint32_t va = v[k], vb = v[(k + 1) % 3];
            target[e] = std::min(target[e], evaluate(Midpoint(points[pov[va]], points[pov[vb]]),
                                                     Midpoint(uv_of(va), uv_of(vb))));
          }
        }
      }
      marked.assign(ne, 0);
      size_t splittable = 0, too_short = 0;
      double worst_ratio = 1, worst_length = 0, worst_target = 0;
      for (size_t e = 0; e < ne; ++e) {
        if (!(length[e] > target[e])) continue;
        const double ratio = length[e] / target[e];
        if (ratio > worst_ratio) {
          worst_ratio = ratio;
          worst_length = length[e];
          worst_target = target[e];
        }
        if (length[e] >= min_split) {
          marked[e] = 1;
          ++splittable;
        } else {
          ++too_short;
        }
      }

      auto stop = [&](const std::string& why) {
        out->bound_met = false;
        diag->Warning(where,
                      "adaptive refinement (MODEL.md §11) " + why + " after " +
                          std::to_string(out->passes) + " passes with " + std::to_string(nt) +
                          " triangles: " + std::to_string(splittable + too_short) +
                          " edges are still longer than their target, the worst by a factor " +
                          G(worst_ratio) + " (length " + G(worst_length) + ", target " +
                          G(worst_target) +
                          "); expected every edge in a wrinkle support within its target");
      };
      if (splittable == 0) {
        if (too_short > 0) {
          stop("stopped at the shortest edge it splits (" + G(min_split) +
               ", 2e-4 of the bounding-box diagonal or 8 weld tolerances)");
        }
        break;
      }
      if (out->passes >= static_cast<size_t>(std::max(options.max_passes, 0))) {
        stop("stopped at the pass limit (max_passes " + std::to_string(options.max_passes) + ")");
        break;
      }

      // 2. Closure: every triangle with a marked edge has its longest edge marked.
      auto longest = [&](size_t t) {
        int best = 0;
        for (int k = 1; k < 3; ++k) {
          const uint32_t e = et.tri_edge[3 * t + k], b = et.tri_edge[3 * t + best];
          if (length[e] > length[b] || (length[e] == length[b] && e < b)) best = k;
        }
        return best;
      };
      auto has_mark = [&](size_t t) {
        return marked[et.tri_edge[3 * t]] || marked[et.tri_edge[3 * t + 1]] ||
               marked[et.tri_edge[3 * t + 2]];
      };
      std::deque<uint32_t> queue;
      for (size_t t = 0; t < nt; ++t) {
        if (has_mark(t)) queue.push_back(static_cast<uint32_t>(t));
      }
      while (!queue.empty()) {
        const uint32_t t = queue.front();
        queue.pop_front();
        const uint32_t e = et.tri_edge[3 * t + longest(t)];
        if (marked[e]) continue;
        marked[e] = 1;
        for (uint32_t i = et.start[e]; i < et.start[e + 1]; ++i) queue.push_back(et.corners[i] / 3);
      }
      size_t new_count = 0;
      for (size_t t = 0; t < nt; ++t) {
        new_count += 1 + marked[et.tri_edge[3 * t]] + marked[et.tri_edge[3 * t + 1]] +
                     marked[et.tri_edge[3 * t + 2]];
      }
      if (new_count > options.max_triangles) {
        stop("stopped at the triangle limit (max_triangles " +
             std::to_string(options.max_triangles) + "; the next pass would make " +
             std::to_string(new_count) + ")");
        break;
      }

      // 3. Split. New points in edge order, new file vertices in order of first use.
      std::vector<uint32_t> mid_point(ne, kNone);
      for (size_t e = 0; e < ne; ++e) {
        if (!marked[e]) continue;
        mid_point[e] = static_cast<uint32_t>(points.size());
        points.push_back(Midpoint(points[et.keys[e] >> 32], points[et.keys[e] & 0xffffffffu]));
      }
      std::unordered_map<uint64_t, uint32_t> mid_vertex;
      mid_vertex.reserve(2 * (new_count - nt));
      auto midpoint_vertex = [&](uint32_t va, uint32_t vb, uint32_t e) {
        const uint64_t key = EdgeKey(va, vb);
        const auto [it, inserted] =
            mid_vertex.try_emplace(key, static_cast<uint32_t>(mesh.positions.size()));
        if (!inserted) return it->second;
        const uint32_t a = std::min(va, vb), b = std::max(va, vb);
        const float3 position = points[mid_point[e]];
        mesh.positions.push_back(position);
        if (has_normal) {
          const float3 na = mesh.normals[a], nb = mesh.normals[b];
          mesh.normals.push_back(NormalizeOr(na + nb, na));
        }
        if (has_uv) {
          const float2 uv = Midpoint(mesh.uvs[a], mesh.uvs[b]);
          mesh.uvs.push_back(uv);
        }
        pov.push_back(mid_point[e]);
        parents.push_back({a, b});
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
        const uint32_t* e = &et.tri_edge[3 * t];
        if (!has_mark(t)) {
          // Kept as it is; evaluated again only while one of its edges misses its target.
          const bool misses = length[e[0]] > target[e[0]] || length[e[1]] > target[e[1]] ||
                              length[e[2]] > target[e[2]];
          emit(v[0], v[1], v[2], origin[t], misses ? 1 : 0);
          continue;
        }
        const int k = longest(t);
        const uint32_t a = v[k], b = v[(k + 1) % 3], c = v[(k + 2) % 3];
        const uint32_t eab = e[k], ebc = e[(k + 1) % 3], eca = e[(k + 2) % 3];
        const uint32_t m = midpoint_vertex(a, b, eab);
        if (marked[eca]) {
          const uint32_t q = midpoint_vertex(c, a, eca);
          emit(a, m, q, origin[t], 1);
          emit(q, m, c, origin[t], 1);
        } else {
          emit(a, m, c, origin[t], 1);
        }
        if (marked[ebc]) {
          const uint32_t n = midpoint_vertex(b, c, ebc);
          emit(m, b, n, origin[t], 1);
          emit(m, n, c, origin[t], 1);
        } else {
          emit(m, b, c, origin[t], 1);
        }
      }
      mesh.indices = std::move(indices);
      origin = std::move(next_origin);
      dirty = std::move(next_dirty);
      ++out->passes;
    }

    if (nan_count > 0) {
      diag->Warning(where, "the edge-length field returned NaN at " + std::to_string(nan_count) +
                               " places (first at position (" + G(nan_at.x) + ", " +
                               G(nan_at.y) + ", " + G(nan_at.z) +
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

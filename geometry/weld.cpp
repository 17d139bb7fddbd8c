// geometry/weld.cpp: WeldMesh, seam-split vertices -> surface points, then topology checks.
//
// Welding uses a uniform grid (cell size >= tolerance) hashed by cell coordinates: each vertex
// looks for an existing point in its own and the 26 neighbouring cells, so the cost is
// O(#V) expected, not O(#V^2). A point's position is the position of its first vertex (it is
// not averaged), and a vertex joins the lowest-numbered point within tolerance, so the result
// depends only on the vertex order: points are numbered in order of first occurrence.
#include "geometry/weld.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <unordered_map>

#include "geometry/bounds.h"
#include "geometry/normals.h"
#include "geometry/topology.h"

namespace mimetic {
namespace {

struct Cell {
  int64_t x, y, z;
  bool operator==(const Cell& o) const { return x == o.x && y == o.y && z == o.z; }
};
struct CellHash {
  size_t operator()(const Cell& c) const {
    uint64_t h = static_cast<uint64_t>(c.x) * 0x9E3779B97F4A7C15ull;
    h ^= static_cast<uint64_t>(c.y) + 0x7F4A7C159E3779B9ull + (h << 6) + (h >> 2);
    h ^= static_cast<uint64_t>(c.z) * 0xC2B2AE3D27D4EB4Full + (h << 6) + (h >> 2);
    h ^= h >> 31;
    return static_cast<size_t>(h);
  }
};

std::string G(double v) {
  char buf[32];
  std::snprintf(buf, sizeof(buf), "%.6g", v);
  return buf;
}

// Input sanity: welding needs a finite tolerance, whole triangles, indices in range and finite
// positions. Records every problem; returns false when there was any.
bool CheckInput(const MeshData& mesh, float tolerance, Diagnostics* diag) {
  const std::string summary;
  const size_t errors_before = diag->ErrorCount();
  const size_t nv = mesh.positions.size();
  if (!std::isfinite(tolerance)) {
    diag->Error(summary, "weld tolerance " + G(tolerance) +
                             " is not finite (expected a positive number, or <= 0 for the "
                             "default)");
    return false;
  }
  if (mesh.indices.size() % 3 != 0) {
    diag->Error(summary, "index count " + std::to_string(mesh.indices.size()) +
                             " is not a multiple of 3 (expected whole triangles)");
  }
  {
    CappedErrors range(diag, summary, "indices out of range");
    for (size_t i = 0; i < mesh.indices.size(); ++i) {
      if (mesh.indices[i] >= nv) {
        range.Add("triangle " + std::to_string(i / 3),
                  "index " + std::to_string(mesh.indices[i]) + " out of range (mesh has " +
                      std::to_string(nv) + " vertices)");
      }
    }
    CappedErrors finite(diag, summary, "vertices with non-finite positions");
    for (size_t v = 0; v < nv; ++v) {
      if (!IsFinite(mesh.positions[v])) {
        finite.Add("vertex " + std::to_string(v), "position is not finite (expected finite numbers)");
      }
    }
  }
  return diag->ErrorCount() == errors_before;
}

// Each vertex joins the lowest-numbered point within `tol` of it, else starts a new point at
// its own position; the search visits only the grid cells within reach (see the file comment).
void WeldPoints(const MeshData& mesh, const BoundingBox& box, double tol, WeldedMesh* out) {
  const size_t nv = mesh.positions.size();
  const double diag_len = box.Diagonal();
  const double tol2 = tol * tol;
  // Any cell at least as large as the tolerance makes the neighbour search complete. With
  // cells of 4x the tolerance a vertex lies within tolerance of a cell face on a given axis
  // with probability 1/2, so on average ~3.4 of the 27 cells are visited. Cells are also kept
  // >= 1e-7 of the diagonal so cell coordinates stay small integers.
  double cell = std::max(4.0 * tol, 1e-7 * diag_len);
  if (!(cell > 0)) cell = 1.0;  // all vertices coincide (or there are none)
  const double inv_cell = 1.0 / cell;
  const double reach = 1.01 * tol + 1e-12 * cell;  // margin for rounding in the cell math

  std::unordered_map<Cell, uint32_t, CellHash> head;  // cell -> first point in it
  head.reserve(nv);
  std::vector<uint32_t> next;  // per point: next point in the same cell, or UINT32_MAX
  std::vector<double> px;      // point positions in double, 3 per point
  constexpr uint32_t kNone = UINT32_MAX;
  out->point_of_vertex.resize(nv);
  for (size_t v = 0; v < nv; ++v) {
    const float3 p = mesh.positions[v];
    const double c[3] = {p.x, p.y, p.z};
    int64_t home_c[3];
    int from[3], to[3];  // neighbour range per axis: only sides within tolerance
    for (int k = 0; k < 3; ++k) {
      const double f = (c[k] - box.lo[k]) * inv_cell;
      home_c[k] = static_cast<int64_t>(std::floor(f));
      const double in_cell = (f - static_cast<double>(home_c[k])) * cell;  // 0..cell
      from[k] = in_cell <= reach ? -1 : 0;
      to[k] = cell - in_cell <= reach ? 1 : 0;
    }
    const Cell home{home_c[0], home_c[1], home_c[2]};
    uint32_t best = kNone;
    for (int dx = from[0]; dx <= to[0]; ++dx) {
      for (int dy = from[1]; dy <= to[1]; ++dy) {
        for (int dz = from[2]; dz <= to[2]; ++dz) {
          const auto it = head.find({home.x + dx, home.y + dy, home.z + dz});
          if (it == head.end()) continue;
          for (uint32_t q = it->second; q != kNone; q = next[q]) {
            if (q >= best) continue;
            const double ex = px[3 * q] - c[0], ey = px[3 * q + 1] - c[1],
                         ez = px[3 * q + 2] - c[2];
            if (ex * ex + ey * ey + ez * ez <= tol2) best = q;
          }
        }
      }
    }
    if (best == kNone) {
      best = static_cast<uint32_t>(out->points.size());
      out->points.push_back(p);
      px.insert(px.end(), {c[0], c[1], c[2]});
      auto [it, inserted] = head.try_emplace(home, best);
      next.push_back(inserted ? kNone : it->second);
      it->second = best;
    }
    out->point_of_vertex[v] = best;
  }
}

// The file's triangles on points, in the file's order.
void MapTriangles(const MeshData& mesh, WeldedMesh* out) {
  const size_t nt = mesh.indices.size() / 3;
  out->triangles.resize(nt * 3);
  for (size_t i = 0; i < nt * 3; ++i) out->triangles[i] = out->point_of_vertex[mesh.indices[i]];
}

// Triangles that use a point twice, and triangles whose area is below `min_area`.
void CheckTriangles(const MeshData& mesh, const WeldedMesh& welded, double min_area,
                    Diagnostics* diag) {
  const std::string summary;
  CappedErrors repeated(diag, summary, "triangles with repeated points");
  CappedErrors tiny(diag, summary, "triangles with near-zero area");
  for (size_t t = 0; t < welded.triangles.size() / 3; ++t) {
    const uint32_t* vi = &mesh.indices[3 * t];
    const uint32_t* pi = &welded.triangles[3 * t];
    auto name = [&] {
      return "triangle " + std::to_string(t) + " (vertices " + std::to_string(vi[0]) + ", " +
             std::to_string(vi[1]) + ", " + std::to_string(vi[2]) + ")";
    };
    auto points = [&] {
      return "points " + std::to_string(pi[0]) + ", " + std::to_string(pi[1]) + ", " +
             std::to_string(pi[2]);
    };
    if (pi[0] == pi[1] || pi[1] == pi[2] || pi[0] == pi[2]) {
      repeated.Add(name(), "is degenerate: it uses a point twice (" + points() +
                               "); expected three distinct points");
      continue;
    }
    const double area =
        TriangleArea(welded.points[pi[0]], welded.points[pi[1]], welded.points[pi[2]]);
    if (area < min_area || area == 0) {
      tiny.Add(name(), "has near-zero area " + G(area) + " (" + points() +
                           "; expected at least 1e-10 of the squared bounding-box diagonal, " +
                           G(min_area) + ")");
    }
  }
}

// Edges shared by more than two triangles (degenerate triangles have no edges here).
void CheckEdges(const WeldedMesh& welded, Diagnostics* diag) {
  EdgeTable edges;
  BuildEdgeTable(welded.triangles, &edges);
  CappedErrors nonmanifold(diag, "", "non-manifold edges");
  for (const uint32_t e : NonManifoldEdges(edges)) {
    const uint32_t uses = edges.use_count(e);
    std::string tris;
    constexpr size_t kListed = 8;
    for (uint32_t k = 0; k < uses && k < kListed; ++k) {
      if (k > 0) tris += ", ";
      tris += std::to_string(edges.corners[edges.start[e] + k] / 3);
    }
    if (uses > kListed) tris += ", ...";
    nonmanifold.Add("edge (points " + std::to_string(EdgeKeyLow(edges.keys[e])) + ", " +
                        std::to_string(EdgeKeyHigh(edges.keys[e])) + ")",
                    "is non-manifold: shared by " + std::to_string(uses) + " triangles (" + tris +
                        "); expected at most 2");
  }
}

}  // namespace

double EffectiveWeldTolerance(float tolerance, double bbox_diagonal) {
  return tolerance > 0 ? static_cast<double>(tolerance) : 1e-6 * bbox_diagonal;
}

bool WeldMesh(const MeshData& mesh, float tolerance, WeldedMesh* out, Diagnostics* diag) {
  Diagnostics local;
  if (!diag) diag = &local;
  if (!out) {
    diag->Error("", "WeldMesh: no output given");
    return false;
  }
  *out = WeldedMesh{};
  // `where` names the element only; callers prefix the file (Diagnostics::Append).
  const size_t errors_before = diag->ErrorCount();
  try {
    // 1. Finite tolerance and positions, whole triangles, indices in range.
    if (!CheckInput(mesh, tolerance, diag)) return false;
    // 2. The bounding box scales the default tolerance and the zero-area threshold.
    const BoundingBox box = ComputeBounds(mesh.positions);
    const double diag_len = box.Diagonal();
    // 3. Vertices -> points (first occurrence order, first vertex's position).
    WeldPoints(mesh, box, EffectiveWeldTolerance(tolerance, diag_len), out);
    // 4. Triangles on points.
    MapTriangles(mesh, out);
    // 5. Degenerate and near-zero-area triangles.
    CheckTriangles(mesh, *out, 1e-10 * diag_len * diag_len, diag);
    // 6. Non-manifold edges.
    CheckEdges(*out, diag);
  } catch (const std::exception& e) {
    diag->Error("", std::string("internal error while welding: ") + e.what());
  } catch (...) {
    diag->Error("", "internal error while welding");
  }
  return diag->ErrorCount() == errors_before;
}

}  // namespace mimetic

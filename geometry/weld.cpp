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

}  // namespace

bool WeldMesh(const MeshData& mesh, float tolerance, WeldedMesh* out, Diagnostics* diag) {
  Diagnostics local;
  if (!diag) diag = &local;
  if (!out) {
    diag->Error("", "WeldMesh: no output given");
    return false;
  }
  *out = WeldedMesh{};
  // `where` names the element only; callers prefix the file (Diagnostics::Append).
  auto at = [](const std::string& element) { return element; };
  const std::string summary;
  const size_t errors_before = diag->ErrorCount();
  try {
    const size_t nv = mesh.positions.size();
    // Input sanity: welding needs finite positions and valid indices.
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
          range.Add(at("triangle " + std::to_string(i / 3)),
                    "index " + std::to_string(mesh.indices[i]) + " out of range (mesh has " +
                        std::to_string(nv) + " vertices)");
        }
      }
      CappedErrors finite(diag, summary, "vertices with non-finite positions");
      for (size_t v = 0; v < nv; ++v) {
        if (!IsFinite(mesh.positions[v])) {
          finite.Add(at("vertex " + std::to_string(v)),
                     "position is not finite (expected finite numbers)");
        }
      }
    }
    if (diag->ErrorCount() > errors_before) return false;

    // Bounding box (double, so the diagonal of a large mesh does not lose digits).
    double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
    for (size_t v = 0; v < nv; ++v) {
      const float3 p = mesh.positions[v];
      const double c[3] = {p.x, p.y, p.z};
      for (int k = 0; k < 3; ++k) {
        if (v == 0 || c[k] < lo[k]) lo[k] = c[k];
        if (v == 0 || c[k] > hi[k]) hi[k] = c[k];
      }
    }
    const double diag_len = std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) +
                                      (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                                      (hi[2] - lo[2]) * (hi[2] - lo[2]));
    const double tol = tolerance > 0 ? static_cast<double>(tolerance) : 1e-6 * diag_len;
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
        const double f = (c[k] - lo[k]) * inv_cell;
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

    const size_t nt = mesh.indices.size() / 3;
    out->triangles.resize(nt * 3);
    for (size_t i = 0; i < nt * 3; ++i) out->triangles[i] = out->point_of_vertex[mesh.indices[i]];

    // Topology checks on the welded triangles.
    const double min_area = 1e-10 * diag_len * diag_len;
    struct EdgeUse {
      uint64_t key;  // (lo point << 32) | hi point
      uint32_t triangle;
    };
    std::vector<EdgeUse> edges;
    edges.reserve(nt * 3);
    {
      CappedErrors repeated(diag, summary, "triangles with repeated points");
      CappedErrors tiny(diag, summary, "triangles with near-zero area");
      for (size_t t = 0; t < nt; ++t) {
        const uint32_t* vi = &mesh.indices[3 * t];
        const uint32_t* pi = &out->triangles[3 * t];
        auto name = [&] {
          return "triangle " + std::to_string(t) + " (vertices " + std::to_string(vi[0]) + ", " +
                 std::to_string(vi[1]) + ", " + std::to_string(vi[2]) + ")";
        };
        auto points = [&] {
          return "points " + std::to_string(pi[0]) + ", " + std::to_string(pi[1]) + ", " +
                 std::to_string(pi[2]);
        };
        if (pi[0] == pi[1] || pi[1] == pi[2] || pi[0] == pi[2]) {
          repeated.Add(at(name()), "is degenerate: it uses a point twice (" + points() +
                                     "); expected three distinct points");
          continue;
        }
        const double* a = &px[3 * pi[0]];
        const double* b = &px[3 * pi[1]];
        const double* c = &px[3 * pi[2]];
        const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        const double w[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
        const double n[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2],
                             u[0] * w[1] - u[1] * w[0]};
        const double area = 0.5 * std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        if (area < min_area || area == 0) {
          tiny.Add(at(name()), "has near-zero area " + G(area) + " (" + points() +
                                 "; expected at least 1e-10 of the squared bounding-box "
                                 "diagonal, " + G(min_area) + ")");
        }
        for (int e = 0; e < 3; ++e) {
          const uint32_t p0 = pi[e], p1 = pi[(e + 1) % 3];
          const uint64_t key = (static_cast<uint64_t>(std::min(p0, p1)) << 32) | std::max(p0, p1);
          edges.push_back({key, static_cast<uint32_t>(t)});
        }
      }
    }
    std::sort(edges.begin(), edges.end(), [](const EdgeUse& a, const EdgeUse& b) {
      return a.key != b.key ? a.key < b.key : a.triangle < b.triangle;
    });
    CappedErrors nonmanifold(diag, summary, "non-manifold edges");
    for (size_t i = 0; i < edges.size();) {
      size_t j = i + 1;
      while (j < edges.size() && edges[j].key == edges[i].key) ++j;
      if (j - i > 2) {
        const uint32_t p0 = static_cast<uint32_t>(edges[i].key >> 32);
        const uint32_t p1 = static_cast<uint32_t>(edges[i].key & 0xffffffffu);
        std::string tris;
        constexpr size_t kListed = 8;
        for (size_t k = i; k < j && k - i < kListed; ++k) {
          if (k > i) tris += ", ";
          tris += std::to_string(edges[k].triangle);
        }
        if (j - i > kListed) tris += ", ...";
        nonmanifold.Add(at("edge (points " + std::to_string(p0) + ", " + std::to_string(p1) + ")"),
                        "is non-manifold: shared by " + std::to_string(j - i) + " triangles (" +
                            tris + "); expected at most 2");
      }
      i = j;
    }
  } catch (const std::exception& e) {
    diag->Error(summary, std::string("internal error while welding: ") + e.what());
  } catch (...) {
    diag->Error(summary, "internal error while welding");
  }
  return diag->ErrorCount() == errors_before;
}

}  // namespace mimetic

#include "geometry/orientation.h"

#include <cstdio>
#include <string>
#include <utility>

#include "geometry/weld.h"

namespace mimetic {

OrientationResult OrientTriangles(span<const uint32_t> triangles, const EdgeTable& edges) {
  OrientationResult r;
  const size_t tris = triangles.size() / 3;
  constexpr uint8_t kUnset = 2;
  r.flip.assign(tris, kUnset);
  // Direction of corner c's edge relative to its key: true when it runs low -> high.
  auto forward = [&](uint32_t c) {
    const size_t t = c / 3, k = c % 3;
    return triangles[3 * t + k] < triangles[3 * t + (k + 1) % 3];
  };
  std::vector<uint32_t> queue, members;
  for (size_t seed = 0; seed < tris; ++seed) {
    if (r.flip[seed] != kUnset) continue;
    ++r.components;
    queue.assign(1, uint32_t(seed));
    members.clear();
    r.flip[seed] = 0;
    for (size_t head = 0; head < queue.size(); ++head) {
      const uint32_t t = queue[head];
      members.push_back(t);
      for (int k = 0; k < 3; ++k) {
        const uint32_t e = edges.tri_edge[3 * size_t(t) + k];
        if (e == EdgeTable::kNoEdge || edges.use_count(e) != 2) continue;
        const uint32_t c0 = edges.corners[edges.start[e]], c1 = edges.corners[edges.start[e] + 1];
        const uint32_t mine = 3 * t + uint32_t(k);
        const uint32_t other = mine == c0 ? c1 : c0;
        const uint32_t u = other / 3;
        if (u == t) continue;  // a triangle using one edge twice: degenerate, WeldMesh's
        // Consistent when the two corners run opposite ways after their flips.
        const uint8_t want = uint8_t(r.flip[t] ^ (forward(mine) == forward(other) ? 1 : 0));
        if (r.flip[u] == kUnset) {
          r.flip[u] = want;
          queue.push_back(u);
        } else if (r.flip[u] != want && r.orientable) {
          r.orientable = false;
          r.conflict_a = EdgeKeyLow(edges.keys[e]);
          r.conflict_b = EdgeKeyHigh(edges.keys[e]);
          r.conflict_triangle[0] = t < u ? t : u;
          r.conflict_triangle[1] = t < u ? u : t;
        }
      }
    }
    size_t flips = 0;
    for (uint32_t t : members) flips += r.flip[t];
    if (2 * flips > members.size())  // keep the majority's winding
      for (uint32_t t : members) r.flip[t] ^= 1;
  }
  for (uint8_t f : r.flip) r.flipped += f;
  return r;
}

bool MakeWindingConsistent(const MeshData& mesh, float weld_tolerance, const std::string& where,
                           std::vector<uint32_t>* fixed_indices, Diagnostics* diag) {
  fixed_indices->clear();
  WeldedMesh welded;
  Diagnostics quiet;  // the caller welds again and reports what is wrong with the mesh
  if (!WeldMesh(mesh, weld_tolerance, &welded, &quiet)) return true;
  EdgeTable edges;
  BuildEdgeTable(welded.triangles, &edges);
  const OrientationResult r = OrientTriangles(welded.triangles, edges);
  const size_t tris = mesh.triangle_count();
  if (!r.orientable) {
    diag->Error(where, "the surface is not orientable: no winding of its triangles agrees "
                       "across every edge (triangles " + std::to_string(r.conflict_triangle[0]) +
                       " and " + std::to_string(r.conflict_triangle[1]) + " meet at edge (points " +
                       std::to_string(r.conflict_a) + ", " + std::to_string(r.conflict_b) +
                       ") with windings that cannot both be kept, as on a Moebius strip); "
                       "expected a surface whose triangles can all face outward");
    return false;
  }
  if (r.flipped == 0) return true;
  size_t example = 0;
  while (example < tris && !r.flip[example]) ++example;
  *fixed_indices = mesh.indices;
  for (size_t t = 0; t < tris; ++t)
    if (r.flip[t]) std::swap((*fixed_indices)[3 * t + 1], (*fixed_indices)[3 * t + 2]);
  char percent[32];
  std::snprintf(percent, sizeof percent, "%.1f%%", 100.0 * double(r.flipped) / double(tris));
  diag->Warning(where, std::to_string(r.flipped) + " of " + std::to_string(tris) +
                           " triangles (" + percent + ") were wound against their neighbours "
                           "(first: triangle " + std::to_string(example) + "); reversed them "
                           "to agree with the majority of their connected surface, so that "
                           "normals point one way. Fix the winding in the mesh file to silence "
                           "this");
  return true;
}

}  // namespace mimetic

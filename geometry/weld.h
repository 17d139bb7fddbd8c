// geometry/weld.h: welds seam-split vertices into surface points and checks topology.
#pragma once

#include <cstdint>
#include <vector>

#include "core/diagnostics.h"
#include "core/math.h"
#include "geometry/mesh.h"

namespace mimetic {

// The geometric surface: one point per distinct position. Everything geometric (stretch,
// normals, muscle weights) runs on points; outputs are scattered back to file vertices.
struct WeldedMesh {
  std::vector<float3> points;             // #P welded positions
  std::vector<uint32_t> point_of_vertex;  // #V: file vertex -> point
  std::vector<uint32_t> triangles;        // 3 per triangle, into points (same order as file)
};

// Vertices within `tolerance` (mesh units; <= 0 means 1e-6 of the bounding-box diagonal) of a
// point's position become that point. Deterministic: vertices are visited in order, a vertex
// joins the lowest-numbered point within tolerance (else starts a new one), so points are
// numbered in order of first occurrence and keep their first vertex's exact position (not an
// average). A spatial hash grid makes this O(#V) expected.
// Then checks the welded triangles and records errors (with the element: `triangle 17
// (vertices 3, 4, 5)`, `edge (points 8, 9)`; callers prefix the file, e.g. with Append) for
// degenerate triangles (a point used twice), near-zero area (below 1e-10 of the squared
// bounding-box diagonal) and non-manifold edges (shared by more than two triangles); at most
// 20 messages per kind, then "... and N more". Out-of-range indices, non-finite positions or a
// non-finite tolerance are reported too (then nothing is welded). Returns false when any
// error was recorded.
// The edge checks use geometry/topology.h (BuildEdgeTable, NonManifoldEdges).
bool WeldMesh(const MeshData& mesh, float tolerance, WeldedMesh* out, Diagnostics* diag);

// The tolerance WeldMesh uses, mesh units: `tolerance` when > 0, else 1e-6 of
// `bbox_diagonal` (the diagonal of the positions' bounding box, geometry/bounds.h).
double EffectiveWeldTolerance(float tolerance, double bbox_diagonal);

}  // namespace mimetic

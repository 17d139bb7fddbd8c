// rig/offline/weld.h: welds seam-split vertices into surface points and checks topology.
#pragma once

#include <cstdint>
#include <vector>

#include "core/diagnostics.h"
#include "core/math.h"
#include "rig/offline/mesh.h"

namespace mimetic {

// The geometric surface: one point per distinct position. Everything geometric (stretch,
// normals, muscle weights) runs on points; outputs are scattered back to file vertices.
struct WeldedMesh {
  std::vector<float3> points;             // #P welded positions
  std::vector<uint32_t> point_of_vertex;  // #V: file vertex -> point
  std::vector<uint32_t> triangles;        // 3 per triangle, into points (same order as file)
};

// Vertices closer than `tolerance` (mesh units; <= 0 means 1e-6 of the bounding-box
// diagonal) become one point. Records errors (with the element: `triangle 17 (vertices 3,
// 4, 5)`, `edge (points 8, 9)`) for degenerate or zero-area triangles (area below 1e-10 of
// the squared bounding-box diagonal, or repeated points) and non-manifold edges (shared by
// more than two triangles). Returns false when any error was recorded.
bool WeldMesh(const MeshData& mesh, float tolerance, WeldedMesh* out, Diagnostics* diag);

}  // namespace mimetic

// geometry/orientation.h: consistent triangle winding (issue 11: a mesh with every other
// triangle flipped validated, and its posed normals came out half backwards).
//
// Two triangles that share an edge are consistently wound when they traverse it in opposite
// directions (a -> b in one, b -> a in the other). Over each connected component (triangles
// joined through manifold edges, geometry/topology.h) the winding is propagated from one
// triangle by a breadth-first walk; a component is orientable when no edge then asks for both
// answers (a Moebius strip is the smallest one that does). Non-manifold edges (more than two
// triangles) and degenerate triangles join nothing here: WeldMesh reports them.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/diagnostics.h"
#include "core/span.h"
#include "geometry/mesh.h"
#include "geometry/topology.h"

namespace mimetic {

struct OrientationResult {
  // Per triangle: 1 when reversing it makes it agree with its component, which keeps the
  // winding of the majority of its triangles (fewest flips; ties keep triangle 0's side).
  std::vector<uint8_t> flip;
  size_t flipped = 0;     // triangles with flip = 1
  size_t components = 0;  // connected components (an isolated triangle is one)
  bool orientable = true;
  // When not orientable: the first edge found that no winding can satisfy, as its two point
  // indices, and the two triangles that meet there.
  uint32_t conflict_a = 0, conflict_b = 0;
  uint32_t conflict_triangle[2] = {0, 0};
};

// `triangles`: 3 indices per triangle into welded points (a seam-split file layout would cut
// the surface at every seam); `edges`: BuildEdgeTable of the same list. O(#T).
OrientationResult OrientTriangles(span<const uint32_t> triangles, const EdgeTable& edges);

// Welds `mesh` (geometry/weld.h, `weld_tolerance` as there) and checks its winding. Where
// triangles are wound inconsistently, fills `fixed_indices` with the mesh's index buffer with
// the minority reversed (a triangle's last two corners swapped) and records one warning with
// the count and the first such triangle; otherwise leaves `fixed_indices` empty. A
// non-orientable surface is an error naming the edge and the two triangles that meet there.
// `where` is the `where` of the messages (the mesh file). A mesh that does not weld is left
// alone (WeldMesh, run again by the caller, reports why). Returns false only when the surface
// is not orientable.
bool MakeWindingConsistent(const MeshData& mesh, float weld_tolerance, const std::string& where,
                           std::vector<uint32_t>* fixed_indices, Diagnostics* diag);

}  // namespace mimetic

// geometry/topology.h: adjacency of an indexed triangle list, the one home of the offline
// topology builders (edges, point -> triangles, point -> points) and the edge-use checks
// built on them (boundary and non-manifold edges).
//
// Inputs are `triangles`: 3 point (or vertex) indices per triangle, counter-clockwise or not;
// the builders never look at positions. Every table is deterministic: it depends only on the
// index list, so the same input gives the same bytes. Costs are O(n) for the CSR tables and
// O(n log n) for the edge table (a sort of the 3 * #T edge uses).
//
// OpenMesh (libopenmesh) is not used here: its half-edge kernel cannot hold a non-manifold
// edge at all (PolyConnectivity::add_face refuses the third face on an edge, printing
// "complex edge" to omerr), so it could not list the triangles of such an edge the way
// WeldMesh reports them, and building a second structure would only re-answer what the sorted
// edge list below answers.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/span.h"

namespace mimetic {

// A compressed sparse row table: row i owns items[offsets[i] .. offsets[i+1]).
struct CsrTable {
  std::vector<uint32_t> offsets;  // #rows + 1, offsets[0] = 0
  std::vector<uint32_t> items;
};

// point -> incident triangles (ascending triangle index; a triangle using a point twice is
// listed twice). Indices >= point_count are skipped. O(#T + #P).
CsrTable BuildPointTriangles(span<const uint32_t> triangles, size_t point_count);

// point -> neighbouring points through triangle edges (ascending, no duplicates, no self).
// Edges with an index >= point_count are skipped. O(#T log(valence) + #P).
CsrTable BuildPointNeighbors(span<const uint32_t> triangles, size_t point_count);

// The undirected edge (a, b) as one 64-bit key: (min << 32) | max. Symmetric in (a, b).
inline uint64_t EdgeKey(uint32_t a, uint32_t b) {
  return (static_cast<uint64_t>(a < b ? a : b) << 32) | (a < b ? b : a);
}
inline uint32_t EdgeKeyLow(uint64_t key) { return static_cast<uint32_t>(key >> 32); }
inline uint32_t EdgeKeyHigh(uint64_t key) { return static_cast<uint32_t>(key & 0xffffffffu); }

// The edges of a triangle list and the corners that use them. Corner 3t+k is the edge from
// corner k to corner (k+1) % 3 of triangle t. Edge ids follow ascending keys; the corners of
// one edge are grouped (CSR) in ascending corner order, hence ascending triangle order.
struct EdgeTable {
  static constexpr uint32_t kNoEdge = UINT32_MAX;
  std::vector<uint64_t> keys;      // #E, ascending (EdgeKey)
  std::vector<uint32_t> tri_edge;  // 3 per triangle: the corner's edge id, or kNoEdge
  std::vector<uint32_t> start;     // #E + 1: edge e's corners are corners[start[e] .. start[e+1])
  std::vector<uint32_t> corners;   // the used corners, grouped by edge

  size_t edge_count() const { return keys.size(); }
  uint32_t use_count(size_t e) const { return start[e + 1] - start[e]; }
};

// Builds `out` (reusing its storage) from `triangles` (3 indices each; a trailing partial
// triangle is ignored). A triangle that uses an index twice is degenerate: it contributes no
// edges (its three tri_edge entries are kNoEdge). O(#T log #T).
void BuildEdgeTable(span<const uint32_t> triangles, EdgeTable* out);

// Edges used by exactly one corner (the boundary; a closed manifold surface has none), and
// edges used by more than two (non-manifold), as edge ids of `edges`, ascending.
std::vector<uint32_t> BoundaryEdges(const EdgeTable& edges);
std::vector<uint32_t> NonManifoldEdges(const EdgeTable& edges);

}  // namespace mimetic

// geometry/refine.h: adaptive refinement of the rest mesh when the rig is compiled
// (docs/model.md §11).
//
// docs/model.md §11 (choice): refine once at compile time, so the runtime topology is fixed: split
// the triangles in each wrinkle's support until their edges are shorter than a fraction of the
// wrinkle's width (kDefaultRefineWidthFraction). This header knows nothing about wrinkles: the
// caller describes the wanted edge length as a field over the surface.
//
// Method: conforming longest-edge bisection (Rivara 1984; "4-T" partition), decided on the
// welded topology so that both sides of a UV/normal seam split identically. Triangles whose
// edges all meet the field, and that no neighbour's split reaches, keep their vertices and
// their index order. New points are placed on a smooth surface through the input points, the
// PN triangle (curved point-normal triangle, Vlachos et al. 2001) of the input triangle they
// lie in (docs/model.md §14), so the refined rest pose is not faceted and the input vertices
// stay where they were (RefinePlacement).
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <utility>
#include <vector>

#include "core/diagnostics.h"
#include "core/math.h"
#include "geometry/mesh.h"

namespace mimetic {

// Default target edge length inside a wrinkle's support, as a fraction of the wrinkle's width.
inline constexpr float kDefaultRefineWidthFraction = 0.25f;

// Target (maximum) edge length at a place on the surface, in mesh units. Return +infinity, or
// any value <= 0, for "no constraint" (outside every wrinkle's support). NaN is treated as no
// constraint and reported as a warning. Called with a triangle's centroid and with edge
// midpoints (position in mesh units; uv interpolated from the file vertices, {0, 0} when the
// mesh has no uvs). An edge must not be longer than the field at its midpoint nor at the
// centroid of a triangle that uses it. Must not throw (an exception is recorded as an error).
// The field is only sampled at those places, so a support narrower than the triangles can be
// missed: make the field conservative by widening each support by the longest input edge
// (every point of a triangle is within 2/3 of its longest edge from its centroid).
using EdgeLengthField = std::function<float(float3 position, float2 uv)>;

// Where a new point goes (docs/model.md §14).
enum class RefinePlacement {
  // On the PN triangle (Vlachos et al. 2001) of the input triangle it lies in: a cubic patch
  // through the triangle's corners, tangent there to the planes of the input's area-weighted
  // point normals (geometry/normals.h); its edges depend only on the edge's two ends and their
  // normals, so neighbouring patches meet without cracks. Interpolating: input points keep
  // their exact position. On a flat region (all normals perpendicular to it) this is the flat
  // position, bit for bit.
  kSmooth,
  // On the input's flat triangles: the exact midpoint of the edge (docs/model.md §11).
  kFlat,
};

struct RefineOptions {
  RefinePlacement placement = RefinePlacement::kSmooth;
  int max_passes = 8;                // >= 0; each pass bisects every marked edge once
  size_t max_triangles = 4'000'000;  // a pass that would exceed this is not run
  float weld_tolerance = 0.f;        // as WeldMesh: mesh units; <= 0: 1e-6 of the bbox diagonal
};

struct RefineResult {
  // Refined mesh in the file-vertex layout (seams kept split), `source` copied from the input.
  // Vertices 0 .. #V_in-1 are the input vertices, unchanged and in order; new vertices follow.
  // Triangles appear in the order of the input triangles they come from; an unsplit triangle
  // keeps its indices in the same order.
  MeshData mesh;
  // One per output vertex: the two earlier vertices whose edge it splits, in parameter space
  // the midpoint (its barycentric coordinates in its input triangle are the mean of theirs),
  // or (v, v) for an input vertex v. Any per-vertex attribute carries by value = (value[a] +
  // value[b]) / 2, applied in vertex order (CarryAttribute): the attribute interpolated
  // linearly over the input triangle. uvs are carried by this rule; normals are the
  // normalised average. A new vertex's position is, with RefinePlacement::kFlat, the midpoint
  // of its welded edge, and with kSmooth (the default) that flat position moved onto the
  // input triangle's PN patch (docs/model.md §14); either way the same bits for every file
  // vertex of one point, so the result welds exactly. Which edges split is decided on the
  // flat positions, so the topology (indices, parents, origins) does not depend on placement.
  std::vector<std::pair<uint32_t, uint32_t>> parents;
  // One per output triangle: the input triangle it lies in.
  std::vector<uint32_t> triangle_origin;
  size_t input_vertex_count = 0;  // #V_in
  size_t passes = 0;              // refinement passes run (0 when nothing needed splitting)
  bool bound_met = true;          // false: a limit stopped refinement (a warning says how far)
};

// Refines `in` where `max_edge` asks for shorter edges. Welds first (WeldMesh with
// options.weld_tolerance): weld errors (degenerate triangles, non-manifold edges, bad indices
// or non-finite positions) are recorded and make it return false, as do normals/uvs whose
// count is neither 0 nor #V, and a missing field. Stops with a warning (returning true) when
// max_passes or max_triangles is reached before every edge meets its target, or when the
// target is below 2e-4 of the bounding-box diagonal (edges that short are never split, so the
// result still welds at the default tolerance and passes WeldMesh's zero-area check).
// Deterministic: the same input gives the same bytes. Cost O(n log n) per pass.
// @param[in]  in        #V vertices, #T triangles; may be empty (the result is then empty too)
// @param[out] out       the refined mesh and the maps back to the input
bool RefineMesh(const MeshData& in, const EdgeLengthField& max_edge, const RefineOptions& options,
                RefineResult* out, Diagnostics* diag);

// Carries a per-vertex value (e.g. skin thickness per file vertex) through `refined.parents`
// (computed in double, rounded once). Returns one value per output vertex, or an empty vector
// when `per_input_vertex` has fewer than refined.input_vertex_count values.
std::vector<float> CarryAttribute(const RefineResult& refined,
                                  const std::vector<float>& per_input_vertex);

}  // namespace mimetic

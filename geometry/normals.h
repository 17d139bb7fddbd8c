// geometry/normals.h: area-weighted vertex normals and the triangle quantities behind them
// (the offline copy; the per-frame one is rig/runtime/normals_job.h).
//
// A triangle (a, b, c) has the cross product (b - a) x (c - a): its direction is the normal
// seen counter-clockwise, its length twice the triangle's area. A vertex normal is the sum of
// the cross products of the triangles that use the vertex (so larger triangles weigh more),
// normalised. Everything is computed in double from the float positions and rounded once to
// float at the end (the sample head's mesh and the welder's area check depend on these bits).
#pragma once

#include <cstdint>
#include <vector>

#include "core/math.h"
#include "core/span.h"
#include "geometry/mesh.h"

namespace mimetic {

// (b - a) x (c - a) in double: out[0..2]. Units: mesh units^2.
void TriangleCross(float3 a, float3 b, float3 c, double out[3]);

// The triangle's area, mesh units^2 (0 for a degenerate triangle): |TriangleCross| / 2.
double TriangleArea(float3 a, float3 b, float3 c);

// How far the triangle is from a sliver: its height over its longest edge L, divided by L
// (|TriangleCross| / L^2; sqrt(3)/2 for an equilateral triangle, 0 for a degenerate one or
// L = 0). Below kSliverShape a triangle counts as a sliver (docs/model.md §2-3, §11).
double TriangleShape(float3 a, float3 b, float3 c);
inline constexpr double kSliverShape = 0.05;

// The triangle's unit normal (counter-clockwise), or `fallback` when its area is 0 or not a
// finite number.
float3 TriangleNormal(float3 a, float3 b, float3 c, float3 fallback);

struct VertexNormalOptions {
  // Vertices at exactly the same position (compared with ==, so -0 == +0; non-finite
  // positions never share) get one normal, from the sum over all of them: a UV or normal seam
  // then shades smoothly. Off: each file vertex sums its own triangles only.
  bool share_by_position = false;
  // Written where the sum is zero (an unused vertex, or triangles that cancel out).
  float3 fallback{0.f, 0.f, 1.f};
};

// Area-weighted vertex normals: one unit vector (or options.fallback) per position, #V.
// `indices`: 3 per triangle into `positions` (a trailing partial triangle is ignored);
// triangles with an index >= #V are skipped. Triangles add in index order and a shared
// position's vertices in vertex order, so the result is deterministic. O(#T), plus
// O(#V log #V) with share_by_position.
std::vector<float3> ComputeVertexNormals(span<const float3> positions,
                                         span<const uint32_t> indices,
                                         const VertexNormalOptions& options = {});
// The same for a mesh's positions and indices (its own normals are not read).
std::vector<float3> ComputeVertexNormals(const MeshData& mesh,
                                         const VertexNormalOptions& options = {});

}  // namespace mimetic

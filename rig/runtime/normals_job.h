// rig/runtime/normals_job.h: area-weighted vertex normals on the welded topology.
//
// Two passes so that any range split gives the same bits (a one-ring formulation that sums
// (b - p) x (c - p) per point was measured 50% slower: three times the cross products): FaceNormalsJob writes each
// triangle's unnormalised normal (e1 x e2, length = twice its area) for a triangle range;
// PointNormalsJob sums, for a point range, the face normals of each point's triangles in the
// CSR's fixed order and normalises. A point whose triangles all collapsed to zero area has no
// defined normal; it gets +Z rather than NaN.
#pragma once

#include <cstdint>

#include "core/math.h"
#include "core/span.h"

namespace mimetic {

struct FaceNormalsJob {
  // Validate(): triangles.size() multiple of 3; out_face_normals >= #T; begin <= end <= #T;
  // every index of triangles in [begin, end) < points.size() is NOT checked here (the rig
  // builder guarantees it).
  bool Validate() const;
  bool Run() const;

  span<const float3> points;        // #P
  span<const uint32_t> triangles;   // 3 * #T
  span<float3> out_face_normals;    // #T, unnormalised (length = 2 * area)
  uint32_t begin = 0, end = 0;      // triangle range
  // Optional, fused (saves a second pass over the triangles): the area ratio S'/S per
  // triangle (docs/model.md §4, 002 eq. 1). Both empty, or rest_areas >= #T (mesh units^2, from
  // TriangleRestArea) and out_area_ratios >= #T. A zero rest area gives 1.
  span<const float> rest_areas;
  span<float> out_area_ratios;
};

struct PointNormalsJob {
  bool Validate() const;
  bool Run() const;

  span<const float3> face_normals;           // #T from FaceNormalsJob
  span<const uint32_t> point_triangle_offsets; // #P + 1
  span<const uint32_t> point_triangles;      // offsets[#P] entries, each < #T
  span<float3> out_normals;                  // #P, unit length
  uint32_t begin = 0, end = 0;               // point range
  // Optional, fused: r per point, the mean of its triangles' ratios (docs/model.md §4, 002 eq. 1);
  // 1 for a point without triangles. Both empty, or triangle_ratios >= #T and out_ratios >= #P.
  span<const float> triangle_ratios;
  span<float> out_ratios;
};

// The area-weighted unit normal of point p from the face normals of its triangles, summed in
// CSR order (PointNormalsJob's per-point step; EvaluateJob gathers the same bits from its
// 16-byte face slots with GatherFaces4 + UnitNormal, rig/runtime/face_kernels.h).
inline float3 GatherPointNormal(const uint32_t* offsets, const uint32_t* triangles,
                                const float3* face_normals, uint32_t p) {
  float3 n{};
  for (uint32_t k = offsets[p]; k < offsets[p + 1]; ++k) n += face_normals[triangles[k]];
  return NormalizeOr(n, float3{0.f, 0.f, 1.f});
}

// A triangle's area with the expression FaceNormalsJob uses (|e1 x e2| / 2), so that rest
// areas computed with it give r = 1 exactly at the rest pose.
float TriangleRestArea(float3 a, float3 b, float3 c);

}  // namespace mimetic

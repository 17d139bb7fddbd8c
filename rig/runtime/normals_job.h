// rig/runtime/normals_job.h: area-weighted vertex normals on the welded topology.
//
// Two passes so that any range split gives the same bits: FaceNormalsJob writes each
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
};

struct PointNormalsJob {
  bool Validate() const;
  bool Run() const;

  span<const float3> face_normals;           // #T from FaceNormalsJob
  span<const uint32_t> point_triangle_offsets; // #P + 1
  span<const uint32_t> point_triangles;      // offsets[#P] entries, each < #T
  span<float3> out_normals;                  // #P, unit length
  uint32_t begin = 0, end = 0;               // point range
};

}  // namespace mimetic

// rig/runtime/face_kernels.h: the per-frame geometry kernels EvaluateJob (and the benchmark's
// reference kernel) run over padded scratch buffers: face normals into 16-byte slots with the
// area ratio in the spare lane, per-point gathers of those slots, and edge lengths.
//
// Why not the public stage jobs (FaceNormalsJob, PointNormalsJob, EdgeCompressionJob): those
// take caller spans of tightly packed float3 and cannot read past them. Here the point buffer
// is the context's own, allocated with kPointPadFloats spare floats, so a point loads as one
// unaligned 16-byte SIMD load, a face normal as one aligned load, and the ratio r (docs/model.md §4)
// rides in the same register as the normal through the gather. The results are the same bits
// as the scalar expressions of the stage jobs (Cross, 0.5 |n| / S, Length, CSR-order sums),
// with or without SSE (tests/rig/face_kernels_test.cpp compares them).
#pragma once

#include <cstddef>
#include <cstdint>

#include "core/math.h"
#include "muscles/runtime/muscle_table.h"

#if defined(__SSE2__) || defined(_M_X64)
#include <emmintrin.h>
#define MIMETIC_FACE_KERNELS_SSE 1
#else
#define MIMETIC_FACE_KERNELS_SSE 0
#endif

namespace mimetic {

// Floats a point buffer passed to these kernels must hold past its last point (readable; the
// value does not matter).
inline constexpr size_t kPointPadFloats = 1;

// out[t] for t in [begin, end): xyz = (b - a) x (c - a) of triangle t (unnormalised, length =
// twice the area), w = its area ratio S'/S (0.5 |n| / rest_areas[t], 1 where the rest area is
// not positive) when rest_areas is non-null, else 0. `points` padded (kPointPadFloats). With
// ratios, eight triangles at a time with AVX where the CPU has it (checked at run time; the
// same bits as the SSE and scalar paths).
void FaceNormals4(const float3* points, const uint32_t* triangles, uint32_t begin, uint32_t end,
                  const float* rest_areas, float4* out);
// The same without ratios for the listed triangles only: out[list[k]] for k < count.
void FaceNormals4Listed(const float3* points, const uint32_t* triangles, const uint32_t* list,
                        size_t count, float4* out);
// out[e] = |x[pairs[2e]] - x[pairs[2e+1]]| for e in [begin, end) (Length's expression).
// `points` padded (kPointPadFloats).
void EdgeLengths(const float3* points, const uint32_t* pairs, uint32_t begin, uint32_t end,
                 float* out);

// MuscleDeformJob's sum for p in [begin, end) with activations already in [0, 1] (no clamp per
// entry; SanitizeActivations gives such): out[p] = rest[p] + sum of a * displacement in CSR
// order, the same bits. `out` padded (kPointPadFloats); `rest` holds the table's points; end <=
// the table's point count. Every point is written as one 16-byte store whose spare lane lands
// on out[p + 1].x, which the next point then rewrites, except the last point of the range
// (written exactly, so ranges on other threads are not touched).
void MusclePoints(const MuscleTable& table, const float* activations, const float3* rest,
                  uint32_t begin, uint32_t end, float3* out);

// Sum of the face slots of point p's triangles, in CSR order (xyz: the unnormalised
// area-weighted normal; w: the sum of the ratios).
inline float4 GatherFaces4(const uint32_t* offsets, const uint32_t* triangles,
                           const float4* faces, uint32_t p) {
#if MIMETIC_FACE_KERNELS_SSE
  __m128 sum = _mm_setzero_ps();
  for (uint32_t k = offsets[p]; k < offsets[p + 1]; ++k)
    sum = _mm_add_ps(sum, _mm_load_ps(&faces[triangles[k]].x));
  float4 out;
  _mm_store_ps(&out.x, sum);
  return out;
#else
  float4 s;
  for (uint32_t k = offsets[p]; k < offsets[p + 1]; ++k) {
    const float4& f = faces[triangles[k]];
    s.x += f.x;
    s.y += f.y;
    s.z += f.z;
    s.w += f.w;
  }
  return s;
#endif
}

// The unit normal of a gathered sum (NormalizeOr with +Z for a point whose triangles all
// collapsed): the same bits as GatherPointNormal over float3 face normals.
inline float3 UnitNormal(const float4& sum) {
  return NormalizeOr(float3{sum.x, sum.y, sum.z}, float3{0.f, 0.f, 1.f});
}

// Scalar versions of the kernels above, for platforms without SSE and for the tests that hold
// the SIMD paths to the same bits.
void FaceNormals4Scalar(const float3* points, const uint32_t* triangles, uint32_t begin,
                        uint32_t end, const float* rest_areas, float4* out);
void EdgeLengthsScalar(const float3* points, const uint32_t* pairs, uint32_t begin, uint32_t end,
                       float* out);
void MusclePointsScalar(const MuscleTable& table, const float* activations, const float3* rest,
                        uint32_t begin, uint32_t end, float3* out);

}  // namespace mimetic

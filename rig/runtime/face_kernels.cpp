// rig/runtime/face_kernels.cpp: see face_kernels.h. Every SIMD expression below is the scalar
// one lane by lane (same operations, same order; no fused multiply-add), so both paths give the
// same bits.
#include "rig/runtime/face_kernels.h"

#include <cmath>
#include <cstddef>

#if defined(__x86_64__) || defined(__i386__)
#include <immintrin.h>
#endif

namespace mimetic {

static_assert(offsetof(MuscleInfluence, displacement) == 4, "MusclePoints loads an entry whole");

void FaceNormals4Scalar(const float3* points, const uint32_t* triangles, uint32_t begin,
                        uint32_t end, const float* rest_areas, float4* out) {
  for (uint32_t t = begin; t < end; ++t) {
    const uint32_t* c = triangles + 3 * t;
    const float3 a = points[c[0]];
    const float3 n = Cross(points[c[1]] - a, points[c[2]] - a);
    float w = 0.f;
    if (rest_areas) {
      const float area = 0.5f * Length(n);  // as TriangleRestArea
      w = rest_areas[t] > 0.f ? area / rest_areas[t] : 1.f;
    }
    out[t] = float4{n.x, n.y, n.z, w};
  }
}

void EdgeLengthsScalar(const float3* points, const uint32_t* pairs, uint32_t begin, uint32_t end,
                       float* out) {
  for (uint32_t e = begin; e < end; ++e)
    out[e] = Length(points[pairs[2 * e]] - points[pairs[2 * e + 1]]);
}

void MusclePointsScalar(const MuscleTable& table, const float* activations, const float3* rest,
                        uint32_t begin, uint32_t end, float3* out) {
  const uint32_t* offsets = table.offsets.data();
  const MuscleInfluence* entries = table.entries.data();
  for (uint32_t p = begin; p < end; ++p) {
    float3 pos = rest[p];
    for (uint32_t e = offsets[p]; e < offsets[p + 1]; ++e)
      pos += activations[entries[e].muscle] * entries[e].displacement;
    out[p] = pos;
  }
}

#if MIMETIC_FACE_KERNELS_SSE

namespace {

// One point as x, y, z, (next float): the buffer is padded, so the load stays inside it.
inline __m128 LoadPoint(const float3* points, uint32_t i) { return _mm_loadu_ps(&points[i].x); }

inline __m128 XyzMask() { return _mm_castsi128_ps(_mm_set_epi32(0, -1, -1, -1)); }

// (b - a) x (c - a) in lanes x, y, z (Cross's products and differences), 0 in lane w.
inline __m128 FaceNormal(const float3* points, const uint32_t* c) {
  const __m128 a = LoadPoint(points, c[0]);
  const __m128 e1 = _mm_sub_ps(LoadPoint(points, c[1]), a);
  const __m128 e2 = _mm_sub_ps(LoadPoint(points, c[2]), a);
  const __m128 e1_yzx = _mm_shuffle_ps(e1, e1, _MM_SHUFFLE(3, 0, 2, 1));
  const __m128 e2_yzx = _mm_shuffle_ps(e2, e2, _MM_SHUFFLE(3, 0, 2, 1));
  // lanes: x1 y2 - y1 x2, y1 z2 - z1 y2, z1 x2 - x1 z2 -> rotate to (y, z, x) order.
  const __m128 t = _mm_sub_ps(_mm_mul_ps(e1, e2_yzx), _mm_mul_ps(e1_yzx, e2));
  return _mm_and_ps(_mm_shuffle_ps(t, t, _MM_SHUFFLE(3, 0, 2, 1)), XyzMask());
}

// (x*x + y*y) + z*z of four vectors (Dot's order), one per lane.
inline __m128 LengthsSquared(__m128 v0, __m128 v1, __m128 v2, __m128 v3) {
  v0 = _mm_mul_ps(v0, v0);
  v1 = _mm_mul_ps(v1, v1);
  v2 = _mm_mul_ps(v2, v2);
  v3 = _mm_mul_ps(v3, v3);
  _MM_TRANSPOSE4_PS(v0, v1, v2, v3);
  return _mm_add_ps(_mm_add_ps(v0, v1), v2);
}

}  // namespace

#if defined(__GNUC__) && !defined(__AVX__) && (defined(__x86_64__) || defined(__i386__))
#define MIMETIC_FACE_KERNELS_AVX 1

// The ratio pass eight triangles at a time with AVX (chosen at run time when the CPU has it):
// each 256-bit register holds two triangles, one per 128-bit half, and every instruction below
// is the SSE one applied to both halves, so the bits are the SSE path's (no FMA: the target
// is plain AVX, so nothing can be contracted).
#define MIMETIC_AVX __attribute__((target("avx")))

// Points i (low half) and j (high half).
MIMETIC_AVX inline __m256 Load2(const float3* points, uint32_t i, uint32_t j) {
  return _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_loadu_ps(&points[i].x)),
                              _mm_loadu_ps(&points[j].x), 1);
}

// FaceNormal of triangles c[0..2] (low half) and c[3..5] (high half).
MIMETIC_AVX inline __m256 FaceNormal2(const float3* points, const uint32_t* c) {
  const __m256 a = Load2(points, c[0], c[3]);
  const __m256 e1 = _mm256_sub_ps(Load2(points, c[1], c[4]), a);
  const __m256 e2 = _mm256_sub_ps(Load2(points, c[2], c[5]), a);
  const __m256 e1_yzx = _mm256_shuffle_ps(e1, e1, _MM_SHUFFLE(3, 0, 2, 1));
  const __m256 e2_yzx = _mm256_shuffle_ps(e2, e2, _MM_SHUFFLE(3, 0, 2, 1));
  const __m256 n = _mm256_sub_ps(_mm256_mul_ps(e1, e2_yzx), _mm256_mul_ps(e1_yzx, e2));
  const __m256 xyz = _mm256_castsi256_ps(_mm256_set_epi32(0, -1, -1, -1, 0, -1, -1, -1));
  return _mm256_and_ps(_mm256_shuffle_ps(n, n, _MM_SHUFFLE(3, 0, 2, 1)), xyz);
}

MIMETIC_AVX uint32_t FaceNormalsRatiosAvx(const float3* points, const uint32_t* triangles,
                                          uint32_t t, uint32_t end, const float* rest_areas,
                                          float4* out) {
  const __m256 half = _mm256_set1_ps(0.5f), one = _mm256_set1_ps(1.f);
  const __m256 zero = _mm256_setzero_ps();
  for (; t + 8 <= end; t += 8) {
    const uint32_t* c = triangles + 3 * t;
    const __m256 n01 = FaceNormal2(points, c), n23 = FaceNormal2(points, c + 6);
    const __m256 n45 = FaceNormal2(points, c + 12), n67 = FaceNormal2(points, c + 18);
    // Squared lengths, transposed within each half: (t0 t2 t4 t6 | t1 t3 t5 t7).
    __m256 s0 = _mm256_mul_ps(n01, n01), s1 = _mm256_mul_ps(n23, n23);
    __m256 s2 = _mm256_mul_ps(n45, n45), s3 = _mm256_mul_ps(n67, n67);
    const __m256 u0 = _mm256_unpacklo_ps(s0, s1), u1 = _mm256_unpacklo_ps(s2, s3);
    const __m256 u2 = _mm256_unpackhi_ps(s0, s1), u3 = _mm256_unpackhi_ps(s2, s3);
    const __m256 x = _mm256_shuffle_ps(u0, u1, _MM_SHUFFLE(1, 0, 1, 0));
    const __m256 y = _mm256_shuffle_ps(u0, u1, _MM_SHUFFLE(3, 2, 3, 2));
    const __m256 z = _mm256_shuffle_ps(u2, u3, _MM_SHUFFLE(1, 0, 1, 0));
    const __m256 area = _mm256_mul_ps(half, _mm256_sqrt_ps(_mm256_add_ps(_mm256_add_ps(x, y), z)));
    // Rest areas in the same order.
    const __m128 r_lo = _mm_loadu_ps(rest_areas + t), r_hi = _mm_loadu_ps(rest_areas + t + 4);
    const __m256 rest = _mm256_insertf128_ps(
        _mm256_castps128_ps256(_mm_shuffle_ps(r_lo, r_hi, _MM_SHUFFLE(2, 0, 2, 0))),
        _mm_shuffle_ps(r_lo, r_hi, _MM_SHUFFLE(3, 1, 3, 1)), 1);
    const __m256 positive = _mm256_cmp_ps(rest, zero, _CMP_GT_OQ);  // as `rest > 0.f`
    const __m256 ratio = _mm256_or_ps(_mm256_and_ps(positive, _mm256_div_ps(area, rest)),
                                      _mm256_andnot_ps(positive, one));
    // Ratio k of each half into lane w of its normal.
    _mm256_storeu_ps(&out[t].x, _mm256_blend_ps(n01, _mm256_permute_ps(ratio, 0x00), 0x88));
    _mm256_storeu_ps(&out[t + 2].x, _mm256_blend_ps(n23, _mm256_permute_ps(ratio, 0x55), 0x88));
    _mm256_storeu_ps(&out[t + 4].x, _mm256_blend_ps(n45, _mm256_permute_ps(ratio, 0xaa), 0x88));
    _mm256_storeu_ps(&out[t + 6].x, _mm256_blend_ps(n67, _mm256_permute_ps(ratio, 0xff), 0x88));
  }
  return t;
}
#else
#define MIMETIC_FACE_KERNELS_AVX 0
#endif

void FaceNormals4(const float3* points, const uint32_t* triangles, uint32_t begin, uint32_t end,
                  const float* rest_areas, float4* out) {
  if (!rest_areas) {
    for (uint32_t t = begin; t < end; ++t)
      _mm_store_ps(&out[t].x, FaceNormal(points, triangles + 3 * t));
    return;
  }
  uint32_t t = begin;
#if MIMETIC_FACE_KERNELS_AVX
  static const bool avx = __builtin_cpu_supports("avx");
  if (avx) t = FaceNormalsRatiosAvx(points, triangles, t, end, rest_areas, out);
#endif
  const __m128 half = _mm_set1_ps(0.5f), one = _mm_set1_ps(1.f), zero = _mm_setzero_ps();
  for (; t + 4 <= end; t += 4) {
    const __m128 n0 = FaceNormal(points, triangles + 3 * t);
    const __m128 n1 = FaceNormal(points, triangles + 3 * t + 3);
    const __m128 n2 = FaceNormal(points, triangles + 3 * t + 6);
    const __m128 n3 = FaceNormal(points, triangles + 3 * t + 9);
    _mm_store_ps(&out[t].x, n0);
    _mm_store_ps(&out[t + 1].x, n1);
    _mm_store_ps(&out[t + 2].x, n2);
    _mm_store_ps(&out[t + 3].x, n3);
    const __m128 area = _mm_mul_ps(half, _mm_sqrt_ps(LengthsSquared(n0, n1, n2, n3)));
    const __m128 rest = _mm_loadu_ps(rest_areas + t);
    const __m128 positive = _mm_cmpgt_ps(rest, zero);  // false for NaN, as `rest > 0.f`
    const __m128 ratio =
        _mm_or_ps(_mm_and_ps(positive, _mm_div_ps(area, rest)), _mm_andnot_ps(positive, one));
    alignas(16) float r[4];
    _mm_store_ps(r, ratio);
    out[t].w = r[0];
    out[t + 1].w = r[1];
    out[t + 2].w = r[2];
    out[t + 3].w = r[3];
  }
  FaceNormals4Scalar(points, triangles, t, end, rest_areas, out);
}

void FaceNormals4Listed(const float3* points, const uint32_t* triangles, const uint32_t* list,
                        size_t count, float4* out) {
  for (size_t k = 0; k < count; ++k)
    _mm_store_ps(&out[list[k]].x, FaceNormal(points, triangles + 3 * list[k]));
}

void EdgeLengths(const float3* points, const uint32_t* pairs, uint32_t begin, uint32_t end,
                 float* out) {
  uint32_t e = begin;
  for (; e + 4 <= end; e += 4) {
    const uint32_t* q = pairs + 2 * e;
    const __m128 d0 = _mm_sub_ps(LoadPoint(points, q[0]), LoadPoint(points, q[1]));
    const __m128 d1 = _mm_sub_ps(LoadPoint(points, q[2]), LoadPoint(points, q[3]));
    const __m128 d2 = _mm_sub_ps(LoadPoint(points, q[4]), LoadPoint(points, q[5]));
    const __m128 d3 = _mm_sub_ps(LoadPoint(points, q[6]), LoadPoint(points, q[7]));
    _mm_storeu_ps(out + e, _mm_sqrt_ps(LengthsSquared(d0, d1, d2, d3)));
  }
  EdgeLengthsScalar(points, pairs, e, end, out);
}

void MusclePoints(const MuscleTable& table, const float* activations, const float3* rest,
                  uint32_t begin, uint32_t end, float3* out) {
  if (begin >= end) return;
  const uint32_t* offsets = table.offsets.data();
  const MuscleInfluence* entries = table.entries.data();
  // An entry loads as (muscle bits, dx, dy, dz); the mask zeroes the index lane so the sum
  // never sees it (as a float it would be a denormal).
  const __m128 yzw = _mm_castsi128_ps(_mm_set_epi32(-1, -1, -1, 0));
  const uint32_t last = end - 1;
  for (uint32_t p = begin; p < last; ++p) {
    // rest[p + 1] exists (p + 1 <= last < point count), so the 16-byte load stays inside;
    // rotate (x, y, z, next) to (next, x, y, z) to line up with the entries.
    const __m128 r = _mm_loadu_ps(&rest[p].x);
    __m128 pos = _mm_shuffle_ps(r, r, _MM_SHUFFLE(2, 1, 0, 3));
    for (uint32_t e = offsets[p]; e < offsets[p + 1]; ++e) {
      const __m128 d = _mm_and_ps(_mm_loadu_ps(reinterpret_cast<const float*>(&entries[e])), yzw);
      pos = _mm_add_ps(pos, _mm_mul_ps(_mm_set1_ps(activations[entries[e].muscle]), d));
    }
    _mm_storeu_ps(&out[p].x, _mm_shuffle_ps(pos, pos, _MM_SHUFFLE(0, 3, 2, 1)));
  }
  MusclePointsScalar(table, activations, rest, last, end, out);
}

#else  // no SSE: the scalar kernels

void MusclePoints(const MuscleTable& table, const float* activations, const float3* rest,
                  uint32_t begin, uint32_t end, float3* out) {
  MusclePointsScalar(table, activations, rest, begin, end, out);
}

void FaceNormals4(const float3* points, const uint32_t* triangles, uint32_t begin, uint32_t end,
                  const float* rest_areas, float4* out) {
  FaceNormals4Scalar(points, triangles, begin, end, rest_areas, out);
}

void FaceNormals4Listed(const float3* points, const uint32_t* triangles, const uint32_t* list,
                        size_t count, float4* out) {
  for (size_t k = 0; k < count; ++k)
    FaceNormals4Scalar(points, triangles, list[k], list[k] + 1, nullptr, out);
}

void EdgeLengths(const float3* points, const uint32_t* pairs, uint32_t begin, uint32_t end,
                 float* out) {
  EdgeLengthsScalar(points, pairs, begin, end, out);
}

#endif

}  // namespace mimetic

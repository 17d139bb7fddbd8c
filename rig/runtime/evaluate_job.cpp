#include "rig/runtime/evaluate_job.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <limits>

#include "expressions/runtime/activations.h"
#include "rig/runtime/face_kernels.h"
#include "wrinkles/runtime/profiles.h"
#include "wrinkles/runtime/strain_jobs.h"
#include "wrinkles/runtime/thickness_job.h"
#include "wrinkles/runtime/wrinkle_jobs.h"

#if defined(__SSE2__)
#include <emmintrin.h>
#endif
#if defined(__GNUC__) && !defined(__AVX__) && defined(__x86_64__)
#include <immintrin.h>
#define MIMETIC_RUNTIME_AVX 1  // eight-lane forms (fine-scale probes, the jaw), chosen at run time
#else
#define MIMETIC_RUNTIME_AVX 0
#endif

namespace mimetic {

void EvaluateContext::Resize(const Rig& rig) {
  rig_uid_ = rig.uid();
  point_count_ = rig.point_count();
  triangle_count_ = rig.triangle_count();
  muscle_count_ = rig.muscle_count();
  const RigTables& t = rig.tables();
  activations_.assign(muscle_count_, 0.f);
  wrinkle_gates_.assign(muscle_count_, 1.f);
  jaw_ = 0.f;
  // One float3 of padding covers kPointPadFloats.
  static_assert(kPointPadFloats <= 3, "pad points_ by more than one float3");
  points_.assign(point_count_ + 1, float3{});
  faces_.assign(triangle_count_, float4{});
  point_ratios_.assign(point_count_, 1.f);
  point_compressions_.assign(point_count_, 0.f);
  point_fine_.assign(2 * size_t(point_count_),
                     rig.fine_scale().empty() ? 0.f : rig.fine_scale().rest_amplitude);
  point_sums_.assign(point_count_, float4{});
  edge_lengths_.assign(size_t(t.edge_count()) + t.fine_edge_count() + 1, 0.f);
  edge_lengths_.back() = 1.f;  // the slot of missing sides (RigTables::fine_probe_edges)
  wrinkle_offsets_.assign(point_count_, 0.f);
  thickness_a_.assign(point_count_ + 1, 0.f);  // static points keep 0 (r = 1 there)
  thickness_b_.assign(point_count_ + 1, 0.f);
  skin_base_.assign(point_count_, float3{});
  skin_full_.assign(point_count_, float3{});
  limit_levels_.assign(point_count_, 0);
  fold_limits_.assign(triangle_count_, 0.f);
  limit_flags_.assign(point_count_, 0);
  slope_min_bounds_.assign(point_count_, 0.f);
  limit_edge_lengths_.assign(t.neighbor_edge_count(), 0.f);
  // (Clamped: an unchecked rig's ranges are not trusted, and IsFor refuses it anyway.)
  const uint32_t active = std::min(rig.active_point_count(), point_count_);
  const uint32_t active_tris = std::min(rig.active_triangle_count(), triangle_count_);
  limit_moved_.assign(active, 0);
  limit_flagged_.assign(active, 0);
  limit_recheck_.assign(active, 0);
  limit_tris_.assign(active_tris, 0);
  limit_point_marks_.assign(active, 0);
  limit_tri_marks_.assign(active_tris, 0);
  limit_tri_bad_.assign(active_tris, 0);
  limited_points_ = limiter_passes_ = 0;
  if (!rig.tables_checked()) return;  // IsFor refuses it; nothing below is safe to read
  // Rest values everywhere: a frame rewrites only the leading ranges that can change
  // (Rig::active()); the rest keep these.
  std::copy(rig.rest_points().begin(), rig.rest_points().end(), points_.begin());
  std::copy(t.rest_faces.begin(), t.rest_faces.end(), faces_.begin());
  // Past the active points, skin_full_ holds the rest normals for good (LimitedOffsets reads
  // the unit normals of every neighbour from it; a frame writes only its active points).
  std::copy(t.rest_point_normals.begin() + active, t.rest_point_normals.end(),
            skin_full_.begin() + active);
}

bool EvaluateContext::IsFor(const Rig& rig) const {
  return rig.tables_checked() && rig_uid_ != 0 && rig_uid_ == rig.uid() &&
         point_count_ == rig.point_count() && triangle_count_ == rig.triangle_count() &&
         muscle_count_ == rig.muscle_count();
}

template <class T>
static size_t Bytes(const std::vector<T>& v) {
  return v.capacity() * sizeof(T);
}

size_t EvaluateContext::ByteSize() const {
  return sizeof(EvaluateContext) + Bytes(activations_) + Bytes(wrinkle_gates_) + Bytes(points_) + Bytes(faces_) +
         Bytes(point_ratios_) + Bytes(point_compressions_) + Bytes(point_fine_) + Bytes(point_sums_) + Bytes(edge_lengths_) +
         Bytes(wrinkle_offsets_) + Bytes(thickness_a_) + Bytes(thickness_b_) + Bytes(skin_base_) + Bytes(skin_full_) + Bytes(limit_levels_) + Bytes(fold_limits_) + Bytes(limit_flags_) +
         Bytes(slope_min_bounds_) + Bytes(limit_edge_lengths_) +
         Bytes(limit_moved_) + Bytes(limit_flagged_) + Bytes(limit_recheck_) + Bytes(limit_tris_) +
         Bytes(limit_point_marks_) + Bytes(limit_tri_marks_) + Bytes(limit_tri_bad_);
}

size_t RequiredFloats(size_t count, size_t stride_bytes, size_t floats) {
  return count == 0 ? 0 : (count - 1) * (stride_bytes / 4) + floats;
}

static bool StrideOk(size_t stride) { return stride >= 12 && stride % 4 == 0; }

bool EvaluateJob::Validate() const {
  if (!rig || !context || !context->IsFor(*rig)) return false;
  if (activations.size() < rig->muscle_count()) return false;
  if (!StrideOk(out_positions_stride)) return false;
  if (out_positions.size() < RequiredFloats(rig->vertex_count(), out_positions_stride)) return false;
  if (!out_normals.empty()) {
    if (!StrideOk(out_normals_stride)) return false;
    if (out_normals.size() < RequiredFloats(rig->vertex_count(), out_normals_stride)) return false;
  }
  if (!out_tension.empty()) {
    if (out_tension_stride < 8 || out_tension_stride % 4 != 0) return false;
    if (out_tension.size() < RequiredFloats(rig->vertex_count(), out_tension_stride, 2))
      return false;
  }
  if (!out_region_weights.empty() && out_region_weights.size() < rig->tension_region_count())
    return false;
  if (!out_fine_amplitudes.empty()) {
    if (out_fine_amplitudes_stride < 8 || out_fine_amplitudes_stride % 4 != 0) return false;
    if (out_fine_amplitudes.size() < RequiredFloats(rig->vertex_count(), out_fine_amplitudes_stride, 2))
      return false;
  }
  return true;
}

namespace {

// Runs `fn(begin, end)` over [0, count) through the caller's scheduler, or serially.
template <class Fn>
void ParallelFor(const EvaluateJob& job, uint32_t count, const Fn& fn) {
  if (count == 0) return;
  if (!job.parallel_for || count < job.parallel_min_count) {
    fn(0u, count);
    return;
  }
  auto trampoline = [](void* data, uint32_t begin, uint32_t end) {
    (*static_cast<const Fn*>(data))(begin, end);
  };
  job.parallel_for(job.parallel_for_user, count, trampoline,
                   const_cast<void*>(static_cast<const void*>(&fn)));
}

void Scatter(span<const float3> src, span<const uint32_t> vertex_points, span<float> out,
             size_t stride_bytes, uint32_t begin, uint32_t end) {
  const size_t stride = stride_bytes / 4;
  float* dst = out.data();
  for (uint32_t v = begin; v < end; ++v) {
    const float3 p = src[vertex_points[v]];
    float* o = dst + v * stride;
    o[0] = p.x;
    o[1] = p.y;
    o[2] = p.z;
  }
}

// r of a point from its gathered slots (docs/model.md §4: the mean over its triangles; 1 for a
// point without any).
inline float PointRatio(const float4& sum, uint32_t count) {
  return count ? sum.w / float(count) : 1.f;
}

// One point of DisplaceAlongNormals (the scalar lane). The offset d = (1/rc - 1) h + extra
// (docs/model.md §4 with rc = max(r, r_min), plus the wrinkle sum) and the normalisation share one
// division: d / |n| = ((1 - rc) h + rc extra) / (rc |n|).
inline void DisplacePoint(const float4& s, float r, const float* h, float min_ratio,
                          const float* extra, uint32_t p, float3* points) {
  float rc = 1.f, num = 0.f;
  if (h) {  // ThicknessOffset's clamp: r below r_min (or NaN) counts as r_min
    rc = r >= min_ratio ? r : min_ratio;
    num = (1.f - rc) * h[p];
  }
  if (extra) num = num + rc * extra[p];
  const float len2 = (s.x * s.x + s.y * s.y) + s.z * s.z;
  const bool ok = len2 > 1e-30f;  // NormalizeOr's test; its fallback normal is +Z
  const float k = num / (rc * (ok ? std::sqrt(len2) : 1.f));
  points[p] += ok ? float3{s.x * k, s.y * k, s.z * k} : float3{0.f, 0.f, k};
}

// For p in [b, e): with r = ratios[p], d = (1/max(r, r_min) - 1) h[p] (h non-null) + extra[p]
// (non-null), points[p] += d * sums[p].xyz / |sums[p].xyz|. Four points per step with SSE (the
// same operations lane by lane as DisplacePoint): one division and one square root per four
// points.
void DisplaceAlongNormals(const float4* sums, const float* ratios, const float* h,
                          float min_ratio, const float* extra, uint32_t b, uint32_t e,
                          float3* points) {
  uint32_t p = b;
#if MIMETIC_FACE_KERNELS_SSE
  const __m128 zero = _mm_setzero_ps(), one = _mm_set1_ps(1.f), rmin = _mm_set1_ps(min_ratio);
  const __m128 tiny = _mm_set1_ps(1e-30f);
  for (; p + 4 <= e; p += 4) {
    __m128 x = _mm_load_ps(&sums[p].x), y = _mm_load_ps(&sums[p + 1].x);
    __m128 z = _mm_load_ps(&sums[p + 2].x), w = _mm_load_ps(&sums[p + 3].x);
    _MM_TRANSPOSE4_PS(x, y, z, w);
    __m128 rc = one, num = zero;
    if (h) {
      const __m128 r = _mm_loadu_ps(ratios + p);
      const __m128 keep = _mm_cmpge_ps(r, rmin);  // false for NaN, as `r >= min_ratio`
      rc = _mm_or_ps(_mm_and_ps(keep, r), _mm_andnot_ps(keep, rmin));
      num = _mm_mul_ps(_mm_sub_ps(one, rc), _mm_loadu_ps(h + p));
    }
    if (extra) num = _mm_add_ps(num, _mm_mul_ps(rc, _mm_loadu_ps(extra + p)));
    const __m128 len2 = _mm_add_ps(_mm_add_ps(_mm_mul_ps(x, x), _mm_mul_ps(y, y)), _mm_mul_ps(z, z));
    const __m128 ok = _mm_cmpgt_ps(len2, tiny);
    const __m128 len = _mm_or_ps(_mm_and_ps(ok, _mm_sqrt_ps(len2)), _mm_andnot_ps(ok, one));
    const __m128 k = _mm_div_ps(num, _mm_mul_ps(rc, len));
    alignas(16) float dx[4], dy[4], dz[4];
    _mm_store_ps(dx, _mm_and_ps(ok, _mm_mul_ps(x, k)));
    _mm_store_ps(dy, _mm_and_ps(ok, _mm_mul_ps(y, k)));
    _mm_store_ps(dz, _mm_or_ps(_mm_and_ps(ok, _mm_mul_ps(z, k)), _mm_andnot_ps(ok, k)));
    for (uint32_t j = 0; j < 4; ++j) points[p + j] += float3{dx[j], dy[j], dz[j]};
  }
#endif
  for (; p < e; ++p) DisplacePoint(sums[p], ratios[p], h, min_ratio, extra, p, points);
}


// Everything one frame's stages share: resolved once by Run() (after Validate), read by every
// stage. Plain pointers into the rig, its tables and the context's scratch.
struct FrameState {
  const EvaluateJob& job;
  const Rig& rig;
  const RigTables& tables;
  // Layers that run this frame: compiled into the rig AND enabled in job.layers (and with
  // something to do).
  bool thickness, muscle_wrinkles, curve_wrinkles;
  bool skin() const { return thickness || muscle_wrinkles || curve_wrinkles; }
  bool wrinkles() const { return muscle_wrinkles || curve_wrinkles; }
  bool normals;                    // out_normals requested
  bool tension;                    // out_tension or out_region_weights requested
  bool tension_eps;                // out_tension requested and the rig has muscle-wrinkle rows
  bool edges;                      // StageStrain measures the edge lengths
  float* compressions;             // #P compression eps (context), StageTension
  float* fine;                     // 2 #P fine-scale amplitudes (context), StageFineScale
  const float* activations;        // #muscles, sanitised
  const float* wrinkle_gates;      // #muscles: G of each muscle's wrinkles (1 without a gate)
  const float3* base;              // #P: the pose the muscles add to (the rest pose)
  float3* points;                  // #P + pad: X1, then X3 (context)
  float4* faces;                   // #T face slots (context)
  float* ratios;                   // #P area ratios (context)
  float4* sums;                    // #P gathered face slots (context)
  float* edge_lengths;             // RigTables::edge_count() + fine_edge_count() + 1 (context)
  float* wrinkle_offsets;          // #P (context)
  bool limit_folds;                // StageLimit runs (job.limit_folds and a skin layer ran)
  float* thickness_a;              // #P (context)
  float* thickness_b;              // #P (context)
  float3* skin_base;               // #P: X1 (context), written by StageDisplace when limiting
  float3* skin_full;               // #P: X3 before the limiter (context)
  uint8_t* limit_levels;           // #P (context)
  float* fold_limits;              // #T (context)
  uint8_t* limit_flags;            // #P (context; 0 past the active points)
  float* slope_min_bounds;         // #P (context)
  float* limit_edge_lengths;       // RigTables::neighbor_edge_count() (context)
  uint32_t* limit_moved;           // active points (context)
  uint32_t* limit_flagged;         // active points (context)
  uint32_t* limit_recheck;         // active points (context)
  uint32_t* limit_tris;            // active triangles (context)
  uint8_t* limit_point_marks;      // active points (context; 0 between StageLimit's phases)
  uint8_t* limit_tri_marks;        // active triangles (context; 0 between its phases)
  uint8_t* limit_tri_bad;          // active triangles (context): FoldVerdict of this pass
  const uint32_t* point_tri_offsets;  // Rig::point_triangle_offsets
  const uint32_t* point_tris;         // Rig::point_triangles
};

// Face normals of the current points, only for triangles touching a point that can move (the
// others keep the rest face normals set when the context was sized); with `ratios`, each
// triangle's area ratio in w (docs/model.md §4).
void FaceNormalsOfActive(const FrameState& f, bool ratios) {
  const float* rest = ratios ? f.rig.rest_triangle_areas().data() : nullptr;
  const float3* points = f.points;
  float4* faces = f.faces;
  const uint32_t* triangles = f.rig.triangles().data();
  ParallelFor(f.job, f.rig.active_triangle_count(), [&](uint32_t b, uint32_t e) {
    FaceNormals4(points, triangles, b, e, rest, faces);
  });
}

// docs/model.md §1 step 1: muscles summed on the base pose; only points that can move.
void StageMuscles(const FrameState& f) {
  ParallelFor(f.job, f.rig.active_point_count(), [&](uint32_t b, uint32_t e) {
    MusclePoints(f.rig.muscles(), f.activations, f.base, b, e, f.points);
  });
}

// docs/model.md §18, the jaw: each carried point p turns about the hinge (pivot, unit axis k)
// by theta_p = w_p jaw range, Rodrigues' formula v' = v cos + (k x v) sin + k (k.v)(1 - cos) on
// v = X - pivot, then the glide w_p jaw T. X is the muscles' X0 + U, so this is J(X0) + R_p U:
// the jaw pose with the muscle displacement turned with the jaw. Each point reads and writes
// itself only.
// sin t and cos t for the jaw's angles, t in [0, pi/2] (weights in [0, 1] times a range of at
// most 90 degrees, Rig::Build checks both): their Taylor series to t^13 and t^14 in Horner form
// (truncation below 1e-9 at pi/2, so the float rounding of a few ulp is the error). Plain
// arithmetic instead of libm: a third of the cost of the jaw stage's sin and cos per point
// (16k of the sample head's 20k carried points have their own angle), and the same bits on
// every C library. The coefficients innermost first, as the scalar, SSE2 and AVX forms all use
// them: sin t = t (1 + t^2 (kJawSin[5] + t^2 (... + t^2 kJawSin[0]))) and
// cos t = 1 + t^2 (kJawCos[6] + t^2 (... + t^2 kJawCos[0])).
constexpr float kJawSin[6] = {1.f / 6227020800.f, -1.f / 39916800, 1.f / 362880,
                              -1.f / 5040,        1.f / 120,       -1.f / 6};
constexpr float kJawCos[7] = {-1.f / 87178291200.f, 1.f / 479001600, -1.f / 3628800, 1.f / 40320,
                              -1.f / 720,           1.f / 24,        -0.5f};
inline void JawSinCos(float t, float* sn, float* cs) {
  const float t2 = t * t;
  float s = kJawSin[0];
  for (int k = 1; k < 6; ++k) s = kJawSin[k] + t2 * s;
  *sn = t * (1.f + t2 * s);
  float c = kJawCos[0];
  for (int k = 1; k < 7; ++k) c = kJawCos[k] + t2 * c;
  *cs = 1.f + t2 * c;
}

// JawSinCos on n (<= kJawBlock) angles w[i] * angle at once: the same operations in the same
// order per element (no FMA: each product is rounded as in the scalar form), so the same bits;
// with SSE2 four lanes at a time, the scalar form for the tail and elsewhere.
constexpr uint32_t kJawBlock = 64;
void JawSinCosBlock(const float* w, float angle, uint32_t n, float* sn, float* cs) {
  uint32_t i = 0;
#if defined(__SSE2__)
  const __m128 a = _mm_set1_ps(angle);
  auto c = [](float v) { return _mm_set1_ps(v); };
  for (; i + 4 <= n; i += 4) {
    const __m128 t = _mm_mul_ps(_mm_loadu_ps(w + i), a);
    const __m128 t2 = _mm_mul_ps(t, t);
    __m128 s = c(kJawSin[0]);
    for (int j = 1; j < 6; ++j) s = _mm_add_ps(c(kJawSin[j]), _mm_mul_ps(t2, s));
    s = _mm_mul_ps(t, _mm_add_ps(c(1.f), _mm_mul_ps(t2, s)));
    __m128 k = c(kJawCos[0]);
    for (int j = 1; j < 7; ++j) k = _mm_add_ps(c(kJawCos[j]), _mm_mul_ps(t2, k));
    k = _mm_add_ps(c(1.f), _mm_mul_ps(t2, k));
    _mm_storeu_ps(sn + i, s);
    _mm_storeu_ps(cs + i, k);
  }
#endif
  for (; i < n; ++i) JawSinCos(w[i] * angle, &sn[i], &cs[i]);
}

#if MIMETIC_RUNTIME_AVX
// Whether this CPU runs the eight-lane forms (asked once).
inline bool CpuHasAvx() {
  static const bool avx = __builtin_cpu_supports("avx");
  return avx;
}

// One coordinate of a turned point: (c + ((v cos + (k x v) sin) + k d)) + g t, as in StageJaw.
__attribute__((target("avx"))) inline __m256 JawAxisAvx(__m256 c, __m256 v, __m256 kv, __m256 k,
                                                        __m256 t, __m256 cs, __m256 sn, __m256 d,
                                                        __m256 g) {
  const __m256 turn = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(v, cs), _mm256_mul_ps(kv, sn)),
                                    _mm256_mul_ps(k, d));
  return _mm256_add_ps(_mm256_add_ps(c, turn), _mm256_mul_ps(g, t));
}

// JawSinCosBlock and the SSE2 rotation of StageJaw on eight lanes (AVX, no FMA: the same
// operations per lane in the same order, so each point gets the scalar loop's bits). Points
// [0, n) of a block starting at `points`/`w`; returns how many it turned (a multiple of 8).
__attribute__((target("avx"))) uint32_t JawBlockAvx(const uint32_t* points, const float* w,
                                                    uint32_t n, float angle, float jaw, float3 c,
                                                    float3 k, float3 tr, float3* x) {
  const __m256 a = _mm256_set1_ps(angle), one = _mm256_set1_ps(1.f), jv = _mm256_set1_ps(jaw);
  const __m256 cx = _mm256_set1_ps(c.x), cy = _mm256_set1_ps(c.y), cz = _mm256_set1_ps(c.z),
               kx = _mm256_set1_ps(k.x), ky = _mm256_set1_ps(k.y), kz = _mm256_set1_ps(k.z);
  const __m256 tx = _mm256_set1_ps(tr.x), ty = _mm256_set1_ps(tr.y), tz = _mm256_set1_ps(tr.z);
  uint32_t q = 0;
  for (; q + 8 <= n; q += 8) {
    const __m256 wq = _mm256_loadu_ps(w + q);
    const __m256 t = _mm256_mul_ps(wq, a);
    const __m256 t2 = _mm256_mul_ps(t, t);
    __m256 sn = _mm256_set1_ps(kJawSin[0]);
    for (int j = 1; j < 6; ++j)
      sn = _mm256_add_ps(_mm256_set1_ps(kJawSin[j]), _mm256_mul_ps(t2, sn));
    sn = _mm256_mul_ps(t, _mm256_add_ps(one, _mm256_mul_ps(t2, sn)));
    __m256 cs = _mm256_set1_ps(kJawCos[0]);
    for (int j = 1; j < 7; ++j)
      cs = _mm256_add_ps(_mm256_set1_ps(kJawCos[j]), _mm256_mul_ps(t2, cs));
    cs = _mm256_add_ps(one, _mm256_mul_ps(t2, cs));
    const uint32_t* pp = points + q;
    // Eight consecutive points (the list ascends, each point once, so pp[7] - pp[0] == 7 means
    // pp[0] .. pp[0] + 7): their 24 floats loaded as six quarters and sorted into lanes by
    // shuffles. Otherwise each point's own 12 bytes through the stack.
    const bool run = pp[7] - pp[0] == 7;
    alignas(32) float px[8], py[8], pz[8];
    __m256 lx, ly, lz;
    if (run) {
      const float* m = &x[pp[0]].x;  // x0 y0 z0 x1 | y1 z1 x2 y2 | z2 x3 y3 z3 | x4 ...
      const __m256 m03 = _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_loadu_ps(m)),
                                              _mm_loadu_ps(m + 12), 1);
      const __m256 m14 = _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_loadu_ps(m + 4)),
                                              _mm_loadu_ps(m + 16), 1);
      const __m256 m25 = _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_loadu_ps(m + 8)),
                                              _mm_loadu_ps(m + 20), 1);
      const __m256 xy = _mm256_shuffle_ps(m14, m25, _MM_SHUFFLE(2, 1, 3, 2));  // x2 y2 x3 y3
      const __m256 yz = _mm256_shuffle_ps(m03, m14, _MM_SHUFFLE(1, 0, 2, 1));  // y0 z0 y1 z1
      lx = _mm256_shuffle_ps(m03, xy, _MM_SHUFFLE(2, 0, 3, 0));                // x0 x1 x2 x3
      ly = _mm256_shuffle_ps(yz, xy, _MM_SHUFFLE(3, 1, 2, 0));                 // y0 y1 y2 y3
      lz = _mm256_shuffle_ps(yz, m25, _MM_SHUFFLE(3, 0, 3, 1));                // z0 z1 z2 z3
    } else {
      for (int l = 0; l < 8; ++l) {
        const float3 xp = x[pp[l]];
        px[l] = xp.x;
        py[l] = xp.y;
        pz[l] = xp.z;
      }
      lx = _mm256_load_ps(px);
      ly = _mm256_load_ps(py);
      lz = _mm256_load_ps(pz);
    }
    const __m256 vx = _mm256_sub_ps(lx, cx);
    const __m256 vy = _mm256_sub_ps(ly, cy);
    const __m256 vz = _mm256_sub_ps(lz, cz);
    const __m256 kvx = _mm256_sub_ps(_mm256_mul_ps(ky, vz), _mm256_mul_ps(kz, vy));
    const __m256 kvy = _mm256_sub_ps(_mm256_mul_ps(kz, vx), _mm256_mul_ps(kx, vz));
    const __m256 kvz = _mm256_sub_ps(_mm256_mul_ps(kx, vy), _mm256_mul_ps(ky, vx));
    const __m256 dot = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(kx, vx), _mm256_mul_ps(ky, vy)),
                                     _mm256_mul_ps(kz, vz));
    const __m256 d = _mm256_mul_ps(dot, _mm256_sub_ps(one, cs));
    const __m256 g = _mm256_mul_ps(wq, jv);
    const __m256 ox = JawAxisAvx(cx, vx, kvx, kx, tx, cs, sn, d, g);
    const __m256 oy = JawAxisAvx(cy, vy, kvy, ky, ty, cs, sn, d, g);
    const __m256 oz = JawAxisAvx(cz, vz, kvz, kz, tz, cs, sn, d, g);
    if (run) {  // the lanes back into the 24 floats: the load's shuffles undone
      const __m256 rxy = _mm256_shuffle_ps(ox, oy, _MM_SHUFFLE(2, 0, 2, 0));  // x0 x2 y0 y2
      const __m256 ryz = _mm256_shuffle_ps(oy, oz, _MM_SHUFFLE(3, 1, 3, 1));  // y1 y3 z1 z3
      const __m256 rzx = _mm256_shuffle_ps(oz, ox, _MM_SHUFFLE(3, 1, 2, 0));  // z0 z2 x1 x3
      const __m256 r03 = _mm256_shuffle_ps(rxy, rzx, _MM_SHUFFLE(2, 0, 2, 0));  // x0 y0 z0 x1
      const __m256 r14 = _mm256_shuffle_ps(ryz, rxy, _MM_SHUFFLE(3, 1, 2, 0));  // y1 z1 x2 y2
      const __m256 r25 = _mm256_shuffle_ps(rzx, ryz, _MM_SHUFFLE(3, 1, 3, 1));  // z2 x3 y3 z3
      float* m = &x[pp[0]].x;
      _mm_storeu_ps(m, _mm256_castps256_ps128(r03));
      _mm_storeu_ps(m + 4, _mm256_castps256_ps128(r14));
      _mm_storeu_ps(m + 8, _mm256_castps256_ps128(r25));
      _mm_storeu_ps(m + 12, _mm256_extractf128_ps(r03, 1));
      _mm_storeu_ps(m + 16, _mm256_extractf128_ps(r14, 1));
      _mm_storeu_ps(m + 20, _mm256_extractf128_ps(r25, 1));
    } else {
      _mm256_store_ps(px, ox);
      _mm256_store_ps(py, oy);
      _mm256_store_ps(pz, oz);
      for (int l = 0; l < 8; ++l) x[pp[l]] = float3{px[l], py[l], pz[l]};
    }
  }
  return q;
}
#endif

void StageJaw(const FrameState& f, float jaw) {
  const RigJaw& j = f.rig.jaw();
  const float3 c = j.pivot, k = j.axis, tr = j.translation;
  const float angle = jaw * j.range;
  const uint32_t* points = j.points.data();
  const float* weights = j.weights.data();
  float3* x = f.points;
  ParallelFor(f.job, uint32_t(j.points.size()), [&](uint32_t b, uint32_t e) {
    // Where the CPU has AVX, eight points at a time (JawBlockAvx: sine, cosine and rotation in
    // one pass, the same bits). The rest in blocks of kJawBlock: the angles' sines and cosines
    // first (contiguous weights, four lanes), then the rotation of each point (a gather and a
    // scatter of its own position).
    float sns[kJawBlock], css[kJawBlock];
    uint32_t b0 = b;
#if MIMETIC_RUNTIME_AVX
    if (CpuHasAvx()) b0 += JawBlockAvx(points + b, weights + b, e - b, angle, jaw, c, k, tr, x);
#endif
    for (; b0 < e; b0 += kJawBlock) {
      const uint32_t n = std::min(kJawBlock, e - b0);
      JawSinCosBlock(weights + b0, angle, n, sns, css);
      uint32_t q = 0;
#if defined(__SSE2__)
      // Four points a step: the scalar loop's operations below lane by lane, in its order
      // (no FMA), so the same bits whichever points fall in a lane or the tail. Each position
      // is read and written as its own 12 bytes (a neighbour may belong to another thread).
      {
        const __m128 cx = _mm_set1_ps(c.x), cy = _mm_set1_ps(c.y), cz = _mm_set1_ps(c.z);
        const __m128 kx = _mm_set1_ps(k.x), ky = _mm_set1_ps(k.y), kz = _mm_set1_ps(k.z);
        const __m128 tx = _mm_set1_ps(tr.x), ty = _mm_set1_ps(tr.y), tz = _mm_set1_ps(tr.z);
        const __m128 one = _mm_set1_ps(1.f), jv = _mm_set1_ps(jaw);
        for (; q + 4 <= n; q += 4) {
          const uint32_t* pp = points + b0 + q;
          alignas(16) float px[4], py[4], pz[4];
          for (int l = 0; l < 4; ++l) {
            const float3 xp = x[pp[l]];
            px[l] = xp.x;
            py[l] = xp.y;
            pz[l] = xp.z;
          }
          const __m128 vx = _mm_sub_ps(_mm_load_ps(px), cx);
          const __m128 vy = _mm_sub_ps(_mm_load_ps(py), cy);
          const __m128 vz = _mm_sub_ps(_mm_load_ps(pz), cz);
          const __m128 cs = _mm_loadu_ps(css + q), sn = _mm_loadu_ps(sns + q);
          const __m128 kvx = _mm_sub_ps(_mm_mul_ps(ky, vz), _mm_mul_ps(kz, vy));
          const __m128 kvy = _mm_sub_ps(_mm_mul_ps(kz, vx), _mm_mul_ps(kx, vz));
          const __m128 kvz = _mm_sub_ps(_mm_mul_ps(kx, vy), _mm_mul_ps(ky, vx));
          const __m128 dot =
              _mm_add_ps(_mm_add_ps(_mm_mul_ps(kx, vx), _mm_mul_ps(ky, vy)), _mm_mul_ps(kz, vz));
          const __m128 d = _mm_mul_ps(dot, _mm_sub_ps(one, cs));
          const __m128 g = _mm_mul_ps(_mm_loadu_ps(weights + b0 + q), jv);
          auto axis = [&](__m128 cc, __m128 v, __m128 kv, __m128 kk, __m128 t) {
            const __m128 turn = _mm_add_ps(_mm_add_ps(_mm_mul_ps(v, cs), _mm_mul_ps(kv, sn)),
                                           _mm_mul_ps(kk, d));
            return _mm_add_ps(_mm_add_ps(cc, turn), _mm_mul_ps(g, t));
          };
          _mm_store_ps(px, axis(cx, vx, kvx, kx, tx));
          _mm_store_ps(py, axis(cy, vy, kvy, ky, ty));
          _mm_store_ps(pz, axis(cz, vz, kvz, kz, tz));
          for (int l = 0; l < 4; ++l) x[pp[l]] = float3{px[l], py[l], pz[l]};
        }
      }
#endif
      for (; q < n; ++q) {
        const uint32_t i = b0 + q;
        const uint32_t p = points[i];
        const float cs = css[q], sn = sns[q];
        const float3 v = x[p] - c;
        const float3 kv = Cross(k, v);
        const float d = Dot(k, v) * (1.f - cs);
        const float g = weights[i] * jaw;  // the glide's share
        x[p] = float3{c.x + (v.x * cs + kv.x * sn + k.x * d) + g * tr.x,
                      c.y + (v.y * cs + kv.y * sn + k.y * d) + g * tr.y,
                      c.z + (v.z * cs + kv.z * sn + k.z * d) + g * tr.z};
      }
    }
  });
}

// docs/model.md §24: the lids slide on the eyeballs. Each listed point that the muscles or the
// jaw moved (its bits differ from the rest pose's: a point at rest stays bit for bit) goes
// toward the point at its rest distance R_p from its eyeball's centre c along c -> x, by its
// weight: x + w (c + (x - c) R_p / |x - c| - x). Each point reads and writes only itself.
void StageEyes(const FrameState& f) {
  const RigEyes& eyes = f.rig.eyes();
  const uint32_t* points = eyes.points.data();
  const uint32_t* which = eyes.eyes.data();
  const float* radii = eyes.radii.data();
  const float* weights = eyes.weights.data();
  const float3* centers = eyes.centers.data();
  const float3* rest = f.base;
  float3* x = f.points;
  ParallelFor(f.job, uint32_t(eyes.points.size()), [&](uint32_t b, uint32_t e) {
    for (uint32_t i = b; i < e; ++i) {
      const uint32_t p = points[i];
      const float3 xp = x[p], r = rest[p];
      if (xp.x == r.x && xp.y == r.y && xp.z == r.z) continue;
      const float3 c = centers[which[i]];
      const float3 v = xp - c;
      const float len = Length(v);
      if (!(len > 0.f)) continue;  // at the centre (or not finite): no direction to slide on
      const float s = radii[i] / len;
      const float w = weights[i];
      x[p] = float3{xp.x + w * (c.x + v.x * s - xp.x), xp.y + w * (c.y + v.y * s - xp.y),
                    xp.z + w * (c.z + v.z * s - xp.z)};
    }
  });
}

// The strain of X1 against the rest pose (docs/model.md §4-5): face normals and triangle area
// ratios of X1, and the lengths of the edges the strain measures read (compression eps per
// wrinkled-muscle row, 001 eq. 9-10, and shrinkage s per curve-wrinkle entry, 000 eq. 4, are
// computed from them where StageDisplace needs them). All read X1, so they run before
// anything moves.
void StageStrain(const FrameState& f) {
  FaceNormalsOfActive(f, true);
  if (f.edges) {
    const float3* points = f.points;
    const uint32_t* pairs = f.tables.edge_pairs.data();
    float* lengths = f.edge_lengths;
    ParallelFor(f.job, f.tables.edge_count(), [&](uint32_t b, uint32_t e) {
      EdgeLengths(points, pairs, b, e, lengths);
    });
  }
}

// g L_pq, the slope bound between p (at xp) and its neighbour q, from X1: L_pq^2 as
// (x^2 + y^2) + z^2, then g sqrt (the same bits wherever it is computed).
inline float SlopeBound(const float3* xs, float3 xp, uint32_t q) {
  const float3 e = xs[q] - xp;
  return kOffsetSlope * std::sqrt((e.x * e.x + e.y * e.y) + e.z * e.z);
}

// One Jacobi pass of the thickness slope limit for point p: with t = in[p] > 0, the result is
// max(0, min(t, min_q (in[q] + g L_pq))) over p's neighbours q (L_pq the edge length at X1,
// `xs`); with t < 0, the mirror image. Only lowers magnitudes and never changes a sign, so a
// peak (a pinched one-ring whose r is near r_min) comes down to its neighbours plus the slope,
// and flat or gently sloped offsets keep their bits. A NaN neighbour never binds (std::min/max
// keep the first argument).
inline float SlopeLimitPoint(const float* in, const uint32_t* off, const uint32_t* nbr,
                             const float3* xs, uint32_t p) {
  const float t = in[p];
  if (t == 0.f) return t;
  const float3 xp = xs[p];
  float out = t;
  if (t > 0.f) {
    for (uint32_t k = off[p]; k < off[p + 1]; ++k)
      out = std::min(out, in[nbr[k]] + SlopeBound(xs, xp, nbr[k]));
    return std::max(out, 0.f);
  }
  for (uint32_t k = off[p]; k < off[p + 1]; ++k)
    out = std::max(out, in[nbr[k]] - SlopeBound(xs, xp, nbr[k]));
  return std::min(out, 0.f);
}

// SlopeLimitPoint with p's edge lengths at X1 read from `lengths` (per slot k of p, the length
// of edge `edges[k]`, EdgeLengths' |X1q - X1p|: the square root of the same sum SlopeBound
// takes, so g times it is SlopeBound's bits) instead of measured again from the positions.
inline float SlopeLimitPointEdges(const float* in, const uint32_t* off, const uint32_t* nbr,
                                  const uint32_t* edges, const float* lengths, uint32_t p) {
  const float t = in[p];
  if (t == 0.f) return t;
  float out = t;
  if (t > 0.f) {
    for (uint32_t k = off[p]; k < off[p + 1]; ++k)
      out = std::min(out, in[nbr[k]] + kOffsetSlope * lengths[edges[k]]);
    return std::max(out, 0.f);
  }
  for (uint32_t k = off[p]; k < off[p + 1]; ++k)
    out = std::max(out, in[nbr[k]] - kOffsetSlope * lengths[edges[k]]);
  return std::min(out, 0.f);
}

// SlopeLimitPoint, first deciding from `min_bound` = g min_q L_pq (the smallest of p's bounds,
// computed the same way) whether any neighbour can bind: with t > 0, when t <= min_q in[q] +
// min_bound no neighbour does (each in[q] + g L_pq is at least that sum, float rounding being
// monotone) and t is the result, with no neighbour's position read; the mirror image for t < 0.
// NaN neighbours are skipped here as they never bind there. The same bits as SlopeLimitPoint.
inline float SlopeLimitPointQuick(const float* in, const uint32_t* off, const uint32_t* nbr,
                                  const uint32_t* edges, const float* lengths,
                                  const float* min_bound, uint32_t p) {
  const float t = in[p];
  if (t == 0.f) return t;
  const uint32_t k0 = off[p], k1 = off[p + 1];
  if (t > 0.f) {
    float m = std::numeric_limits<float>::infinity();
    for (uint32_t k = k0; k < k1; ++k) {
      const float v = in[nbr[k]];
      m = v < m ? v : m;
    }
    if (t <= m + min_bound[p]) return t;
  } else {
    float m = -std::numeric_limits<float>::infinity();
    for (uint32_t k = k0; k < k1; ++k) {
      const float v = in[nbr[k]];
      m = v > m ? v : m;
    }
    if (t >= m - min_bound[p]) return t;
  }
  return SlopeLimitPointEdges(in, off, nbr, edges, lengths, p);
}

// The skin offset of each active point with the fold limiter on: d_p = t_p + w_p (t the
// thickness term (1/max(r, r_min) - 1) h, w the wrinkle sum), then bounded by the local radius
// of curvature of X1: |d_p| <= kOffsetCurvature * min_q L_pq / |N_p - N_q| over p's neighbours q
// (RigTables::point_neighbors; unit normals N of X1). An offset surface folds where the offset exceeds the
// radius of curvature on the concave side; the bound keeps it a fraction of it on either side.
// Then the thickness-style slope limit (SlopeLimitPoint) smooths the steps the bound leaves.
// The one offset per point DisplaceAlongNormals then adds (with h = null).
const float* LimitedOffsets(const FrameState& f, const float* h, const float* extra) {
  const Rig& r = f.rig;
  const uint32_t count = r.active_point_count();
  const float min_ratio = r.min_area_ratio();
  float* a = f.thickness_a;
  float* b = f.thickness_b;
  // The unit normals of X1: the active points' written here (scratch: StageLimit rewrites
  // them before reading them), the rest normals past them (EvaluateContext::Resize).
  float3* unit = f.skin_full;
  ParallelFor(f.job, count, [&](uint32_t lo, uint32_t hi) {
    for (uint32_t p = lo; p < hi; ++p) {
      unit[p] = UnitNormal(f.sums[p]);
      float d = h ? ThicknessOffset(f.ratios[p], h[p], min_ratio) : 0.f;
      if (extra) d += extra[p];
      a[p] = d;
    }
  });
  const uint32_t* noff = f.tables.point_neighbor_offsets.data();
  const uint32_t* nbr = f.tables.point_neighbors.data();
  // The curvature bound, and in the same sweep over the neighbours the slope limit's smallest
  // bound g min_q L_pq per point (SlopeLimitPointQuick's test; the edge lengths at X1 are the
  // same in every pass). A point whose offset is 0 keeps 0 through every slope pass
  // (SlopeLimitPoint returns it), so its bound is never read and is not computed.
  float* min_bound = f.slope_min_bounds;
  const float3* x1 = f.points;
  // The shortcut below is exact; limit_folds_full_scan (the tests' reference) runs without it,
  // so FoldOver.LimiterWorklistGivesTheFullScansBits compares the two bit for bit.
  const bool quick = !f.job.limit_folds_full_scan;
  // With the shortcuts, every edge of the one-rings measured once (RigTables::
  // neighbor_edge_pairs), for both of its points: p's shortest edge is then the smallest of
  // its slots' lengths, the square root of the smallest squared length the full scan takes
  // from the positions (the root is monotone and correctly rounded: the same bits, so the
  // same slope bound g min_q L_pq). The shortcuts compare its square, within a few ulp of
  // that squared length: far inside their 1% margin.
  const uint32_t* nedge = f.tables.point_neighbor_edges.data();
  float* lengths = f.limit_edge_lengths;
  if (quick) {
    const uint32_t* pairs = f.tables.neighbor_edge_pairs.data();
    ParallelFor(f.job, f.tables.neighbor_edge_count(), [&](uint32_t lo, uint32_t hi) {
      EdgeLengths(x1, pairs, lo, hi, lengths);
    });
  }
  ParallelFor(f.job, count, [&, a, b](uint32_t lo, uint32_t hi) {
    // Plain locals: the stores to `bound` and `b` cannot alias them in the compiler's eyes
    // (through the captured references it reloaded every pointer after every store).
    const float* offsets = a;
    float* out = b;
    float* min_bounds = min_bound;
    const float3* xs = x1;
    const float3* units = unit;
    const float* edge_lengths = lengths;
    for (uint32_t p = lo; p < hi; ++p) {
      const float d = offsets[p];
      if (d == 0.f) {
        out[p] = 0.f;
        continue;
      }
      // First the shortest edge (its slope bound kept): unit normals differ by at most 2
      // (|dN|^2 <= 4), so when 4 d^2 is below c^2 L_min^2 (with a margin of 1% for the
      // rounding of normals and products) no neighbour can bind and the curvature needs no
      // normals at all: the same result as the full test, which then keeps d.
      const float3 xp = xs[p];
      const uint32_t k0 = noff[p], k1 = noff[p + 1];
      float l2_min = std::numeric_limits<float>::infinity();
      if (quick) {
        float l_min = std::numeric_limits<float>::infinity();
        for (uint32_t k = k0; k < k1; ++k) {
          const float l = edge_lengths[nedge[k]];
          l_min = l < l_min ? l : l_min;
        }
        min_bounds[p] = kOffsetSlope * l_min;
        l2_min = l_min * l_min;
      } else {
        for (uint32_t k = k0; k < k1; ++k) {
          const float3 e = xs[nbr[k]] - xp;
          const float l2 = (e.x * e.x + e.y * e.y) + e.z * e.z;
          l2_min = l2 < l2_min ? l2 : l2_min;
        }
        min_bounds[p] = kOffsetSlope * std::sqrt(l2_min);
      }
      const float c2 = kOffsetCurvature * kOffsetCurvature;
      if (quick && d * d * 4.04f <= c2 * l2_min) {
        out[p] = d;
        continue;
      }
      // Then the largest normal change: where d^2 max_q |dN_q|^2 is below c^2 L_min^2 (the
      // same 1% margin) no neighbour binds either, and the pairs need no comparing.
      const float3 np = units[p];
      auto normal_change = [&](uint32_t q) {
        const float3 nq = units[q];
        const float3 dn = nq - np;
        return (dn.x * dn.x + dn.y * dn.y) + dn.z * dn.z;
      };
      if (quick) {
        float n2_max = 0.f;
        for (uint32_t k = k0; k < k1; ++k) {
          const float n2 = normal_change(nbr[k]);
          n2_max = n2 > n2_max ? n2 : n2_max;
        }
        if (d * d * (n2_max * 1.01f) <= c2 * l2_min) {
          out[p] = d;
          continue;
        }
      }
      // min over q of L^2 / |dN|^2, compared without division, in two independent chains
      // (even and odd slots, merged at the end): one chain's compare-and-select waited on the
      // previous slot's, which bounded the loop.
      float l2a = 1.f, n2a = 0.f, l2b = 1.f, n2b = 0.f;  // ratios l2 / n2, infinite at first
      auto slot = [&](uint32_t k, float& best_l2, float& best_n2) {
        const uint32_t q = nbr[k];
        const float3 e = xs[q] - xp;
        const float n2 = normal_change(q);
        const float l2 = (e.x * e.x + e.y * e.y) + e.z * e.z;
        if (l2 * best_n2 < best_l2 * n2) {
          best_l2 = l2;
          best_n2 = n2;
        }
      };
      uint32_t k = k0;
      for (; k + 1 < k1; k += 2) {
        slot(k, l2a, n2a);
        slot(k + 1, l2b, n2b);
      }
      if (k < k1) slot(k, l2a, n2a);
      float best_l2 = l2a, best_n2 = n2a;
      if (l2b * best_n2 < best_l2 * n2b) {
        best_l2 = l2b;
        best_n2 = n2b;
      }
      if (best_n2 > 0.f && d * d * best_n2 > c2 * best_l2) {
        const float limit = kOffsetCurvature * std::sqrt(best_l2 / best_n2);
        out[p] = d > 0.f ? limit : -limit;
      } else {
        out[p] = d;
      }
    }
  });
  std::swap(a, b);
  // The slope passes (Jacobi). The first runs over every point. A point keeps its bits in a
  // pass when neither it nor any neighbour changed in the pass before (SlopeLimitPoint reads
  // only those, so it returns what it returned then), so each later pass recomputes only the
  // points the previous one changed and their active neighbours: the same bits as a full
  // pass (bits compared, so a zero turning into -0 counts as a change), a few hundred points
  // instead of all. The lists after the first are built serially in a fixed order; each
  // parallel phase writes only its own point.
  auto bits = [](float v) {
    uint32_t u;
    std::memcpy(&u, &v, 4);
    return u;
  };
  uint32_t* changed = f.limit_moved;   // StageLimit's lists and marks, free until it runs
  uint32_t* redo = f.limit_recheck;
  uint8_t* mark = f.limit_point_marks;  // 0 on entry and on exit
  // The first pass also lists the points it changed (bits compared), each appended by the
  // thread that computed it; sorted below, so the list is the serial scan's, in its order.
  std::atomic<uint32_t> first_changed{0};
  ParallelFor(f.job, count, [&](uint32_t lo, uint32_t hi) {
    if (quick) {
      for (uint32_t p = lo; p < hi; ++p) {
        const float v = SlopeLimitPointQuick(a, noff, nbr, nedge, lengths, min_bound, p);
        b[p] = v;
        if (bits(v) != bits(a[p])) changed[first_changed.fetch_add(1, std::memory_order_relaxed)] = p;
      }
    } else {
      for (uint32_t p = lo; p < hi; ++p) b[p] = SlopeLimitPoint(a, noff, nbr, x1, p);
    }
  });
  std::swap(a, b);  // a: after the first pass, b: before it
  if (f.job.limit_folds_full_scan) {  // every pass over every point (tests compare the bits)
    for (uint32_t pass = 1; pass < kOffsetSlopePasses; ++pass) {
      ParallelFor(f.job, count, [&](uint32_t lo, uint32_t hi) {
        for (uint32_t p = lo; p < hi; ++p) b[p] = SlopeLimitPoint(a, noff, nbr, x1, p);
      });
      std::swap(a, b);
    }
    return a;
  }
  uint32_t n_changed = first_changed.load(std::memory_order_relaxed);
  std::sort(changed, changed + n_changed);
  for (uint32_t pass = 1; pass < kOffsetSlopePasses && n_changed > 0; ++pass) {
    uint32_t n_redo = 0;
    auto add = [&](uint32_t q) {
      if (q < count && !mark[q]) mark[q] = 1, redo[n_redo++] = q;
    };
    for (uint32_t i = 0; i < n_changed; ++i) {
      const uint32_t p = changed[i];
      add(p);
      for (uint32_t k = noff[p]; k < noff[p + 1]; ++k) add(nbr[k]);
    }
    // The quick test holds here too: a point whose offset is not 0 had one before the first
    // pass (a 0 stays 0), so its smallest bound was computed above.
    ParallelFor(f.job, n_redo, [&](uint32_t lo, uint32_t hi) {
      for (uint32_t i = lo; i < hi; ++i)
        b[redo[i]] = SlopeLimitPointQuick(a, noff, nbr, nedge, lengths, min_bound, redo[i]);
    });
    n_changed = 0;
    for (uint32_t i = 0; i < n_redo; ++i) {
      const uint32_t p = redo[i];
      mark[p] = 0;
      if (bits(a[p]) != bits(b[p])) changed[n_changed++] = p;
      a[p] = b[p];
    }
  }
  return a;
}

// Per point: N1 and r from its triangles (docs/model.md §1 step 2, §4), then one displacement
// along N1 (docs/model.md §4, §6-8): the volume-preserving thickness (1/r - 1) h, its
// muscle-wrinkle rows H At A(eps) in rig order, its curve wrinkles S(l) M. Three sweeps: the
// gathers alone (independent load chains that overlap), the wrinkle sums of the points that
// have any, then four points at a time share the square root and the divisions. Each point
// reads only its own values and the face slots of X1, so it moves in place.
// Per active point: its face slots gathered (N1 unnormalised in xyz) and its area ratio r.
void GatherRatios(const FrameState& f) {
  const uint32_t* off = f.point_tri_offsets;
  const uint32_t* tri = f.point_tris;
  const float4* faces = f.faces;
  float4* sums = f.sums;
  ParallelFor(f.job, f.rig.active_point_count(), [&](uint32_t b, uint32_t e) {
    float* ratios = f.ratios;
    for (uint32_t p = b; p < e; ++p) {
      sums[p] = GatherFaces4(off, tri, faces, p);
      ratios[p] = PointRatio(sums[p], off[p + 1] - off[p]);
    }
  });
}

void StageDisplace(const FrameState& f) {
  const Rig& r = f.rig;
  const RigTables& t = f.tables;
  float4* sums = f.sums;
  GatherRatios(f);
  const bool muscle_wrinkles = f.muscle_wrinkles, curve_wrinkles = f.curve_wrinkles;
  if (f.wrinkles()) {
    ParallelFor(f.job, uint32_t(t.wrinkle_points.size()), [&](uint32_t b, uint32_t e) {
      // Plain pointers: the stores to `offsets` cannot alias them in the compiler's eyes.
      const float* length = f.edge_lengths;
      const uint32_t* wrinkle_points = t.wrinkle_points.data();
      const uint32_t* point_rows = t.point_row_offsets.data();
      const uint32_t* row_entries = t.row_offsets.data();
      const uint32_t* edges = t.entry_edges.data();
      const float* coeffs = t.entry_coeffs.data();
      const float* rest = t.entry_rest.data();
      const float* profiles = t.row_profiles.data();
      const uint32_t* row_muscles = t.row_muscles.data();
      const float* gates = f.wrinkle_gates;
      const CurveWrinkleParams* params = r.curve_wrinkles().wrinkles.data();
      const CurveWrinkleEntry* entries = r.curve_wrinkles().entries.data();
      const ShrinkageProbe* probes = r.curve_wrinkles().probes.data();
      const uint32_t* probe_edges = t.probe_edges.data();
      const uint32_t* curve_offsets = r.curve_wrinkles().offsets.data();
      const uint32_t* point_curves = t.point_curve_offsets.data();
      const uint32_t* curve_rows = t.point_curve_rows.data();
      const float* ratios = f.ratios;
      float* offsets = f.wrinkle_offsets;
      // Shrinkage s of curve-wrinkle entry k (000 eq. 4) from the edge lengths.
      auto shrinkage = [&](uint32_t k) {
        const uint32_t* pe = probe_edges + 4 * k;
        return ProbeShrinkage(probes[k], [&](uint32_t s, int which) {
          return length[pe[2 * s + which]];
        });
      };
      for (uint32_t i = b; i < e; ++i) {
        const uint32_t p = wrinkle_points[i];
        float d = 0.f;
        if (muscle_wrinkles) {
          for (uint32_t row = point_rows[p]; row < point_rows[p + 1]; ++row) {
            // 001 eq. 9-10: eps = sum_j c_j (L_j - l_j); eq. 4: W = H(w_i) A(eps) At_i,
            // times the muscle's gate G (docs/model.md §5-6).
            float eps = 0.f;
            for (uint32_t k = row_entries[row]; k < row_entries[row + 1]; ++k)
              eps += coeffs[k] * (rest[k] - length[edges[k]]);
            d += profiles[row] * Anisotropy(eps) * gates[row_muscles[row]];
          }
        }
        if (curve_wrinkles) {
          for (uint32_t k = point_curves[p]; k < point_curves[p + 1]; ++k) {
            const uint32_t row = curve_rows[k];
            d += CurveWrinkleRowSumWith(params, entries, curve_offsets[row],
                                        curve_offsets[row + 1], shrinkage, ratios[p]);
          }
        }
        offsets[p] = d;
      }
    });
  }
  const float* h = f.thickness ? r.point_thickness().data() : nullptr;
  const float* extra = f.wrinkles() ? f.wrinkle_offsets : nullptr;
  if (f.limit_folds) {
    extra = LimitedOffsets(f, h, extra);
    h = nullptr;
  }
  float3* base = f.limit_folds ? f.skin_base : nullptr;
  ParallelFor(f.job, r.active_point_count(), [&](uint32_t b, uint32_t e) {
    if (base) std::copy(f.points + b, f.points + e, base + b);  // X1, for StageLimit
    DisplaceAlongNormals(sums, f.ratios, h, r.min_area_ratio(), extra, b, e, f.points);
  });
}

// The cosine of a triangle's current normal against its rest normal.
inline float CosToRest(const float4& a, const float4& q) {
  const float lq = (q.x * q.x + q.y * q.y) + q.z * q.z;
  const float la = (a.x * a.x + a.y * a.y) + a.z * a.z;
  const float d = (a.x * q.x + a.y * q.y) + a.z * q.z;
  if (!(lq > 0.f)) return 1.f;  // degenerate rest triangle: never counts
  // A collapsed triangle counts as 0; a non-finite one stays NaN (never flagged: the limiter
  // does not hide an evaluation that overflowed, the offline guard CheckPosedFinite names it).
  return la == 0.f ? 0.f : d / std::sqrt(la * lq);
}

// True when the cosine between a triangle's current normal `a` (unnormalised) and its rest
// normal `q` is below `limit` (a collapsed triangle counts as cosine 0). A degenerate rest
// triangle (zero normal) never counts.
inline bool CosBelow(const float4& a, const float4& q, float limit) {
  const float lq = (q.x * q.x + q.y * q.y) + q.z * q.z;
  if (!(lq > 0.f)) return false;
  return CosToRest(a, q) < limit;
}

// The limiter's verdict of triangle t this pass: below its limit (CosBelow), once per triangle.
inline void FoldVerdict(const FrameState& f, const float4* rest, uint32_t t) {
  f.limit_tri_bad[t] = CosBelow(f.faces[t], rest[t], f.fold_limits[t]);
}

// A limiter pass's test of point p: one of its triangles is below its limit (the verdicts of
// this pass's face normals, FoldVerdict).
inline bool FoldFlag(const FrameState& f, uint32_t p) {
  const uint32_t* off = f.point_tri_offsets;
  const uint32_t* tri = f.point_tris;
  const uint8_t* bad = f.limit_tri_bad;
  uint8_t any = 0;
  for (uint32_t k = off[p]; k < off[p + 1]; ++k) any |= bad[tri[k]];
  return any != 0;
}

// Face normals of every active triangle and their verdicts.
void FoldVerdictsOfActive(const FrameState& f, const float4* rest) {
  const float3* points = f.points;
  float4* faces = f.faces;
  const uint32_t* triangles = f.rig.triangles().data();
  ParallelFor(f.job, f.rig.active_triangle_count(), [&](uint32_t b, uint32_t e) {
    FaceNormals4(points, triangles, b, e, nullptr, faces);
    for (uint32_t t = b; t < e; ++t) FoldVerdict(f, rest, t);
  });
}

// One more reduction of point p, whose level is below kFoldLimitCutLevel: the next power of two
// of its offset, or none from the cut on. True when it is p's first.
inline bool ReduceOffset(const FrameState& f, uint32_t p) {
  uint8_t level = f.limit_levels[p];
  const bool first = level == 0;
  if (first) f.skin_full[p] = f.points[p];
  f.limit_levels[p] = ++level;
  if (level >= kFoldLimitCutLevel) {
    f.points[p] = f.skin_base[p];
  } else {
    const float s = 1.f / float(1u << level);  // a power of two: exact
    const float3 x1 = f.skin_base[p], x3 = f.skin_full[p];
    f.points[p] = float3{x1.x + (x3.x - x1.x) * s, x1.y + (x3.y - x1.y) * s,
                         x1.z + (x3.z - x1.z) * s};
  }
  return first;
}

// The limiter as a full scan: every pass recomputes the face normals of every active triangle,
// tests every active point, and reduces every flagged point and its one-ring.
bool FoldLimitFullScan(const FrameState& f, uint32_t* limited, uint32_t* passes) {
  const Rig& r = f.rig;
  const uint32_t count = r.active_point_count();
  const float4* rest = f.tables.rest_faces.data();
  uint32_t first_total = 0, pass = 0;
  bool current = false;
  while (pass < kFoldLimitPasses) {
    FoldVerdictsOfActive(f, rest);
    ++pass;
    std::atomic<uint32_t> flagged{0}, first{0};
    const uint32_t* off = f.point_tri_offsets;
    const uint32_t* tri = f.point_tris;
    const uint32_t* triangles = r.triangles().data();
    uint8_t* flags = f.limit_flags;
    // Flag the points with a triangle below its limit.
    ParallelFor(f.job, count, [&](uint32_t b, uint32_t e) {
      uint32_t n = 0;
      for (uint32_t p = b; p < e; ++p) {
        const bool bad = FoldFlag(f, p);
        flags[p] = bad;
        n += bad;
      }
      flagged.fetch_add(n, std::memory_order_relaxed);
    });
    if (flagged.load() == 0) {
      current = true;
      break;
    }
    // Reduce the offset of every flagged point and of its one-ring (so the reduction spreads
    // as a ramp instead of a step next to points that keep their offset).
    ParallelFor(f.job, count, [&](uint32_t b, uint32_t e) {
      uint32_t n_first = 0;
      for (uint32_t p = b; p < e; ++p) {
        if (f.limit_levels[p] >= kFoldLimitCutLevel) continue;  // already at X1
        bool near = flags[p] != 0;
        for (uint32_t k = off[p]; k < off[p + 1] && !near; ++k) {
          const uint32_t* c = triangles + 3 * size_t(tri[k]);
          near = flags[c[0]] | flags[c[1]] | flags[c[2]];
        }
        if (near) n_first += ReduceOffset(f, p);
      }
      first.fetch_add(n_first, std::memory_order_relaxed);
    });
    first_total += first.load();
  }
  *limited = first_total;
  *passes = pass;
  return current;
}

// The same passes as a worklist (see StageLimit; needs RigTables::point_triangles_exact).
bool FoldLimitWorklist(const FrameState& f, uint32_t* limited, uint32_t* passes) {
  const Rig& r = f.rig;
  const uint32_t count = r.active_point_count();
  const float4* rest = f.tables.rest_faces.data();
  const uint32_t* off = f.point_tri_offsets;
  const uint32_t* tri = f.point_tris;
  const uint32_t* triangles = r.triangles().data();
  uint8_t* flags = f.limit_flags;
  uint32_t* moved = f.limit_moved;      // [0, n_moved): the points the last pass moved
  uint32_t* flagged = f.limit_flagged;  // [0, n_flagged): every point flagged now
  uint32_t* recheck = f.limit_recheck;
  uint32_t* dirty = f.limit_tris;
  uint8_t* point_mark = f.limit_point_marks;
  uint8_t* tri_mark = f.limit_tri_marks;
  const uint32_t* noff = f.tables.point_neighbor_offsets.data();
  const uint32_t* nbr = f.tables.point_neighbors.data();
  uint32_t n_moved = 0, n_flagged = 0, first_total = 0, pass = 0;
  bool current = false;
  while (pass < kFoldLimitPasses) {
    if (pass == 0) {  // every active triangle and point
      FoldVerdictsOfActive(f, rest);
      // The flagged points appended by the thread that tested them, then sorted: the serial
      // scan's list, in its order.
      std::atomic<uint32_t> n{0};
      ParallelFor(f.job, count, [&](uint32_t b, uint32_t e) {
        for (uint32_t p = b; p < e; ++p) {
          flags[p] = FoldFlag(f, p);
          if (flags[p]) flagged[n.fetch_add(1, std::memory_order_relaxed)] = p;
        }
      });
      n_flagged = n.load(std::memory_order_relaxed);
      std::sort(flagged, flagged + n_flagged);
    } else {
      // The triangles touching a point the last pass moved: the only normals that can differ.
      uint32_t n_dirty = 0;
      for (uint32_t i = 0; i < n_moved; ++i) {
        const uint32_t p = moved[i];
        for (uint32_t k = off[p]; k < off[p + 1]; ++k) {
          const uint32_t t = tri[k];
          if (tri_mark[t]) continue;
          tri_mark[t] = 1;
          dirty[n_dirty++] = t;
        }
      }
      ParallelFor(f.job, n_dirty, [&](uint32_t b, uint32_t e) {
        FaceNormals4Listed(f.points, triangles, dirty + b, e - b, f.faces);
        for (uint32_t i = b; i < e; ++i) FoldVerdict(f, rest, dirty[i]);
      });
      // The points with one of those in their one-ring: the only flags that can differ.
      uint32_t n_recheck = 0;
      for (uint32_t i = 0; i < n_dirty; ++i) {
        const uint32_t* c = triangles + 3 * size_t(dirty[i]);
        tri_mark[dirty[i]] = 0;
        for (int j = 0; j < 3; ++j) {
          const uint32_t q = c[j];
          if (q >= count || point_mark[q]) continue;
          point_mark[q] = 1;
          recheck[n_recheck++] = q;
        }
      }
      ParallelFor(f.job, n_recheck, [&](uint32_t b, uint32_t e) {
        for (uint32_t i = b; i < e; ++i) flags[recheck[i]] = FoldFlag(f, recheck[i]);
      });
      // Flagged now: the flagged points not retested, and the retested ones that are.
      uint32_t n = 0;
      for (uint32_t i = 0; i < n_flagged; ++i)
        if (!point_mark[flagged[i]]) flagged[n++] = flagged[i];
      for (uint32_t i = 0; i < n_recheck; ++i) {
        point_mark[recheck[i]] = 0;
        if (flags[recheck[i]]) flagged[n++] = recheck[i];
      }
      n_flagged = n;
    }
    ++pass;
    if (n_flagged == 0) {
      current = true;
      break;
    }
    // The points the full scan reduces: the flagged ones and their one-rings (the points that
    // share a triangle with one: with exact triangle lists, RigTables::point_neighbors, each
    // once), below the cut, to the front; those at the cut to the back.
    uint32_t front = 0, back = count;
    auto visit = [&](uint32_t q) {
      if (point_mark[q]) return;
      point_mark[q] = 1;
      if (f.limit_levels[q] < kFoldLimitCutLevel)
        moved[front++] = q;
      else
        moved[--back] = q;
    };
    for (uint32_t i = 0; i < n_flagged; ++i) {
      const uint32_t q = flagged[i];
      visit(q);
      for (uint32_t k = noff[q]; k < noff[q + 1]; ++k)
        if (nbr[k] < count) visit(nbr[k]);
    }
    for (uint32_t i = 0; i < front; ++i) point_mark[moved[i]] = 0;
    for (uint32_t i = back; i < count; ++i) point_mark[moved[i]] = 0;
    n_moved = front;
    std::atomic<uint32_t> first{0};
    ParallelFor(f.job, n_moved, [&](uint32_t b, uint32_t e) {
      uint32_t n_first = 0;
      for (uint32_t i = b; i < e; ++i) n_first += ReduceOffset(f, moved[i]);
      first.fetch_add(n_first, std::memory_order_relaxed);
    });
    first_total += first.load();
    if (n_moved == 0) {  // a fixed point: the full scan repeats this pass to the last
      pass = kFoldLimitPasses;
      current = true;  // nothing moved since the face slots were computed
      break;
    }
  }
  *limited = first_total;
  *passes = pass;
  return current;
}

// docs/model.md §16, the fold limiter. The skin layers move each point along N1 (X3 = X1 +
// d N1); where the muscles crease the skin, offsets along normals that turn fast fold the
// surface. LimitedOffsets bounds the offsets first; what still folds is caught here. Pass
// after pass: face normals of the current points; a point is flagged when one of its
// triangles is below its limit (kFoldLimitDot against rest, or X1's own cosine where the
// muscles already went below it); every flagged point and its one-ring move back toward X1
// (half of the offset, a quarter, an eighth, then none from kFoldLimitCutLevel on); stop when
// a pass flags nothing, or after kFoldLimitPasses.
// As a worklist (FoldLimitWorklist): a triangle none of whose corners the previous pass moved
// keeps its normal bits, hence its verdict, and a point none of whose triangles changed keeps
// its flag; so after the first pass only the triangles touching a moved point are recomputed
// and only the points around them retested, and the points to reduce are gathered from the
// list of flagged points. Every quantity is the full scan's (FoldLimitFullScan: the same
// per-triangle and per-point expressions, of the same inputs), so are the bits; it relies on
// RigTables::point_triangles_exact (the full scan runs where a rig lacks it, and with
// EvaluateJob::limit_folds_full_scan). A pass that moves nothing is a fixed point: the full
// scan would repeat it until kFoldLimitPasses, so the worklist stops there and counts them.
// The lists are built serially in a fixed order (the first pass's flagged points are appended
// in parallel and then sorted, which gives the same list); each point or triangle of a
// parallel phase reads only the previous phase's values and writes only itself, so the result
// does not depend on how parallel_for splits the work. Points never reduced keep their bits.
// Returns true when the face slots hold the normals of the final points.
bool StageLimit(const FrameState& f, uint32_t* limited, uint32_t* passes) {
  const Rig& r = f.rig;
  std::fill(f.limit_levels, f.limit_levels + r.active_point_count(), uint8_t{0});
  const float4* rest = f.tables.rest_faces.data();
  // Each triangle's limit: kFoldLimitDot, or below X1's own cosine where the muscles already
  // brought it closer to turning over (the skin layers may not make it worse; X1 keeps it).
  float* limits = f.fold_limits;
  ParallelFor(f.job, r.active_triangle_count(), [&](uint32_t b, uint32_t e) {
    for (uint32_t t = b; t < e; ++t) {
      const float c = CosToRest(f.faces[t], rest[t]);
      limits[t] = c > kFoldLimitDot ? kFoldLimitDot : c - 1e-4f;
    }
  });
  if (f.job.limit_folds_full_scan || !f.tables.point_triangles_exact)
    return FoldLimitFullScan(f, limited, passes);
  return FoldLimitWorklist(f, limited, passes);
}

// docs/tension.md, docs/model.md §19: the tension outputs of X1. Per point with muscle-wrinkle
// rows (when out_tension is requested), eps = the largest of its rows' sum_j c_j (L_j - l_j)
// (the expression StageDisplace evaluates, from the same edge lengths); per region R with
// point weights w_i, C_R = sum_i w_i max(0, 1 - r_i) / sum_i w_i (in double, in the region's
// point order) and weight 1 - exp(-C_R / c0_R). Each point writes itself only, the regions run
// serially in a fixed order: the same bits however the work is split.
void StageTension(const FrameState& f) {
  const RigTables& t = f.tables;
  if (f.tension_eps) {
    ParallelFor(f.job, uint32_t(t.wrinkle_points.size()), [&](uint32_t b, uint32_t e) {
      const float* length = f.edge_lengths;
      const uint32_t* point_rows = t.point_row_offsets.data();
      const uint32_t* row_entries = t.row_offsets.data();
      const uint32_t* edges = t.entry_edges.data();
      const float* coeffs = t.entry_coeffs.data();
      const float* rest = t.entry_rest.data();
      float* out = f.compressions;
      for (uint32_t i = b; i < e; ++i) {
        const uint32_t p = t.wrinkle_points[i];
        float best = 0.f;
        for (uint32_t row = point_rows[p]; row < point_rows[p + 1]; ++row) {
          float eps = 0.f;
          for (uint32_t k = row_entries[row]; k < row_entries[row + 1]; ++k)
            eps += coeffs[k] * (rest[k] - length[edges[k]]);
          best = row == point_rows[p] ? eps : std::max(best, eps);
        }
        out[p] = best;
      }
    });
  }
  const span<float> weights = f.job.out_region_weights;
  if (weights.empty()) return;
  const RigTensionRegions& g = f.rig.tension_regions();
  for (uint32_t i = 0; i < g.region_count(); ++i) {
    double num = 0.0, den = 0.0;
    for (uint32_t k = g.offsets[i]; k < g.offsets[i + 1]; ++k) {
      const double w = g.weights[k];
      const float c = 1.f - f.ratios[g.points[k]];
      num += w * (c > 0.f ? c : 0.f);  // NaN (a non-finite pose) counts as 0
      den += w;
    }
    const double mean = den > 0.0 ? num / den : 0.0;
    weights[i] = float(1.0 - std::exp(-mean / double(g.references[i])));
  }
}

// exp(x) for the fine-scale modulation's stretched side (x <= 0): Cephes' expf (range
// reduction by ln 2 in two parts, a degree-6 polynomial, 2^n from the exponent bits), about
// 1 ulp, x below -87 taken as -87. One sequence of operations for the scalar and the SSE2
// form, so a probe gets the same bits in either (and so with any split of the points).
constexpr float kExpLog2e = 1.44269504088896341f, kExpC1 = 0.693359375f, kExpC2 = -2.12194440e-4f;
constexpr float kExpP[6] = {1.9875691500e-4f, 1.3981999507e-3f, 8.3334519073e-3f,
                            4.1665795894e-2f, 1.6666665459e-1f, 5.0000001201e-1f};
inline float ExpNonPositive(float x) {
  x = x > -87.f ? x : -87.f;
  const float nf = std::nearbyint(x * kExpLog2e);
  const float r = (x - nf * kExpC1) - nf * kExpC2;
  const float z = r * r;
  float y = kExpP[0];
  for (int k = 1; k < 6; ++k) y = y * r + kExpP[k];
  y = (y * z + r) + 1.f;
  const uint32_t bits = uint32_t(int32_t(nf) + 127) << 23;
  float p;
  std::memcpy(&p, &bits, 4);
  return y * p;
}
#if defined(__SSE2__)
inline __m128 ExpNonPositive4(__m128 x) {
  x = _mm_max_ps(x, _mm_set1_ps(-87.f));
  const __m128i n = _mm_cvtps_epi32(_mm_mul_ps(x, _mm_set1_ps(kExpLog2e)));  // nearest, as nearbyint
  const __m128 nf = _mm_cvtepi32_ps(n);
  const __m128 r = _mm_sub_ps(_mm_sub_ps(x, _mm_mul_ps(nf, _mm_set1_ps(kExpC1))), _mm_mul_ps(nf, _mm_set1_ps(kExpC2)));
  const __m128 z = _mm_mul_ps(r, r);
  __m128 y = _mm_set1_ps(kExpP[0]);
  for (int k = 1; k < 6; ++k) y = _mm_add_ps(_mm_mul_ps(y, r), _mm_set1_ps(kExpP[k]));
  y = _mm_add_ps(_mm_add_ps(_mm_mul_ps(y, z), r), _mm_set1_ps(1.f));
  const __m128 p = _mm_castsi128_ps(_mm_slli_epi32(_mm_add_epi32(n, _mm_set1_epi32(127)), 23));
  return _mm_mul_ps(y, p);
}
#endif

#if MIMETIC_RUNTIME_AVX
// ExpNonPositive4 on eight lanes with AVX (no AVX2: the exponent bits go through the two SSE2
// halves; no FMA: nothing is contracted), so each lane gets ExpNonPositive's bits.
__attribute__((target("avx"))) inline __m256 ExpNonPositive8(__m256 x) {
  x = _mm256_max_ps(x, _mm256_set1_ps(-87.f));
  const __m256i n = _mm256_cvtps_epi32(_mm256_mul_ps(x, _mm256_set1_ps(kExpLog2e)));
  const __m256 nf = _mm256_cvtepi32_ps(n);
  const __m256 r = _mm256_sub_ps(_mm256_sub_ps(x, _mm256_mul_ps(nf, _mm256_set1_ps(kExpC1))),
                                 _mm256_mul_ps(nf, _mm256_set1_ps(kExpC2)));
  const __m256 z = _mm256_mul_ps(r, r);
  __m256 y = _mm256_set1_ps(kExpP[0]);
  for (int k = 1; k < 6; ++k) y = _mm256_add_ps(_mm256_mul_ps(y, r), _mm256_set1_ps(kExpP[k]));
  y = _mm256_add_ps(_mm256_add_ps(_mm256_mul_ps(y, z), r), _mm256_set1_ps(1.f));
  const __m128i bias = _mm_set1_epi32(127);
  const __m128i lo = _mm_slli_epi32(_mm_add_epi32(_mm256_castsi256_si128(n), bias), 23);
  const __m128i hi = _mm_slli_epi32(_mm_add_epi32(_mm256_extractf128_si256(n, 1), bias), 23);
  const __m256 p = _mm256_castsi256_ps(_mm256_insertf128_si256(_mm256_castsi128_si256(lo), hi, 1));
  return _mm256_mul_ps(y, p);
}

// A parameter kind of two consecutive blocks (q and q + 7 kFineProbeBlock), and an edge
// slot's lengths of two blocks (e and e + 4 kFineProbeBlock).
__attribute__((target("avx"))) inline __m256 FineParams8(const float* q) {
  constexpr uint32_t B = RigTables::kFineProbeBlock;
  return _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_loadu_ps(q)), _mm_loadu_ps(q + 7 * B), 1);
}
__attribute__((target("avx"))) inline __m256 FineLengths8(const float* lengths, const uint32_t* e) {
  constexpr uint32_t B = RigTables::kFineProbeBlock;
  return _mm256_setr_ps(lengths[e[0]], lengths[e[1]], lengths[e[2]], lengths[e[3]],
                        lengths[e[4 * B]], lengths[e[4 * B + 1]], lengths[e[4 * B + 2]],
                        lengths[e[4 * B + 3]]);
}

// Two blocks of fine-scale probes at a time (block k in the low half, k + 1 in the high one):
// the SSE2 block form of StageFineScale on eight lanes, the same operations per lane. From i
// (a multiple of kFineProbeBlock) while i + 2 kFineProbeBlock <= end; returns where it stopped.
__attribute__((target("avx"))) uint32_t FineProbeBlocksAvx(const float* lengths,
                                                           const uint32_t* edges,
                                                           const float* params, float r, float c,
                                                           uint32_t i, uint32_t end, float* out) {
  constexpr uint32_t B = RigTables::kFineProbeBlock;
  const __m256 one = _mm256_set1_ps(1.f), zero = _mm256_setzero_ps(), vr = _mm256_set1_ps(r);
  const __m256 vc = _mm256_set1_ps(c), one_r = _mm256_set1_ps(1.f - r);
  // In runs of up to kRun eight-probe groups: first s, written out as M(s) where s >= 0 and
  // as s itself where it is negative (M >= 0 there, so the sign tells them apart), listing the
  // groups with a negative lane without a branch; then M(s) = r exp(c s) on the listed groups
  // only (about half of them in a moving face, and no mispredicted branch a group).
  constexpr uint32_t kRun = 64;
  uint32_t listed[kRun];
  while (i + 2 * B <= end) {
    uint32_t count = 0;
    const uint32_t run_end = std::min(end, i + kRun * 2 * B);
    for (; i + 2 * B <= run_end; i += 2 * B) {
      const uint32_t* eb = edges + (i / B) * 4 * B;
      const float* qb = params + (i / B) * 7 * B;
      __m256 side[2];
      for (uint32_t j = 0; j < 2; ++j) {
        const __m256 l2 = FineLengths8(lengths, eb + 2 * j * B);
        const __m256 l3 = FineLengths8(lengths, eb + (2 * j + 1) * B);
        const __m256 beta = FineParams8(qb + 3 * j * B), r2 = FineParams8(qb + (3 * j + 1) * B);
        const __m256 r3 = FineParams8(qb + (3 * j + 2) * B);
        const __m256 den = _mm256_add_ps(_mm256_mul_ps(_mm256_sub_ps(one, beta), _mm256_mul_ps(l3, r2)),
                                         _mm256_mul_ps(beta, _mm256_mul_ps(l2, r3)));
        const __m256 ratio = _mm256_and_ps(_mm256_cmp_ps(den, zero, _CMP_GT_OQ),
                                           _mm256_div_ps(_mm256_mul_ps(l2, l3), den));
        const __m256 rest = _mm256_and_ps(_mm256_cmp_ps(l2, r2, _CMP_EQ_OQ), _mm256_cmp_ps(l3, r3, _CMP_EQ_OQ));
        side[j] = _mm256_andnot_ps(rest, _mm256_sub_ps(one, ratio));
      }
      __m256 s = _mm256_mul_ps(_mm256_add_ps(side[0], side[1]), FineParams8(qb + 6 * B));
      s = _mm256_and_ps(s, _mm256_cmp_ps(s, s, _CMP_EQ_OQ));  // NaN -> 0
      const __m256 pos = _mm256_cmp_ps(s, zero, _CMP_GE_OQ);
      const __m256 mp = _mm256_add_ps(_mm256_mul_ps(one_r, _mm256_min_ps(s, one)), vr);
      _mm256_storeu_ps(out + i, _mm256_or_ps(_mm256_and_ps(pos, mp), _mm256_andnot_ps(pos, s)));
      listed[count] = i;
      count += _mm256_movemask_ps(pos) != 0xFF;
    }
    for (uint32_t k = 0; k < count; ++k) {
      float* o = out + listed[k];
      const __m256 s = _mm256_loadu_ps(o);
      const __m256 neg = _mm256_cmp_ps(s, zero, _CMP_LT_OQ);
      const __m256 mn = r > 0.f ? _mm256_mul_ps(vr, ExpNonPositive8(_mm256_mul_ps(vc, s))) : zero;
      _mm256_storeu_ps(o, _mm256_or_ps(_mm256_and_ps(neg, mn), _mm256_andnot_ps(neg, s)));
    }
  }
  return i;
}
#endif

// One fine-scale probe's amplitude M(s) (docs/model.md §23) from the blocked tables
// (RigTables::fine_probe_edges / fine_probe_params: `e` and `q` point at its lane, slots
// kFineProbeBlock apart): s per side as SideShrinkageFromLengths, the sides' mean, then
// DirectionalModulation with ExpNonPositive for the stretched side. `c` = 1/r - 1.
inline float FineProbeAmplitude(const float* lengths, const uint32_t* e, const float* q, float r,
                                float c) {
  constexpr uint32_t B = RigTables::kFineProbeBlock;
  float side[2];
  for (uint32_t j = 0; j < 2; ++j) {
    const float l2 = lengths[e[2 * j * B]], l3 = lengths[e[(2 * j + 1) * B]];
    const float beta = q[3 * j * B], r2 = q[(3 * j + 1) * B], r3 = q[(3 * j + 2) * B];
    const float den = (1.f - beta) * (l3 * r2) + beta * (l2 * r3);
    const float ratio = den > 0.f ? (l2 * l3) / den : 0.f;
    side[j] = l2 == r2 && l3 == r3 ? 0.f : 1.f - ratio;
  }
  float s = (side[0] + side[1]) * q[6 * B];
  if (s != s) s = 0.f;
  if (s >= 0.f) return (1.f - r) * (s < 1.f ? s : 1.f) + r;
  return r > 0.f ? r * ExpNonPositive(c * s) : 0.f;
}

// docs/model.md §23: the fine-scale probes' edge lengths on X1 (each edge once, with the
// strain's edges: the probes read most of them and StageStrain then skips its pass), then per
// probe s across its field and M(s) (FineProbeAmplitude), eight probes at a time with AVX
// (FineProbeBlocksAvx, where the CPU has it) or four in SSE2 lanes where whole blocks lie in
// the range (the same operations: the same bits as the scalar form, whatever the split).
// Each edge and each point writes its own values only.
void StageFineScale(const FrameState& f) {
  const RigFineScale& fs = f.rig.fine_scale();
  const uint32_t* pairs = f.tables.edge_pairs.data();
  const uint32_t* fine_pairs = f.tables.fine_edge_pairs.data();
  const uint32_t strain_edges = f.tables.edge_count();
  float* lengths = f.edge_lengths;
  const float3* x = f.points;
  // The strain's edges and the probes' own ones, as one range (the strain's come first).
  ParallelFor(f.job, strain_edges + f.tables.fine_edge_count(), [&](uint32_t b, uint32_t e) {
    if (b < strain_edges) EdgeLengths(x, pairs, b, std::min(e, strain_edges), lengths);
    if (e > strain_edges) {
      const uint32_t fb = b > strain_edges ? b - strain_edges : 0u;
      EdgeLengths(x, fine_pairs, fb, e - strain_edges, lengths + strain_edges);
    }
  });
  constexpr uint32_t B = RigTables::kFineProbeBlock;
  const uint32_t* edges = f.tables.fine_probe_edges.data();
  const float* params = f.tables.fine_probe_params.data();
  const float r = std::clamp(fs.rest_amplitude, 0.f, 1.f);  // as DirectionalModulation
  const float c = r > 0.f ? 1.f / r - 1.f : 0.f;
  float* out = f.fine;
  ParallelFor(f.job, fs.point_count(), [&](uint32_t b, uint32_t e) {
    auto scalar = [&](uint32_t i) {
      out[i] = FineProbeAmplitude(lengths, edges + (i / B) * 4 * B + i % B,
                                  params + (i / B) * 7 * B + i % B, r, c);
    };
    uint32_t i = 2 * b;
#if defined(__SSE2__)
    static_assert(B == 4, "one SSE2 register a block");
    for (; i < 2 * e && i % B != 0; ++i) scalar(i);
    // Whole blocks from i (a multiple of B) while i + B <= end; returns where it stopped. As
    // FineProbeBlocksAvx: s first for runs of up to kRun blocks (M(s) where s >= 0, s itself
    // where it is negative, the blocks with a negative lane listed), then the exponential on
    // the listed blocks only.
    auto sse_blocks = [&](uint32_t i, uint32_t end) {
      const __m128 one = _mm_set1_ps(1.f), zero = _mm_setzero_ps(), vr = _mm_set1_ps(r);
      const __m128 vc = _mm_set1_ps(c), one_r = _mm_set1_ps(1.f - r);
      constexpr uint32_t kRun = 64;
      uint32_t listed[kRun];
      while (i + B <= end) {
        uint32_t count = 0;
        const uint32_t run_end = std::min(end, i + kRun * B);
        for (; i + B <= run_end; i += B) {
          const uint32_t* eb = edges + (i / B) * 4 * B;
          const float* qb = params + (i / B) * 7 * B;
          __m128 side[2];
          for (uint32_t j = 0; j < 2; ++j) {
            const uint32_t* e2 = eb + 2 * j * B;
            const uint32_t* e3 = eb + (2 * j + 1) * B;
            const __m128 l2 = _mm_setr_ps(lengths[e2[0]], lengths[e2[1]], lengths[e2[2]], lengths[e2[3]]);
            const __m128 l3 = _mm_setr_ps(lengths[e3[0]], lengths[e3[1]], lengths[e3[2]], lengths[e3[3]]);
            const __m128 beta = _mm_loadu_ps(qb + 3 * j * B), r2 = _mm_loadu_ps(qb + (3 * j + 1) * B);
            const __m128 r3 = _mm_loadu_ps(qb + (3 * j + 2) * B);
            const __m128 den = _mm_add_ps(_mm_mul_ps(_mm_sub_ps(one, beta), _mm_mul_ps(l3, r2)),
                                          _mm_mul_ps(beta, _mm_mul_ps(l2, r3)));
            const __m128 ratio = _mm_and_ps(_mm_cmpgt_ps(den, zero), _mm_div_ps(_mm_mul_ps(l2, l3), den));
            const __m128 rest = _mm_and_ps(_mm_cmpeq_ps(l2, r2), _mm_cmpeq_ps(l3, r3));
            side[j] = _mm_andnot_ps(rest, _mm_sub_ps(one, ratio));
          }
          __m128 s = _mm_mul_ps(_mm_add_ps(side[0], side[1]), _mm_loadu_ps(qb + 6 * B));
          s = _mm_and_ps(s, _mm_cmpeq_ps(s, s));  // NaN -> 0
          const __m128 pos = _mm_cmpge_ps(s, zero);
          const __m128 mp = _mm_add_ps(_mm_mul_ps(one_r, _mm_min_ps(s, one)), vr);
          _mm_storeu_ps(out + i, _mm_or_ps(_mm_and_ps(pos, mp), _mm_andnot_ps(pos, s)));
          listed[count] = i;
          count += _mm_movemask_ps(pos) != 0xF;
        }
        for (uint32_t k = 0; k < count; ++k) {
          float* o = out + listed[k];
          const __m128 s = _mm_loadu_ps(o);
          const __m128 neg = _mm_cmplt_ps(s, zero);
          const __m128 mn = r > 0.f ? _mm_mul_ps(vr, ExpNonPositive4(_mm_mul_ps(vc, s))) : zero;
          _mm_storeu_ps(o, _mm_or_ps(_mm_and_ps(neg, mn), _mm_andnot_ps(neg, s)));
        }
      }
      return i;
    };
#if MIMETIC_RUNTIME_AVX
    if (CpuHasAvx()) i = FineProbeBlocksAvx(lengths, edges, params, r, c, i, 2 * e, out);
#endif
    i = sse_blocks(i, 2 * e);
#endif
    for (; i < 2 * e; ++i) scalar(i);
  });
}

// Face normals of the final points (the per-point gather happens in StageOutputs).
void StageNormals(const FrameState& f) { FaceNormalsOfActive(f, false); }

// Output: positions scattered to the file's vertex layout; normals gathered per vertex from
// the face normals where they can change (a seam vertex repeats its point's gather: the same
// bits), the rest normals elsewhere. One pass instead of gather + scatter.
void StageOutputs(const FrameState& f) {
  const Rig& r = f.rig;
  const EvaluateJob& job = f.job;
  const uint32_t* off = f.point_tri_offsets;
  const uint32_t* tri = f.point_tris;
  const float4* faces = f.faces;
  const span<const float3> points(f.points, r.point_count());
  ParallelFor(job, r.vertex_count(), [&](uint32_t b, uint32_t e) {
    Scatter(points, r.vertex_points(), job.out_positions, job.out_positions_stride, b, e);
    if (!job.out_tension.empty()) {
      const size_t stride = job.out_tension_stride / 4;
      for (uint32_t v = b; v < e; ++v) {
        const uint32_t p = r.vertex_points()[v];
        float* o = job.out_tension.data() + v * stride;
        o[0] = f.ratios[p];
        o[1] = f.compressions[p];
      }
    }
    if (!job.out_fine_amplitudes.empty()) {
      const size_t stride = job.out_fine_amplitudes_stride / 4;
      for (uint32_t v = b; v < e; ++v) {
        const uint32_t p = r.vertex_points()[v];
        float* o = job.out_fine_amplitudes.data() + v * stride;
        o[0] = f.fine[2 * size_t(p)];
        o[1] = f.fine[2 * size_t(p) + 1];
      }
    }
    if (!f.normals) return;
    const size_t stride = job.out_normals_stride / 4;
    const uint32_t normal_points = r.normal_point_count();
    const float3* rest_normals = f.tables.rest_point_normals.data();
    for (uint32_t v = b; v < e; ++v) {
      const uint32_t p = r.vertex_points()[v];
      const float3 n = p < normal_points ? UnitNormal(GatherFaces4(off, tri, faces, p))
                                         : rest_normals[p];
      float* o = job.out_normals.data() + v * stride;
      o[0] = n.x;
      o[1] = n.y;
      o[2] = n.z;
    }
  });
}

}  // namespace

bool EvaluateJob::Run() const {
  if (!Validate()) return false;
  EvaluateContext& ctx = *context;
  const Rig& r = *rig;
  const RigTables& t = r.tables();
  SanitizeActivations(activations.first(r.muscle_count()), ctx.activations_);
  for (const RigMuscleWrinkles& w : r.muscle_wrinkles())  // docs/model.md §6: G = 1 ungated
    ctx.wrinkle_gates_[w.muscle] = WrinkleGate(ctx.activations_[w.muscle], w.gate);
  ctx.jaw_ = jaw >= 0.f ? (jaw <= 1.f ? jaw : 1.f) : 0.f;  // NaN -> 0
  FrameState f{
      .job = *this,
      .rig = r,
      .tables = t,
      .thickness = layers.thickness && r.layers().thickness,
      .muscle_wrinkles =
          layers.muscle_wrinkles && r.layers().muscle_wrinkles && !t.row_profiles.empty(),
      .curve_wrinkles =
          layers.curve_wrinkles && r.layers().curve_wrinkles && r.curve_wrinkles().row_count() > 0,
      .normals = !out_normals.empty(),
      .tension = !out_tension.empty() || (!out_region_weights.empty() && r.tension_region_count() > 0),
      .tension_eps = !out_tension.empty() && !t.row_profiles.empty(),
      .edges = false,
      .compressions = ctx.point_compressions_.data(),
      .fine = ctx.point_fine_.data(),
      .activations = ctx.activations_.data(),
      .wrinkle_gates = ctx.wrinkle_gates_.data(),
      .base = r.rest_points().data(),
      .points = ctx.points_.data(),  // padded (face_kernels.h)
      .faces = ctx.faces_.data(),
      .ratios = ctx.point_ratios_.data(),
      .sums = ctx.point_sums_.data(),
      .edge_lengths = ctx.edge_lengths_.data(),
      .wrinkle_offsets = ctx.wrinkle_offsets_.data(),
      .limit_folds = false,
      .thickness_a = ctx.thickness_a_.data(),
      .thickness_b = ctx.thickness_b_.data(),
      .skin_base = ctx.skin_base_.data(),
      .skin_full = ctx.skin_full_.data(),
      .limit_levels = ctx.limit_levels_.data(),
      .fold_limits = ctx.fold_limits_.data(),
      .limit_flags = ctx.limit_flags_.data(),
      .slope_min_bounds = ctx.slope_min_bounds_.data(),
      .limit_edge_lengths = ctx.limit_edge_lengths_.data(),
      .limit_moved = ctx.limit_moved_.data(),
      .limit_flagged = ctx.limit_flagged_.data(),
      .limit_recheck = ctx.limit_recheck_.data(),
      .limit_tris = ctx.limit_tris_.data(),
      .limit_point_marks = ctx.limit_point_marks_.data(),
      .limit_tri_marks = ctx.limit_tri_marks_.data(),
      .limit_tri_bad = ctx.limit_tri_bad_.data(),
      .point_tri_offsets = r.point_triangle_offsets().data(),
      .point_tris = r.point_triangles().data(),
  };
  f.limit_folds = limit_folds && f.skin();
  f.edges = f.wrinkles() || f.tension_eps;
  // r of X1 for the tension outputs needs the rest areas (every rig with a skin layer or a
  // tension region keeps them; Rig::Build checked their size then).
  const bool tension_strain = f.tension && !f.skin() && r.triangle_count() > 0 &&
                              r.rest_triangle_areas().size() >= r.triangle_count();
  ctx.limited_points_ = ctx.limiter_passes_ = 0;
  StageMuscles(f);
  if (ctx.jaw_ > 0.f && !r.jaw().empty()) StageJaw(f, ctx.jaw_);
  if (!r.eyes().empty()) StageEyes(f);
  if (!out_fine_amplitudes.empty() && !r.fine_scale().empty()) {
    StageFineScale(f);  // on X1
    f.edges = false;    // it measured the strain's edges on X1 too: StageStrain has them
  }
  bool faces_current = false;
  if (f.skin()) {
    StageStrain(f);
    StageDisplace(f);
    if (f.limit_folds) faces_current = StageLimit(f, &ctx.limited_points_, &ctx.limiter_passes_);
  } else if (tension_strain) {
    StageStrain(f);  // (StageNormals recomputes the output normals: the bits of a frame without)
    GatherRatios(f);
  } else {
    std::fill(f.ratios, f.ratios + r.active_point_count(), 1.f);  // r = 1: no skin layer ran
  }
  if (f.tension) StageTension(f);
  if (f.normals && !faces_current) StageNormals(f);
  StageOutputs(f);
  return true;
}

}  // namespace mimetic

#include "rig/runtime/evaluate_job.h"

#include <algorithm>
#include <cmath>

#include "expressions/runtime/activations.h"
#include "rig/runtime/face_kernels.h"
#include "wrinkles/runtime/profiles.h"
#include "wrinkles/runtime/strain_jobs.h"
#include "wrinkles/runtime/thickness_job.h"
#include "wrinkles/runtime/wrinkle_jobs.h"

namespace mimetic {

void EvaluateContext::Resize(const Rig& rig) {
  rig_uid_ = rig.uid();
  point_count_ = rig.point_count();
  triangle_count_ = rig.triangle_count();
  muscle_count_ = rig.muscle_count();
  const RigTables& t = rig.tables();
  activations_.assign(muscle_count_, 0.f);
  // One float3 of padding covers kPointPadFloats.
  static_assert(kPointPadFloats <= 3, "pad points_ by more than one float3");
  points_.assign(point_count_ + 1, float3{});
  faces_.assign(triangle_count_, float4{});
  point_ratios_.assign(point_count_, 1.f);
  point_sums_.assign(point_count_, float4{});
  edge_lengths_.assign(t.edge_count(), 0.f);
  wrinkle_offsets_.assign(point_count_, 0.f);
  if (!rig.tables_checked()) return;  // IsFor refuses it; nothing below is safe to read
  // Rest values everywhere: a frame rewrites only the leading ranges that can change
  // (Rig::active()); the rest keep these.
  std::copy(rig.rest_points().begin(), rig.rest_points().end(), points_.begin());
  std::copy(t.rest_faces.begin(), t.rest_faces.end(), faces_.begin());
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
  return sizeof(EvaluateContext) + Bytes(activations_) + Bytes(points_) + Bytes(faces_) +
         Bytes(point_ratios_) + Bytes(point_sums_) + Bytes(edge_lengths_) +
         Bytes(wrinkle_offsets_);
}

size_t RequiredFloats(size_t count, size_t stride_bytes) {
  return count == 0 ? 0 : (count - 1) * (stride_bytes / 4) + 3;
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
  return true;
}

namespace {

// Runs `fn(begin, end)` over [0, count) through the caller's scheduler, or serially.
template <class Fn>
void ParallelFor(const EvaluateJob& job, uint32_t count, const Fn& fn) {
  if (count == 0) return;
  if (!job.parallel_for) {
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
  const float* activations;        // #muscles, sanitised
  const float3* base;              // #P: the pose the muscles add to (the rest pose)
  float3* points;                  // #P + pad: X1, then X3 (context)
  float4* faces;                   // #T face slots (context)
  float* ratios;                   // #P area ratios (context)
  float4* sums;                    // #P gathered face slots (context)
  float* edge_lengths;             // RigTables::edge_count() (context)
  float* wrinkle_offsets;          // #P (context)
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

// The strain of X1 against the rest pose (docs/model.md §4-5): face normals and triangle area
// ratios of X1, and the lengths of the edges the strain measures read (compression eps per
// wrinkled-muscle row, 001 eq. 9-10, and shrinkage s per curve-wrinkle entry, 000 eq. 4, are
// computed from them where StageDisplace needs them). All read X1, so they run before
// anything moves.
void StageStrain(const FrameState& f) {
  FaceNormalsOfActive(f, true);
  if (f.wrinkles()) {
    const float3* points = f.points;
    const uint32_t* pairs = f.tables.edge_pairs.data();
    float* lengths = f.edge_lengths;
    ParallelFor(f.job, f.tables.edge_count(), [&](uint32_t b, uint32_t e) {
      EdgeLengths(points, pairs, b, e, lengths);
    });
  }
}

// Per point: N1 and r from its triangles (docs/model.md §1 step 2, §4), then one displacement
// along N1 (docs/model.md §4, §6-8): the volume-preserving thickness (1/r - 1) h, its
// muscle-wrinkle rows H At A(eps) in rig order, its curve wrinkles S(l) M. Three sweeps: the
// gathers alone (independent load chains that overlap), the wrinkle sums of the points that
// have any, then four points at a time share the square root and the divisions. Each point
// reads only its own values and the face slots of X1, so it moves in place.
void StageDisplace(const FrameState& f) {
  const Rig& r = f.rig;
  const RigTables& t = f.tables;
  const uint32_t* off = f.point_tri_offsets;
  const uint32_t* tri = f.point_tris;
  const float4* faces = f.faces;
  float4* sums = f.sums;
  ParallelFor(f.job, r.active_point_count(), [&](uint32_t b, uint32_t e) {
    float* ratios = f.ratios;
    for (uint32_t p = b; p < e; ++p) {
      sums[p] = GatherFaces4(off, tri, faces, p);
      ratios[p] = PointRatio(sums[p], off[p + 1] - off[p]);
    }
  });
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
            // 001 eq. 9-10: eps = sum_j c_j (L_j - l_j); eq. 4: W = H(w_i) A(eps) At_i
            // (docs/model.md §5-6).
            float eps = 0.f;
            for (uint32_t k = row_entries[row]; k < row_entries[row + 1]; ++k)
              eps += coeffs[k] * (rest[k] - length[edges[k]]);
            d += profiles[row] * Anisotropy(eps);
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
  ParallelFor(f.job, r.active_point_count(), [&](uint32_t b, uint32_t e) {
    DisplaceAlongNormals(sums, f.ratios, h, r.min_area_ratio(), extra, b, e, f.points);
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
  const FrameState f{
      .job = *this,
      .rig = r,
      .tables = t,
      .thickness = layers.thickness && r.layers().thickness,
      .muscle_wrinkles =
          layers.muscle_wrinkles && r.layers().muscle_wrinkles && !t.row_profiles.empty(),
      .curve_wrinkles =
          layers.curve_wrinkles && r.layers().curve_wrinkles && r.curve_wrinkles().row_count() > 0,
      .normals = !out_normals.empty(),
      .activations = ctx.activations_.data(),
      .base = r.rest_points().data(),
      .points = ctx.points_.data(),  // padded (face_kernels.h)
      .faces = ctx.faces_.data(),
      .ratios = ctx.point_ratios_.data(),
      .sums = ctx.point_sums_.data(),
      .edge_lengths = ctx.edge_lengths_.data(),
      .wrinkle_offsets = ctx.wrinkle_offsets_.data(),
      .point_tri_offsets = r.point_triangle_offsets().data(),
      .point_tris = r.point_triangles().data(),
  };
  StageMuscles(f);
  if (f.skin()) {
    StageStrain(f);
    StageDisplace(f);
  } else {
    std::fill(f.ratios, f.ratios + r.active_point_count(), 1.f);  // r = 1: no skin layer ran
  }
  if (f.normals) StageNormals(f);
  StageOutputs(f);
  return true;
}

}  // namespace mimetic

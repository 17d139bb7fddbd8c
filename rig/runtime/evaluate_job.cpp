#include "rig/runtime/evaluate_job.h"

#include <algorithm>

#include <unordered_map>

#include "expressions/runtime/activations.h"
#include "rig/runtime/face_kernels.h"
#include "wrinkles/runtime/profiles.h"
#include "wrinkles/runtime/strain_jobs.h"
#include "wrinkles/runtime/thickness_job.h"
#include "wrinkles/runtime/wrinkle_jobs.h"

namespace mimetic {

void EvaluateContext::Resize(const Rig& rig) {
  rig_uid_ = rig.uid;
  point_count_ = rig.point_count();
  triangle_count_ = rig.triangle_count();
  muscle_count_ = rig.muscle_count();
  activations_.assign(muscle_count_, 0.f);
  // One float3 of padding covers kPointPadFloats.
  static_assert(kPointPadFloats <= 3, "pad points_ by more than one float3");
  points_.assign(point_count_ + 1, float3{});
  faces_.assign(triangle_count_, float4{});
  point_normals_.assign(point_count_, float3{});
  point_ratios_.assign(point_count_, 1.f);
  point_sums_.assign(point_count_, float4{});
  tables_valid_ = CheckTables(rig);
  if (!tables_valid_) return;
  BuildStrainTables(rig);
  // Rest values everywhere: a frame rewrites only the leading ranges that can change
  // (Rig::active_point_count and friends); the rest keep these.
  std::copy(rig.rest_points.begin(), rig.rest_points.end(), points_.begin());
  FaceNormals4(points_.data(), rig.triangles.data(), 0, triangle_count_, nullptr, faces_.data());
  for (uint32_t p = 0; p < point_count_; ++p)
    point_normals_[p] = UnitNormal(GatherFaces4(rig.point_triangle_offsets.data(),
                                                rig.point_triangles.data(), faces_.data(), p));
}

// The fused strain and displacement tables (see the members): edges read by the compression
// rows and the shrinkage probes, each once; per-row coefficients; per-point row lists.
void EvaluateContext::BuildStrainTables(const Rig& r) {
  std::unordered_map<uint64_t, uint32_t> edge_ids;
  edge_pairs_.clear();
  auto edge = [&](uint32_t a, uint32_t b) {
    if (a > b) std::swap(a, b);
    const uint64_t key = (uint64_t(a) << 32) | b;
    auto [it, added] = edge_ids.emplace(key, uint32_t(edge_pairs_.size() / 2));
    if (added) {
      edge_pairs_.push_back(a);
      edge_pairs_.push_back(b);
    }
    return it->second;
  };
  // Muscle-wrinkle rows, point-major: a point's rows are contiguous (in rig order among
  // themselves, so its sum adds them in the order MuscleWrinkleJob would), and so are their
  // entries.
  const uint32_t active = r.active_point_count;
  struct RowRef {
    const RigMuscleWrinkles* table;
    uint32_t index;
  };
  std::vector<std::vector<RowRef>> rows_of(active);
  std::vector<std::vector<uint32_t>> curves_of(active);
  for (const RigMuscleWrinkles& w : r.muscle_wrinkles)
    for (uint32_t i = 0; i < w.row_count(); ++i) rows_of[w.points[i]].push_back({&w, i});
  row_offsets_.assign(1, 0u);
  entry_edges_.clear();
  entry_rest_.clear();
  entry_coeffs_.clear();
  row_profiles_.clear();
  point_row_offsets_.assign(1, 0u);
  for (uint32_t p = 0; p < active; ++p) {
    for (const RowRef& ref : rows_of[p]) {
      const RigMuscleWrinkles& w = *ref.table;
      const uint32_t i = ref.index;
      row_profiles_.push_back(w.profile.empty()
                                  ? MuscleWrinkleProfile(w.phase[i], w.half_cycle, w.furrow_depth,
                                                         w.shape, w.attenuation[i])
                                  : w.profile[i]);
      float weight_sum = 0.f;
      for (uint32_t k = w.edge_offsets[i]; k < w.edge_offsets[i + 1]; ++k)
        weight_sum += w.edge_weights[k];
      for (uint32_t k = w.edge_offsets[i]; k < w.edge_offsets[i + 1]; ++k) {
        const float rest = w.edge_rest_lengths[k];
        entry_edges_.push_back(edge(p, w.edge_neighbors[k]));
        entry_rest_.push_back(rest);
        // 001 eq. 9-10: eps = sum_j w_j (L_j - l_j) / L_j / sum_j w_j, as sum_j c_j (L_j - l_j)
        // (no division per frame; L_j - l_j is exactly 0 at rest, so is eps).
        entry_coeffs_.push_back(rest > 0.f && weight_sum > 0.f
                                    ? w.edge_weights[k] / (rest * weight_sum)
                                    : 0.f);
      }
      row_offsets_.push_back(uint32_t(entry_edges_.size()));
    }
    point_row_offsets_.push_back(uint32_t(row_profiles_.size()));
  }
  const RigCurveWrinkles& c = r.curve_wrinkles;
  probe_edges_.assign(4 * c.probes.size(), 0u);
  for (size_t k = 0; k < c.probes.size(); ++k) {
    const ShrinkageProbe& probe = c.probes[k];
    for (uint32_t s = 0; s < probe.side_count; ++s) {
      probe_edges_[4 * k + 2 * s] = edge(probe.point, probe.sides[s].v2);
      probe_edges_[4 * k + 2 * s + 1] = edge(probe.point, probe.sides[s].v3);
    }
  }
  for (uint32_t i = 0; i < c.row_count(); ++i) curves_of[c.points[i]].push_back(i);
  edge_lengths_.assign(edge_pairs_.size() / 2, 0.f);
  point_curve_offsets_.assign(1, 0u);
  point_curve_rows_.clear();
  for (const std::vector<uint32_t>& l : curves_of) {
    point_curve_rows_.insert(point_curve_rows_.end(), l.begin(), l.end());
    point_curve_offsets_.push_back(uint32_t(point_curve_rows_.size()));
  }
  wrinkle_points_.clear();
  for (uint32_t p = 0; p < active; ++p)
    if (!rows_of[p].empty() || !curves_of[p].empty()) wrinkle_points_.push_back(p);
  wrinkle_offsets_.assign(point_count_, 0.f);
}

// Every stage job over its full range, validated once, so that Run() needs no index checks.
bool EvaluateContext::CheckTables(const Rig& r) {
  const uint32_t points = r.point_count(), tris = r.triangle_count();
  if (r.vertex_points.size() != r.vertex_count()) return false;
  for (uint32_t p : r.vertex_points)
    if (p >= points) return false;
  for (uint32_t i : r.triangles)
    if (i >= points) return false;
  if (r.point_triangle_offsets.size() != size_t(points) + 1) return false;
  for (uint32_t p = 0; p < points; ++p)
    if (r.point_triangle_offsets[p] > r.point_triangle_offsets[p + 1]) return false;
  if (r.point_triangle_offsets[points] > r.point_triangles.size()) return false;
  for (uint32_t t : r.point_triangles)
    if (t >= tris) return false;
  // The ordering the per-frame ranges rely on (see Rig::active_point_count).
  const uint32_t n_active = r.active_point_count, n_normal = r.normal_point_count;
  const uint32_t t_active = r.active_triangle_count;
  if (n_active > n_normal || n_normal > points || t_active > tris) return false;
  for (uint32_t p = n_active; p < points; ++p)  // muscles move active points only
    if (r.muscles.offsets.size() == size_t(points) + 1 &&
        r.muscles.offsets[p + 1] != r.muscles.offsets[p])
      return false;
  for (uint32_t t = 0; t < tris; ++t) {
    const uint32_t* c = &r.triangles[3 * t];
    const bool active = c[0] < n_active || c[1] < n_active || c[2] < n_active;
    if (active && t >= t_active) return false;  // its normal would be missed
  }
  for (uint32_t p = n_normal; p < points; ++p)  // static points see static triangles only
    for (uint32_t k = r.point_triangle_offsets[p]; k < r.point_triangle_offsets[p + 1]; ++k)
      if (r.point_triangles[k] < t_active) return false;
  for (const RigMuscleWrinkles& w : r.muscle_wrinkles)
    for (uint32_t p : w.points)
      if (p >= n_active) return false;
  for (uint32_t p : r.curve_wrinkles.points)
    if (p >= n_active) return false;
  if (MuscleDeformJob{&r.muscles, activations_, r.rest_points, points_, 0, points}.Validate() ==
      false)
    return false;
  for (const MuscleInfluence& e : r.muscles.entries)
    if (e.muscle >= r.muscle_count()) return false;
  const bool skin = r.layers.thickness || r.layers.muscle_wrinkles || r.layers.curve_wrinkles;
  if (!skin) return true;
  if (r.rest_triangle_areas.size() < tris || r.point_thickness.size() < points) return false;
  // The stage jobs' own checks over full ranges (scratch outputs; positions and normals need
  // only the point count).
  const span<const float3> any_points = r.rest_points;
  std::vector<float3> scratch_points(points);
  for (const RigMuscleWrinkles& w : r.muscle_wrinkles) {
    std::vector<float> eps(w.row_count());
    EdgeCompressionJob e;
    e.positions = any_points;
    e.points = w.points;
    e.offsets = w.edge_offsets;
    e.neighbors = w.edge_neighbors;
    e.rest_lengths = w.edge_rest_lengths;
    e.weights = w.edge_weights;
    e.end = w.row_count();
    e.out_compression = eps;
    MuscleWrinkleJob wr;
    wr.normals = any_points;
    wr.points = w.points;
    wr.profile = w.profile;
    wr.phase = w.phase;
    wr.attenuation = w.attenuation;
    wr.half_cycle = w.half_cycle;
    wr.furrow_depth = w.furrow_depth;
    wr.shape = w.shape;
    wr.compression = eps;
    wr.end = w.row_count();
    wr.positions = scratch_points;
    if (!e.Validate() || !wr.Validate()) return false;
  }
  const RigCurveWrinkles& c = r.curve_wrinkles;
  if (!c.entries.empty() || c.row_count() > 0) {
    std::vector<float> s(c.probes.size()), ratios(points, 1.f);
    DirectionalShrinkageJob sj;
    sj.positions = any_points;
    sj.probes = c.probes;
    sj.end = c.probes.size();
    sj.out_shrinkage = s;
    CurveWrinkleJob cw;
    cw.normals = any_points;
    cw.wrinkles = c.wrinkles;
    cw.points = c.points;
    cw.offsets = c.offsets;
    cw.entries = c.entries;
    cw.entry_shrinkage = s;
    cw.area_ratios = ratios;
    cw.end = c.row_count();
    cw.positions = scratch_points;
    if (!sj.Validate() || !cw.Validate() || c.probes.size() != c.entries.size()) return false;
  }
  return true;
}

bool EvaluateContext::IsFor(const Rig& rig) const {
  return tables_valid_ && rig_uid_ == rig.uid && point_count_ == rig.point_count() &&
         triangle_count_ == rig.triangle_count() && muscle_count_ == rig.muscle_count();
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

// r of a point from its gathered slots (MODEL.md §4: the mean over its triangles; 1 for a
// point without any).
inline float PointRatio(const float4& sum, uint32_t count) {
  return count ? sum.w / float(count) : 1.f;
}

// One point of DisplaceAlongNormals (the scalar lane). The offset d = (1/rc - 1) h + extra
// (MODEL.md §4 with rc = max(r, r_min), plus the wrinkle sum) and the normalisation share one
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

}  // namespace

bool EvaluateJob::Run() const {
  if (!Validate()) return false;
  EvaluateContext& ctx = *context;
  const Rig& r = *rig;
  SanitizeActivations(activations.first(r.muscle_count()), ctx.activations_);
  const float3* points = ctx.points_.data();  // padded (face_kernels.h)
  float4* faces = ctx.faces_.data();
  const uint32_t* off = r.point_triangle_offsets.data();
  const uint32_t* tri = r.point_triangles.data();

  // 1. Muscles (MODEL.md §1 step 1): summed on the rest pose; only points that can move.
  ParallelFor(*this, r.active_point_count, [&](uint32_t b, uint32_t e) {
    MusclePoints(r.muscles, ctx.activations_.data(), r.rest_points.data(), b, e, ctx.points_.data());
  });

  const bool thickness = layers.thickness && r.layers.thickness;
  const bool muscle_wrinkles =
      layers.muscle_wrinkles && r.layers.muscle_wrinkles && !ctx.row_profiles_.empty();
  const bool curve_wrinkles =
      layers.curve_wrinkles && r.layers.curve_wrinkles && r.curve_wrinkles.row_count() > 0;
  const bool want_normals = !out_normals.empty();
  // Face normals of the current points, only for triangles touching a point that can move
  // (the others keep the rest face normals set when the context was sized); with `ratios`,
  // each triangle's area ratio in w (MODEL.md §4).
  auto face_normals = [&](bool ratios) {
    const float* rest = ratios ? r.rest_triangle_areas.data() : nullptr;
    ParallelFor(*this, r.active_triangle_count, [&](uint32_t b, uint32_t e) {
      FaceNormals4(points, r.triangles.data(), b, e, rest, faces);
    });
  };

  if (thickness || muscle_wrinkles || curve_wrinkles) {
    // 2. The strain of X1 against the rest pose (MODEL.md §4-5): face normals and triangle
    // area ratios of X1, and the lengths of the edges the strain measures read (compression
    // eps per wrinkled-muscle row, 001 eq. 9-10, and shrinkage s per curve-wrinkle entry,
    // 000 eq. 4, are computed from them where step 3 needs them). All read X1, so they run
    // before anything moves.
    face_normals(true);
    if (muscle_wrinkles || curve_wrinkles) {
      ParallelFor(*this, uint32_t(ctx.edge_lengths_.size()), [&](uint32_t b, uint32_t e) {
        EdgeLengths(points, ctx.edge_pairs_.data(), b, e, ctx.edge_lengths_.data());
      });
    }
    // 3. Per point: N1 and r from its triangles (MODEL.md §1 step 2, §4), then one
    // displacement along N1 (MODEL.md §4, §6-8): the volume-preserving thickness (1/r - 1) h,
    // its muscle-wrinkle rows H At A(eps) in rig order, its curve wrinkles S(l) M. Three
    // sweeps: the gathers alone (independent load chains that overlap), the wrinkle sums of
    // the points that have any, then four points at a time share the square root and the
    // divisions. Each point reads only its own values and the face slots of X1, so it moves
    // in place.
    float4* sums = ctx.point_sums_.data();
    ParallelFor(*this, r.active_point_count, [&](uint32_t b, uint32_t e) {
      float* ratios = ctx.point_ratios_.data();
      for (uint32_t p = b; p < e; ++p) {
        sums[p] = GatherFaces4(off, tri, faces, p);
        ratios[p] = PointRatio(sums[p], off[p + 1] - off[p]);
      }
    });
    const bool wrinkles = muscle_wrinkles || curve_wrinkles;
    if (wrinkles) {
      ParallelFor(*this, uint32_t(ctx.wrinkle_points_.size()), [&](uint32_t b, uint32_t e) {
        // Plain pointers: the stores to `offsets` cannot alias them in the compiler's eyes.
        const float* length = ctx.edge_lengths_.data();
        const uint32_t* wrinkle_points = ctx.wrinkle_points_.data();
        const uint32_t* point_rows = ctx.point_row_offsets_.data();
        const uint32_t* row_entries = ctx.row_offsets_.data();
        const uint32_t* edges = ctx.entry_edges_.data();
        const float* coeffs = ctx.entry_coeffs_.data();
        const float* rest = ctx.entry_rest_.data();
        const float* profiles = ctx.row_profiles_.data();
        const CurveWrinkleParams* params = r.curve_wrinkles.wrinkles.data();
        const CurveWrinkleEntry* entries = r.curve_wrinkles.entries.data();
        const ShrinkageProbe* probes = r.curve_wrinkles.probes.data();
        const uint32_t* probe_edges = ctx.probe_edges_.data();
        const uint32_t* curve_offsets = r.curve_wrinkles.offsets.data();
        const uint32_t* point_curves = ctx.point_curve_offsets_.data();
        const uint32_t* curve_rows = ctx.point_curve_rows_.data();
        const float* ratios = ctx.point_ratios_.data();
        float* offsets = ctx.wrinkle_offsets_.data();
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
              // (MODEL.md §5-6).
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
    ParallelFor(*this, r.active_point_count, [&](uint32_t b, uint32_t e) {
      DisplaceAlongNormals(sums, ctx.point_ratios_.data(),
                           thickness ? r.point_thickness.data() : nullptr, r.min_area_ratio,
                           wrinkles ? ctx.wrinkle_offsets_.data() : nullptr, b, e,
                           ctx.points_.data());
    });
    // 4. Face normals of X3 (the per-point gather happens in the output pass).
    if (want_normals) face_normals(false);
  } else {
    std::fill(ctx.point_ratios_.begin(), ctx.point_ratios_.begin() + r.active_point_count, 1.f);
    if (want_normals) face_normals(false);
  }

  // 5. Output: positions scattered to the file's vertex layout; normals gathered per vertex
  // from the face normals where they can change (a seam vertex repeats its point's gather:
  // the same bits), the rest normals elsewhere. One pass instead of gather + scatter.
  ParallelFor(*this, r.vertex_count(), [&](uint32_t b, uint32_t e) {
    Scatter(ctx.points_, r.vertex_points, out_positions, out_positions_stride, b, e);
    if (!want_normals) return;
    const size_t stride = out_normals_stride / 4;
    for (uint32_t v = b; v < e; ++v) {
      const uint32_t p = r.vertex_points[v];
      const float3 n = p < r.normal_point_count ? UnitNormal(GatherFaces4(off, tri, faces, p))
                                                : ctx.point_normals_[p];
      float* o = out_normals.data() + v * stride;
      o[0] = n.x;
      o[1] = n.y;
      o[2] = n.z;
    }
  });
  return true;
}

}  // namespace mimetic

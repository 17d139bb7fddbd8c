#include "rig/runtime/evaluate_job.h"

#include <algorithm>

#include "expressions/runtime/activations.h"
#include "rig/runtime/normals_job.h"
#include "wrinkles/runtime/thickness_job.h"

namespace mimetic {

void EvaluateContext::Resize(const Rig& rig) {
  rig_uid_ = rig.uid;
  point_count_ = rig.point_count();
  triangle_count_ = rig.triangle_count();
  muscle_count_ = rig.muscle_count();
  activations_.assign(muscle_count_, 0.f);
  points_.assign(point_count_, float3{});
  face_normals_.assign(triangle_count_, float3{});
  point_normals_.assign(point_count_, float3{});
  const bool skin = rig.layers.thickness || rig.layers.muscle_wrinkles || rig.layers.curve_wrinkles;
  normals1_.assign(skin ? point_count_ : 0, float3{});
  triangle_ratios_.assign(skin ? triangle_count_ : 0, 1.f);
  point_ratios_.assign(point_count_, 1.f);
  size_t rows = 0;
  for (const RigMuscleWrinkles& w : rig.muscle_wrinkles) rows += w.row_count();
  compression_.assign(rows, 0.f);
  shrinkage_.assign(rig.curve_wrinkles.entries.size(), 0.f);
  tables_valid_ = CheckTables(rig);
  if (!tables_valid_) return;
  // Rest values everywhere: a frame rewrites only the leading ranges that can change
  // (Rig::active_point_count and friends); the rest keep these.
  points_ = rig.rest_points;
  FaceNormalsJob faces;
  faces.points = points_;
  faces.triangles = rig.triangles;
  faces.out_face_normals = face_normals_;
  faces.end = triangle_count_;
  faces.Run();
  PointNormalsJob normals;
  normals.face_normals = face_normals_;
  normals.point_triangle_offsets = rig.point_triangle_offsets;
  normals.point_triangles = rig.point_triangles;
  normals.out_normals = point_normals_;
  normals.end = point_count_;
  normals.Run();
  if (skin) normals1_ = point_normals_;
}

// Every stage job over its full range, validated once; Run() then uses RunUnchecked().
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
  size_t row0 = 0;
  for (const RigMuscleWrinkles& w : r.muscle_wrinkles) {
    EdgeCompressionJob eps;
    eps.positions = points_;
    eps.points = w.points;
    eps.offsets = w.edge_offsets;
    eps.neighbors = w.edge_neighbors;
    eps.rest_lengths = w.edge_rest_lengths;
    eps.weights = w.edge_weights;
    eps.end = w.row_count();
    eps.out_compression = span<float>(compression_).subspan(row0, w.row_count());
    MuscleWrinkleJob wr;
    wr.normals = normals1_;
    wr.points = w.points;
    wr.profile = w.profile;
    wr.compression = eps.out_compression;
    wr.end = w.row_count();
    wr.positions = points_;
    if (!eps.Validate() || !wr.Validate()) return false;
    row0 += w.row_count();
  }
  const RigCurveWrinkles& c = r.curve_wrinkles;
  if (!c.entries.empty()) {
    DirectionalShrinkageJob s;
    s.positions = points_;
    s.probes = c.probes;
    s.end = c.probes.size();
    s.out_shrinkage = shrinkage_;
    CurveWrinkleJob cw;
    cw.normals = normals1_;
    cw.wrinkles = c.wrinkles;
    cw.points = c.points;
    cw.offsets = c.offsets;
    cw.entries = c.entries;
    cw.entry_shrinkage = shrinkage_;
    cw.area_ratios = point_ratios_;
    cw.end = c.row_count();
    cw.positions = points_;
    if (!s.Validate() || !cw.Validate() || c.probes.size() != c.entries.size()) return false;
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

}  // namespace

bool EvaluateJob::Run() const {
  if (!Validate()) return false;
  EvaluateContext& ctx = *context;
  const Rig& r = *rig;
  SanitizeActivations(activations.first(r.muscle_count()), ctx.activations_);

  // Normals of ctx.points_ into `out` (area-weighted, MODEL.md §1 steps 2 and 5); with
  // `ratios`, the area ratios r of MODEL.md §4 in the same two passes.
  // Face normals of the current points, only for triangles touching a point that can move
  // (the others keep the rest face normals set when the context was sized).
  auto face_normals = [&]() {
    ParallelFor(*this, r.active_triangle_count, [&](uint32_t b, uint32_t e) {
      FaceNormalsJob job;
      job.points = ctx.points_;
      job.triangles = r.triangles;
      job.out_face_normals = ctx.face_normals_;
      job.begin = b;
      job.end = e;
      job.Run();
    });
  };

  // 1. Muscles (MODEL.md §1 step 1): summed on the rest pose; only points that can move.
  ParallelFor(*this, r.active_point_count, [&](uint32_t b, uint32_t e) {
    MuscleDeformJob job;
    job.table = &r.muscles;
    job.activations = ctx.activations_;
    job.rest_points = r.rest_points;
    job.out_points = ctx.points_;
    job.begin = b;
    job.end = e;
    job.Run();
  });

  const bool thickness = layers.thickness && r.layers.thickness;
  const bool muscle_wrinkles = layers.muscle_wrinkles && r.layers.muscle_wrinkles;
  const bool curve_wrinkles = layers.curve_wrinkles && r.layers.curve_wrinkles;
  const bool want_normals = !out_normals.empty();

  if (thickness || muscle_wrinkles || curve_wrinkles) {
    // 2. The strain of X1 against the rest pose (MODEL.md §4-5): face normals and triangle
    // area ratios of X1, compression eps per wrinkled muscle and shrinkage s across each
    // curve wrinkle (these read X1, so they run before anything moves).
    const bool need_ratio = thickness || curve_wrinkles;
    ParallelFor(*this, r.active_triangle_count, [&](uint32_t b, uint32_t e) {
      FaceNormalsJob job;
      job.points = ctx.points_;
      job.triangles = r.triangles;
      job.out_face_normals = ctx.face_normals_;
      job.begin = b;
      job.end = e;
      if (need_ratio) {
        job.rest_areas = r.rest_triangle_areas;
        job.out_area_ratios = ctx.triangle_ratios_;
      }
      job.Run();
    });
    if (muscle_wrinkles) {
      size_t row0 = 0;
      for (const RigMuscleWrinkles& w : r.muscle_wrinkles) {
        const span<float> eps = span<float>(ctx.compression_).subspan(row0, w.row_count());
        ParallelFor(*this, w.row_count(), [&](uint32_t b, uint32_t e) {
          EdgeCompressionJob job;
          job.positions = ctx.points_;
          job.points = w.points;
          job.offsets = w.edge_offsets;
          job.neighbors = w.edge_neighbors;
          job.rest_lengths = w.edge_rest_lengths;
          job.weights = w.edge_weights;
          job.begin = b;
          job.end = e;
          job.out_compression = eps;
          job.RunUnchecked();
        });
        row0 += w.row_count();
      }
    }
    if (curve_wrinkles) {
      ParallelFor(*this, uint32_t(r.curve_wrinkles.probes.size()), [&](uint32_t b, uint32_t e) {
        DirectionalShrinkageJob job;
        job.positions = ctx.points_;
        job.probes = r.curve_wrinkles.probes;
        job.begin = b;
        job.end = e;
        job.out_shrinkage = ctx.shrinkage_;
        job.RunUnchecked();
      });
    }

    // 3. N1 and r per point (PointNormalsJob's gather) and, in the same pass, the
    // volume-preserving thickness in place: X2 = X1 + (1/r - 1) h N1 (MODEL.md §4). Fused
    // because each point needs only its own N1 and r; PointNormalsJob + ThicknessJob compute
    // the same bits for engines that run the stages themselves.
    ParallelFor(*this, r.active_point_count, [&](uint32_t b, uint32_t e) {
      const uint32_t* off = r.point_triangle_offsets.data();
      const uint32_t* tri = r.point_triangles.data();
      const float3* fn = ctx.face_normals_.data();
      const float* ratio = ctx.triangle_ratios_.data();
      const float* h = r.point_thickness.data();
      for (uint32_t p = b; p < e; ++p) {
        float3 n{};
        float sum = 0.f;
        for (uint32_t k = off[p]; k < off[p + 1]; ++k) {
          n += fn[tri[k]];
          if (need_ratio) sum += ratio[tri[k]];
        }
        const float3 n1 = NormalizeOr(n, float3{0.f, 0.f, 1.f});
        ctx.normals1_[p] = n1;
        if (!need_ratio) continue;
        const uint32_t count = off[p + 1] - off[p];
        const float rp = count ? sum / float(count) : 1.f;  // MODEL.md §4: mean over I_j
        ctx.point_ratios_[p] = rp;
        if (thickness) ctx.points_[p] += n1 * ThicknessOffset(rp, h[p], r.min_area_ratio);
      }
    });

    // 4. Large-scale wrinkles along N1: X3 (MODEL.md §6-8). Tables may share points, so they
    // run one after another in rig order; rows within a table split freely.
    if (muscle_wrinkles) {
      size_t row0 = 0;
      for (const RigMuscleWrinkles& w : r.muscle_wrinkles) {
        const span<const float> eps =
            span<const float>(ctx.compression_).subspan(row0, w.row_count());
        ParallelFor(*this, w.row_count(), [&](uint32_t b, uint32_t e) {
          MuscleWrinkleJob job;
          job.normals = ctx.normals1_;
          job.points = w.points;
          job.profile = w.profile;
          job.compression = eps;
          job.begin = b;
          job.end = e;
          job.positions = ctx.points_;
          job.RunUnchecked();
        });
        row0 += w.row_count();
      }
    }
    if (curve_wrinkles) {
      const RigCurveWrinkles& c = r.curve_wrinkles;
      ParallelFor(*this, c.row_count(), [&](uint32_t b, uint32_t e) {
        CurveWrinkleJob job;
        job.normals = ctx.normals1_;
        job.wrinkles = c.wrinkles;
        job.points = c.points;
        job.offsets = c.offsets;
        job.entries = c.entries;
        job.entry_shrinkage = ctx.shrinkage_;
        job.area_ratios = ctx.point_ratios_;
        job.begin = b;
        job.end = e;
        job.positions = ctx.points_;
        job.RunUnchecked();
      });
    }
    // 5. Face normals of X3 (the per-point gather happens in the output pass).
    if (want_normals) face_normals();
  } else {
    std::fill(ctx.point_ratios_.begin(), ctx.point_ratios_.begin() + r.active_point_count, 1.f);
    if (want_normals) face_normals();
  }

  // 6. Output: positions scattered to the file's vertex layout; normals gathered per vertex
  // from the face normals where they can change (a seam vertex repeats its point's gather:
  // the same bits), the rest normals elsewhere. One pass instead of gather + scatter.
  ParallelFor(*this, r.vertex_count(), [&](uint32_t b, uint32_t e) {
    Scatter(ctx.points_, r.vertex_points, out_positions, out_positions_stride, b, e);
    if (!want_normals) return;
    const size_t stride = out_normals_stride / 4;
    const uint32_t* off = r.point_triangle_offsets.data();
    const uint32_t* tri = r.point_triangles.data();
    const float3* fn = ctx.face_normals_.data();
    for (uint32_t v = b; v < e; ++v) {
      const uint32_t p = r.vertex_points[v];
      const float3 n = p < r.normal_point_count ? GatherPointNormal(off, tri, fn, p)
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

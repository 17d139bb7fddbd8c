#include "rig/runtime/evaluate_job.h"

#include "expressions/runtime/activations.h"
#include "rig/runtime/normals_job.h"

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
}

bool EvaluateContext::IsFor(const Rig& rig) const {
  return rig_uid_ == rig.uid && point_count_ == rig.point_count() &&
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

  // 1. Muscles (MODEL.md §1 step 1): summed on the rest pose.
  ParallelFor(*this, r.point_count(), [&](uint32_t b, uint32_t e) {
    MuscleDeformJob job;
    job.table = &r.muscles;
    job.activations = ctx.activations_;
    job.rest_points = r.rest_points;
    job.out_points = ctx.points_;
    job.begin = b;
    job.end = e;
    job.Run();
  });

  // 2. Normals of the deformed points, area-weighted.
  const bool want_normals = !out_normals.empty();
  if (want_normals) {
    ParallelFor(*this, r.triangle_count(), [&](uint32_t b, uint32_t e) {
      FaceNormalsJob job;
      job.points = ctx.points_;
      job.triangles = r.triangles;
      job.out_face_normals = ctx.face_normals_;
      job.begin = b;
      job.end = e;
      job.Run();
    });
    ParallelFor(*this, r.point_count(), [&](uint32_t b, uint32_t e) {
      PointNormalsJob job;
      job.face_normals = ctx.face_normals_;
      job.point_triangle_offsets = r.point_triangle_offsets;
      job.point_triangles = r.point_triangles;
      job.out_normals = ctx.point_normals_;
      job.begin = b;
      job.end = e;
      job.Run();
    });
  }

  // 3. Scatter to the file's vertex layout.
  ParallelFor(*this, r.vertex_count(), [&](uint32_t b, uint32_t e) {
    Scatter(ctx.points_, r.vertex_points, out_positions, out_positions_stride, b, e);
    if (want_normals)
      Scatter(ctx.point_normals_, r.vertex_points, out_normals, out_normals_stride, b, e);
  });
  return true;
}

}  // namespace mimetic

#include "rig/runtime/normals_job.h"

namespace mimetic {

bool FaceNormalsJob::Validate() const {
  if (triangles.size() % 3 != 0) return false;
  const size_t tris = triangles.size() / 3;
  return out_face_normals.size() >= tris && begin <= end && end <= tris;
}

bool FaceNormalsJob::Run() const {
  if (!Validate()) return false;
  const uint32_t* t = triangles.data();
  const float3* p = points.data();
  for (uint32_t i = begin; i < end; ++i) {
    const float3 a = p[t[3 * i]], b = p[t[3 * i + 1]], c = p[t[3 * i + 2]];
    out_face_normals[i] = Cross(b - a, c - a);
  }
  return true;
}

bool PointNormalsJob::Validate() const {
  if (point_triangle_offsets.empty()) return false;
  const size_t points = point_triangle_offsets.size() - 1;
  return point_triangles.size() >= point_triangle_offsets[points] &&
         out_normals.size() >= points && begin <= end && end <= points;
}

bool PointNormalsJob::Run() const {
  if (!Validate()) return false;
  const uint32_t* off = point_triangle_offsets.data();
  const uint32_t* tri = point_triangles.data();
  const float3* fn = face_normals.data();
  for (uint32_t p = begin; p < end; ++p) {
    float3 n{};
    for (uint32_t k = off[p]; k < off[p + 1]; ++k) n += fn[tri[k]];
    out_normals[p] = NormalizeOr(n, float3{0.f, 0.f, 1.f});
  }
  return true;
}

}  // namespace mimetic

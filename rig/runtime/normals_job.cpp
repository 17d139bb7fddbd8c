#include "rig/runtime/normals_job.h"

namespace mimetic {

float TriangleRestArea(float3 a, float3 b, float3 c) { return 0.5f * Length(Cross(b - a, c - a)); }

bool FaceNormalsJob::Validate() const {
  if (triangles.size() % 3 != 0) return false;
  const size_t tris = triangles.size() / 3;
  if (rest_areas.empty() != out_area_ratios.empty()) return false;
  if (!rest_areas.empty() && (rest_areas.size() < tris || out_area_ratios.size() < tris))
    return false;
  return out_face_normals.size() >= tris && begin <= end && end <= tris;
}

bool FaceNormalsJob::Run() const {
  if (!Validate()) return false;
  const uint32_t* t = triangles.data();
  const float3* p = points.data();
  if (out_area_ratios.empty()) {
    for (uint32_t i = begin; i < end; ++i) {
      const float3 a = p[t[3 * i]], b = p[t[3 * i + 1]], c = p[t[3 * i + 2]];
      out_face_normals[i] = Cross(b - a, c - a);
    }
    return true;
  }
  for (uint32_t i = begin; i < end; ++i) {
    const float3 a = p[t[3 * i]], b = p[t[3 * i + 1]], c = p[t[3 * i + 2]];
    const float3 n = Cross(b - a, c - a);
    out_face_normals[i] = n;
    const float area = 0.5f * Length(n);  // as TriangleRestArea
    out_area_ratios[i] = rest_areas[i] > 0.f ? area / rest_areas[i] : 1.f;
  }
  return true;
}

bool PointNormalsJob::Validate() const {
  if (point_triangle_offsets.empty()) return false;
  const size_t points = point_triangle_offsets.size() - 1;
  if (triangle_ratios.empty() != out_ratios.empty()) return false;
  if (!out_ratios.empty() &&
      (out_ratios.size() < points || triangle_ratios.size() < face_normals.size()))
    return false;
  return point_triangles.size() >= point_triangle_offsets[points] &&
         out_normals.size() >= points && begin <= end && end <= points;
}

bool PointNormalsJob::Run() const {
  if (!Validate()) return false;
  const uint32_t* off = point_triangle_offsets.data();
  const uint32_t* tri = point_triangles.data();
  const float3* fn = face_normals.data();
  if (out_ratios.empty()) {
    for (uint32_t p = begin; p < end; ++p) out_normals[p] = GatherPointNormal(off, tri, fn, p);
    return true;
  }
  const float* ratio = triangle_ratios.data();
  for (uint32_t p = begin; p < end; ++p) {
    float3 n{};
    float sum = 0.f;
    for (uint32_t k = off[p]; k < off[p + 1]; ++k) {
      n += fn[tri[k]];
      sum += ratio[tri[k]];
    }
    out_normals[p] = NormalizeOr(n, float3{0.f, 0.f, 1.f});
    const uint32_t count = off[p + 1] - off[p];
    out_ratios[p] = count ? sum / float(count) : 1.f;  // docs/model.md §4: mean over I_j
  }
  return true;
}

}  // namespace mimetic

#include "bench/reference_blendshapes.h"

#include <algorithm>
#include <cstring>
#include <random>

#include "rig/runtime/normals_job.h"

namespace mimetic::bench {

std::vector<SparseShape> MakeReferenceShapes(const Rig& rig, uint32_t shapes, float fraction) {
  std::mt19937 rng(12345);
  std::vector<SparseShape> out(shapes);
  const uint32_t points = rig.point_count();
  const uint32_t moved = uint32_t(fraction * float(points));
  std::vector<uint32_t> all(points);
  for (uint32_t i = 0; i < points; ++i) all[i] = i;
  std::uniform_real_distribution<float> delta(-1.f, 1.f);
  for (SparseShape& s : out) {
    // A contiguous band of points, like a real shape's region, starting at a random point.
    const uint32_t start = std::uniform_int_distribution<uint32_t>(0, points - 1)(rng);
    for (uint32_t k = 0; k < moved; ++k) s.indices.push_back((start + k) % points);
    std::sort(s.indices.begin(), s.indices.end());
    for (uint32_t k = 0; k < moved; ++k) s.deltas.push_back({delta(rng), delta(rng), delta(rng)});
  }
  return out;
}

ReferenceContext::ReferenceContext(const Rig& rig)
    : points(rig.point_count()), face_normals(rig.triangle_count()), point_normals(rig.point_count()) {}

void EvaluateReference(const Rig& rig, const std::vector<SparseShape>& shapes,
                       span<const float> weights, ReferenceContext* ctx,
                       span<float> out_positions, span<float> out_normals) {
  std::memcpy(ctx->points.data(), rig.rest_points.data(), rig.point_count() * sizeof(float3));
  for (size_t s = 0; s < shapes.size(); ++s) {
    const float w = weights[s];
    if (w == 0.f) continue;
    const uint32_t* idx = shapes[s].indices.data();
    const float3* d = shapes[s].deltas.data();
    float3* p = ctx->points.data();
    for (size_t k = 0, n = shapes[s].indices.size(); k < n; ++k) p[idx[k]] += w * d[k];
  }
  FaceNormalsJob faces;
  faces.points = ctx->points;
  faces.triangles = rig.triangles;
  faces.out_face_normals = ctx->face_normals;
  faces.begin = 0;
  faces.end = rig.triangle_count();
  faces.Run();
  PointNormalsJob normals;
  normals.face_normals = ctx->face_normals;
  normals.point_triangle_offsets = rig.point_triangle_offsets;
  normals.point_triangles = rig.point_triangles;
  normals.out_normals = ctx->point_normals;
  normals.begin = 0;
  normals.end = rig.point_count();
  normals.Run();
  for (uint32_t v = 0; v < rig.vertex_count(); ++v) {
    const float3 p = ctx->points[rig.vertex_points[v]], n = ctx->point_normals[rig.vertex_points[v]];
    float* op = &out_positions[3 * v];
    float* on = &out_normals[3 * v];
    op[0] = p.x, op[1] = p.y, op[2] = p.z;
    on[0] = n.x, on[1] = n.y, on[2] = n.z;
  }
}

}  // namespace mimetic::bench

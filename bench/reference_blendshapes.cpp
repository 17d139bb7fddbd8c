#include "bench/reference_blendshapes.h"

#include <algorithm>
#include <random>

#include "rig/runtime/face_kernels.h"

namespace mimetic::bench {

ReferenceRig MakeReferenceRig(const Rig& rig, uint32_t shapes, float fraction,
                              const std::vector<uint32_t>& centres) {
  std::mt19937 rng(12345);
  ReferenceRig out;
  out.shapes.resize(shapes);
  const uint32_t points = rig.point_count();
  const uint32_t moved = uint32_t(fraction * float(points));
  std::uniform_real_distribution<float> delta(-1.f, 1.f);
  std::vector<std::pair<float, uint32_t>> by_distance(points);
  std::vector<uint8_t> any(points, 0);
  for (SparseShape& s : out.shapes) {
    // A ball around a random centre, like a real shape's region.
    const uint32_t pick = std::uniform_int_distribution<uint32_t>(
        0, uint32_t((centres.empty() ? points : centres.size()) - 1))(rng);
    const float3 c = rig.rest_points()[centres.empty() ? pick : centres[pick]];
    for (uint32_t p = 0; p < points; ++p) by_distance[p] = {LengthSquared(rig.rest_points()[p] - c), p};
    std::nth_element(by_distance.begin(), by_distance.begin() + moved, by_distance.end());
    for (uint32_t k = 0; k < moved; ++k) s.indices.push_back(by_distance[k].second);
    std::sort(s.indices.begin(), s.indices.end());
    for (uint32_t k = 0; k < moved; ++k) {
      s.deltas.push_back({delta(rng), delta(rng), delta(rng)});
      any[s.indices[k]] = 1;
    }
  }
  std::vector<uint8_t> in_list(points, 0);
  for (uint32_t t = 0; t < rig.triangle_count(); ++t) {
    const uint32_t* c = &rig.triangles()[3 * t];
    if (!(any[c[0]] || any[c[1]] || any[c[2]])) continue;
    out.triangles.push_back(t);
    in_list[c[0]] = in_list[c[1]] = in_list[c[2]] = 1;
  }
  for (uint32_t p = 0; p < points; ++p)
    if (in_list[p]) out.points.push_back(p);
  out.normal_changes = std::move(in_list);
  return out;
}

ReferenceContext::ReferenceContext(const Rig& rig)
    : points(rig.point_count() + 1), point_normals(rig.point_count()),
      face_normals(rig.triangle_count()) {
  std::copy(rig.rest_points().begin(), rig.rest_points().end(), points.begin());
  FaceNormals4(points.data(), rig.triangles().data(), 0, rig.triangle_count(), nullptr,
               face_normals.data());
  for (uint32_t p = 0; p < rig.point_count(); ++p)
    point_normals[p] = UnitNormal(GatherFaces4(rig.point_triangle_offsets().data(),
                                               rig.point_triangles().data(), face_normals.data(), p));
}

void EvaluateReference(const Rig& rig, const ReferenceRig& ref, span<const float> weights,
                       ReferenceContext* ctx, span<float> out_positions, span<float> out_normals) {
  // Plain pointers, read once: stores through `p` and the outputs cannot move them.
  float3* p = ctx->points.data();
  const float3* rest = rig.rest_points().data();
  const uint32_t* vertex_points = rig.vertex_points().data();
  const uint32_t vertex_count = rig.vertex_count();
  for (uint32_t i : ref.points) p[i] = rest[i];
  for (size_t s = 0; s < ref.shapes.size(); ++s) {
    const float w = weights[s];
    if (w == 0.f) continue;
    const uint32_t* idx = ref.shapes[s].indices.data();
    const float3* d = ref.shapes[s].deltas.data();
    for (size_t k = 0, n = ref.shapes[s].indices.size(); k < n; ++k) p[idx[k]] += w * d[k];
  }
  // The same area-weighted normals as EvaluateJob (face_kernels.h), on the lists.
  FaceNormals4Listed(p, rig.triangles().data(), ref.triangles.data(), ref.triangles.size(),
                     ctx->face_normals.data());
  const uint32_t* off = rig.point_triangle_offsets().data();
  const uint32_t* tri = rig.point_triangles().data();
  const float4* fn = ctx->face_normals.data();
  for (uint32_t v = 0; v < vertex_count; ++v) {
    const uint32_t i = vertex_points[v];
    const float3 q = p[i];
    const float3 n =
        ref.normal_changes[i] ? UnitNormal(GatherFaces4(off, tri, fn, i)) : ctx->point_normals[i];
    float* op = &out_positions[3 * v];
    float* on = &out_normals[3 * v];
    op[0] = q.x, op[1] = q.y, op[2] = q.z;
    on[0] = n.x, on[1] = n.y, on[2] = n.z;
  }
}

}  // namespace mimetic::bench

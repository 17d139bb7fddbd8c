#include "geometry/refine_estimate.h"

#include <algorithm>
#include <cmath>

#include "geometry/bounds.h"

namespace mimetic {

double EstimateRefinedTriangles(const MeshData& mesh, const EdgeLengthField& max_edge,
                                const RefineOptions& options) {
  const size_t tris = mesh.triangle_count();
  if (tris == 0 || !max_edge) return double(tris);
  const BoundingBox box = ComputeBounds(mesh.positions);
  const double floor = 2e-4 * double(Length(box.Hi() - box.Lo()));
  const bool has_uvs = mesh.uvs.size() == mesh.vertex_count();
  const int passes = std::max(0, options.max_passes);
  auto sample = [&](float3 p, float2 uv) {
    float t;
    try {
      t = max_edge(p, uv);
    } catch (...) {
      return HUGE_VAL;  // RefineMesh reports it
    }
    return t > 0.f && std::isfinite(t) ? double(t) : HUGE_VAL;
  };
  double total = 0;
  for (size_t t = 0; t < tris; ++t) {
    const uint32_t* i = &mesh.indices[3 * t];
    if (i[0] >= mesh.vertex_count() || i[1] >= mesh.vertex_count() || i[2] >= mesh.vertex_count()) {
      total += 1;
      continue;
    }
    const float3 p[3] = {mesh.positions[i[0]], mesh.positions[i[1]], mesh.positions[i[2]]};
    float2 q[3] = {};
    if (has_uvs) q[0] = mesh.uvs[i[0]], q[1] = mesh.uvs[i[1]], q[2] = mesh.uvs[i[2]];
    double target = sample((p[0] + p[1] + p[2]) * (1.f / 3.f),
                           {(q[0].x + q[1].x + q[2].x) / 3.f, (q[0].y + q[1].y + q[2].y) / 3.f});
    double longest = 0;
    for (int k = 0; k < 3; ++k) {
      const float3 a = p[k], b = p[(k + 1) % 3];
      const float2 u = q[k], w = q[(k + 1) % 3];
      target = std::min(target, sample((a + b) * 0.5f, {(u.x + w.x) * 0.5f, (u.y + w.y) * 0.5f}));
      longest = std::max(longest, double(Length(b - a)));
    }
    target = std::max(target, floor);
    if (!(longest > target)) {
      total += 1;
      continue;
    }
    const int p_needed = int(std::ceil(std::log2(longest / target)));
    total += std::pow(4.0, std::clamp(p_needed, 0, passes));
  }
  return total;
}

}  // namespace mimetic

// geometry/normals.cpp: see normals.h.
#include "geometry/normals.h"

#include <algorithm>
#include <cmath>

namespace mimetic {

void TriangleCross(float3 a, float3 b, float3 c, double out[3]) {
  const double u[3] = {double(b.x) - a.x, double(b.y) - a.y, double(b.z) - a.z};
  const double w[3] = {double(c.x) - a.x, double(c.y) - a.y, double(c.z) - a.z};
  out[0] = u[1] * w[2] - u[2] * w[1];
  out[1] = u[2] * w[0] - u[0] * w[2];
  out[2] = u[0] * w[1] - u[1] * w[0];
}

double TriangleShape(float3 a, float3 b, float3 c) {
  double n[3];
  TriangleCross(a, b, c, n);
  const double area2 = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  const double l = std::max({Length(b - a), Length(c - b), Length(a - c)});
  return l > 0.0 ? area2 / (l * l) : 0.0;
}

double TriangleArea(float3 a, float3 b, float3 c) {
  double n[3];
  TriangleCross(a, b, c, n);
  return 0.5 * std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
}

namespace {

// n / |n| rounded to float, or `fallback` when |n| is 0 or not finite.
float3 Unit(const double n[3], float3 fallback) {
  const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
  if (!(len > 0) || !std::isfinite(len)) return fallback;
  const double inv = 1.0 / len;
  return {static_cast<float>(n[0] * inv), static_cast<float>(n[1] * inv),
          static_cast<float>(n[2] * inv)};
}

}  // namespace

float3 TriangleNormal(float3 a, float3 b, float3 c, float3 fallback) {
  double n[3];
  TriangleCross(a, b, c, n);
  return Unit(n, fallback);
}

std::vector<float3> ComputeVertexNormals(span<const float3> positions,
                                         span<const uint32_t> indices,
                                         const VertexNormalOptions& options) {
  const size_t nv = positions.size();
  std::vector<double> acc(3 * nv, 0.0);
  for (size_t t = 0; t + 2 < indices.size(); t += 3) {
    const uint32_t v[3] = {indices[t], indices[t + 1], indices[t + 2]};
    if (v[0] >= nv || v[1] >= nv || v[2] >= nv) continue;
    double n[3];
    TriangleCross(positions[v[0]], positions[v[1]], positions[v[2]], n);
    for (uint32_t k : v) {
      acc[3 * k] += n[0];
      acc[3 * k + 1] += n[1];
      acc[3 * k + 2] += n[2];
    }
  }
  if (options.share_by_position) {
    // Group vertices by position (ties in vertex order), sum each group in vertex order.
    std::vector<uint32_t> order;
    order.reserve(nv);
    for (uint32_t v = 0; v < nv; ++v)
      if (IsFinite(positions[v])) order.push_back(v);
    auto less = [&](uint32_t a, uint32_t b) {
      const float3 p = positions[a], q = positions[b];
      if (p.x != q.x) return p.x < q.x;
      if (p.y != q.y) return p.y < q.y;
      if (p.z != q.z) return p.z < q.z;
      return a < b;
    };
    std::sort(order.begin(), order.end(), less);
    for (size_t i = 0; i < order.size();) {
      size_t j = i + 1;
      while (j < order.size() && positions[order[j]] == positions[order[i]]) ++j;
      if (j - i > 1) {
        double sum[3] = {0, 0, 0};
        for (size_t k = i; k < j; ++k)
          for (int c = 0; c < 3; ++c) sum[c] += acc[3 * order[k] + c];
        for (size_t k = i; k < j; ++k)
          for (int c = 0; c < 3; ++c) acc[3 * order[k] + c] = sum[c];
      }
      i = j;
    }
  }
  std::vector<float3> normals(nv);
  for (size_t v = 0; v < nv; ++v) normals[v] = Unit(&acc[3 * v], options.fallback);
  return normals;
}

std::vector<float3> ComputeVertexNormals(const MeshData& mesh, const VertexNormalOptions& options) {
  return ComputeVertexNormals(mesh.positions, mesh.indices, options);
}

}  // namespace mimetic

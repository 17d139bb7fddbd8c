// tests/jaw_checks.h: what the jaw tests measure on any head (ICT-FaceKit in
// tests/fitting/jaw_test.cpp, the sample head in tests/fitting/jaw_sample_head_test.cpp): the posed mesh at a jaw opening,
// the triangles that turn over against the rest pose, the smallest distance between two sets
// of vertices (the lips), the pairs of triangles that pass through each other.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include <gtest/gtest.h>

#include "core/math.h"
#include "geometry/mesh.h"
#include "rig/offline/rig_builder.h"
#include "rig/runtime/rig.h"

namespace mimetic::test {

// The rig posed with every muscle at 0, every skin layer and the fold limiter on, the jaw at
// `jaw`: RestMesh's layout (the mesh file's vertices first).
inline std::vector<float3> PosedAtJaw(const Rig& rig, float jaw, SkinLayers layers = {}) {
  MeshData m;
  const std::vector<float> zero(rig.muscle_count(), 0.f);
  EXPECT_TRUE(PosedMesh(rig, zero, layers, &m, jaw));
  return m.positions;
}

// Triangles whose posed normal turned over against the rest one (the criterion of
// tests/fitting/foldover_test.cpp: dot <= 0, or a collapsed triangle, is a flip; triangles with
// no rest area are skipped). `first` is the first one found (0 when none).
struct TurnedOver {
  size_t count = 0;
  size_t first = 0;
};
inline TurnedOver CountTurnedOver(const MeshData& rest, const std::vector<float3>& posed) {
  TurnedOver out;
  for (size_t t = 0; t < rest.triangle_count(); ++t) {
    const uint32_t* i = &rest.indices[3 * t];
    const float3 n0 = Cross(rest.positions[i[1]] - rest.positions[i[0]],
                            rest.positions[i[2]] - rest.positions[i[0]]);
    const float3 n1 = Cross(posed[i[1]] - posed[i[0]], posed[i[2]] - posed[i[0]]);
    if (!(Length(n0) > 0.f)) continue;
    if (!(Dot(n0, n1) > 0.f) && out.count++ == 0) out.first = t;
  }
  return out;
}

// The smallest distance between a vertex of `a` and one of `b` at positions `x`.
inline float SmallestDistance(const std::vector<float3>& x, const std::vector<uint32_t>& a,
                              const std::vector<uint32_t>& b) {
  float best = 1e30f;
  for (uint32_t i : a)
    for (uint32_t j : b) best = std::min(best, Length(x[i] - x[j]));
  return best;
}

// Does the segment [p, q] pass through the inside of triangle (a, b, c)? Moller-Trumbore in
// double with the barycentrics and the segment parameter strictly inside by `eps` (a segment
// that only touches an edge or a corner does not count; nor does one parallel to the plane).
inline bool SegmentPiercesTriangle(float3 p, float3 q, float3 a, float3 b, float3 c,
                                   double eps = 1e-9) {
  const double e1[3] = {double(b.x) - a.x, double(b.y) - a.y, double(b.z) - a.z};
  const double e2[3] = {double(c.x) - a.x, double(c.y) - a.y, double(c.z) - a.z};
  const double d[3] = {double(q.x) - p.x, double(q.y) - p.y, double(q.z) - p.z};
  const double s[3] = {double(p.x) - a.x, double(p.y) - a.y, double(p.z) - a.z};
  auto cross = [](const double* u, const double* v, double* o) {
    o[0] = u[1] * v[2] - u[2] * v[1], o[1] = u[2] * v[0] - u[0] * v[2], o[2] = u[0] * v[1] - u[1] * v[0];
  };
  auto dot = [](const double* u, const double* v) { return u[0] * v[0] + u[1] * v[1] + u[2] * v[2]; };
  double h[3], k[3];
  cross(d, e2, h);
  const double det = dot(e1, h);
  if (std::fabs(det) < 1e-18) return false;
  const double u = dot(s, h) / det;
  cross(s, e1, k);
  const double v = dot(d, k) / det, t = dot(e2, k) / det;
  return u > eps && v > eps && u + v < 1 - eps && t > eps && t < 1 - eps;
}

// Pairs of triangles of `mesh` (its indices; positions `x`) that pass through each other: an
// edge of one pierces the other. Only triangles whose rest centroid (mesh.positions) lies
// within `radius` of `center` are tested, and two triangles that share a corner (by rest
// position, so a uv seam's split vertices count as one) are skipped. Brute force over the
// pairs whose bounding boxes overlap.
inline size_t CountPiercingPairs(const MeshData& mesh, const std::vector<float3>& x, float3 center,
                                 float radius) {
  std::vector<uint32_t> tris;
  for (uint32_t t = 0; t < mesh.triangle_count(); ++t) {
    const uint32_t* i = &mesh.indices[3 * size_t(t)];
    const float3 c = (mesh.positions[i[0]] + mesh.positions[i[1]] + mesh.positions[i[2]]) * (1.f / 3.f);
    if (Length(c - center) < radius) tris.push_back(t);
  }
  auto corner = [&](uint32_t t, int k) { return mesh.indices[3 * size_t(t) + k]; };
  auto box = [&](uint32_t t, float3* lo, float3* hi) {
    *lo = *hi = x[corner(t, 0)];
    for (int k = 1; k < 3; ++k) {
      const float3 p = x[corner(t, k)];
      *lo = {std::min(lo->x, p.x), std::min(lo->y, p.y), std::min(lo->z, p.z)};
      *hi = {std::max(hi->x, p.x), std::max(hi->y, p.y), std::max(hi->z, p.z)};
    }
  };
  size_t count = 0;
  for (size_t m = 0; m < tris.size(); ++m) {
    float3 lo_a, hi_a;
    box(tris[m], &lo_a, &hi_a);
    for (size_t n = m + 1; n < tris.size(); ++n) {
      float3 lo_b, hi_b;
      box(tris[n], &lo_b, &hi_b);
      if (lo_a.x > hi_b.x || lo_b.x > hi_a.x || lo_a.y > hi_b.y || lo_b.y > hi_a.y ||
          lo_a.z > hi_b.z || lo_b.z > hi_a.z)
        continue;
      bool shared = false;
      for (int i = 0; i < 3 && !shared; ++i)
        for (int j = 0; j < 3 && !shared; ++j)
          shared = mesh.positions[corner(tris[m], i)] == mesh.positions[corner(tris[n], j)];
      if (shared) continue;
      bool pierce = false;
      for (int pass = 0; pass < 2 && !pierce; ++pass) {
        const uint32_t e = pass ? tris[n] : tris[m], f = pass ? tris[m] : tris[n];
        for (int k = 0; k < 3 && !pierce; ++k)
          pierce = SegmentPiercesTriangle(x[corner(e, k)], x[corner(e, (k + 1) % 3)], x[corner(f, 0)],
                                          x[corner(f, 1)], x[corner(f, 2)]);
      }
      count += pierce;
    }
  }
  return count;
}

}  // namespace mimetic::test

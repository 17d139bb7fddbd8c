// geometry/surface_query.cpp: see surface_query.h.
#include "geometry/surface_query.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "geometry/closest_point.h"
#include "geometry/normals.h"
#include "geometry/ray_triangle.h"

namespace mimetic {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

float3 Min3(float3 a, float3 b) { return {FMin(a.x, b.x), FMin(a.y, b.y), FMin(a.z, b.z)}; }
float3 Max3(float3 a, float3 b) { return {FMax(a.x, b.x), FMax(a.y, b.y), FMax(a.z, b.z)}; }
float Comp(float3 v, int axis) { return axis == 0 ? v.x : (axis == 1 ? v.y : v.z); }

// Squared distance from p to the box [lo, hi] (0 inside).
float BoxDistance2(float3 p, float3 lo, float3 hi) {
  const float dx = FMax(FMax(lo.x - p.x, 0.f), p.x - hi.x);
  const float dy = FMax(FMax(lo.y - p.y, 0.f), p.y - hi.y);
  const float dz = FMax(FMax(lo.z - p.z, 0.f), p.z - hi.z);
  return dx * dx + dy * dy + dz * dz;
}

// Slab test: entry distance of the ray into the box, or +inf.
float RayBox(float3 o, float3 inv, float3 lo, float3 hi, float tmax) {
  float t0 = 0.f, t1 = tmax;
  for (int a = 0; a < 3; ++a) {
    float ta = (Comp(lo, a) - Comp(o, a)) * Comp(inv, a);
    float tb = (Comp(hi, a) - Comp(o, a)) * Comp(inv, a);
    if (std::isnan(ta) || std::isnan(tb)) {  // 0 * inf: origin on the slab plane
      if (Comp(o, a) < Comp(lo, a) || Comp(o, a) > Comp(hi, a)) return kInf;
      continue;
    }
    if (ta > tb) std::swap(ta, tb);
    t0 = FMax(t0, ta);
    t1 = FMin(t1, tb);
    if (t0 > t1) return kInf;
  }
  return t0;
}

}  // namespace

SurfaceQuery::SurfaceQuery(const MeshData& mesh) : mesh_(mesh) {
  const size_t nt = mesh.triangle_count();
  // Area-weighted vertex normals, shared by vertices at the same position (UV seams); zero
  // where a vertex has none (NormalAt then falls back to the face normal).
  VertexNormalOptions normal_options;
  normal_options.share_by_position = true;
  normal_options.fallback = {0, 0, 0};
  vertex_normals_ = ComputeVertexNormals(mesh, normal_options);
  order_.resize(nt);
  centroids_.resize(nt);
  for (uint32_t t = 0; t < nt; ++t) {
    order_[t] = t;
    centroids_[t] = (mesh.positions[mesh.indices[3 * t]] + mesh.positions[mesh.indices[3 * t + 1]] +
                     mesh.positions[mesh.indices[3 * t + 2]]) / 3.f;
  }
  nodes_.reserve(nt / 2 + 2);
  if (nt > 0) Build(0, uint32_t(nt), 0);
}

uint32_t SurfaceQuery::Build(uint32_t first, uint32_t count, int depth) {
  const uint32_t index = uint32_t(nodes_.size());
  nodes_.push_back({});
  float3 lo{kInf, kInf, kInf}, hi{-kInf, -kInf, -kInf}, clo = lo, chi = hi;
  for (uint32_t i = first; i < first + count; ++i) {
    const uint32_t t = order_[i];
    for (int k = 0; k < 3; ++k) {
      const float3 p = mesh_.positions[mesh_.indices[3 * t + k]];
      lo = Min3(lo, p), hi = Max3(hi, p);
    }
    clo = Min3(clo, centroids_[t]), chi = Max3(chi, centroids_[t]);
  }
  nodes_[index].lo = lo;
  nodes_[index].hi = hi;
  const float3 ext = chi - clo;
  if (count <= 4 || depth > 60 || (ext.x <= 0 && ext.y <= 0 && ext.z <= 0)) {
    nodes_[index].first = first;
    nodes_[index].count = count;
    return index;
  }
  const int axis = ext.x >= ext.y && ext.x >= ext.z ? 0 : (ext.y >= ext.z ? 1 : 2);
  const uint32_t half = count / 2;
  std::nth_element(order_.begin() + first, order_.begin() + first + half,
                   order_.begin() + first + count, [&](uint32_t a, uint32_t b) {
                     return Comp(centroids_[a], axis) < Comp(centroids_[b], axis);
                   });
  const uint32_t left = Build(first, half, depth + 1);
  const uint32_t right = Build(first + half, count - half, depth + 1);
  nodes_[index].left = left;
  nodes_[index].right = right;
  return index;
}

float3 SurfaceQuery::NormalAt(uint32_t tri, float3 p, float3* bary_out) const {
  const uint32_t a = mesh_.indices[3 * tri], b = mesh_.indices[3 * tri + 1], c = mesh_.indices[3 * tri + 2];
  const float3 pa = mesh_.positions[a], pb = mesh_.positions[b], pc = mesh_.positions[c];
  const float3 face = TriangleNormal(pa, pb, pc, {0, 0, 1});
  float3 bary;
  ClosestPointOnTriangle(p, pa, pb, pc, &bary);
  if (bary_out) *bary_out = bary;
  float3 n = vertex_normals_[a] * bary.x + vertex_normals_[b] * bary.y + vertex_normals_[c] * bary.z;
  n = NormalizeOr(n, face);
  if (Dot(n, face) < 0.f) n = face;  // inconsistent winding around the vertex: trust the face
  return n;
}

SurfaceQuery::Hit SurfaceQuery::Raycast(float3 o, float3 dir) const {
  Hit hit;
  const float len = Length(dir);
  if (nodes_.empty() || !(len > 0.f)) return hit;
  const float3 d = dir / len;
  const float3 inv{1.f / d.x, 1.f / d.y, 1.f / d.z};
  float best = kInf;
  uint32_t best_tri = 0;
  std::vector<uint32_t> stack{0};
  while (!stack.empty()) {
    const Node& n = nodes_[stack.back()];
    stack.pop_back();
    if (RayBox(o, inv, n.lo, n.hi, best) == kInf) continue;
    if (n.count == 0) {
      stack.push_back(n.left);
      stack.push_back(n.right);
      continue;
    }
    for (uint32_t i = n.first; i < n.first + n.count; ++i) {
      const uint32_t t = order_[i];
      float tt = 0.f, u = 0.f, v = 0.f;
      if (RayTriangle(o, d, mesh_.positions[mesh_.indices[3 * t]],
                      mesh_.positions[mesh_.indices[3 * t + 1]],
                      mesh_.positions[mesh_.indices[3 * t + 2]], &tt, &u, &v) &&
          tt < best)
        best = tt, best_tri = t;
    }
  }
  if (best == kInf) return hit;
  hit.found = true;
  hit.t = best;
  hit.point = o + d * best;
  hit.triangle = best_tri;
  hit.normal = NormalAt(best_tri, hit.point, &hit.bary);
  if (Dot(hit.normal, d) > 0.f) hit.normal = -hit.normal;  // face the ray's origin
  return hit;
}

SurfaceQuery::Hit SurfaceQuery::Nearest(float3 p) const {
  Hit hit;
  if (nodes_.empty()) return hit;
  float best2 = kInf;
  float3 best_point;
  uint32_t best_tri = 0;
  std::vector<uint32_t> stack{0};
  while (!stack.empty()) {
    const Node& n = nodes_[stack.back()];
    stack.pop_back();
    if (BoxDistance2(p, n.lo, n.hi) >= best2) continue;
    if (n.count == 0) {
      // Visit the nearer child first (pushed last).
      const float dl = BoxDistance2(p, nodes_[n.left].lo, nodes_[n.left].hi);
      const float dr = BoxDistance2(p, nodes_[n.right].lo, nodes_[n.right].hi);
      if (dl < dr) stack.push_back(n.right), stack.push_back(n.left);
      else stack.push_back(n.left), stack.push_back(n.right);
      continue;
    }
    for (uint32_t i = n.first; i < n.first + n.count; ++i) {
      const uint32_t t = order_[i];
      const float3 q = ClosestPointOnTriangle(p, mesh_.positions[mesh_.indices[3 * t]],
                                              mesh_.positions[mesh_.indices[3 * t + 1]],
                                              mesh_.positions[mesh_.indices[3 * t + 2]]);
      const float d2 = LengthSquared(q - p);
      if (d2 < best2) best2 = d2, best_point = q, best_tri = t;
    }
  }
  hit.found = true;
  hit.t = std::sqrt(best2);
  hit.point = best_point;
  hit.triangle = best_tri;
  hit.normal = NormalAt(best_tri, best_point, &hit.bary);
  return hit;
}

}  // namespace mimetic

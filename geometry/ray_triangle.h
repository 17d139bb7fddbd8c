// geometry/ray_triangle.h: the ray-triangle intersection (Moller and Trumbore, "Fast, minimum
// storage ray/triangle intersection", JGT 1997), both sides, shared by SurfaceQuery::Raycast and
// the viewer's pick (viewer/core/scene_query.h).
#pragma once

#include <cmath>

#include "core/math.h"

namespace mimetic {

// True when the ray o + t d (t > 0) crosses triangle (a, b, c), from either side; then *t, and
// the barycentric weights *u of b and *v of c (a's is 1 - u - v). False for a triangle whose
// plane the ray runs along (|det| < min_det).
inline bool RayTriangle(const float3& o, const float3& d, const float3& a, const float3& b,
                        const float3& c, float* t, float* u, float* v, float min_det = 1e-20f) {
  const float3 e1 = b - a, e2 = c - a;
  const float3 pv = Cross(d, e2);
  const float det = Dot(e1, pv);
  if (std::fabs(det) < min_det) return false;
  const float inv_det = 1.f / det;
  const float3 tv = o - a;
  *u = Dot(tv, pv) * inv_det;
  if (*u < 0.f || *u > 1.f) return false;
  const float3 qv = Cross(tv, e1);
  *v = Dot(d, qv) * inv_det;
  if (*v < 0.f || *u + *v > 1.f) return false;
  *t = Dot(e2, qv) * inv_det;
  return *t > 0.f;
}

}  // namespace mimetic

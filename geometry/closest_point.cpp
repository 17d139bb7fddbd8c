// geometry/closest_point.cpp: see closest_point.h.
#include "geometry/closest_point.h"

namespace mimetic {
namespace {

double Dot(const double a[3], const double b[3]) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// o + d * s, and the weights.
TrianglePoint At(const double o[3], const double d[3], double s, double wa, double wb,
                 double wc) {
  return {{o[0] + d[0] * s, o[1] + d[1] * s, o[2] + d[2] * s}, {wa, wb, wc}};
}

}  // namespace

TrianglePoint ClosestPointOnTriangle(const double p[3], const double a[3], const double b[3],
                                     const double c[3]) {
  const double ab[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  const double ac[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  const double ap[3] = {p[0] - a[0], p[1] - a[1], p[2] - a[2]};
  const double d1 = Dot(ab, ap), d2 = Dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return {{a[0], a[1], a[2]}, {1, 0, 0}};  // vertex a
  const double bp[3] = {p[0] - b[0], p[1] - b[1], p[2] - b[2]};
  const double d3 = Dot(ab, bp), d4 = Dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return {{b[0], b[1], b[2]}, {0, 1, 0}};  // vertex b
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {  // edge ab
    const double v = d1 / (d1 - d3);
    return At(a, ab, v, 1 - v, v, 0);
  }
  const double cp[3] = {p[0] - c[0], p[1] - c[1], p[2] - c[2]};
  const double d5 = Dot(ab, cp), d6 = Dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return {{c[0], c[1], c[2]}, {0, 0, 1}};  // vertex c
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {  // edge ac
    const double w = d2 / (d2 - d6);
    return At(a, ac, w, 1 - w, 0, w);
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {  // edge bc
    const double bc[3] = {c[0] - b[0], c[1] - b[1], c[2] - b[2]};
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return At(b, bc, w, 0, 1 - w, w);
  }
  // Inside the face.
  const double denom = 1.0 / (va + vb + vc);
  const double v = vb * denom, w = vc * denom;
  return {{a[0] + ab[0] * v + ac[0] * w, a[1] + ab[1] * v + ac[1] * w,
           a[2] + ab[2] * v + ac[2] * w},
          {1 - v - w, v, w}};
}

float3 ClosestPointOnTriangle(float3 p, float3 a, float3 b, float3 c, float3* bary) {
  const double pp[3] = {p.x, p.y, p.z}, pa[3] = {a.x, a.y, a.z}, pb[3] = {b.x, b.y, b.z},
               pc[3] = {c.x, c.y, c.z};
  const TrianglePoint r = ClosestPointOnTriangle(pp, pa, pb, pc);
  if (bary) {
    *bary = {static_cast<float>(r.bary[0]), static_cast<float>(r.bary[1]),
             static_cast<float>(r.bary[2])};
  }
  return {static_cast<float>(r.point[0]), static_cast<float>(r.point[1]),
          static_cast<float>(r.point[2])};
}

}  // namespace mimetic

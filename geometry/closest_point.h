// geometry/closest_point.h: the closest point of a triangle to a point (Ericson, Real-Time
// Collision Detection §5.1.5), with its barycentric weights.
//
// The point's Voronoi region of the triangle (one of three vertices, three edges, or the
// face) is found from six dot products; the closest point is then a vertex, the projection
// on an edge, or the projection on the plane. Computed in double. Meant for triangles of
// non-zero area (for a zero-area one the face case can divide by zero).
#pragma once

#include "core/math.h"

namespace mimetic {

struct TrianglePoint {
  double point[3];  // the closest point, mesh units
  double bary[3];   // its weights on a, b, c: each in [0, 1], summing to 1
};

// p, a, b, c: 3 coordinates each, mesh units.
TrianglePoint ClosestPointOnTriangle(const double p[3], const double a[3], const double b[3],
                                     const double c[3]);

// The same for float input: computed in double, the point (and `bary`, when given) rounded
// once to float.
float3 ClosestPointOnTriangle(float3 p, float3 a, float3 b, float3 c, float3* bary = nullptr);

}  // namespace mimetic

// wrinkles/offline/bezier.h: closest point on a planar cubic Bezier curve (the furrow of a
// curve wrinkle, 000 §6, docs/model.md §7), used when the rig is compiled.
#pragma once

#include "core/math.h"

namespace mimetic {

struct BezierClosest {
  double distance = 0.0;  // Euclidean distance from the query point to the curve
  double t = 0.0;         // curve parameter of the closest point, [0, 1]
  float2 point;           // the closest point
  float2 tangent;         // unit tangent there (a curve with a vanishing derivative uses a
                          // finite difference, then the chord, then (1, 0))
};

// Point on the cubic Bezier with control points `c` at t in [0, 1].
float2 BezierPoint(const float2 c[4], double t);

// Closest point to `p`: 64 uniform samples, then every local minimum of the sampled distance
// is refined by golden-section search on its bracket (48 steps) and polished by at most 4
// Newton steps that must stay in the bracket and decrease the distance. Bounded work, no
// allocation; exact up to ~1e-12 of the curve size for any control polygon (including
// degenerate, straight or self-intersecting ones). Non-finite input gives distance +inf.
BezierClosest ClosestPointOnBezier(const float2 c[4], float2 p);

// Whether the curve comes within `reach` of `p`, decided cheaply where that is certain (an
// exact shortcut before ClosestPointOnBezier): 16 chords between curve points B(i/16), each
// within h^2/8 max|B''| of its arc (h = 1/16, |B''| <= 6 max(|c2 - 2c1 + c0|, |c3 - 2c2 + c1|)).
// kWithin when one of the curve points is within reach; kBeyond when the distance to every
// chord, less that bound, exceeds it; kUnsure otherwise and for non-finite input.
enum class BezierReach { kWithin, kBeyond, kUnsure };
BezierReach ClassifyBezierReach(const float2 c[4], float2 p, double reach);

}  // namespace mimetic

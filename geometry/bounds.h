// geometry/bounds.h: the axis-aligned bounding box of a point set, in double.
//
// The welder and the refiner scale their tolerances by the box's diagonal (double keeps the
// diagonal of a large mesh from losing digits); the fitter frames the face with it.
#pragma once

#include "core/math.h"
#include "core/span.h"

namespace mimetic {

struct BoundingBox {
  double lo[3] = {0, 0, 0};  // mesh units; all 0 for an empty set
  double hi[3] = {0, 0, 0};
  // |hi - lo|, mesh units.
  double Diagonal() const;
  // The corners as float3: exact, since every coordinate is one of the points'.
  float3 Lo() const { return {float(lo[0]), float(lo[1]), float(lo[2])}; }
  float3 Hi() const { return {float(hi[0]), float(hi[1]), float(hi[2])}; }
};

// The bounds of `points` (finite coordinates expected; an empty set gives the zero box). O(n).
BoundingBox ComputeBounds(span<const float3> points);

}  // namespace mimetic

// geometry/bounds.cpp: see bounds.h.
#include "geometry/bounds.h"

#include <cmath>

namespace mimetic {

double BoundingBox::Diagonal() const {
  return std::sqrt((hi[0] - lo[0]) * (hi[0] - lo[0]) + (hi[1] - lo[1]) * (hi[1] - lo[1]) +
                   (hi[2] - lo[2]) * (hi[2] - lo[2]));
}

BoundingBox ComputeBounds(span<const float3> points) {
  BoundingBox b;
  for (size_t v = 0; v < points.size(); ++v) {
    const double c[3] = {points[v].x, points[v].y, points[v].z};
    for (int k = 0; k < 3; ++k) {
      if (v == 0 || c[k] < b.lo[k]) b.lo[k] = c[k];
      if (v == 0 || c[k] > b.hi[k]) b.hi[k] = c[k];
    }
  }
  return b;
}

}  // namespace mimetic

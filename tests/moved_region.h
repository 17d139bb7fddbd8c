// tests/moved_region.h: the comparison region the fidelity report uses, written out for the
// tests that check its figures: the vertices the real shape moves more than 2% of its largest
// motion from the neutral (docs/fidelity.md).
#pragma once

#include <algorithm>
#include <cstddef>

#include "fitting/compare.h"

namespace mimetic::test {

inline CompareOptions MovedRegion(const MeshData& neutral, const MeshData& target) {
  double largest = 0;
  for (size_t v = 0; v < target.vertex_count(); ++v)
    largest = std::max(largest, double(Length(target.positions[v] - neutral.positions[v])));
  CompareOptions o;
  o.neutral = &neutral;
  o.region.kind = CompareRegion::Kind::kMoved;
  o.region.threshold = float(0.02 * largest);
  return o;
}

}  // namespace mimetic::test

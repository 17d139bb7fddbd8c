// geometry/normal_field.h: a mesh's rest normals averaged over a ball, the normal a `tangent`
// muscle projects its motion on (docs/model.md §2-3, "Motion").
//
// A point's own normal turns fast where the surface does (round the eye openings, across the
// fold above an upper lid, off the nose bridge): projected on it, a smooth pull becomes a
// motion that changes direction from one point to the next, and the skin folds. Averaged over
// a ball about as wide as the muscle, the normal follows the surface the muscle slides over
// and not its small folds:
//
//   nbar(p) = normalize( sum over cells c with |x_c - p| < r of w(|x_c - p| / r) N_c ),
//   w(t) = (1 - t^2)^2
//
// The cells are the non-empty cubes of side r / 8 of a grid anchored at the origin; a cell's
// N_c is the sum of A_q n_q over its points q, and x_c their area-weighted centroid. n_q is q's
// unit area-weighted normal (geometry/normals.h) and A_q a third of the area of the triangles
// that use q, so the average does not depend on how densely a region is meshed. Summing the
// points one by one (the definition with every point its own cell) costs as many terms as there
// are points in the ball, thousands on a dense head; the cells bound that by about 200 and move
// a normal by under 1% (tests/geometry/normal_field_test.cpp measures both). w is a compact
// kernel that reaches 0 with zero slope at r, so nbar is a smooth function of p: neighbouring
// points project on nearly the same plane, which is what keeps a tangent muscle from folding
// the skin. Every point in the ball counts, the small inward-facing patches (a lid's or a lip's
// inner roll) included: leaving out points that face away from p was tried and makes nbar
// jump where the surface turns past 90 degrees, which folded the sample head's eye corners.
// Where the mean |sum w N_c| / sum w A_c is shorter than 0.05 (both sides of a thin sheet in
// the ball, cancelling) p keeps its own normal. r <= 0 gives the points' own normals.
#pragma once

#include <cstdint>
#include <map>
#include <vector>

#include "core/math.h"
#include "core/span.h"

namespace mimetic {

class NormalField {
 public:
  // `points` and `triangles` (3 indices each, into points) are copied; nothing is computed
  // until the first At(). Points at exactly the same position (a UV seam's copies) share one
  // normal and split their area.
  NormalField(span<const float3> points, span<const uint32_t> triangles);

  // The unit normal of every point averaged over a ball of `radius` (mesh units); the
  // points' own unit normals for radius <= 0 or not finite. Computed once per radius and kept.
  const std::vector<float3>& At(float radius);

  // A third of the area of the triangles that use each point (the weights A_q above).
  const std::vector<double>& Areas();

 private:
  void Prepare();

  std::vector<float3> points_, own_;
  std::vector<uint32_t> triangles_;
  bool prepared_ = false;
  std::vector<double> area_;
  std::map<float, std::vector<float3>> smoothed_;
};

}  // namespace mimetic

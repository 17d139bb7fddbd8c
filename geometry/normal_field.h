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
#include <unordered_map>
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

  // The same normal for one point (bit for bit At(radius)[point]), computing only the cell of
  // side radius / 8 that holds it: a muscle asks for the points it reaches, a small part of a
  // head, and leaves the rest of the mesh unsummed. A point out of range gives (0, 0, 0).
  float3 At(float radius, uint32_t point);

  // A third of the area of the triangles that use each point (the weights A_q above).
  const std::vector<double>& Areas();

 private:
  // One radius's sources, the points grouped by cell, and the normals of the cells done so far.
  struct Smoothed {
    struct Source {
      int64_t c[3];
      double area = 0, n[3] = {0, 0, 0}, x[3] = {0, 0, 0};
    };
    std::vector<Source> sources;
    std::unordered_map<uint64_t, std::vector<uint32_t>> blocks;  // sources by block of side r
    std::vector<uint32_t> point_cell;                            // UINT32_MAX: not finite
    std::vector<uint32_t> cell_start, cell_points;               // points by cell, first-seen order
    std::vector<uint8_t> cell_done;
    size_t cells_left = 0;
    std::vector<float3> out;
  };
  void Prepare();
  Smoothed& FieldOf(float radius);
  void SolveCell(float radius, Smoothed& f, uint32_t cell);

  std::vector<float3> points_, own_;
  std::vector<uint32_t> triangles_;
  bool prepared_ = false;
  std::vector<double> area_;
  std::map<float, Smoothed> smoothed_;
  std::vector<uint32_t> near_;  // SolveCell's scratch
};

}  // namespace mimetic

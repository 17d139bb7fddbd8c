// geometry/refine_estimate.h: how many triangles RefineMesh (refine.h) would make, estimated
// before it runs (issue 11: legal but tiny wrinkle sizes drove refinement to millions of
// triangles and tens of seconds, with only a warning at the end). Kept apart from refine.cpp.
#pragma once

#include <cstddef>

#include "geometry/mesh.h"
#include "geometry/refine.h"

namespace mimetic {

// Per input triangle: the target edge t, the smallest of `max_edge` at its centroid and its
// edge midpoints (the places RefineMesh samples), but not below RefineMesh's floor of 2e-4 of
// the bounding-box diagonal; when the longest edge L exceeds t, longest-edge bisection needs
// p = ceil(log2(L / t)) passes (at most options.max_passes), each of which splits a triangle
// into at most 4, so the triangle becomes at most 4^p triangles; otherwise it stays 1. Returns
// the sum (an upper bound for the triangles themselves; the splits a neighbour's refinement
// forces across a shared edge are not counted, so it can miss by a factor of about 2 at the
// edge of a refined region). O(#T) field samples. An empty mesh gives 0.
double EstimateRefinedTriangles(const MeshData& mesh, const EdgeLengthField& max_edge,
                                const RefineOptions& options);

}  // namespace mimetic

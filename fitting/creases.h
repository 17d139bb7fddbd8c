// fitting/creases.h: how sharply a muscle folds the skin along the edges of its zone, the
// crease number of docs/model.md §2-3 (the measure that compares Waters' fall-offs with the
// smooth ones).
//
// For muscle m alone at activation 1 (the muscle displacement only: X1 = X + U_m), the change
// of dihedral angle of every interior edge of the welded mesh, |theta(X1) - theta(X)| in
// degrees, theta the angle between the edge's two face normals. The band: points on either
// side of the zone's boundary (a point m moves with a neighbour it does not move, and that
// neighbour), grown by `rings` rings of neighbours; an edge counts when both of its points are
// in the band. The muscle's crease number is the largest change in its band; the rig's is the
// largest over its muscles.
//
// Slivers are left out: an edge counts only when both of its triangles have an altitude of at
// least `min_shape` times their longest edge (default kCreaseMinShape). A sliver of altitude h
// turns its normal by about d / h when its apex moves by d: on the sample head's chin, 0.07 mm
// high slivers 18 mm long turn by 50 degrees for 0.04 mm of motion, a number about the mesh,
// not about a fold of the skin (docs/model.md §2-3).
#pragma once

#include "geometry/normals.h"

#include <cstdint>
#include <vector>

#include "core/math.h"
#include "core/span.h"
#include "geometry/topology.h"
#include "rig/offline/rig_builder.h"
#include "rig/runtime/rig.h"

namespace mimetic {

// The smallest altitude / longest edge of a triangle whose edges the crease number measures.
inline constexpr double kCreaseMinShape = kSliverShape;  // geometry/normals.h

struct CreaseReport {
  std::vector<float> muscle_degrees;   // per muscle, rig order (0 for a muscle that moves nothing)
  std::vector<uint32_t> band_edges;    // per muscle: edges measured
  std::vector<float3> worst_at;        // per muscle: the rest midpoint of its worst edge
  float max_degrees = 0.f;             // over the muscles
  uint32_t worst_muscle = 0;
  uint32_t sliver_edges = 0;           // interior edges of the mesh left out as slivers'
};

// Measures every muscle of `rig`. `rings` >= 0 (2 is the documented default); `min_shape` 0
// measures every edge.
CreaseReport MeasureCreases(const Rig& rig, int rings = 2, double min_shape = kCreaseMinShape);

// `spec` built on `mesh` with every muscle's fall-off set to `falloff`: the two rigs a crease
// comparison measures (Waters' against smooth on the same placement). BuildRig's result.
bool BuildRigWithFalloff(RigSpec spec, const MeshData& mesh, MuscleFalloff falloff, Rig* out,
                         Diagnostics* diag);

// The same measure for any displacement field on one mesh (the calibration's crease rule,
// fitting/calibrate.h): built once per mesh, then one field at a time.
class CreaseMeter {
 public:
  CreaseMeter(span<const float3> rest, span<const uint32_t> triangles, int rings = 2,
              double min_shape = kCreaseMinShape);
  // Interior edges left out because a triangle beside them is a sliver.
  uint32_t sliver_edges() const { return sliver_edges_; }
  // The crease number of `moved` (one displacement per point; a point moves when its
  // displacement is not exactly zero), degrees; *band_edges (optional) = edges measured,
  // *worst_at (optional) = the rest midpoint of the edge that folds most (rest[0] when none).
  double Measure(span<const float3> displacement, uint32_t* band_edges = nullptr,
                 float3* worst_at = nullptr) const;

 private:
  std::vector<float3> rest_;
  std::vector<uint32_t> tris_;
  int rings_;
  EdgeTable edges_;
  CsrTable neighbours_;
  std::vector<float> rest_angle_;  // NaN: a sliver's edge, not measured
  uint32_t sliver_edges_ = 0;
};

}  // namespace mimetic

// wrinkles/runtime/strain_jobs.h: per-frame skin strain measures on the welded points
// (docs/model.md §4-5; Bando et al. 2003 eq. 1, Bando et al. 2002 eq. 4, Zhang et al. 2005 eq. 9-10).
//
// Job conventions (DESIGN.md), shared by every job of wrinkles/runtime:
// - A job owns nothing and allocates nothing. `Run()` calls `Validate()` first and leaves every
//   output untouched when it returns false. No exceptions, no logging.
// - Each job works on the rows [begin, end) of its table (triangles, points or table rows as
//   stated); the caller sets both explicitly (the default empty range does nothing). Every row
//   is computed from inputs only, so splitting a range across threads gives bit-identical
//   results. Spans indexed by row must hold at least `end` rows; spans read through an index
//   (positions, normals) must hold every index the rows [begin, end) refer to: Validate() checks
//   those indices (a pass over the range), so a bad table is refused rather than read out of
//   bounds.
// - Positions are welded points, `float3` in mesh units; triangles are 3 point indices each.
#pragma once

#include <cstddef>
#include <cstdint>

#include "core/math.h"
#include "core/span.h"

namespace mimetic {

// Per-triangle area ratio S'_i / S_i (docs/model.md §4, 002 eq. 1). Rows are triangles.
struct TriangleAreaRatioJob {
  bool Validate() const;
  bool Run() const;

  span<const float3> positions;     // current points, mesh units; every index used must exist
  span<const uint32_t> triangles;   // 3 point indices per triangle; >= 3 * end
  span<const float> rest_areas;     // S_i, rest area per triangle, mesh units^2, > 0 (the
                                    // builder rejects degenerate rest triangles); >= end.
                                    // A non-positive value gives ratio 1 (never NaN).
  size_t begin = 0;                 // first triangle
  size_t end = 0;                   // one past the last triangle
  span<float> out_ratios;           // S'_i / S_i per triangle, >= 0 (0 when collapsed); >= end
};

// Per-point area ratio r_j = mean of the ratios of its triangles (docs/model.md §4, 002 eq. 1).
// Rows are points. r = 1 at rest, -> 0 compressed, > 1 stretched; a point with no triangle
// gets 1.
struct PointAreaRatioJob {
  bool Validate() const;
  bool Run() const;

  span<const float> triangle_ratios;       // from TriangleAreaRatioJob, one per triangle
  span<const uint32_t> offsets;            // point -> triangle CSR offsets, >= end + 1,
                                           // non-decreasing over [begin, end]
  span<const uint32_t> point_triangles;    // triangle indices, >= offsets[end]; each < #T
  size_t begin = 0;                        // first point
  size_t end = 0;                          // one past the last point
  span<float> out_ratios;                  // r per point, >= 0; >= end
};

// Edge compression rate eps_i (docs/model.md §5, 001 eq. 9-10) over the rows of a table: row i is
// point points[i] with neighbours neighbors[offsets[i] .. offsets[i+1]):
//   tau_ij = (L_ij - |x_i - x_j|) / L_ij,   eps_i = sum_j w_ij tau_ij / sum_j w_ij,
// with w_ij = |cos theta_ij| (docs/model.md §5 choice: both sides of the point count).
// **choice**: w_ij is computed once on the REST edge and the contraction direction (see
// ComputeCompressionWeights in wrinkles/offline), so a collapsed edge keeps its weight and
// eps reaches 1 when everything collapses; it differs from using the current edge direction
// only at second order in the deformation. eps = 0 at rest, < 0 stretched, 1 fully collapsed;
// a row whose weights sum to 0 gets 0.
struct EdgeCompressionJob {
  bool Validate() const;
  bool Run() const;

  span<const float3> positions;         // current points, mesh units; every index used must exist
  span<const uint32_t> points;          // point of each row; >= end
  span<const uint32_t> offsets;         // row -> neighbour CSR offsets; >= end + 1,
                                        // non-decreasing over [begin, end]
  span<const uint32_t> neighbors;       // neighbour points x_j; >= offsets[end]
  span<const float> rest_lengths;       // L_ij per neighbour entry, mesh units, > 0 (an entry
                                        // with L <= 0 counts as tau = 0); >= offsets[end]
  span<const float> weights;            // w_ij = |cos theta_ij| per entry, >= 0; >= offsets[end]
  size_t begin = 0;                     // first row
  size_t end = 0;                       // one past the last row
  span<float> out_compression;          // eps per row, <= 1; >= end
};

// One side of a directional shrinkage probe (000 eq. 4): the triangle (v1, v2, v3) hit from v1
// along +dp or -dp in texture space, found when the rig is compiled.
struct ShrinkageSide {
  uint32_t v2 = 0, v3 = 0;     // the points of the edge opposite v1
  float beta = 0.f;            // where the ray crosses v2v3 in texture space: (1-beta) v2 +
                               // beta v3, in [0, 1]
  float rest_length2 = 0.f;    // |X2 - X1| at rest, mesh units, > 0
  float rest_length3 = 0.f;    // |X3 - X1| at rest, mesh units, > 0
};

// A (point, direction) sample of the directional shrinkage s (000 eq. 4), precomputed by
// BuildShrinkageProbe (wrinkles/offline).
struct ShrinkageProbe {
  uint32_t point = 0;          // v1
  uint32_t side_count = 0;     // 0 (s = 0), 1 (boundary) or 2 (+dp and -dp); > 2 is invalid
  ShrinkageSide sides[2];
};

// Directional shrinkage s per probe (docs/model.md §5, 000 eq. 4). For a side with 3D edge length
// ratios t2 = |x2 - x1| / |X2 - X1| and t3 likewise, scaling the texture-space edges v1v2, v1v3
// by t2, t3 moves the crossing of the ray from v1 so that
//   L'/L = 1 / ((1 - beta)/t2 + beta/t3) = t2 t3 / ((1 - beta) t3 + beta t2),
//   s = 1 - L'/L   (0 when the denominator vanishes: both edges collapsed, s = 1),
// and the probe's s is the mean over its sides. s = 0 rest, < 0 stretched, -> 1 shrunk.
struct DirectionalShrinkageJob {
  bool Validate() const;
  bool Run() const;

  span<const float3> positions;          // current points, mesh units; every index used must exist
  span<const ShrinkageProbe> probes;     // >= end
  size_t begin = 0;                      // first probe
  size_t end = 0;                        // one past the last probe
  span<float> out_shrinkage;             // s per probe, <= 1; >= end
};

// Shrinkage of one side (exposed for tests and the fine-scale modulation): t2, t3 >= 0.
inline float SideShrinkage(float t2, float t3, float beta) {
  const float den = (1.f - beta) * t3 + beta * t2;
  const float ratio = den > 1e-30f ? t2 * t3 / den : 0.f;
  return 1.f - ratio;
}

// SideShrinkage from lengths: with t2 = l2 / L2 and t3 = l3 / L3 (a rest length that is not
// positive gives t = 1, as l = L = 1), L'/L = l2 l3 / ((1 - beta) l3 L2 + beta l2 L3): the same
// value with one division instead of three (rounding aside). Exactly 0 when both edges have
// their rest lengths (as SideShrinkage(1, 1, beta): 1 - beta rounds so that adding beta gives 1).
inline float SideShrinkageFromLengths(float l2, float l3, float rest2, float rest3, float beta) {
  if (!(rest2 > 0.f)) l2 = rest2 = 1.f;
  if (!(rest3 > 0.f)) l3 = rest3 = 1.f;
  if (l2 == rest2 && l3 == rest3) return 0.f;
  const float den = (1.f - beta) * (l3 * rest2) + beta * (l2 * rest3);
  return 1.f - (den > 0.f ? l2 * l3 / den : 0.f);
}

// s of one probe from its sides' current lengths: length(side, 0) = |x2 - x1|, length(side, 1)
// = |x3 - x1| (DirectionalShrinkageJob's per-probe step; EvaluateJob feeds it edge lengths
// computed once per edge).
template <class LengthFn>
inline float ProbeShrinkage(const ShrinkageProbe& probe, const LengthFn& length) {
  float sum = 0.f;
  for (uint32_t s = 0; s < probe.side_count; ++s) {
    const ShrinkageSide& side = probe.sides[s];
    sum += SideShrinkageFromLengths(length(s, 0), length(s, 1), side.rest_length2,
                                    side.rest_length3, side.beta);  // 000 eq. 4
  }
  // 000 §7: average the two triangles hit along +dp and -dp (side_count is at most 2, and
  // halving is exact: no division).
  return probe.side_count == 2 ? 0.5f * sum : sum;
}

}  // namespace mimetic

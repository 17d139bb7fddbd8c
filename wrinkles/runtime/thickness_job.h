// wrinkles/runtime/thickness_job.h: volume-preserving skin thickness (docs/model.md §4, Bando et al.
// 2003 eq. 3). Job conventions: see strain_jobs.h.
#pragma once

#include <cstddef>

#include "core/math.h"
#include "core/span.h"

namespace mimetic {

// Default lower clamp of the area ratio r (docs/model.md §4 choice): a point whose triangles
// collapse is pushed out by at most (1/0.05 - 1) h = 19 h instead of to infinity.
inline constexpr float kDefaultMinAreaRatio = 0.05f;

// The offset along the normal, (1/max(r, r_min) - 1) h (docs/model.md §4, 002 eq. 3); NaN r counts
// as r_min. ThicknessJob uses it; EvaluateJob folds the same clamp into its one division per
// point (DisplacePoint in rig/runtime/evaluate_job.cpp).
inline float ThicknessOffset(float r, float h, float min_area_ratio) {
  if (!(r >= min_area_ratio)) r = min_area_ratio;
  return (1.f / r - 1.f) * h;
}

// x' = x + (1/max(r, r_min) - 1) h N per point: the subcutaneous layer of thickness h under a
// surface element whose area became r times its rest area keeps its volume h dS (002 eq. 3), so
// the new thickness is h/r. r > 1 (stretched) moves the point inward, by at most h. Rows are
// points.
struct ThicknessJob {
  bool Validate() const;
  bool Run() const;

  span<const float3> positions;        // X1, current points, mesh units; >= end
  span<const float3> normals;          // N1, unit normals of X1 (a zero normal gives no
                                       // displacement); >= end
  span<const float> area_ratios;       // r per point (PointAreaRatioJob), >= 0; NaN counts as
                                       // r_min; >= end
  span<const float> thickness;         // h per point, mesh units, >= 0 (per-vertex attribute or
                                       // sampled from the thickness map offline); >= end, or
                                       // empty to use `constant_thickness` everywhere
  float constant_thickness = 0.f;      // h, mesh units, >= 0, used when `thickness` is empty
  float min_area_ratio = kDefaultMinAreaRatio;  // r_min, in (0, 1]; Validate refuses <= 0
  size_t begin = 0;                    // first point
  size_t end = 0;                      // one past the last point
  span<float3> out_positions;          // X2 per point; >= end; may be the same span as
                                       // `positions` (each point reads then writes itself)
};

}  // namespace mimetic

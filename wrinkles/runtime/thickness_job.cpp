// wrinkles/runtime/thickness_job.cpp: docs/model.md §4 thickness (see thickness_job.h).
#include "wrinkles/runtime/thickness_job.h"

namespace mimetic {

bool ThicknessJob::Validate() const {
  if (begin > end || positions.size() < end || normals.size() < end ||
      area_ratios.size() < end || out_positions.size() < end) {
    return false;
  }
  if (!thickness.empty() && thickness.size() < end) return false;
  return min_area_ratio > 0.f && min_area_ratio <= 1.f;  // also refuses NaN
}

bool ThicknessJob::Run() const {
  if (!Validate()) return false;
  const bool per_point = !thickness.empty();
  for (size_t p = begin; p < end; ++p) {
    const float h = per_point ? thickness[p] : constant_thickness;
    out_positions[p] = positions[p] + normals[p] * ThicknessOffset(area_ratios[p], h, min_area_ratio);
  }
  return true;
}

}  // namespace mimetic

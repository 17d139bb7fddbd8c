// wrinkles/runtime/strain_jobs.cpp: docs/model.md §4-5 strain measures (see strain_jobs.h).
#include "wrinkles/runtime/strain_jobs.h"

#include <cmath>

#include "wrinkles/runtime/job_util.h"

namespace mimetic {

// ----------------------------------------------------------------------------------------------
bool TriangleAreaRatioJob::Validate() const {
  if (begin > end || triangles.size() / 3 < end || rest_areas.size() < end ||
      out_ratios.size() < end) {
    return false;
  }
  return detail::IndicesBelow(triangles.subspan(3 * begin, 3 * (end - begin)), positions.size());
}

bool TriangleAreaRatioJob::Run() const {
  if (!Validate()) return false;
  for (size_t t = begin; t < end; ++t) {
    const float3 a = positions[triangles[3 * t]];
    const float3 b = positions[triangles[3 * t + 1]];
    const float3 c = positions[triangles[3 * t + 2]];
    const float area = 0.5f * Length(Cross(b - a, c - a));  // docs/model.md §4: S'_i
    const float rest = rest_areas[t];
    out_ratios[t] = rest > 0.f ? area / rest : 1.f;
  }
  return true;
}

// ----------------------------------------------------------------------------------------------
bool PointAreaRatioJob::Validate() const {
  if (!detail::RowsValid(begin, end, offsets, point_triangles.size()) ||
      out_ratios.size() < end) {
    return false;
  }
  return detail::IndicesBelow(
      point_triangles.subspan(offsets[begin], offsets[end] - offsets[begin]),
      triangle_ratios.size());
}

bool PointAreaRatioJob::Run() const {
  if (!Validate()) return false;
  for (size_t p = begin; p < end; ++p) {
    const uint32_t first = offsets[p], last = offsets[p + 1];
    if (first == last) {
      out_ratios[p] = 1.f;
      continue;
    }
    float sum = 0.f;
    for (uint32_t k = first; k < last; ++k) sum += triangle_ratios[point_triangles[k]];
    out_ratios[p] = sum / static_cast<float>(last - first);  // docs/model.md §4: mean over I_j
  }
  return true;
}

// ----------------------------------------------------------------------------------------------
bool EdgeCompressionJob::Validate() const {
  if (points.size() < end || out_compression.size() < end ||
      !detail::RowsValid(begin, end, offsets, neighbors.size())) {
    return false;
  }
  const size_t entries = offsets[end];
  if (rest_lengths.size() < entries || weights.size() < entries) return false;
  const size_t first = offsets[begin];
  return detail::IndicesBelow(points.subspan(begin, end - begin), positions.size()) &&
         detail::IndicesBelow(neighbors.subspan(first, entries - first), positions.size());
}

bool EdgeCompressionJob::Run() const {
  if (!Validate()) return false;
  for (size_t i = begin; i < end; ++i) {
    const float3 xi = positions[points[i]];
    float num = 0.f, den = 0.f;
    for (uint32_t k = offsets[i]; k < offsets[i + 1]; ++k) {
      const float rest = rest_lengths[k];
      const float w = weights[k];
      // 001 eq. 9: tau_ij = (L_ij - |x_i - x_j|) / L_ij.
      const float tau = rest > 0.f ? (rest - Length(xi - positions[neighbors[k]])) / rest : 0.f;
      num += w * tau;
      den += w;
    }
    // 001 eq. 10 with |cos| weights (docs/model.md §5 choice).
    out_compression[i] = den > 0.f ? num / den : 0.f;
  }
  return true;
}

// ----------------------------------------------------------------------------------------------
bool DirectionalShrinkageJob::Validate() const {
  if (begin > end || probes.size() < end || out_shrinkage.size() < end) return false;
  const size_t n = positions.size();
  for (size_t k = begin; k < end; ++k) {
    const ShrinkageProbe& probe = probes[k];
    if (probe.point >= n || probe.side_count > 2) return false;
    for (uint32_t s = 0; s < probe.side_count; ++s) {
      if (probe.sides[s].v2 >= n || probe.sides[s].v3 >= n) return false;
    }
  }
  return true;
}

bool DirectionalShrinkageJob::Run() const {
  if (!Validate()) return false;
  for (size_t k = begin; k < end; ++k) {
    const ShrinkageProbe& probe = probes[k];
    const float3 x1 = positions[probe.point];
    out_shrinkage[k] = ProbeShrinkage(probe, [&](uint32_t s, int which) {
      const ShrinkageSide& side = probe.sides[s];
      return Length(positions[which == 0 ? side.v2 : side.v3] - x1);
    });
  }
  return true;
}

}  // namespace mimetic

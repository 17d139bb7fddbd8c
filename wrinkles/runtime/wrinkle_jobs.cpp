// wrinkles/runtime/wrinkle_jobs.cpp: docs/model.md §6-8 wrinkle displacement (see wrinkle_jobs.h).
#include "wrinkles/runtime/wrinkle_jobs.h"

#include <cmath>

#include "wrinkles/runtime/job_util.h"
#include "wrinkles/runtime/profiles.h"

namespace mimetic {

// ----------------------------------------------------------------------------------------------
float MuscleWrinkleProfile(float phase, float half_cycle, float furrow_depth, float shape,
                           float attenuation) {
  return ZhangShape(phase, half_cycle, furrow_depth, shape) * ClampOrLow(attenuation, 0.f, 1.f);
}

bool MuscleWrinkleJob::Validate() const {
  if (begin > end || points.size() < end || compression.size() < end) return false;
  if (!out_amplitudes.empty() && out_amplitudes.size() < end) return false;
  if (!(gate >= 0.f && gate <= 1.f)) return false;
  if (!profile.empty()) {
    if (profile.size() < end) return false;
  } else if (phase.size() < end || attenuation.size() < end || !(half_cycle > 0.f) ||
             !std::isfinite(half_cycle) || !std::isfinite(furrow_depth) || !std::isfinite(shape)) {
    return false;
  }
  const auto rows = points.subspan(begin, end - begin);
  return detail::IndicesBelow(rows, normals.size()) && detail::IndicesBelow(rows, positions.size());
}

bool MuscleWrinkleJob::Run() const {
  if (!Validate()) return false;
  for (size_t i = begin; i < end; ++i) {
    // 001 eq. 4: W = H(w_i) A(eps_i) At_i (docs/model.md §6), times the gate G (1 without).
    const float h_at = profile.empty()
                           ? MuscleWrinkleProfile(phase[i], half_cycle, furrow_depth, shape,
                                                  attenuation[i])
                           : profile[i];
    const float w = h_at * Anisotropy(compression[i]) * gate;
    const uint32_t p = points[i];
    positions[p] += normals[p] * w;
    if (!out_amplitudes.empty()) out_amplitudes[i] = w;
  }
  return true;
}

// ----------------------------------------------------------------------------------------------
float CurveWrinkleValue(const CurveWrinkleParams& p, float l, float s, float r) {
  const bool directional = p.modulation == CurveWrinkleModulation::kDirectional;
  if (p.profile == CurveWrinkleProfile::kBando) {
    // 000 eq. 2 times 000 eq. 5 or 002 eq. 6 (docs/model.md §7).
    const float m = directional ? DirectionalModulation(s, p.rest_amplitude)
                                : AreaModulation(r, p.rest_amplitude);
    return CurveProfile(l, p.depth, p.width) * m;
  }
  // Yang-Zhang (docs/model.md §8): skin length ratio across the furrow, a = S a0 (004 eq. 8).
  float S = directional ? 1.f - s : r;
  if (!(S >= 0.f)) S = S != S ? 1.f : 0.f;
  if (!(S < 1e6f)) S = 1e6f;  // far past the point where the depth is 0
  const float a = S * p.width;
  const float h = p.profile == CurveWrinkleProfile::kYangZhang
                      ? YangZhangDepth(p.depth, p.width, S)
                      : static_cast<float>(YangZhangDepthNewton(p.depth, p.width, S,
                                                                p.rest_length,
                                                                YangZhangSpan::kFlank));
  return YangZhangProfile(l, a, h);
}

bool CurveWrinkleJob::Validate() const {
  if (points.size() < end || !detail::RowsValid(begin, end, offsets, entries.size())) {
    return false;
  }
  if (!out_amplitudes.empty() && out_amplitudes.size() < end) return false;
  bool any_directional = false, any_area = false;
  for (const CurveWrinkleParams& p : wrinkles) {
    if (p.profile != CurveWrinkleProfile::kBando && p.profile != CurveWrinkleProfile::kYangZhang &&
        p.profile != CurveWrinkleProfile::kYangZhangExact) {
      return false;
    }
    if (p.modulation == CurveWrinkleModulation::kDirectional) {
      any_directional = true;
    } else if (p.modulation == CurveWrinkleModulation::kArea) {
      any_area = true;
    } else {
      return false;
    }
  }
  if (any_directional && entry_shrinkage.size() < offsets[end]) return false;
  const auto rows = points.subspan(begin, end - begin);
  if (!detail::IndicesBelow(rows, normals.size()) || !detail::IndicesBelow(rows, positions.size())) {
    return false;
  }
  if (any_area && !detail::IndicesBelow(rows, area_ratios.size())) return false;
  for (uint32_t k = offsets[begin]; k < offsets[end]; ++k) {
    if (entries[k].wrinkle >= wrinkles.size()) return false;
  }
  return true;
}

bool CurveWrinkleJob::Run() const {
  if (!Validate()) return false;
  for (size_t i = begin; i < end; ++i) {
    const uint32_t p = points[i];
    // area_ratios may be short when every wrinkle is directional (then r is not used).
    const float r = p < area_ratios.size() ? area_ratios[p] : 1.f;
    const float sum = CurveWrinkleRowSum(wrinkles.data(), entries.data(), offsets[i],
                                         offsets[i + 1], entry_shrinkage.data(), r);
    positions[p] += normals[p] * sum;  // docs/model.md §7: x' = x + S(l) M N
    if (!out_amplitudes.empty()) out_amplitudes[i] = sum;
  }
  return true;
}

}  // namespace mimetic

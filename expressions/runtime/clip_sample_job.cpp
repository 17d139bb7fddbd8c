// expressions/runtime/clip_sample_job.cpp: the sampling job (docs/expressions.md).
// Cubic segments are cubic Hermite splines (Fritsch & Carlson, "Monotone piecewise cubic
// interpolation", SIAM J. Numer. Anal. 17(2), 1980); the builder limits the tangents so each
// segment is monotone between its two keys, and the clamp below keeps that true after rounding.
#include "expressions/runtime/clip_sample_job.h"

#include <algorithm>
#include <cmath>

namespace mimetic {
namespace {

inline float Clamp01(float v) { return v < 0.f ? 0.f : (v > 1.f ? 1.f : v); }

inline float ClampBetween(float v, float a, float b) {
  const float lo = a < b ? a : b, hi = a < b ? b : a;
  return v < lo ? lo : (v > hi ? hi : v);
}

// Apply: one channel's value onto the activations (the layer rules of clip.h).
inline void Apply(const CompiledClip& clip, uint32_t c, float value, float* a, float* jaw) {
  const uint32_t target = clip.targets()[c];
  if (clip.kinds()[c] == ClipChannelKind::kMuscle) {
    a[target] = value;
    return;
  }
  if (clip.kinds()[c] == ClipChannelKind::kJaw) {
    *jaw = value;
    return;
  }
  // The expression's jaw value, under the layer's rule (a jaw it does not name adds 0).
  const float ej = clip.expression_jaws()[target];
  switch (clip.layers()[c]) {
    case ClipLayer::kAdd: *jaw = std::min(1.f, *jaw + value * ej); break;
    case ClipLayer::kMax: *jaw = std::max(*jaw, value * ej); break;
    case ClipLayer::kOverride:
      if (clip.expression_jaw_masks()[target]) *jaw = Clamp01(*jaw + value * (ej - *jaw));
      break;
  }
  const uint32_t n = clip.muscle_count();
  const float* e = clip.expression_activations().data() + size_t(target) * n;
  switch (clip.layers()[c]) {
    case ClipLayer::kAdd:
      for (uint32_t m = 0; m < n; ++m) a[m] = std::min(1.f, a[m] + value * e[m]);
      break;
    case ClipLayer::kMax:
      for (uint32_t m = 0; m < n; ++m) a[m] = std::max(a[m], value * e[m]);
      break;
    case ClipLayer::kOverride: {
      const uint8_t* mask = clip.expression_masks().data() + size_t(target) * n;
      for (uint32_t m = 0; m < n; ++m)
        if (mask[m]) a[m] = Clamp01(a[m] + value * (e[m] - a[m]));
      break;
    }
  }
}

}  // namespace

float HermiteSegment(float t0, float v0, float m0, float t1, float v1, float m1, float t) {
  const float h = t1 - t0;
  const float s = (t - t0) / h;
  const float s2 = s * s, s3 = s2 * s;
  const float h00 = 2.f * s3 - 3.f * s2 + 1.f;
  const float h10 = s3 - 2.f * s2 + s;
  const float h01 = -2.f * s3 + 3.f * s2;
  const float h11 = s3 - s2;
  const float p = h00 * v0 + h10 * (h * m0) + h01 * v1 + h11 * (h * m1);
  return ClampBetween(p, v0, v1);
}

float ClipLocalTime(const CompiledClip& clip, float time) {
  if (std::isnan(time)) return 0.f;
  const float d = clip.duration();
  if (clip.end() == ClipEnd::kClamp || !(d > 0.f)) return std::clamp(time, 0.f, d);
  if (!std::isfinite(time)) return 0.f;
  // In double: t - d floor(t / d) is exact for the float inputs of a clip's range of use, and
  // the guard below catches the rounding at the period's ends.
  const double dd = double(d);
  const float local = float(double(time) - dd * std::floor(double(time) / dd));
  return local >= 0.f && local < d ? local : 0.f;
}

float SampleClipChannel(const CompiledClip& clip, uint32_t c, float t) {
  const uint32_t begin = clip.key_offsets()[c], end = clip.key_offsets()[c + 1];
  const float* times = clip.key_times().data() + begin;
  const float* values = clip.key_values().data() + begin;
  const uint32_t n = end - begin;
  if (!(t > times[0])) return values[0];
  if (t >= times[n - 1]) return values[n - 1];
  // times[k] <= t < times[k + 1], 0 <= k < n - 1.
  const uint32_t k = uint32_t(std::upper_bound(times, times + n, t) - times) - 1;
  const float t0 = times[k], t1 = times[k + 1], v0 = values[k], v1 = values[k + 1];
  switch (clip.key_interps()[begin + k]) {
    case KeyInterp::kStep:
      return v0;
    case KeyInterp::kLinear:
      return ClampBetween(v0 + (t - t0) / (t1 - t0) * (v1 - v0), v0, v1);
    case KeyInterp::kCubic: {
      const float* m = clip.key_tangents().data() + begin;
      return HermiteSegment(t0, v0, m[k], t1, v1, m[k + 1], t);
    }
  }
  return v0;
}

bool ClipSampleJob::Validate() const {
  return clip && clip->built() && out_activations.size() >= clip->muscle_count();
}

bool ClipSampleJob::Run() const {
  if (!Validate()) return false;
  const CompiledClip& c = *clip;
  const float local = ClipLocalTime(c, time);
  float* a = out_activations.data();
  std::fill(a, a + c.muscle_count(), 0.f);
  float jaw = 0.f;
  for (uint32_t channel = 0; channel < c.channel_count(); ++channel)
    Apply(c, channel, SampleClipChannel(c, channel, local), a, &jaw);
  if (!out_jaw.empty()) out_jaw[0] = jaw;
  return true;
}

}  // namespace mimetic

// expressions/runtime/clip_sample_job.h: clip + time -> one activation per muscle
// (docs/expressions.md, "Sampling").
//
// Run() is a fixed sequence of named steps over the clip's plain arrays:
//   LocalTime      the time in the clip: NaN -> 0; clamp: into [0, duration] (+-inf clamp
//                  like any number); loop: t - duration * floor(t / duration), in
//                  [0, duration) (+-inf -> 0, having no phase)
//   Clear          out_activations[0, muscle_count) = 0
//   per channel c, in the clip's channel order (the file's order):
//     SampleChannel   binary search of the channel's key times (std::upper_bound); before the
//                     first key its value, from the last key on its value; between keys k and
//                     k + 1 the interpolation of key k: step, linear or cubic Hermite, the
//                     result clamped to the two key values (docs/expressions.md, "Cubic")
//     Apply           a muscle channel sets a[m] = v; an expression channel of weight w and
//                     activations e: add a = min(1, a + w e), max a = max(a, w e), override
//                     a = a + w (e - a) on the muscles the expression names; the jaw (0 at
//                     first) the same way: a jaw channel sets it, expressions that name it
//                     combine it
// Sampling is stateless: no cursor, no cache, so seeking to any time gives the same bits as
// playing up to it, and one clip may be sampled by many threads at once. Run() allocates
// nothing, throws nothing and reads only the clip and `time`.
#pragma once

#include <cstdint>

#include "core/span.h"
#include "expressions/runtime/clip.h"

namespace mimetic {

struct ClipSampleJob {
  // False when: clip is null or was never built (CompiledClip::built()); out_activations has
  // fewer than clip->muscle_count() floats. `time` is never a reason (NaN -> 0).
  bool Validate() const;
  // Validates first; on false, out_activations is untouched. Writes out_activations[0,
  // clip->muscle_count()) (each in [0, 1]); floats past that are left alone; and out_jaw[0]
  // (in [0, 1], 0 when the clip does not animate the jaw) when out_jaw is not empty.
  bool Run() const;

  const CompiledClip* clip = nullptr;  // built by BuildClip; shared, read-only
  float time = 0.f;                    // seconds since the clip's start; any value
  span<float> out_activations;         // >= clip->muscle_count() floats, rig muscle order
  span<float> out_jaw;                 // empty, or >= 1 float: the jaw (EvaluateJob::jaw)
};

// The steps of Run(), for tests and tools (the clip must be built; channel < channel_count()).
// The time in the clip that `time` maps to (LocalTime above), in [0, duration].
float ClipLocalTime(const CompiledClip& clip, float time);
// The value of channel `channel` at clip time `local_time` (SampleChannel above), in [0, 1].
float SampleClipChannel(const CompiledClip& clip, uint32_t channel, float local_time);

// One cubic Hermite segment from (t0, v0) with slope m0 to (t1, v1) with slope m1 (values per
// second), at t in [t0, t1], t1 > t0; the result clamped to [min(v0, v1), max(v0, v1)].
//   s = (t - t0) / h, h = t1 - t0
//   p = (2s^3 - 3s^2 + 1) v0 + (s^3 - 2s^2 + s) h m0 + (-2s^3 + 3s^2) v1 + (s^3 - s^2) h m1
float HermiteSegment(float t0, float v0, float m0, float t1, float v1, float m1, float t);

}  // namespace mimetic

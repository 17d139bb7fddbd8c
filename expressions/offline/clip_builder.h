// expressions/offline/clip_builder.h: ClipSpec + the rig's muscle names + expressions ->
// CompiledClip (the offline "builder" of the runtime clip, expressions/runtime/clip.h).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "core/diagnostics.h"
#include "expressions/offline/clip_spec.h"
#include "expressions/runtime/clip.h"

namespace mimetic {

// An expression as the builder needs it: a name and muscle name -> activation in [0, 1]. (The
// expression file's `Expression` of io/expression_file.h carries the same two members; io sits
// above this module, so io/clip_file.h has the overload of BuildClip that takes those.)
struct ClipExpression {
  std::string name;
  std::vector<std::pair<std::string, float>> activations;
};

class ClipBuilder {
 public:
  // Checks `clip` (CheckClipSpec), resolves every channel and fills `out`; false (with every
  // problem recorded, `out` untouched) otherwise. Paths are the clip file's
  // (`channels[3].muscle: ...`); callers prefix the file name.
  //   - a muscle channel names a muscle of `muscle_names`, or NAME where the rig has no muscle
  //     NAME but has NAME_L and NAME_R (the channel then drives both, as `--set NAME=` does);
  //     an unknown name is an error listing the closest names; a muscle driven by two
  //     channels (`smile` and `smile_L`) is an error naming both;
  //   - an expression channel names one of `expressions` (an unknown name is an error listing
  //     the closest; a name given twice in `expressions` is an error when a channel uses it);
  //     every muscle the expression names must be in the rig (closest names listed), at most
  //     once, with an activation in [0, 1];
  //   - tangents are made and limited here (ClipTangents).
  // The compiled clip keeps the expressions its channels use, in the order of first use.
  static bool Build(const ClipSpec& clip, const std::vector<std::string>& muscle_names,
                    const std::vector<ClipExpression>& expressions, CompiledClip* out,
                    Diagnostics* diag);
};

inline bool BuildClip(const ClipSpec& clip, const std::vector<std::string>& muscle_names,
                      const std::vector<ClipExpression>& expressions, CompiledClip* out,
                      Diagnostics* diag) {
  return ClipBuilder::Build(clip, muscle_names, expressions, out, diag);
}

// The tangent (value per second) of every key of one channel (keys strictly increasing in t),
// docs/expressions.md "Tangents". With the secants d[j] = (v[j+1] - v[j]) / (t[j+1] - t[j]):
//   auto     key k inside: (v[k+1] - v[k-1]) / (t[k+1] - t[k-1]) (Catmull-Rom on uneven
//            spacing); the first key d[0], the last d[n-2]
//   clamped  key k inside: 0 where d[k-1] d[k] <= 0, else the Fritsch-Butland weighted
//            harmonic mean (w1 + w2) / (w1 / d[k-1] + w2 / d[k]), w1 = 2 h[k] + h[k-1],
//            w2 = h[k] + 2 h[k-1], h[j] = t[j+1] - t[j]; the first and last keys 0
// then, for both, the limiter: with the secants next to the key (one at an end, two inside),
//   m = 0 when a secant is 0, when the two have opposite signs, or when m's sign is not theirs;
//   else |m| = min(|m|, 3 min |d|).
// So every cubic segment has tangents m0 = a d, m1 = b d with a, b in [0, 3], the box where a
// cubic Hermite segment is monotone (Fritsch & Carlson 1980), and never leaves its two values.
// A single key gets 0. Computed in double, stored as float.
std::vector<float> ClipTangents(const std::vector<ClipKeySpec>& keys);

}  // namespace mimetic

// expressions/offline/clip_spec.h: a clip as authored (the "mimetic-clip" file of
// io/clip_file.h, docs/expressions.md), before it is resolved against a rig by BuildClip.
#pragma once

#include <string>
#include <vector>

#include "core/diagnostics.h"
#include "expressions/runtime/clip.h"

namespace mimetic {

// How a cubic key's tangent is made (docs/expressions.md, "Tangents"); both are limited so
// that no segment leaves its two key values.
enum class KeyTangent : uint8_t {
  kAuto = 0,     // Catmull-Rom: (v[k+1] - v[k-1]) / (t[k+1] - t[k-1]); an end key, its secant
  kClamped = 1,  // Fritsch-Butland weighted harmonic mean of the two secants; an end key, 0
};

struct ClipKeySpec {
  float t = 0.f;   // seconds, >= 0
  float v = 0.f;   // activation or weight, [0, 1]
  KeyInterp interp = KeyInterp::kLinear;  // from this key to the next
  KeyTangent tangent = KeyTangent::kAuto;
};

struct ClipChannelSpec {
  ClipChannelKind kind = ClipChannelKind::kMuscle;
  std::string target;                   // a muscle name (or NAME for NAME_L + NAME_R), or an
                                        // expression name
  ClipLayer layer = ClipLayer::kAdd;    // expression channels only
  std::vector<ClipKeySpec> keys;        // at least one, strictly increasing t
};

struct ClipSpec {
  std::string name;
  float duration = -1.f;                // seconds; < 0 = not given: the last key's time
  ClipEnd end = ClipEnd::kClamp;
  std::vector<ClipChannelSpec> channels;
};

// The clip's duration: `duration` when given (>= 0), else the latest key time (0 without keys).
float ClipDuration(const ClipSpec& clip);

// The rules of a clip that need no rig (docs/expressions.md, "Rules"), each error with the
// JSON path of the file's layout (`channels[2].keys[3].t`): a non-empty name; at least one
// channel; a non-empty target, named by at most one channel of its kind; at least one key per
// channel; key times finite, >= 0 and strictly increasing; values in [0, 1]; a given duration
// finite and > 0 and not before the last key; a looping clip with a duration > 0. Returns
// false when any error was recorded. The reader (io/clip_file.h), SaveClip and BuildClip all
// run it.
bool CheckClipSpec(const ClipSpec& clip, Diagnostics* diag);

}  // namespace mimetic

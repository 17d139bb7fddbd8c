// viewer/core/timeline.h: a clip's channels and keys as the timeline draws them, and playback.
#pragma once

#include <string>
#include <vector>

#include "expressions/offline/clip_spec.h"
#include "expressions/runtime/clip.h"

namespace mimetic::viewer {

struct TimelineChannel {
  std::string label;  // "muscle NAME", "expression NAME", "jaw"
  std::vector<float> key_times;   // seconds, ascending
  std::vector<float> key_values;  // in [0, 1]
};

// One row per channel of `clip`, in its order, with every key. Labels name the channel's target:
// a muscle from `muscle_names` (the rig's), an expression from `spec` (the clip file the clip
// was built from; nullptr for a compiled .mclip, whose expressions have no names: "expression
// #i").
std::vector<TimelineChannel> ListTimeline(const CompiledClip& clip,
                                          const std::vector<std::string>& muscle_names,
                                          const ClipSpec* spec);

// Playback: the playhead after `dt` seconds from `time` on a clip of `duration`: looping wraps
// into [0, duration), otherwise it stops at duration (and *stopped becomes true when it gets
// there). dt < 0 plays backwards the same way; duration <= 0 gives 0.
float AdvancePlayhead(float time, float dt, float duration, bool loop, bool* stopped);

}  // namespace mimetic::viewer

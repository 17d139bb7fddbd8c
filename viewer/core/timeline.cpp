// viewer/core/timeline.cpp: see timeline.h.
#include "viewer/core/timeline.h"

#include <cmath>

namespace mimetic::viewer {

std::vector<TimelineChannel> ListTimeline(const CompiledClip& clip,
                                          const std::vector<std::string>& muscle_names,
                                          const ClipSpec* spec) {
  std::vector<TimelineChannel> rows;
  if (!clip.built()) return rows;
  // A spec channel NAME may stand for NAME_L and NAME_R (two compiled channels); its labels
  // are used only when the channels correspond one to one.
  const bool spec_matches = spec && spec->channels.size() == clip.channel_count();
  for (uint32_t c = 0; c < clip.channel_count(); ++c) {
    TimelineChannel row;
    const uint32_t target = clip.targets()[c];
    switch (clip.kinds()[c]) {
      case ClipChannelKind::kMuscle:
        row.label = "muscle " + (target < muscle_names.size() ? muscle_names[target]
                                                              : "#" + std::to_string(target));
        break;
      case ClipChannelKind::kExpression:
        row.label = "expression " + (spec_matches ? spec->channels[c].target
                                                  : "#" + std::to_string(target));
        break;
      case ClipChannelKind::kJaw: row.label = "jaw"; break;
    }
    for (uint32_t k = clip.key_offsets()[c]; k < clip.key_offsets()[c + 1]; ++k) {
      row.key_times.push_back(clip.key_times()[k]);
      row.key_values.push_back(clip.key_values()[k]);
    }
    rows.push_back(std::move(row));
  }
  return rows;
}

float AdvancePlayhead(float time, float dt, float duration, bool loop, bool* stopped) {
  if (stopped) *stopped = false;
  if (!(duration > 0.f)) return 0.f;
  float t = time + (std::isfinite(dt) ? dt : 0.f);
  if (loop) {
    t -= duration * std::floor(t / duration);
    if (!(t < duration)) t = 0.f;  // rounding at the wrap
    return t;
  }
  if (t >= duration) {
    if (stopped) *stopped = true;
    return duration;
  }
  if (t <= 0.f) {
    if (stopped) *stopped = dt < 0.f;
    return 0.f;
  }
  return t;
}

}  // namespace mimetic::viewer

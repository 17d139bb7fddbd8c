#include "expressions/offline/clip_spec.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <map>

namespace mimetic {
namespace {

std::string Num(float f) {
  char buf[64];
  const auto res = std::to_chars(buf, buf + sizeof buf, f);
  return res.ec == std::errc() ? std::string(buf, res.ptr) : std::to_string(f);
}

std::string Channel(size_t i) { return "channels[" + std::to_string(i) + "]"; }

}  // namespace

float ClipDuration(const ClipSpec& clip) {
  if (clip.duration >= 0.f) return clip.duration;
  float last = 0.f;
  for (const ClipChannelSpec& c : clip.channels)
    if (!c.keys.empty() && c.keys.back().t > last) last = c.keys.back().t;
  return last;
}

bool CheckClipSpec(const ClipSpec& clip, Diagnostics* diag) {
  const size_t before = diag->ErrorCount();
  if (clip.name.empty()) diag->Error("name", "is empty; expected the clip's name");
  if (clip.channels.empty())
    diag->Error("channels", "is empty; expected at least one channel");
  if (clip.duration >= 0.f && !std::isfinite(clip.duration))
    diag->Error("duration", "is not finite; expected a number of seconds > 0");
  else if (clip.duration == 0.f)
    diag->Error("duration", "is 0; expected a number of seconds > 0 (or no duration: the last "
                            "key's time)");
  // Each target once per kind: the first channel naming it, by name.
  std::map<std::string, size_t> muscles, expressions;
  float last_time = 0.f;
  size_t last_channel = 0, last_key = 0;
  for (size_t i = 0; i < clip.channels.size(); ++i) {
    const ClipChannelSpec& c = clip.channels[i];
    const bool muscle = c.kind == ClipChannelKind::kMuscle;
    const std::string key = Channel(i) + (muscle ? ".muscle" : ".expression");
    if (c.target.empty()) {
      diag->Error(key, muscle ? "is empty; expected a muscle name"
                              : "is empty; expected an expression name");
    } else {
      auto& seen = muscle ? muscles : expressions;
      const auto [it, inserted] = seen.insert({c.target, i});
      if (!inserted)
        diag->Error(key, "\"" + c.target + "\" is already the target of " + Channel(it->second) +
                             "; expected each " + (muscle ? "muscle" : "expression") +
                             " in at most one channel");
    }
    if (c.keys.empty()) diag->Error(Channel(i) + ".keys", "is empty; expected at least one key");
    for (size_t k = 0; k < c.keys.size(); ++k) {
      const ClipKeySpec& key_spec = c.keys[k];
      const std::string at = Channel(i) + ".keys[" + std::to_string(k) + "]";
      if (!std::isfinite(key_spec.t) || key_spec.t < 0.f) {
        diag->Error(at + ".t", "is " + Num(key_spec.t) + "; expected a time in seconds >= 0");
      } else if (k > 0 && std::isfinite(c.keys[k - 1].t) && !(key_spec.t > c.keys[k - 1].t)) {
        diag->Error(at + ".t", "is " + Num(key_spec.t) + ", not after keys[" +
                                   std::to_string(k - 1) + "].t = " + Num(c.keys[k - 1].t) +
                                   "; expected key times strictly increasing");
      }
      if (!(key_spec.v >= 0.f && key_spec.v <= 1.f))
        diag->Error(at + ".v", "is " + Num(key_spec.v) + "; expected a value in [0, 1]");
      if (std::isfinite(key_spec.t) && key_spec.t >= last_time)
        last_time = key_spec.t, last_channel = i, last_key = k;
    }
  }
  if (clip.duration > 0.f && std::isfinite(clip.duration) && clip.duration < last_time)
    diag->Error("duration", "is " + Num(clip.duration) + " s, before the last key (" +
                                Channel(last_channel) + ".keys[" + std::to_string(last_key) +
                                "].t = " + Num(last_time) + "); expected at least " +
                                Num(last_time));
  if (clip.end == ClipEnd::kLoop && clip.duration < 0.f && !clip.channels.empty() &&
      ClipDuration(clip) <= 0.f)
    diag->Error("end", "is \"loop\" but the clip lasts 0 s (every key at t = 0); expected a "
                       "duration > 0 or keys after 0");
  return diag->ErrorCount() == before;
}

}  // namespace mimetic

// expressions/runtime/clip.h: a compiled clip, the runtime form of a keyframed animation of
// muscle activations and expression weights (docs/expressions.md).
//
// Built offline by BuildClip (expressions/offline/clip_builder.h) from a parsed clip
// (expressions/offline/clip_spec.h, read by io/clip_file.h) resolved against one rig's
// muscles and a set of expressions, or read from a compiled clip (.mclip, clip_binary.h);
// sampled per frame by ClipSampleJob (clip_sample_job.h). Immutable and move-only like Rig:
// members are private with const accessors and only the builder and the .mclip reader fill
// them, after checking every invariant listed below, so the sampling job reads the arrays
// without per-frame checks.
//
// Layout (plain arrays):
//   channels c in [0, channel_count()), in the file's order (the order they are applied):
//     kind(c), layer(c), target(c)      a muscle index (kMuscle), an expression row
//                                       (kExpression), or 0 (kJaw: the rig's jaw opening)
//     keys [key_offsets()[c], key_offsets()[c + 1]) of the key arrays, at least one each
//   keys k:
//     key_times()[k]     seconds, >= 0, strictly increasing within a channel, <= duration()
//     key_values()[k]    in [0, 1]
//     key_tangents()[k]  value per second: the slope of cubic segments at the key, already
//                        limited so that no cubic segment leaves its two key values
//     key_interps()[k]   how the channel goes from key k to key k + 1 (ignored on a
//                        channel's last key)
//   expressions e in [0, expression_count()): muscle_count() floats each, row-major:
//     expression_activations()[e * muscle_count() + m]  in [0, 1]
//     expression_masks()[e * muscle_count() + m]         1 where the expression names muscle m
//                                                        (an override layer replaces those only)
//     expression_jaws()[e], expression_jaw_masks()[e]    the expression's jaw value in [0, 1]
//                                                        and 1 where it names the jaw
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/span.h"

namespace mimetic {

// The name that stands for the rig's jaw opening (EvaluateJob::jaw, docs/model.md §18)
// wherever a muscle name goes: a clip's "muscle" channel, an expression's activations,
// `mimetic eval --set` (unless the rig has a muscle of that name).
inline constexpr char kJawInputName[] = "jaw";

// What the clip does after its duration (and before 0).
enum class ClipEnd : uint8_t {
  kClamp = 0,  // time clamped to [0, duration]: holds the first and last poses
  kLoop = 1,   // time wrapped into [0, duration)
};

enum class ClipChannelKind : uint8_t {
  kMuscle = 0,      // the channel's value is the activation of one muscle
  kExpression = 1,  // the channel's value is the weight of one expression
  kJaw = 2,         // the channel's value is the jaw opening (EvaluateJob::jaw)
};

// How an expression channel of weight w combines the expression's activations e with what
// the channels before it gave (a):  kAdd a = min(1, a + w e);  kMax a = max(a, w e);
// kOverride a = a + w (e - a) on the muscles the expression names. Muscle channels set their
// muscle's activation (a = v) and have no layer (stored as kOverride). The jaw is one more
// value under the same rules: a jaw channel sets it, an expression that names it combines it.
enum class ClipLayer : uint8_t { kAdd = 0, kMax = 1, kOverride = 2 };

// How a channel goes from one key to the next.
enum class KeyInterp : uint8_t {
  kStep = 0,    // holds the key's value until the next key's time
  kLinear = 1,  // straight line to the next key
  kCubic = 2,   // cubic Hermite with the two keys' tangents (never leaves the two values)
};

class ClipBuilder;       // expressions/offline/clip_builder.h
class ClipBinaryReader;  // expressions/runtime/clip_binary.cpp (the .mclip reader)

class CompiledClip {
 public:
  CompiledClip() = default;
  CompiledClip(CompiledClip&&) = default;
  CompiledClip& operator=(CompiledClip&&) = default;
  CompiledClip(const CompiledClip&) = delete;
  CompiledClip& operator=(const CompiledClip&) = delete;

  const std::string& name() const { return name_; }
  float duration() const { return duration_; }  // seconds, >= 0 (> 0 when looping)
  ClipEnd end() const { return end_; }
  uint32_t muscle_count() const { return muscle_count_; }  // the rig's, at build time
  uint32_t channel_count() const { return uint32_t(kinds_.size()); }
  uint32_t expression_count() const { return expression_count_; }
  // False for a default-constructed clip (nothing built into it).
  bool built() const { return built_; }
  // True when a channel or an expression it uses sets the jaw (ClipSampleJob::out_jaw).
  bool animates_jaw() const { return animates_jaw_; }

  span<const ClipChannelKind> kinds() const { return kinds_; }
  span<const ClipLayer> layers() const { return layers_; }
  span<const uint32_t> targets() const { return targets_; }
  span<const uint32_t> key_offsets() const { return key_offsets_; }  // channel_count() + 1
  span<const float> key_times() const { return key_times_; }
  span<const float> key_values() const { return key_values_; }
  span<const float> key_tangents() const { return key_tangents_; }
  span<const KeyInterp> key_interps() const { return key_interps_; }
  span<const float> expression_activations() const { return expression_activations_; }
  span<const uint8_t> expression_masks() const { return expression_masks_; }
  span<const float> expression_jaws() const { return expression_jaws_; }
  span<const uint8_t> expression_jaw_masks() const { return expression_jaw_masks_; }

  // Bytes this clip holds: sizeof(CompiledClip) plus the capacity of every array.
  size_t ByteSize() const;

 private:
  friend class ClipBuilder;
  friend class ClipBinaryReader;
  std::string name_;
  float duration_ = 0.f;
  ClipEnd end_ = ClipEnd::kClamp;
  uint32_t muscle_count_ = 0;
  uint32_t expression_count_ = 0;
  bool built_ = false;
  bool animates_jaw_ = false;
  std::vector<ClipChannelKind> kinds_;
  std::vector<ClipLayer> layers_;
  std::vector<uint32_t> targets_;
  std::vector<uint32_t> key_offsets_;
  std::vector<float> key_times_;
  std::vector<float> key_values_;
  std::vector<float> key_tangents_;
  std::vector<KeyInterp> key_interps_;
  std::vector<float> expression_activations_;
  std::vector<uint8_t> expression_masks_;
  std::vector<float> expression_jaws_;
  std::vector<uint8_t> expression_jaw_masks_;
};

}  // namespace mimetic

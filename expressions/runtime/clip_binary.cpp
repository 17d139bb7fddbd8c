// expressions/runtime/clip_binary.cpp: the .mclip writer and reader (docs/mclip-format.md).
#include "expressions/runtime/clip_binary.h"

#include <cmath>
#include <cstring>
#include <limits>
#include <utility>
#include <vector>

#include "core/binary_sections.h"

namespace mimetic {
namespace {

using binary::InSection;
using binary::LoadF32;
using binary::LoadU32;
using binary::SectionDesc;

// Section ids of format 1.x. Adding a CompiledClip array: one id here, one row in kSections,
// one write in WriteClipBinary, one read and its checks in ClipBinaryReader::Read, a row in
// docs/mclip-format.md (a new id in a new minor version is skipped by older readers).
enum SectionId : uint32_t {
  kName = 1,
  kParams = 2,
  kChannelKinds = 3,
  kChannelLayers = 4,
  kChannelTargets = 5,
  kKeyOffsets = 6,
  kKeyTimes = 7,
  kKeyValues = 8,
  kKeyTangents = 9,
  kKeyInterps = 10,
  kExpressionActivations = 11,
  kExpressionMasks = 12,
  kExpressionJaws = 13,
  kExpressionJawMasks = 14,
};

// clip_params: f32 duration, u32 end, u32 muscle_count, u32 expression_count, u32 animates_jaw.
constexpr uint32_t kParamsBytes = 20;

constexpr SectionDesc kSections[] = {
    {kName, "name", 0, 1, true},
    {kParams, "clip_params", kParamsBytes, 1, true},
    {kChannelKinds, "channel_kinds", 1, 0, true},
    {kChannelLayers, "channel_layers", 1, 0, true},
    {kChannelTargets, "channel_targets", 4, 0, true},
    {kKeyOffsets, "key_offsets", 4, 0, true},
    {kKeyTimes, "key_times", 4, 0, true},
    {kKeyValues, "key_values", 4, 0, true},
    {kKeyTangents, "key_tangents", 4, 0, true},
    {kKeyInterps, "key_interps", 1, 0, true},
    {kExpressionActivations, "expression_activations", 4, 0, true},
    {kExpressionMasks, "expression_masks", 1, 0, true},
    {kExpressionJaws, "expression_jaws", 4, 0, true},
    {kExpressionJawMasks, "expression_jaw_masks", 1, 0, true},
};

constexpr binary::Format kFormat = {
    {kClipBinaryTag[0], kClipBinaryTag[1], kClipBinaryTag[2], kClipBinaryTag[3]},
    kClipBinaryMajor,
    kClipBinaryMinor,
    ".mclip",
    "compiled clip",
    "rebuild the clip with this version's `mimetic build`",
    kSections,
    std::size(kSections)};

template <class E>
std::vector<uint8_t> EnumBytes(span<const E> v) {
  std::vector<uint8_t> out(v.size());
  for (size_t i = 0; i < v.size(); ++i) out[i] = uint8_t(v[i]);
  return out;
}

template <class T>
std::vector<T> Copy(span<const T> v) {
  return std::vector<T>(v.begin(), v.end());
}

std::string Num(uint64_t v) { return std::to_string(v); }

std::string Float(float v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", double(v));
  return buf;
}

const char* KindName(ClipChannelKind k) {
  switch (k) {
    case ClipChannelKind::kMuscle: return "a muscle channel";
    case ClipChannelKind::kExpression: return "an expression channel";
    case ClipChannelKind::kJaw: return "the jaw channel";
  }
  return "?";
}

}  // namespace

// The reader: CompiledClip's friend, so that it fills the private arrays after its checks.
class ClipBinaryReader {
 public:
  static bool Read(span<const uint8_t> bytes, CompiledClip* out, std::string* error);
};

bool ClipBinaryReader::Read(span<const uint8_t> bytes, CompiledClip* out, std::string* error) {
  std::vector<InSection> known;
  if (!binary::ReadSections(bytes, kFormat, &known, error)) return false;
  const binary::SectionReader r(kFormat, known, error);
  CompiledClip c;

  std::vector<std::string> name;
  if (!r.Strings(kName, &name)) return false;
  c.name_ = std::move(name[0]);

  const InSection& params = r.Of(kParams);
  const uint8_t* p = params.data;
  const float duration = LoadF32(p);
  const uint32_t end = LoadU32(p + 4), muscle_count = LoadU32(p + 8),
                 expression_count = LoadU32(p + 12), animates_jaw = LoadU32(p + 16);
  if (!(std::isfinite(duration) && duration >= 0.f))
    return r.Fail(params, "duration " + Float(duration) + "; expected a finite number >= 0");
  if (end > uint32_t(ClipEnd::kLoop))
    return r.Fail(params, "end " + Num(end) + "; expected 0 (clamp) or 1 (loop)");
  if (end == uint32_t(ClipEnd::kLoop) && !(duration > 0.f))
    return r.Fail(params, "a looping clip of duration 0; expected a duration > 0");
  if (muscle_count > std::numeric_limits<uint32_t>::max() / 2)
    return r.Fail(params, "muscle count " + Num(muscle_count) + "; expected at most " +
                              Num(std::numeric_limits<uint32_t>::max() / 2));
  if (animates_jaw > 1)
    return r.Fail(params, "animates_jaw " + Num(animates_jaw) + "; expected 0 or 1");
  c.duration_ = duration;
  c.end_ = ClipEnd(end);
  c.muscle_count_ = muscle_count;
  c.expression_count_ = expression_count;

  // Channels: counts first, then every kind, layer and target.
  const InSection& kinds = r.Of(kChannelKinds);
  const uint64_t channels = kinds.count;
  if (channels == 0) return r.Fail(kinds, "0 channels; expected at least one");
  for (uint32_t id : {kChannelLayers, kChannelTargets})
    if (r.Of(id).count != channels)
      return r.Fail(r.Of(id), Num(r.Of(id).count) + " elements; channel_kinds has " +
                                  Num(channels) + " (one per channel)");
  const InSection& offsets = r.Of(kKeyOffsets);
  if (offsets.count != channels + 1)
    return r.Fail(offsets, Num(offsets.count) + " offsets; expected " + Num(channels + 1) +
                               " (channels + 1)");
  const InSection& layers = r.Of(kChannelLayers);
  const InSection& targets = r.Of(kChannelTargets);
  bool jaw_channel = false;
  for (uint64_t i = 0; i < channels; ++i) {
    const uint8_t kind = kinds.data[i], layer = layers.data[i];
    const uint32_t target = LoadU32(targets.data + 4 * i);
    const std::string ch = "channel " + Num(i);
    if (kind > uint8_t(ClipChannelKind::kJaw))
      return r.Fail(kinds, ch + " has kind " + Num(kind) +
                               "; expected 0 (muscle), 1 (expression) or 2 (jaw)");
    if (layer > uint8_t(ClipLayer::kOverride))
      return r.Fail(layers, ch + " has layer " + Num(layer) +
                                "; expected 0 (add), 1 (max) or 2 (override)");
    const ClipChannelKind k = ClipChannelKind(kind);
    if (k != ClipChannelKind::kExpression && layer != uint8_t(ClipLayer::kOverride))
      return r.Fail(layers, ch + " (" + KindName(k) + ") has layer " + Num(layer) +
                                "; expected 2 (override: a muscle or jaw channel sets its value)");
    if (k == ClipChannelKind::kMuscle && target >= muscle_count)
      return r.Fail(targets, ch + " (a muscle channel) targets muscle " + Num(target) +
                                 "; the clip has " + Num(muscle_count) + " muscles");
    if (k == ClipChannelKind::kExpression && target >= expression_count)
      return r.Fail(targets, ch + " (an expression channel) targets expression " + Num(target) +
                                 "; the clip has " + Num(expression_count) + " expressions");
    if (k == ClipChannelKind::kJaw) {
      if (target != 0)
        return r.Fail(targets, ch + " (the jaw channel) targets " + Num(target) + "; expected 0");
      if (jaw_channel) return r.Fail(kinds, ch + " is a second jaw channel; expected at most one");
      jaw_channel = true;
    }
  }

  // Keys: offsets monotone from 0 to the key count, at least one key per channel, every key
  // array of the key count, times finite, sorted and inside [0, duration].
  const InSection& times = r.Of(kKeyTimes);
  const uint64_t keys = times.count;
  for (uint32_t id : {kKeyValues, kKeyTangents, kKeyInterps})
    if (r.Of(id).count != keys)
      return r.Fail(r.Of(id), Num(r.Of(id).count) + " elements; key_times has " + Num(keys) +
                                  " (one per key)");
  if (LoadU32(offsets.data) != 0)
    return r.Fail(offsets, "offset 0 is " + Num(LoadU32(offsets.data)) + "; expected 0");
  if (LoadU32(offsets.data + 4 * channels) != keys)
    return r.Fail(offsets, "the last offset is " + Num(LoadU32(offsets.data + 4 * channels)) +
                               "; key_times has " + Num(keys) + " keys");
  const InSection& values = r.Of(kKeyValues);
  const InSection& tangents = r.Of(kKeyTangents);
  const InSection& interps = r.Of(kKeyInterps);
  for (uint64_t i = 0; i < channels; ++i) {
    const uint32_t first = LoadU32(offsets.data + 4 * i), last = LoadU32(offsets.data + 4 * i + 4);
    if (last <= first || last > keys)
      return r.Fail(offsets, "channel " + Num(i) + " has keys [" + Num(first) + ", " +
                                 Num(last) + "); expected a non-empty range, increasing, "
                                 "inside the " + Num(keys) + " keys");
    for (uint32_t k = first; k < last; ++k) {
      const float t = LoadF32(times.data + 4 * size_t(k));
      const std::string key = "key " + Num(k) + " (channel " + Num(i) + ")";
      if (!(std::isfinite(t) && t >= 0.f && t <= duration))
        return r.Fail(times, key + " at t = " + Float(t) + "; expected a time in [0, " +
                                 Float(duration) + "] (the clip's duration)");
      if (k > first && !(t > LoadF32(times.data + 4 * size_t(k - 1))))
        return r.Fail(times, key + " at t = " + Float(t) + " is not after the key before it (" +
                                 Float(LoadF32(times.data + 4 * size_t(k - 1))) +
                                 "); expected strictly increasing times in a channel");
      const float v = LoadF32(values.data + 4 * size_t(k));
      if (!(v >= 0.f && v <= 1.f))
        return r.Fail(values, key + " has value " + Float(v) + "; expected a value in [0, 1]");
      const float m = LoadF32(tangents.data + 4 * size_t(k));
      if (!std::isfinite(m))
        return r.Fail(tangents, key + " has tangent " + Float(m) + "; expected a finite slope");
      if (interps.data[k] > uint8_t(KeyInterp::kCubic))
        return r.Fail(interps, key + " has interpolation " + Num(interps.data[k]) +
                                   "; expected 0 (step), 1 (linear) or 2 (cubic)");
    }
  }

  // Expressions: rows of muscle_count, values in [0, 1], masks 0 or 1.
  const uint64_t cells = uint64_t(expression_count) * muscle_count;  // < 2^63
  const InSection& acts = r.Of(kExpressionActivations);
  const InSection& masks = r.Of(kExpressionMasks);
  for (const InSection* s : {&acts, &masks})
    if (s->count != cells)
      return r.Fail(*s, Num(s->count) + " elements; expected " + Num(expression_count) +
                            " expressions x " + Num(muscle_count) + " muscles = " + Num(cells));
  const InSection& jaws = r.Of(kExpressionJaws);
  const InSection& jaw_masks = r.Of(kExpressionJawMasks);
  for (const InSection* s : {&jaws, &jaw_masks})
    if (s->count != expression_count)
      return r.Fail(*s, Num(s->count) + " elements; expected " + Num(expression_count) +
                            " (one per expression)");
  for (uint64_t i = 0; i < cells; ++i) {
    const float a = LoadF32(acts.data + 4 * i);
    const std::string at = "expression " + Num(i / (muscle_count ? muscle_count : 1)) +
                           ", muscle " + Num(i % (muscle_count ? muscle_count : 1));
    if (!(a >= 0.f && a <= 1.f))
      return r.Fail(acts, at + " has activation " + Float(a) + "; expected [0, 1]");
    if (masks.data[i] > 1)
      return r.Fail(masks, at + " has mask " + Num(masks.data[i]) + "; expected 0 or 1");
  }
  bool jaw_expression = false;
  for (uint64_t e = 0; e < expression_count; ++e) {
    const float j = LoadF32(jaws.data + 4 * e);
    if (!(j >= 0.f && j <= 1.f))
      return r.Fail(jaws, "expression " + Num(e) + " has jaw " + Float(j) + "; expected [0, 1]");
    if (jaw_masks.data[e] > 1)
      return r.Fail(jaw_masks, "expression " + Num(e) + " has jaw mask " +
                                   Num(jaw_masks.data[e]) + "; expected 0 or 1");
    jaw_expression = jaw_expression || jaw_masks.data[e];
  }
  if ((animates_jaw != 0) != (jaw_channel || jaw_expression))
    return r.Fail(params, "animates_jaw is " + Num(animates_jaw) + ", but the clip " +
                              (jaw_channel || jaw_expression
                                   ? "has a jaw channel or an expression that names the jaw"
                                   : "has no jaw channel and no expression that names the jaw"));
  c.animates_jaw_ = animates_jaw != 0;

  // Every check passed: copy the arrays.
  std::vector<uint8_t> raw;
  r.U8s(kChannelKinds, &raw);
  for (uint8_t v : raw) c.kinds_.push_back(ClipChannelKind(v));
  r.U8s(kChannelLayers, &raw);
  for (uint8_t v : raw) c.layers_.push_back(ClipLayer(v));
  r.U32s(kChannelTargets, &c.targets_);
  r.U32s(kKeyOffsets, &c.key_offsets_);
  r.F32s(kKeyTimes, &c.key_times_);
  r.F32s(kKeyValues, &c.key_values_);
  r.F32s(kKeyTangents, &c.key_tangents_);
  r.U8s(kKeyInterps, &raw);
  for (uint8_t v : raw) c.key_interps_.push_back(KeyInterp(v));
  r.F32s(kExpressionActivations, &c.expression_activations_);
  r.U8s(kExpressionMasks, &c.expression_masks_);
  r.F32s(kExpressionJaws, &c.expression_jaws_);
  r.U8s(kExpressionJawMasks, &c.expression_jaw_masks_);
  c.built_ = true;
  *out = std::move(c);
  return true;
}

std::string WriteClipBinary(const CompiledClip& c) {
  binary::SectionWriter w(kFormat);
  w.Strings(kName, {c.name()});
  {
    binary::Payload p(&w.Begin(kParams, 1));
    p.F32(c.duration());
    p.U32(uint32_t(c.end()));
    p.U32(c.muscle_count());
    p.U32(c.expression_count());
    p.U32(c.animates_jaw() ? 1 : 0);
  }
  w.U8s(kChannelKinds, EnumBytes(c.kinds()));
  w.U8s(kChannelLayers, EnumBytes(c.layers()));
  w.U32s(kChannelTargets, Copy(c.targets()));
  // An unbuilt clip has no offsets; the reader needs channels + 1 of them (and refuses the
  // result only if the rest is inconsistent), so write the one a clip of no channels has.
  w.U32s(kKeyOffsets, c.key_offsets().empty() ? std::vector<uint32_t>{0} : Copy(c.key_offsets()));
  w.F32s(kKeyTimes, Copy(c.key_times()));
  w.F32s(kKeyValues, Copy(c.key_values()));
  w.F32s(kKeyTangents, Copy(c.key_tangents()));
  w.U8s(kKeyInterps, EnumBytes(c.key_interps()));
  w.F32s(kExpressionActivations, Copy(c.expression_activations()));
  w.U8s(kExpressionMasks, Copy(c.expression_masks()));
  w.F32s(kExpressionJaws, Copy(c.expression_jaws()));
  w.U8s(kExpressionJawMasks, Copy(c.expression_jaw_masks()));
  return w.Finish();
}

bool HasClipBinaryTag(span<const uint8_t> bytes) {
  return bytes.size() >= 4 && std::memcmp(bytes.data(), kClipBinaryTag, 4) == 0;
}

bool ReadClipBinary(span<const uint8_t> bytes, CompiledClip* out, std::string* error) {
  std::string local_error;
  return ClipBinaryReader::Read(bytes, out, error ? error : &local_error);
}

bool LoadClipBinaryFile(const std::string& path, CompiledClip* out, std::string* error) {
  std::string bytes, why;
  if (!binary::ReadFileBytes(path, kFormat.what, kMaxClipBinaryFileBytes, &bytes, &why) ||
      !ReadClipBinary(span<const uint8_t>(reinterpret_cast<const uint8_t*>(bytes.data()),
                                          bytes.size()),
                      out, &why)) {
    if (error) *error = path + ": " + why;
    return false;
  }
  return true;
}

}  // namespace mimetic

// io/clip_file.cpp: clip files (docs/expressions.md): the table of the format (io/json_reader.h
// checks it and generates assets/schema/mimetic-clip.schema.json from it), its rules between
// fields, and writing.
#include "io/clip_file.h"

#include <cctype>
#include <charconv>
#include <cstdio>
#include <cmath>

#include <nlohmann/json.hpp>

#include "core/file_util.h"
#include "expressions/runtime/clip_binary.h"
#include "io/formats.h"
#include "io/json_reader.h"

namespace mimetic {
namespace {

using namespace json_reader;

const Object kKey = {"a key", {
    Number("t", "a time in seconds >= 0").Min(0).Required()
        .About("s, the key's time from the clip's start"),
    Number("v", "a value in [0, 1]").Min(0).Max(1).Required()
        .About("the muscle's activation or the expression's weight, [0, 1]"),
    Enum("interp", {"step", "linear", "cubic"})
        .About("how the channel goes from this key to the next (default \"linear\")"),
    Enum("tangent", {"auto", "clamped"})
        .About("the key's slope for cubic segments (default \"auto\"); both never overshoot")},
    {}, {}, {}, "a key of a channel"};

const Object kChannel = {"a channel", {
    String("muscle").NonEmpty()
        .About("the muscle this channel animates (NAME drives NAME_L and NAME_R when the rig "
               "has no NAME); give either muscle or expression"),
    String("expression").NonEmpty()
        .About("the expression whose weight this channel animates; give either muscle or "
               "expression"),
    Enum("layer", {"add", "max", "override"})
        .About("expression channels: how the weighted expression combines with the channels "
               "before it (default \"add\")"),
    Array("keys", ObjectOf("", kKey), "a non-empty array of keys {\"t\": s, \"v\": value}")
        .NonEmpty().Required().About("at least one key, times strictly increasing")},
    {}, {}, {}, "one animated muscle activation or expression weight"};

const Object kClipFile = {"a clip file", {
    Enum("format", {"mimetic-clip"}).Required(),
    Integer("version", "the integer 1").Version(1).Required(),
    String("name").NonEmpty().Required().About("the clip's name"),
    Number("duration", "a number of seconds > 0").Above(0)
        .About("s, at least the last key's time (default: the last key's time)"),
    Enum("end", {"clamp", "loop"})
        .About("after the duration: hold the last pose or start again (default \"clamp\")"),
    Array("channels", ObjectOf("", kChannel), "a non-empty array of channels")
        .NonEmpty().Required().About("applied in this order")}};

const Format kClipFormat = {
    .name = "mimetic-clip",
    .root = ObjectOf("", kClipFile, "an object with \"format\": \"mimetic-clip\""),
    .title = "mimetic clip file, version 1"};

// The shortest decimal that reads back as `f`, as a JSON number.
nlohmann::ordered_json JsonFloat(float f) {
  char buf[64];
  const auto res = std::to_chars(buf, buf + sizeof buf, f);
  return nlohmann::ordered_json::parse(std::string(buf, res.ptr));
}

const char* const kInterp[] = {"step", "linear", "cubic"};
const char* const kTangent[] = {"auto", "clamped"};
const char* const kLayer[] = {"add", "max", "override"};
const char* const kEnd[] = {"clamp", "loop"};

}  // namespace

const json_reader::Format& ClipFileFormat() { return kClipFormat; }

bool ParseClip(const std::string& text, const std::string& where, ClipSpec* out,
               Diagnostics* diag) {
  Diagnostics local;
  if (!diag) diag = &local;
  return NoThrow(diag, where + ": internal error while reading the clip", [&] {
    Reader r(kClipFormat, diag, where);
    if (!r.Parse(text)) return false;
    const View top = r.Check();
    if (r.stopped() || !top.present() || !top.value()->is_object()) return false;
    ClipSpec clip;
    top.Read("name", &clip.name);
    top.Read("duration", &clip.duration);
    size_t choice = 0;
    if (top.Choice("end", &choice)) clip.end = ClipEnd(choice);
    // A generic problem below a channel leaves the channel out, so the rules below do not
    // speak about what was never read; every problem still has its message.
    bool channels_complete = true;
    for (size_t i = 0; i < top.Size("channels"); ++i) {
      const View c = top.Element("channels", i);
      if (!c.present() || !c.value()->is_object()) { channels_complete = false; continue; }
      const bool muscle = c.Has("muscle"), expression = c.Has("expression");
      if (muscle && expression)
        r.Error(c.path(), "has both \"muscle\" and \"expression\"; expected one of them (a "
                          "channel animates one target)");
      else if (!muscle && !expression)
        r.Error(c.path(), "has neither \"muscle\" nor \"expression\"; expected one of them");
      if (muscle && c.Has("layer"))
        r.Error(Key(c.path(), "layer"), "is given on a muscle channel; expected \"layer\" on "
                                        "expression channels only (a muscle channel sets its "
                                        "muscle's activation)");
      if (!c.ok() || muscle == expression) { channels_complete = false; continue; }
      ClipChannelSpec spec;
      spec.kind = muscle ? ClipChannelKind::kMuscle : ClipChannelKind::kExpression;
      c.Read(muscle ? "muscle" : "expression", &spec.target);
      if (c.Choice("layer", &choice)) spec.layer = ClipLayer(choice);
      for (size_t k = 0; k < c.Size("keys"); ++k) {
        const View key = c.Element("keys", k);
        ClipKeySpec ks;
        key.Read("t", &ks.t);
        key.Read("v", &ks.v);
        if (key.Choice("interp", &choice)) ks.interp = KeyInterp(choice);
        if (key.Choice("tangent", &choice)) ks.tangent = KeyTangent(choice);
        spec.keys.push_back(ks);
      }
      clip.channels.push_back(std::move(spec));
    }
    if (channels_complete && !r.failed()) {
      Diagnostics rules;
      CheckClipSpec(clip, &rules);
      for (const Diagnostic& d : rules.items()) r.Error(d.where, d.what);
    }
    if (r.failed()) return false;
    *out = std::move(clip);
    return true;
  });
}

bool LoadClip(const std::string& path, ClipSpec* out, Diagnostics* diag) {
  return ParseFile(path, diag, [&](const std::string& text, Diagnostics* local) {
    return ParseClip(text, "", out, local);
  });
}

std::string ClipToJson(const ClipSpec& clip) {
  nlohmann::ordered_json j;
  j["format"] = "mimetic-clip";
  j["version"] = 1;
  j["name"] = clip.name;
  if (clip.duration >= 0.f && std::isfinite(clip.duration)) j["duration"] = JsonFloat(clip.duration);
  j["end"] = kEnd[size_t(clip.end) % 2];
  nlohmann::ordered_json channels = nlohmann::ordered_json::array();
  for (const ClipChannelSpec& c : clip.channels) {
    nlohmann::ordered_json cj;
    if (c.kind == ClipChannelKind::kMuscle) {
      cj["muscle"] = c.target;
    } else {
      cj["expression"] = c.target;
      cj["layer"] = kLayer[size_t(c.layer) % 3];
    }
    nlohmann::ordered_json keys = nlohmann::ordered_json::array();
    for (const ClipKeySpec& k : c.keys) {
      nlohmann::ordered_json kj;
      kj["t"] = std::isfinite(k.t) ? JsonFloat(k.t) : nullptr;
      kj["v"] = std::isfinite(k.v) ? JsonFloat(k.v) : nullptr;
      kj["interp"] = kInterp[size_t(k.interp) % 3];
      kj["tangent"] = kTangent[size_t(k.tangent) % 2];
      keys.push_back(std::move(kj));
    }
    cj["keys"] = std::move(keys);
    channels.push_back(std::move(cj));
  }
  j["channels"] = std::move(channels);
  return j.dump(2) + "\n";
}

bool SaveClip(const std::string& path, const ClipSpec& clip, Diagnostics* diag) {
  Diagnostics rules;
  if (!CheckClipSpec(clip, &rules)) {
    diag->Append(rules, path);
    return false;
  }
  return WriteFileAtomic(path, ClipToJson(clip), diag);
}

bool IsCompiledClipPath(const std::string& path) {
  std::string lower = path;
  for (char& c : lower) c = char(std::tolower(static_cast<unsigned char>(c)));
  if (lower.size() >= 6 && lower.compare(lower.size() - 6, 6, ".mclip") == 0) return true;
  if (!CheckRegularFile(path, kMaxClipBinaryFileBytes, "clip file").empty()) return false;
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) return false;
  uint8_t tag[4] = {};
  const size_t got = std::fread(tag, 1, 4, f);
  std::fclose(f);
  return got == 4 && HasClipBinaryTag(span<const uint8_t>(tag, 4));
}

bool BuildClip(const ClipSpec& clip, const std::vector<std::string>& muscle_names,
               const std::vector<Expression>& expressions, CompiledClip* out, Diagnostics* diag) {
  std::vector<ClipExpression> in;
  in.reserve(expressions.size());
  for (const Expression& e : expressions) in.push_back({e.name, e.activations});
  return ClipBuilder::Build(clip, muscle_names, in, out, diag);
}

}  // namespace mimetic

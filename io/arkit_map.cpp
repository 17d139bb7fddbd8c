// io/arkit_map.cpp: reading and writing ARKit maps.
#include "io/arkit_map.h"

#include <cmath>
#include <map>
#include <set>

#include <nlohmann/json.hpp>

#include "core/file_util.h"
#include "expressions/offline/activation_binding.h"
#include "expressions/runtime/clip.h"
#include "io/formats.h"
#include "io/json_reader.h"

namespace mimetic {
namespace {

using namespace json_reader;

constexpr const char* kNames[] = {
    "eyeBlinkLeft", "eyeLookDownLeft", "eyeLookInLeft", "eyeLookOutLeft", "eyeLookUpLeft",
    "eyeSquintLeft", "eyeWideLeft",
    "eyeBlinkRight", "eyeLookDownRight", "eyeLookInRight", "eyeLookOutRight", "eyeLookUpRight",
    "eyeSquintRight", "eyeWideRight",
    "jawForward", "jawLeft", "jawRight", "jawOpen",
    "mouthClose", "mouthFunnel", "mouthPucker", "mouthLeft", "mouthRight",
    "mouthSmileLeft", "mouthSmileRight", "mouthFrownLeft", "mouthFrownRight",
    "mouthDimpleLeft", "mouthDimpleRight", "mouthStretchLeft", "mouthStretchRight",
    "mouthRollLower", "mouthRollUpper", "mouthShrugLower", "mouthShrugUpper",
    "mouthPressLeft", "mouthPressRight", "mouthLowerDownLeft", "mouthLowerDownRight",
    "mouthUpperUpLeft", "mouthUpperUpRight",
    "browDownLeft", "browDownRight", "browInnerUp", "browOuterUpLeft", "browOuterUpRight",
    "cheekPuff", "cheekSquintLeft", "cheekSquintRight",
    "noseSneerLeft", "noseSneerRight",
    "tongueOut"};
constexpr size_t kCount = sizeof(kNames) / sizeof(kNames[0]);
static_assert(kCount == 52, "Apple's ARKit has 52 blendshapes");

const Field kActivations =
    AnyObject("activations", "an object {\"muscle name\": activation in [0, 1], ...}")
        .Required().About("muscle name -> activation in [0, 1]; muscles not named are 0");
const Field kNote = String("note").About("why it is set this way, or what the solve shows");

const Object kSolved = {"a solved ARKit shape", {
    kActivations, kNote,
    String("target").NonEmpty().Required()
        .About("the real shape solved, relative to the data folder (ICT-FaceKit)"),
    Number("mean_distance").Min(0).Required()
        .About("mean distance of the real shape to the solved rig (mesh units, docs/model.md §13)"),
    Number("neutral_mean_distance").Above(0).Required()
        .About("the same for the rig at rest"),
    Number("ratio").Min(0).Required().About("mean_distance / neutral_mean_distance")}};
const Object kAnatomy = {"an ARKit shape set from anatomy", {kActivations, kNote}};
const Object kNone = {"an ARKit shape the muscles cannot make", {kActivations, kNote}};

const Object kShape = {
    .owner = "an ARKit shape",
    .fields = {Enum("how", {"solved", "anatomy", "none"}).Required()
                   .About("solved on a real shape, set by hand from anatomy, or not made")},
    .variant_key = "how",
    .variants = {{"solved", &kSolved}, {"anatomy", &kAnatomy}, {"none", &kNone}},
    .description = "One ARKit blendshape: the muscle activations that make it."};

Object MakeShapes() {
  Object o{"the ARKit shapes", {}};
  for (const char* n : kNames)
    o.fields.push_back(ObjectOf(n, kShape, "an object {\"how\": ..., \"activations\": {...}}")
                           .Required());
  o.description = "Every one of Apple's 52 ARKit blendshape names, exactly once.";
  return o;
}
const Object kShapes = MakeShapes();

const Object kMapFile = {"an ARKit map", {
    Enum("format", {"mimetic-arkit-map"}).Required(),
    Integer("version", "the integer 1").Version(1).Required(),
    ObjectOf("shapes", kShapes, "an object {\"ARKit name\": {...}, ...} with all 52 names")
        .Required().About("ARKit blendshape name -> how the rig makes it")}};

const Format kMapFormat = {
    .name = "mimetic-arkit-map",
    .root = ObjectOf("", kMapFile, "an object with \"format\": \"mimetic-arkit-map\""),
    .title = "mimetic ARKit map, version 1"};

bool RatioMatches(double mean, double neutral, double ratio) {
  return neutral > 0 && std::fabs(ratio - mean / neutral) <= 0.005 * std::fabs(mean / neutral) + 1e-6;
}

std::vector<std::string> NameList() { return {kNames, kNames + kCount}; }

}  // namespace

const json_reader::Format& ArkitMapFormat() { return kMapFormat; }

span<const char* const> ArkitShapeNames() { return {kNames, kCount}; }

const char* ArkitHowName(ArkitShape::How how) {
  switch (how) {
    case ArkitShape::How::kSolved: return "solved";
    case ArkitShape::How::kAnatomy: return "anatomy";
    case ArkitShape::How::kNone: return "none";
  }
  return "none";
}

bool ParseArkitMap(const std::string& text, const std::string& where,
                   std::vector<ArkitShape>* out, Diagnostics* diag) {
  Diagnostics local;
  if (!diag) diag = &local;
  return NoThrow(diag, where + ": internal error while reading the ARKit map", [&] {
    Reader r(kMapFormat, diag, where);
    if (!r.Parse(text)) return false;
    const View top = r.Check();
    if (r.stopped() || !top.present() || !top.value()->is_object()) return false;
    const View shapes = top.Member("shapes");
    if (const Json* raw = top.Raw("shapes"); raw && raw->is_object()) {
      // The generic check lists all 52 names for an unknown key; add the closest ones.
      const std::set<std::string> known(kNames, kNames + kCount);
      for (const auto& [key, value] : raw->items())
        if (!known.count(key))
          r.Error(Key("shapes", key), "is not an ARKit blendshape name; the closest: " +
                                          ClosestNames(NameList(), key));
    }
    std::vector<ArkitShape> list;
    for (const char* name : kNames) {
      ArkitShape s;
      s.name = name;
      const View v = shapes.Member(name);
      const std::string path = Key("shapes", name);
      size_t how = 0;
      if (v.Choice("how", &how)) s.how = ArkitShape::How(how);
      if (const Json* a = v.Get("activations")) {
        for (const auto& [muscle, value] : a->items()) {
          const std::string apath = Key(Key(path, "activations"), muscle);
          if (muscle.empty()) r.Error(Key(path, "activations"), "has an empty muscle name");
          if (!value.is_number() ||
              !(value.get<double>() >= 0.0 && value.get<double>() <= 1.0)) {
            r.Error(apath, "is " + Describe(value) + "; expected an activation in [0, 1]");
            continue;
          }
          s.activations.push_back({muscle, value.get<float>()});
          if (s.how == ArkitShape::How::kNone && value.get<double>() != 0.0)
            r.Error(apath, "is " + Describe(value) +
                               " in a shape the muscles cannot make (\"how\": \"none\"); "
                               "expected 0 or no activation");
        }
      }
      v.Read("note", &s.note);
      if (s.how == ArkitShape::How::kSolved) {
        v.Read("target", &s.target);
        const bool all = v.Read("mean_distance", &s.mean_distance) &&
                         v.Read("neutral_mean_distance", &s.neutral_mean_distance) &&
                         v.Read("ratio", &s.ratio);
        if (all && !RatioMatches(s.mean_distance, s.neutral_mean_distance, s.ratio))
          r.Error(Key(path, "ratio"),
                  "is " + FormatFloat(float(s.ratio)) + "; expected mean_distance / "
                  "neutral_mean_distance = " +
                      FormatFloat(float(s.mean_distance / s.neutral_mean_distance)));
      }
      list.push_back(std::move(s));
    }
    if (r.failed()) return false;
    *out = std::move(list);
    return true;
  });
}

bool LoadArkitMap(const std::string& path, std::vector<ArkitShape>* out, Diagnostics* diag) {
  return ParseFile(path, diag, [&](const std::string& text, Diagnostics* local) {
    return ParseArkitMap(text, "", out, local);
  });
}

std::string ArkitMapToJson(const std::vector<ArkitShape>& shapes) {
  auto round6 = [](double v) { return std::round(v * 1e6) / 1e6; };
  nlohmann::ordered_json j;
  j["format"] = "mimetic-arkit-map";
  j["version"] = 1;
  nlohmann::ordered_json all = nlohmann::ordered_json::object();
  for (const ArkitShape& s : shapes) {
    nlohmann::ordered_json x;
    x["how"] = ArkitHowName(s.how);
    nlohmann::ordered_json a = nlohmann::ordered_json::object();
    for (const auto& [muscle, value] : s.activations) a[muscle] = round6(double(value));
    x["activations"] = a;
    if (!s.note.empty()) x["note"] = s.note;
    if (s.how == ArkitShape::How::kSolved) {
      x["target"] = s.target;
      x["mean_distance"] = round6(s.mean_distance);
      x["neutral_mean_distance"] = round6(s.neutral_mean_distance);
      x["ratio"] = round6(s.ratio);
    }
    all[s.name] = x;
  }
  j["shapes"] = all;
  return j.dump(2) + "\n";
}

bool SaveArkitMap(const std::string& path, const std::vector<ArkitShape>& shapes,
                  Diagnostics* diag) {
  const size_t before = diag->ErrorCount();
  std::map<std::string, int> count;
  for (const ArkitShape& s : shapes) ++count[s.name];
  for (const char* n : kNames)
    if (count[n] != 1)
      diag->Error(path + ": shapes." + n, count[n] == 0 ? "is missing; expected all 52 ARKit names"
                                                        : "appears more than once");
  const std::set<std::string> known(kNames, kNames + kCount);
  for (const ArkitShape& s : shapes) {
    const std::string where = path + ": shapes." + s.name;
    if (!known.count(s.name))
      diag->Error(where, "is not an ARKit blendshape name; the closest: " +
                             ClosestNames(NameList(), s.name));
    std::set<std::string> seen;
    for (const auto& [muscle, value] : s.activations) {
      if (muscle.empty()) diag->Error(where + ".activations", "has an empty muscle name");
      else if (!seen.insert(muscle).second)
        diag->Error(where + ".activations." + muscle, "appears twice");
      if (!(value >= 0.f && value <= 1.f))
        diag->Error(where + ".activations." + muscle,
                    std::to_string(value) + "; expected an activation in [0, 1]");
      else if (s.how == ArkitShape::How::kNone && value != 0.f)
        diag->Error(where + ".activations." + muscle,
                    "is non-zero in a shape the muscles cannot make");
    }
    if (s.how == ArkitShape::How::kSolved &&
        (s.target.empty() || !(s.neutral_mean_distance > 0) || !(s.mean_distance >= 0) ||
         !RatioMatches(s.mean_distance, s.neutral_mean_distance, s.ratio)))
      diag->Error(where, "a solved shape needs its target, mean distances (neutral > 0) and "
                         "ratio = mean / neutral");
  }
  if (diag->ErrorCount() != before) return false;
  return WriteFileAtomic(path, ArkitMapToJson(shapes), diag);
}

bool CheckArkitMuscles(const std::vector<ArkitShape>& shapes,
                       const std::vector<std::string>& muscle_names, const std::string& where,
                       Diagnostics* diag) {
  const size_t before = diag->ErrorCount();
  const std::set<std::string> known(muscle_names.begin(), muscle_names.end());
  const std::string prefix = where.empty() ? "" : where + ": ";
  for (const ArkitShape& s : shapes)
    for (const auto& [muscle, value] : s.activations)
      if (!known.count(muscle) && muscle != kJawInputName)  // "jaw": any rig (clip.h)
        diag->Error(prefix + "shapes." + s.name + ".activations." + muscle,
                    "unknown muscle '" + muscle + "'; the closest muscles of the rig: " +
                        ClosestNames(muscle_names, muscle));
  return diag->ErrorCount() == before;
}

}  // namespace mimetic

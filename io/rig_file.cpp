// io/rig_file.cpp: the rig file (docs/rig-format.md, version 1): parse, validate, save.
//
// The file holds what MODEL.md §2 (linear muscles), §3 (sheet muscles), §4 (skin thickness),
// §6 (muscle-derived wrinkles), §7-8 (curve wrinkles) and §11 (refinement) need. Angles are
// degrees in the file and radians in the spec structs. Every problem in the file is recorded in
// `Diagnostics` with its JSON path and what was expected; nothing throws out of this file
// (nlohmann::json exceptions are caught at the boundary).
#include <algorithm>
#include <charconv>
#include <climits>
#include <cmath>
#include <filesystem>
#include <map>
#include <numbers>
#include <set>
#include <string>
#include <system_error>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/file_util.h"
#include "io/rig_file.h"

namespace mimetic {
namespace {

using json = nlohmann::json;
using ordered_json = nlohmann::ordered_json;

constexpr const char* kFormatName = "mimetic-rig";
constexpr int kFormatVersion = 1;
// A huge array of bad elements is reported element by element up to this many, then summed up.
constexpr size_t kMaxElementErrors = 20;

const std::vector<std::string> kUnits = {"mm", "cm", "dm", "m", "in"};
const std::vector<std::string> kTopKeys = {"format",  "version",        "mesh",
                                           "units",   "thickness",      "muscles",
                                           "curve_wrinkles", "layers", "refinement"};
const std::vector<std::string> kReservedTopKeys = {"fine_scale", "expressions"};
const std::vector<std::string> kMeshKeys = {"path", "name"};
const std::vector<std::string> kLinearKeys = {"name",          "type",        "strength",
                                              "attachment",    "insertion",   "zone_angle_deg",
                                              "falloff_start", "falloff_end", "wrinkles"};
const std::vector<std::string> kSheetKeys = {"name",      "type",   "strength", "attachment",
                                             "insertion", "length", "width",    "falloff_start",
                                             "wrinkles"};
const std::vector<std::string> kAnyMuscleKeys = {
    "name",          "type",        "strength", "attachment", "insertion", "zone_angle_deg",
    "falloff_start", "falloff_end", "length",   "width",      "wrinkles"};
// MODEL.md §6: the wrinkle block of a muscle; the attenuation key depends on the muscle type.
const std::vector<std::string> kLinearWrinkleKeys = {"lambda_w", "count", "depth", "shape",
                                                     "phi_c_deg"};
const std::vector<std::string> kSheetWrinkleKeys = {"lambda_w", "count", "depth", "shape", "h_c"};
// MODEL.md §7-8.
const std::vector<std::string> kCurveWrinkleKeys = {"name",    "control",    "depth",
                                                    "width",   "profile",    "modulation",
                                                    "rest_amplitude"};
const std::vector<std::string> kLayerKeys = {"thickness", "muscle_wrinkles", "curve_wrinkles"};
const std::vector<std::string> kRefinementKeys = {"enabled", "edge_fraction"};

const std::vector<std::string>& ProfileNames() {
  static const std::vector<std::string> names = {
      CurveWrinkleProfileName(CurveWrinkleProfile::kBando),
      CurveWrinkleProfileName(CurveWrinkleProfile::kYangZhang),
      CurveWrinkleProfileName(CurveWrinkleProfile::kYangZhangExact)};
  return names;
}
const std::vector<std::string>& ModulationNames() {
  static const std::vector<std::string> names = {
      CurveWrinkleModulationName(CurveWrinkleModulation::kDirectional),
      CurveWrinkleModulationName(CurveWrinkleModulation::kArea)};
  return names;
}

// Degrees in the file -> radians in the spec (zone angles and phi_c).
float DegreesToRadians(double deg) { return static_cast<float>(deg * std::numbers::pi / 180.0); }

// ---------------------------------------------------------------------------------------------
// Small text helpers.

std::string JoinList(const std::vector<std::string>& items, bool quote) {
  std::string out;
  for (size_t i = 0; i < items.size(); ++i) {
    if (i) out += ", ";
    out += quote ? "\"" + items[i] + "\"" : items[i];
  }
  return out;
}

bool Contains(const std::vector<std::string>& items, const std::string& s) {
  for (const std::string& i : items)
    if (i == s) return true;
  return false;
}

std::string Key(const std::string& path, const std::string& key) {
  return path.empty() ? key : path + "." + key;
}

std::string Index(const std::string& path, size_t i) {
  return path + "[" + std::to_string(i) + "]";
}

// A JSON string literal for messages: escaped, invalid UTF-8 replaced, long text shortened.
std::string Quoted(const std::string& s) {
  constexpr size_t kMax = 60;
  std::string text = s.size() > kMax ? s.substr(0, kMax) : s;
  std::string out = json(text).dump(-1, ' ', false, json::error_handler_t::replace);
  if (s.size() > kMax) out.insert(out.size() - 1, "...");
  return out;
}

const char* TypeName(const json& v) {
  switch (v.type()) {
    case json::value_t::null: return "null";
    case json::value_t::boolean: return "boolean";
    case json::value_t::number_integer:
    case json::value_t::number_unsigned:
    case json::value_t::number_float: return "number";
    case json::value_t::string: return "string";
    case json::value_t::array: return "array";
    case json::value_t::object: return "object";
    case json::value_t::binary: return "binary";
    case json::value_t::discarded: return "nothing";
  }
  return "unknown";
}

// What a value is, for "got ...": numbers and strings by value, others by type.
std::string Describe(const json& v) {
  if (v.is_number()) {
    // 1e308 stands for a literal that overflowed a double (see ReplaceOverflowingNumbers).
    if (std::fabs(v.get<double>()) >= 1e308) return "a number that overflows to infinity";
    return v.dump();
  }
  if (v.is_string()) {
    const std::string& s = v.get_ref<const std::string&>();
    return s.empty() ? "empty string" : Quoted(s);
  }
  if (v.is_array()) return "array of " + std::to_string(v.size()) + " elements";
  return TypeName(v);
}

// The shortest text that reads back as `f` ("10", "2.05").
std::string FormatFloat(float f) {
  char buf[64];
  const auto res = std::to_chars(buf, buf + sizeof buf, f);
  return res.ec == std::errc() ? std::string(buf, res.ptr) : std::to_string(f);
}

// ---------------------------------------------------------------------------------------------
// Number literals that overflow a double.
//
// nlohmann::json refuses them (out_of_range.406) and stops parsing, so `1e999` would be reported
// as a parse error without its JSON path. Before parsing, each such literal is replaced by
// `1e308` (or `-1e308`), padded with spaces to the same length so that the line and column of
// any later parse error stay the same. 1e308 does not fit a float, so the checker then reports
// it, with its path, as a number that overflows to infinity.

bool IsDigit(char c) { return c >= '0' && c <= '9'; }

// -?(0|[1-9][0-9]*)(\.[0-9]+)?([eE][+-]?[0-9]+)?
bool IsJsonNumber(std::string_view s) {
  size_t i = 0;
  if (i < s.size() && s[i] == '-') ++i;
  if (i >= s.size() || !IsDigit(s[i])) return false;
  if (s[i] == '0') {
    ++i;
  } else {
    while (i < s.size() && IsDigit(s[i])) ++i;
  }
  if (i < s.size() && s[i] == '.') {
    ++i;
    if (i >= s.size() || !IsDigit(s[i])) return false;
    while (i < s.size() && IsDigit(s[i])) ++i;
  }
  if (i < s.size() && (s[i] == 'e' || s[i] == 'E')) {
    ++i;
    if (i < s.size() && (s[i] == '+' || s[i] == '-')) ++i;
    if (i >= s.size() || !IsDigit(s[i])) return false;
    while (i < s.size() && IsDigit(s[i])) ++i;
  }
  return i == s.size();
}

// True when the (valid JSON) number literal is too large in magnitude for a double.
bool OverflowsDouble(std::string_view s) {
  double value = 0.0;
  const auto res = std::from_chars(s.data(), s.data() + s.size(), value);
  if (res.ec != std::errc::result_out_of_range) return !std::isfinite(value) && res.ec == std::errc();
  // Out of range is overflow or underflow: decide by the decimal order of magnitude.
  size_t i = s[0] == '-' ? 1 : 0;
  long long int_digits = 0, first_nonzero = -1, pos = 0;
  bool in_fraction = false;
  for (; i < s.size() && s[i] != 'e' && s[i] != 'E'; ++i) {
    if (s[i] == '.') {
      in_fraction = true;
      continue;
    }
    if (!in_fraction) ++int_digits;
    if (s[i] != '0' && first_nonzero < 0) first_nonzero = pos;
    ++pos;
  }
  if (first_nonzero < 0) return false;  // zero
  long long exponent = 0;
  bool negative = false;
  if (i < s.size()) {
    ++i;
    if (i < s.size() && (s[i] == '+' || s[i] == '-')) negative = s[i++] == '-';
    for (; i < s.size(); ++i) exponent = std::min(exponent * 10 + (s[i] - '0'), 1000000000LL);
  }
  if (negative) exponent = -exponent;
  // value = 0.d1d2... * 10^(int_digits - first_nonzero + exponent)
  return int_digits - first_nonzero + exponent > 0;
}

std::string ReplaceOverflowingNumbers(std::string_view text) {
  std::string out(text);
  bool in_string = false;
  for (size_t i = 0; i < out.size(); ++i) {
    const char c = out[i];
    if (in_string) {
      if (c == '\\') ++i;
      else if (c == '"') in_string = false;
      continue;
    }
    if (c == '"') {
      in_string = true;
      continue;
    }
    if (c != '-' && !IsDigit(c)) continue;
    size_t j = i;
    while (j < out.size() && (IsDigit(out[j]) || out[j] == '-' || out[j] == '+' || out[j] == '.' ||
                              out[j] == 'e' || out[j] == 'E'))
      ++j;
    const std::string_view literal(out.data() + i, j - i);
    if (IsJsonNumber(literal) && OverflowsDouble(literal)) {
      // The shortest overflowing literal is 5 characters ("9e308"), 6 with a minus sign.
      const std::string repl = literal[0] == '-' ? "-1e308" : "1e308";
      if (repl.size() <= literal.size()) {
        out.replace(i, literal.size(), repl + std::string(literal.size() - repl.size(), ' '));
      }
    }
    i = j - 1;
  }
  return out;
}

// ---------------------------------------------------------------------------------------------
// Duplicate object keys (nlohmann keeps the last one silently): found with a parser callback
// that tracks the JSON path of the value being parsed.

class DuplicateKeyTracker {
 public:
  bool operator()(int /*depth*/, json::parse_event_t event, json& parsed) {
    switch (event) {
      case json::parse_event_t::object_start: Push(false); break;
      case json::parse_event_t::array_start: Push(true); break;
      case json::parse_event_t::key:
        if (!stack_.empty() && parsed.is_string()) {
          Frame& top = stack_.back();
          top.key = parsed.get<std::string>();
          if (!top.keys.insert(top.key).second) duplicates.push_back(Path());
        }
        break;
      case json::parse_event_t::object_end:
      case json::parse_event_t::array_end:
        if (!stack_.empty()) stack_.pop_back();
        ElementDone();
        break;
      case json::parse_event_t::value: ElementDone(); break;
    }
    return true;
  }

  std::vector<std::string> duplicates;  // JSON paths of repeated keys

 private:
  struct Frame {
    bool is_array = false;
    size_t index = 0;
    std::string key;
    std::set<std::string> keys;
  };
  void Push(bool is_array) {
    stack_.emplace_back();
    stack_.back().is_array = is_array;
  }
  void ElementDone() {
    if (!stack_.empty() && stack_.back().is_array) ++stack_.back().index;
  }
  std::string Path() const {
    std::string p;
    for (const Frame& f : stack_) p = f.is_array ? Index(p, f.index) : Key(p, f.key);
    return p;
  }
  std::vector<Frame> stack_;
};

// Line and column (1-based) of byte offset `byte` (1-based, as nlohmann reports it).
void LineColumn(std::string_view text, size_t byte, size_t* line, size_t* column) {
  *line = 1;
  *column = 1;
  const size_t end = std::min(byte > 0 ? byte - 1 : 0, text.size());
  for (size_t i = 0; i < end; ++i) {
    if (text[i] == '\n') {
      ++*line;
      *column = 1;
    } else {
      ++*column;
    }
  }
}

// `s` with invalid UTF-8 replaced by U+FFFD (parse errors quote the bytes last read).
std::string ValidUtf8(const std::string& s) {
  try {
    return json::parse(json(s).dump(-1, ' ', false, json::error_handler_t::replace))
        .get<std::string>();
  } catch (const std::exception&) {
    return "(unprintable)";
  }
}

// The part of nlohmann's parse error message after its position ("syntax error while ...").
std::string ParseErrorDetail(const std::string& what) {
  const size_t column = what.find("column ");
  if (column != std::string::npos) {
    const size_t colon = what.find(": ", column);
    if (colon != std::string::npos) return ValidUtf8(what.substr(colon + 2));
  }
  const size_t colon = what.find("parse error: ");
  if (colon != std::string::npos) return ValidUtf8(what.substr(colon + 13));
  return ValidUtf8(what);
}

// ---------------------------------------------------------------------------------------------
// The checker: walks the parsed document, fills a RigSpec, records every problem.

class RigChecker {
 public:
  RigChecker(const std::string& base_dir, Diagnostics* diag) : base_dir_(base_dir), diag_(diag) {}

  void CheckRoot(const json& root, RigSpec* spec);

 private:
  void Error(const std::string& where, std::string what) { diag_->Error(where, std::move(what)); }

  // Reports every key of `obj` not in `allowed`.
  void CheckKeys(const json& obj, const std::string& path, const std::vector<std::string>& allowed,
                 const std::string& owner) {
    for (auto it = obj.begin(); it != obj.end(); ++it) {
      if (Contains(allowed, it.key())) continue;
      std::string what = "unknown key " + Quoted(it.key());
      if (path.empty() && Contains(kReservedTopKeys, it.key()))
        what += " (reserved for a later version of the format; this build reads version 1)";
      if (path.empty() && it.key() == "wrinkles")
        what += " (muscle-derived wrinkles go inside each muscle: muscles[i].wrinkles)";
      what += "; allowed keys" + (owner.empty() ? std::string() : " for " + owner) + ": " +
              JoinList(allowed, false);
      Error(Key(path, it.key()), what);
    }
  }

  // The member `key` of `obj`, or null (reported when `expect` is non-empty: a required key).
  const json* Member(const json& obj, const std::string& path, const std::string& key,
                     const std::string& expect) {
    const auto it = obj.find(key);
    if (it != obj.end()) return &*it;
    if (!expect.empty()) Error(Key(path, key), "missing required key; expected " + expect);
    return nullptr;
  }

  // A number that fits a float. `expect` names the whole expectation, range included.
  bool ReadFloat(const json& v, const std::string& path, const std::string& expect, float* out) {
    if (!v.is_number()) {
      Error(path, "expected " + expect + ", got " + TypeName(v));
      return false;
    }
    const double d = v.get<double>();
    const float f = static_cast<float>(d);
    if (!std::isfinite(d) || !std::isfinite(f)) {
      Error(path, "expected " + expect +
                      ", got a number too large for a 32-bit float (it overflows to infinity)");
      return false;
    }
    *out = f;
    return true;
  }

  bool ReadNonNegative(const json& v, const std::string& path, float* out) {
    const std::string expect = "a finite number >= 0";
    float f = 0.f;
    if (!ReadFloat(v, path, expect, &f)) return false;
    if (!(f >= 0.f)) {
      Error(path, "expected " + expect + ", got " + Describe(v));
      return false;
    }
    *out = f;
    return true;
  }

  bool ReadPositive(const json& v, const std::string& path, float* out) {
    const std::string expect = "a finite number > 0";
    float f = 0.f;
    if (!ReadFloat(v, path, expect, &f)) return false;
    if (!(f > 0.f)) {
      Error(path, "expected " + expect + ", got " + Describe(v));
      return false;
    }
    *out = f;
    return true;
  }

  bool ReadVec3(const json& v, const std::string& path, float3* out) {
    if (!v.is_array() || v.size() != 3) {
      Error(path, std::string("expected array of 3 numbers, got ") +
                      (v.is_array() ? Describe(v) : TypeName(v)));
      return false;
    }
    float c[3] = {0.f, 0.f, 0.f};
    bool ok = true;
    for (size_t i = 0; i < 3; ++i) ok &= ReadFloat(v[i], Index(path, i), "a finite number", &c[i]);
    if (ok) *out = {c[0], c[1], c[2]};
    return ok;
  }

  // Two distinct points.
  bool ReadLine(const json& v, const std::string& path, float3 out[2]) {
    if (!v.is_array() || v.size() != 2) {
      Error(path, std::string("expected array of 2 points (each an array of 3 numbers), got ") +
                      (v.is_array() ? Describe(v) : TypeName(v)));
      return false;
    }
    float3 p[2];
    bool ok = ReadVec3(v[0], Index(path, 0), &p[0]);
    ok &= ReadVec3(v[1], Index(path, 1), &p[1]);
    if (!ok) return false;
    if (!(LengthSquared(p[1] - p[0]) > 0.f)) {
      Error(path, "the two points are equal; expected two distinct points (a line)");
      return false;
    }
    out[0] = p[0];
    out[1] = p[1];
    return true;
  }

  bool ReadNonEmptyString(const json& v, const std::string& path, const std::string& expect,
                          std::string* out) {
    if (!v.is_string() || v.get_ref<const std::string&>().empty()) {
      Error(path, "expected " + expect + ", got " +
                      (v.is_string() ? std::string("empty string") : std::string(TypeName(v))));
      return false;
    }
    *out = v.get<std::string>();
    return true;
  }

  // `value` must be one of `choices` (strings).
  bool ReadChoice(const json& v, const std::string& path, const std::vector<std::string>& choices,
                  std::string* out) {
    if (v.is_string() && Contains(choices, v.get<std::string>())) {
      *out = v.get<std::string>();
      return true;
    }
    Error(path, "expected one of " + JoinList(choices, true) + ", got " + Describe(v));
    return false;
  }

  bool ReadBool(const json& v, const std::string& path, bool* out) {
    if (!v.is_boolean()) {
      Error(path, "expected boolean (true or false), got " + Describe(v));
      return false;
    }
    *out = v.get<bool>();
    return true;
  }

  // A whole number in [min, INT_MAX] (3.0 counts as whole, as in JSON Schema).
  bool ReadInt(const json& v, const std::string& path, int min, int* out) {
    const std::string expect = "an integer >= " + std::to_string(min);
    if (!v.is_number()) {
      Error(path, "expected " + expect + ", got " + TypeName(v));
      return false;
    }
    const double d = v.get<double>();
    if (!(d >= min && d <= static_cast<double>(INT_MAX) && d == std::floor(d))) {
      Error(path, "expected " + expect + ", got " + Describe(v));
      return false;
    }
    *out = static_cast<int>(d);
    return true;
  }

  void CheckFormatAndVersion(const json& root, bool* version_supported);
  void CheckMesh(const json& root, RigSpec* spec);
  void CheckThickness(const json& v, ThicknessSpec* out);
  void CheckMuscles(const json& v, RigSpec* spec);
  bool CheckMuscle(const json& v, const std::string& path, MuscleSpec* out,
                   std::optional<MuscleWrinkleSpec>* wrinkles);
  bool CheckMuscleWrinkles(const json& v, const std::string& path, const json& muscle_json,
                           const MuscleSpec& muscle, bool muscle_ok, MuscleWrinkleSpec* out);
  void CheckCurveWrinkles(const json& v, std::vector<NamedCurveWrinkle>* out);
  bool CheckCurveWrinkle(const json& v, const std::string& path, NamedCurveWrinkle* out);
  void CheckLayers(const json& v, LayerSpec* out);
  void CheckRefinement(const json& v, RefinementSpec* out);
  bool CheckLinear(const json& v, const std::string& path, LinearMuscleSpec* out);
  bool CheckSheet(const json& v, const std::string& path, SheetMuscleSpec* out);

  std::string base_dir_;
  Diagnostics* diag_;
};

void RigChecker::CheckRoot(const json& root, RigSpec* spec) {
  if (!root.is_object()) {
    Error("", std::string("expected the top-level value to be an object {\"format\": \"") +
                  kFormatName + "\", ...}, got " + TypeName(root));
    return;
  }
  bool version_supported = true;
  CheckFormatAndVersion(root, &version_supported);
  // A newer version may have keys and rules this build does not know: one error is enough.
  if (!version_supported) return;

  CheckKeys(root, "", kTopKeys, "");
  CheckMesh(root, spec);
  if (const json* units = Member(root, "", "units", "one of " + JoinList(kUnits, true)))
    ReadChoice(*units, "units", kUnits, &spec->units);
  if (const json* thickness = Member(root, "", "thickness", ""))
    CheckThickness(*thickness, &spec->thickness);
  if (const json* muscles = Member(root, "", "muscles", "array of muscles (may be empty)"))
    CheckMuscles(*muscles, spec);
  // Always parallel to `muscles` (nullopt = no wrinkle block).
  spec->muscle_wrinkles.resize(spec->muscles.size());
  if (const json* curves = Member(root, "", "curve_wrinkles", ""))
    CheckCurveWrinkles(*curves, &spec->curve_wrinkles);
  if (const json* layers = Member(root, "", "layers", "")) CheckLayers(*layers, &spec->layers);
  if (const json* refinement = Member(root, "", "refinement", ""))
    CheckRefinement(*refinement, &spec->refinement);
}

void RigChecker::CheckFormatAndVersion(const json& root, bool* version_supported) {
  if (const json* format = Member(root, "", "format", std::string("\"") + kFormatName + "\"")) {
    if (!format->is_string() || format->get<std::string>() != kFormatName)
      Error("format", std::string("expected \"") + kFormatName + "\", got " + Describe(*format));
  }
  const json* version = Member(root, "", "version", "integer 1");
  if (!version) return;
  if (!version->is_number()) {
    Error("version", std::string("expected integer 1, got ") + TypeName(*version));
    return;
  }
  const double v = version->get<double>();
  if (v == kFormatVersion) return;
  if (v > kFormatVersion && v <= 1e9 && v == std::floor(v)) {
    Error("version", "unsupported version " + version->dump() + ": this build reads version 1");
    *version_supported = false;
    return;
  }
  Error("version", "expected integer 1, got " + Describe(*version));
}

void RigChecker::CheckMesh(const json& root, RigSpec* spec) {
  const json* mesh = Member(root, "", "mesh", "object {\"path\": \"surface.obj\"}");
  if (!mesh) return;
  if (!mesh->is_object()) {
    Error("mesh", std::string("expected object {\"path\": ..., \"name\": ...}, got ") +
                      TypeName(*mesh));
    return;
  }
  CheckKeys(*mesh, "mesh", kMeshKeys, "mesh");
  const std::string path_expect =
      "non-empty string (.obj, .gltf or .glb file, relative to the rig file's directory)";
  if (const json* path = Member(*mesh, "mesh", "path", path_expect)) {
    std::string p;
    if (ReadNonEmptyString(*path, "mesh.path", path_expect, &p))
      spec->mesh_path = JoinPath(base_dir_, p);
  }
  if (const json* name = Member(*mesh, "mesh", "name", "")) {
    if (name->is_string())
      spec->mesh_name = name->get<std::string>();
    else
      Error("mesh.name", std::string("expected string (glTF mesh name), got ") + TypeName(*name));
  }
}

void RigChecker::CheckThickness(const json& v, ThicknessSpec* out) {
  const std::string path = "thickness";
  if (!v.is_object()) {
    Error(path, std::string("expected object {\"type\": \"constant\" | \"per_vertex\" | "
                            "\"image\", ...}, got ") +
                    TypeName(v));
    return;
  }
  static const std::vector<std::string> kTypes = {"constant", "per_vertex", "image"};
  std::string type;
  const json* type_value = Member(v, path, "type", "one of " + JoinList(kTypes, true));
  if (!type_value || !ReadChoice(*type_value, Key(path, "type"), kTypes, &type)) {
    CheckKeys(v, path, {"type", "value", "values", "path", "min", "max"}, "thickness");
    return;
  }
  if (type == "constant") {
    CheckKeys(v, path, {"type", "value"}, "constant thickness");
    out->kind = ThicknessSpec::Kind::kConstant;
    if (const json* value = Member(v, path, "value", "a finite number >= 0 (mesh units)"))
      ReadNonNegative(*value, Key(path, "value"), &out->value);
  } else if (type == "per_vertex") {
    CheckKeys(v, path, {"type", "values"}, "per-vertex thickness");
    out->kind = ThicknessSpec::Kind::kPerVertex;
    const json* values =
        Member(v, path, "values", "array of numbers >= 0, one per vertex of the mesh file");
    if (!values) return;
    const std::string vpath = Key(path, "values");
    if (!values->is_array()) {
      Error(vpath, std::string("expected array of numbers >= 0, one per vertex of the mesh "
                               "file, got ") +
                       TypeName(*values));
      return;
    }
    out->per_vertex.assign(values->size(), 0.f);
    size_t bad = 0;
    for (size_t i = 0; i < values->size(); ++i) {
      const json& e = (*values)[i];
      const bool good = e.is_number() && std::isfinite(static_cast<float>(e.get<double>())) &&
                        e.get<double>() >= 0.0;
      if (good) {
        out->per_vertex[i] = static_cast<float>(e.get<double>());
        continue;
      }
      if (++bad <= kMaxElementErrors) ReadNonNegative(e, Index(vpath, i), &out->per_vertex[i]);
    }
    if (bad > kMaxElementErrors) {
      Error(vpath, std::to_string(bad - kMaxElementErrors) +
                       " more invalid elements not listed; expected finite numbers >= 0");
    }
  } else {
    CheckKeys(v, path, {"type", "path", "min", "max"}, "image thickness");
    out->kind = ThicknessSpec::Kind::kImage;
    const std::string expect = "non-empty string (grayscale image, relative to the rig file)";
    if (const json* p = Member(v, path, "path", expect)) {
      std::string s;
      if (ReadNonEmptyString(*p, Key(path, "path"), expect, &s))
        out->image_path = JoinPath(base_dir_, s);
    }
    bool have_min = false, have_max = false;
    if (const json* m = Member(v, path, "min", "a finite number >= 0 (thickness at black)"))
      have_min = ReadNonNegative(*m, Key(path, "min"), &out->min);
    if (const json* m = Member(v, path, "max", "a finite number >= 0 (thickness at white)"))
      have_max = ReadNonNegative(*m, Key(path, "max"), &out->max);
    if (have_min && have_max && out->min > out->max) {
      Error(path, "min (" + FormatFloat(out->min) + ") > max (" + FormatFloat(out->max) +
                      "); expected min <= max");
    }
  }
}

void RigChecker::CheckMuscles(const json& v, RigSpec* spec) {
  if (!v.is_array()) {
    Error("muscles", std::string("expected array of muscles, got ") + TypeName(v));
    return;
  }
  std::map<std::string, size_t> first_use;  // name -> index of the muscle that used it first
  for (size_t i = 0; i < v.size(); ++i) {
    const std::string path = Index("muscles", i);
    MuscleSpec muscle;
    std::optional<MuscleWrinkleSpec> wrinkles;
    const bool ok = CheckMuscle(v[i], path, &muscle, &wrinkles);
    if (!muscle.name.empty()) {
      const auto [it, inserted] = first_use.emplace(muscle.name, i);
      if (!inserted) {
        Error(Key(path, "name"), "duplicate muscle name " + Quoted(muscle.name) +
                                     " (first used by " + Index("muscles", it->second) +
                                     "); expected a name unique within the rig");
      }
    }
    if (ok) {
      spec->muscles.push_back(std::move(muscle));
      spec->muscle_wrinkles.push_back(wrinkles);
    }
  }
}

bool RigChecker::CheckMuscle(const json& v, const std::string& path, MuscleSpec* out,
                             std::optional<MuscleWrinkleSpec>* wrinkles) {
  if (!v.is_object()) {
    Error(path, std::string("expected object (a muscle), got ") + TypeName(v));
    return false;
  }
  bool ok = true;
  if (const json* name = Member(v, path, "name", "non-empty string")) {
    ok &= ReadNonEmptyString(*name, Key(path, "name"), "non-empty string", &out->name);
  } else {
    ok = false;
  }

  // The type decides which keys are allowed.
  enum { kUnknown, kLinear, kSheet } type = kUnknown;
  const json* type_value = Member(v, path, "type", "\"linear\" or \"sheet\"");
  if (type_value) {
    if (!type_value->is_string()) {
      Error(Key(path, "type"), std::string("expected \"linear\" or \"sheet\", got ") +
                                   TypeName(*type_value));
    } else if (type_value->get<std::string>() == "linear") {
      type = kLinear;
    } else if (type_value->get<std::string>() == "sheet") {
      type = kSheet;
    } else {
      Error(Key(path, "type"),
            "unknown muscle type " + Describe(*type_value) +
                "; supported types: \"linear\", \"sheet\" (sphincter muscles are not supported)");
    }
  }
  CheckKeys(v, path,
            type == kLinear ? kLinearKeys : type == kSheet ? kSheetKeys : kAnyMuscleKeys,
            type == kLinear ? "a linear muscle" : type == kSheet ? "a sheet muscle" : "a muscle");

  if (const json* strength = Member(v, path, "strength",
                                    "a finite number >= 0 (contraction at activation 1, mesh "
                                    "units)")) {
    ok &= ReadNonNegative(*strength, Key(path, "strength"), &out->strength);
  } else {
    ok = false;
  }

  if (type == kLinear) {
    out->type = MuscleType::kLinear;
    ok &= CheckLinear(v, path, &out->linear);
  } else if (type == kSheet) {
    out->type = MuscleType::kSheet;
    ok &= CheckSheet(v, path, &out->sheet);
  } else {
    ok = false;
  }

  // MODEL.md §6: the optional wrinkle block, checked against the muscle's geometry.
  if (type != kUnknown) {
    if (const json* w = Member(v, path, "wrinkles", "")) {
      MuscleWrinkleSpec spec;
      if (CheckMuscleWrinkles(*w, Key(path, "wrinkles"), v, *out, ok, &spec)) {
        *wrinkles = spec;
      } else {
        ok = false;
      }
    }
  }
  return ok;
}

// MODEL.md §6 (001 eq. 5-7, 12, 15). `muscle` is the parsed muscle; its geometry is trusted only
// when `muscle_ok` (otherwise the muscle's own errors are already reported and only the ranges
// that do not depend on it are checked).
bool RigChecker::CheckMuscleWrinkles(const json& v, const std::string& path,
                                     const json& muscle_json, const MuscleSpec& muscle,
                                     bool muscle_ok, MuscleWrinkleSpec* out) {
  const bool linear = muscle.type == MuscleType::kLinear;
  if (!v.is_object()) {
    Error(path, std::string("expected object {\"lambda_w\": ..., \"count\": ..., \"depth\": "
                            "..., \"shape\": ..., ") +
                    (linear ? "\"phi_c_deg\"" : "\"h_c\"") + ": ...}, got " + TypeName(v));
    return false;
  }
  bool ok = true;
  // The attenuation key of the other muscle type gets its own message.
  const std::string wrong_key = linear ? "h_c" : "phi_c_deg";
  if (v.contains(wrong_key)) {
    Error(Key(path, wrong_key),
          linear ? std::string("\"h_c\" is for the wrinkles of a sheet muscle, and this is a "
                               "linear muscle; expected \"phi_c_deg\" (degrees, where the "
                               "attenuation across the zone starts)")
                 : std::string("\"phi_c_deg\" is for the wrinkles of a linear muscle, and this "
                               "is a sheet muscle; expected \"h_c\" (mesh units, distance from "
                               "the central fiber where the attenuation starts)"));
    ok = false;
  }
  // Unknown keys, listing the allowed ones (the wrong-type key was reported above).
  const std::vector<std::string>& allowed = linear ? kLinearWrinkleKeys : kSheetWrinkleKeys;
  for (auto it = v.begin(); it != v.end(); ++it) {
    if (Contains(allowed, it.key()) || it.key() == wrong_key) continue;
    Error(Key(path, it.key()), "unknown key " + Quoted(it.key()) +
                                   "; allowed keys for the wrinkles of a " +
                                   (linear ? "linear" : "sheet") +
                                   " muscle: " + JoinList(allowed, false));
    ok = false;
  }

  MuscleWrinkleSpec spec;  // defaults for absent optional keys
  if (const json* lw = Member(v, path, "lambda_w", "")) {
    const std::string expect = "a number in [0, 1) (start of the wrinkling region, fraction of " +
                               std::string(linear ? "falloff_end" : "length") + ")";
    float f = 0.f;
    if (ReadFloat(*lw, Key(path, "lambda_w"), expect, &f)) {
      if (f >= 0.f && f < 1.f) {
        spec.lambda_w = f;
      } else {
        Error(Key(path, "lambda_w"), "expected " + expect + ", got " + Describe(*lw));
        ok = false;
      }
    } else {
      ok = false;
    }
  }
  if (const json* n = Member(v, path, "count", ""))
    ok &= ReadInt(*n, Key(path, "count"), 1, &spec.count);
  if (const json* d = Member(v, path, "depth", "a finite number >= 0 (k0, mesh units)")) {
    ok &= ReadNonNegative(*d, Key(path, "depth"), &spec.depth);
  } else {
    ok = false;
  }
  if (const json* a = Member(v, path, "shape", ""))
    ok &= ReadFloat(*a, Key(path, "shape"), "a finite number (alpha)", &spec.shape);

  if (linear) {
    const bool have_zone = muscle_ok && muscle.linear.zone_angle > 0.f;
    const json* zone = muscle_json.contains("zone_angle_deg") ? &muscle_json["zone_angle_deg"]
                                                              : nullptr;
    const std::string expect =
        have_zone && zone ? "a number in [0, zone_angle_deg = " + zone->dump() + ") (degrees)"
                          : std::string("a number in [0, zone_angle_deg) (degrees)");
    if (const json* pc = Member(v, path, "phi_c_deg", "")) {
      float deg = 0.f;
      if (ReadFloat(*pc, Key(path, "phi_c_deg"), expect, &deg)) {
        const double d = pc->get<double>();
        const float rad = DegreesToRadians(d);
        if (d >= 0.0 && d < 180.0 && (!have_zone || rad < muscle.linear.zone_angle)) {
          spec.phi_c = rad;
        } else {
          Error(Key(path, "phi_c_deg"), "expected " + expect + ", got " + Describe(*pc));
          ok = false;
        }
      } else {
        ok = false;
      }
    }
  } else {
    const bool have_width = muscle_ok && muscle.sheet.width > 0.f;
    const std::string expect =
        have_width ? "a number in [0, width/2 = " + FormatFloat(0.5f * muscle.sheet.width) +
                         ") (mesh units)"
                   : std::string("a number in [0, width/2) (mesh units)");
    if (const json* hc = Member(v, path, "h_c", "")) {
      float f = 0.f;
      if (ReadFloat(*hc, Key(path, "h_c"), expect, &f)) {
        if (f >= 0.f && (!have_width || f < 0.5f * muscle.sheet.width)) {
          spec.h_c = f;
        } else {
          Error(Key(path, "h_c"), "expected " + expect + ", got " + Describe(*hc));
          ok = false;
        }
      } else {
        ok = false;
      }
    }
  }
  if (!ok) return false;
  *out = spec;
  if (!muscle_ok) return true;  // the muscle's own errors make the rig fail anyway

  // The wrinkle module's own check (same ranges; reported only if it is stricter than the above).
  const WrinkleMuscleGeometry geometry = WrinkleGeometryOf(muscle);
  return ValidateMuscleWrinkleSpec(spec, geometry, path, diag_);
}

// MODEL.md §7-8.
void RigChecker::CheckCurveWrinkles(const json& v, std::vector<NamedCurveWrinkle>* out) {
  if (!v.is_array()) {
    Error("curve_wrinkles", std::string("expected array of curve wrinkles, got ") + TypeName(v));
    return;
  }
  std::map<std::string, size_t> first_use;
  for (size_t i = 0; i < v.size(); ++i) {
    const std::string path = Index("curve_wrinkles", i);
    NamedCurveWrinkle curve;
    const bool ok = CheckCurveWrinkle(v[i], path, &curve);
    if (!curve.name.empty()) {
      const auto [it, inserted] = first_use.emplace(curve.name, i);
      if (!inserted) {
        Error(Key(path, "name"), "duplicate curve wrinkle name " + Quoted(curve.name) +
                                     " (first used by " + Index("curve_wrinkles", it->second) +
                                     "); expected a name unique among the curve wrinkles");
      }
    }
    if (ok) out->push_back(std::move(curve));
  }
}

bool RigChecker::CheckCurveWrinkle(const json& v, const std::string& path, NamedCurveWrinkle* out) {
  if (!v.is_object()) {
    Error(path, std::string("expected object (a curve wrinkle), got ") + TypeName(v));
    return false;
  }
  const size_t errors_before = diag_->ErrorCount();
  CheckKeys(v, path, kCurveWrinkleKeys, "a curve wrinkle");
  bool ok = diag_->ErrorCount() == errors_before;
  if (const json* name = Member(v, path, "name", "non-empty string")) {
    ok &= ReadNonEmptyString(*name, Key(path, "name"), "non-empty string", &out->name);
  } else {
    ok = false;
  }
  CurveWrinkleSpec& spec = out->spec;
  const std::string control_expect =
      "array of 4 points (cubic Bezier control points, each [u, v] in texture space)";
  if (const json* c = Member(v, path, "control", control_expect)) {
    const std::string cpath = Key(path, "control");
    if (!c->is_array() || c->size() != 4) {
      Error(cpath, "expected " + control_expect + ", got " +
                       (c->is_array() ? Describe(*c) : std::string(TypeName(*c))));
      ok = false;
    } else {
      for (size_t k = 0; k < 4; ++k) {
        const json& p = (*c)[k];
        const std::string ppath = Index(cpath, k);
        if (!p.is_array() || p.size() != 2) {
          Error(ppath, "expected array of 2 numbers [u, v], got " +
                           (p.is_array() ? Describe(p) : std::string(TypeName(p))));
          ok = false;
          continue;
        }
        ok &= ReadFloat(p[0], Index(ppath, 0), "a finite number", &spec.control[k].x);
        ok &= ReadFloat(p[1], Index(ppath, 1), "a finite number", &spec.control[k].y);
      }
    }
  } else {
    ok = false;
  }
  if (const json* d = Member(v, path, "depth", "a finite number > 0 (mesh units)")) {
    ok &= ReadPositive(*d, Key(path, "depth"), &spec.depth);
  } else {
    ok = false;
  }
  if (const json* w = Member(v, path, "width", "a finite number > 0 (mesh units)")) {
    ok &= ReadPositive(*w, Key(path, "width"), &spec.width);
  } else {
    ok = false;
  }
  if (const json* p = Member(v, path, "profile", "")) {
    std::string s;
    if (ReadChoice(*p, Key(path, "profile"), ProfileNames(), &s)) {
      spec.profile = s == ProfileNames()[0]   ? CurveWrinkleProfile::kBando
                     : s == ProfileNames()[1] ? CurveWrinkleProfile::kYangZhang
                                              : CurveWrinkleProfile::kYangZhangExact;
    } else {
      ok = false;
    }
  }
  if (const json* m = Member(v, path, "modulation", "")) {
    std::string s;
    if (ReadChoice(*m, Key(path, "modulation"), ModulationNames(), &s)) {
      spec.modulation = s == ModulationNames()[0] ? CurveWrinkleModulation::kDirectional
                                                  : CurveWrinkleModulation::kArea;
    } else {
      ok = false;
    }
  }
  if (const json* r = Member(v, path, "rest_amplitude", "")) {
    const std::string expect = "a number in [0, 1]";
    float f = 0.f;
    if (ReadFloat(*r, Key(path, "rest_amplitude"), expect, &f)) {
      if (f >= 0.f && f <= 1.f) {
        spec.rest_amplitude = f;
      } else {
        Error(Key(path, "rest_amplitude"), "expected " + expect + ", got " + Describe(*r));
        ok = false;
      }
    } else {
      ok = false;
    }
  }
  if (!ok) return false;
  // The wrinkle module's own check (same ranges; reported only if it is stricter than the above).
  return ValidateCurveWrinkleSpec(spec, path, diag_);
}

void RigChecker::CheckLayers(const json& v, LayerSpec* out) {
  if (!v.is_object()) {
    Error("layers", std::string("expected object {\"thickness\": true, \"muscle_wrinkles\": "
                                "true, \"curve_wrinkles\": true}, got ") +
                        TypeName(v));
    return;
  }
  CheckKeys(v, "layers", kLayerKeys, "layers");
  if (const json* b = Member(v, "layers", "thickness", ""))
    ReadBool(*b, "layers.thickness", &out->thickness);
  if (const json* b = Member(v, "layers", "muscle_wrinkles", ""))
    ReadBool(*b, "layers.muscle_wrinkles", &out->muscle_wrinkles);
  if (const json* b = Member(v, "layers", "curve_wrinkles", ""))
    ReadBool(*b, "layers.curve_wrinkles", &out->curve_wrinkles);
}

// MODEL.md §11.
void RigChecker::CheckRefinement(const json& v, RefinementSpec* out) {
  if (!v.is_object()) {
    Error("refinement", std::string("expected object {\"enabled\": true, \"edge_fraction\": "
                                    "0.25}, got ") +
                            TypeName(v));
    return;
  }
  CheckKeys(v, "refinement", kRefinementKeys, "refinement");
  if (const json* b = Member(v, "refinement", "enabled", ""))
    ReadBool(*b, "refinement.enabled", &out->enabled);
  if (const json* e = Member(v, "refinement", "edge_fraction", "")) {
    const std::string expect = "a number in (0, 1] (fraction of the wrinkle width)";
    float f = 0.f;
    if (ReadFloat(*e, "refinement.edge_fraction", expect, &f)) {
      if (f > 0.f && f <= 1.f) {
        out->edge_fraction = f;
      } else {
        Error("refinement.edge_fraction", "expected " + expect + ", got " + Describe(*e));
      }
    }
  }
}

// MODEL.md §2: v1 (attachment), v2 (insertion), Omega, Rs, Rf.
bool RigChecker::CheckLinear(const json& v, const std::string& path, LinearMuscleSpec* out) {
  bool ok = true;
  const json* a = Member(v, path, "attachment", "array of 3 numbers (bone end, v1)");
  const json* b = Member(v, path, "insertion", "array of 3 numbers (skin end, v2)");
  const bool have_a = a && ReadVec3(*a, Key(path, "attachment"), &out->attachment);
  const bool have_b = b && ReadVec3(*b, Key(path, "insertion"), &out->insertion);
  ok &= have_a && have_b;
  if (have_a && have_b && out->attachment == out->insertion) {
    Error(path, "attachment equals insertion; expected two distinct points (the muscle's axis "
                "runs from attachment to insertion)");
    ok = false;
  }

  const std::string angle_expect = "a number in (0, 180) (degrees)";
  if (const json* angle = Member(v, path, "zone_angle_deg", angle_expect)) {
    float deg = 0.f;
    if (ReadFloat(*angle, Key(path, "zone_angle_deg"), angle_expect, &deg)) {
      const double d = angle->get<double>();
      const float rad = DegreesToRadians(d);
      if (!(d > 0.0 && d < 180.0 && rad > 0.f)) {
        Error(Key(path, "zone_angle_deg"), "expected " + angle_expect + ", got " + Describe(*angle));
        ok = false;
      } else {
        out->zone_angle = rad;
      }
    } else {
      ok = false;
    }
  } else {
    ok = false;
  }

  const json* rs = Member(v, path, "falloff_start", "a finite number > 0 (Rs, mesh units)");
  const bool have_rs = rs && ReadPositive(*rs, Key(path, "falloff_start"), &out->falloff_start);
  ok &= have_rs;
  if (const json* rf = Member(v, path, "falloff_end", "a finite number > falloff_start (Rf)")) {
    float f = 0.f;
    const std::string expect =
        have_rs ? "a number > falloff_start (" + FormatFloat(out->falloff_start) + ")"
                : std::string("a finite number > falloff_start");
    if (ReadFloat(*rf, Key(path, "falloff_end"), expect, &f)) {
      if (have_rs && !(f > out->falloff_start)) {
        Error(Key(path, "falloff_end"), "expected " + expect + ", got " + Describe(*rf));
        ok = false;
      } else if (!have_rs && !(f > 0.f)) {
        Error(Key(path, "falloff_end"), "expected " + expect + ", got " + Describe(*rf));
        ok = false;
      }
      out->falloff_end = f;
    } else {
      ok = false;
    }
  } else {
    ok = false;
  }
  return ok;
}

// MODEL.md §3: attachment line mA1 mA2, insertion line mI1 mI2, Ls, Ws, Rs.
bool RigChecker::CheckSheet(const json& v, const std::string& path, SheetMuscleSpec* out) {
  bool ok = true;
  const json* a = Member(v, path, "attachment", "array of 2 points (the attachment line)");
  const json* b = Member(v, path, "insertion", "array of 2 points (the insertion line)");
  const bool have_a = a && ReadLine(*a, Key(path, "attachment"), out->attachment);
  const bool have_b = b && ReadLine(*b, Key(path, "insertion"), out->insertion);
  ok &= have_a && have_b;
  if (have_a && have_b) {
    const float3 mac = (out->attachment[0] + out->attachment[1]) * 0.5f;
    const float3 mic = (out->insertion[0] + out->insertion[1]) * 0.5f;
    if (!(LengthSquared(mic - mac) > 0.f)) {
      Error(path, "zero-length fiber: the midpoints of the attachment and insertion lines "
                  "coincide; expected distinct midpoints (the central fiber runs between them)");
      ok = false;
    }
  }
  const json* len = Member(v, path, "length", "a finite number > 0 (Ls, mesh units)");
  const bool have_len = len && ReadPositive(*len, Key(path, "length"), &out->length);
  ok &= have_len;
  if (const json* w = Member(v, path, "width", "a finite number > 0 (Ws, mesh units)")) {
    ok &= ReadPositive(*w, Key(path, "width"), &out->width);
  } else {
    ok = false;
  }
  const std::string rs_expect = have_len ? "a number in (0, length = " + FormatFloat(out->length) + ")"
                                         : std::string("a number in (0, length)");
  if (const json* rs = Member(v, path, "falloff_start", rs_expect)) {
    float f = 0.f;
    if (ReadFloat(*rs, Key(path, "falloff_start"), rs_expect, &f)) {
      if (!(f > 0.f) || (have_len && !(f < out->length))) {
        Error(Key(path, "falloff_start"), "expected " + rs_expect + ", got " + Describe(*rs));
        ok = false;
      }
      out->falloff_start = f;
    } else {
      ok = false;
    }
  } else {
    ok = false;
  }
  return ok;
}

// ---------------------------------------------------------------------------------------------
// Writing.

// The shortest decimal (as a double) that reads back as `f`: 0.1f is written "0.1", not
// "0.10000000149011612". Falls back to the exact double value of `f`.
double ShortestDecimal(float f) {
  if (!std::isfinite(f)) return static_cast<double>(f);
  char buf[64];
  const auto res = std::to_chars(buf, buf + sizeof buf, f);
  if (res.ec != std::errc()) return static_cast<double>(f);
  double d = 0.0;
  const auto back = std::from_chars(buf, res.ptr, d);
  if (back.ec != std::errc() || static_cast<float>(d) != f) return static_cast<double>(f);
  return d;
}

// Degrees for a zone angle in radians: the shortest decimal `deg` for which the reader's
// conversion, float(deg * pi / 180), gives back exactly `rad` (40 degrees is written "40").
double ShortestDegrees(float rad) {
  const double exact = static_cast<double>(rad) * 180.0 / std::numbers::pi;
  if (!std::isfinite(exact)) return exact;
  for (int precision = 1; precision <= 17; ++precision) {
    char buf[64];
    const auto res =
        std::to_chars(buf, buf + sizeof buf, exact, std::chars_format::general, precision);
    if (res.ec != std::errc()) break;
    double d = 0.0;
    if (std::from_chars(buf, res.ptr, d).ec != std::errc()) break;
    if (static_cast<float>(d * std::numbers::pi / 180.0) == rad) return d;
  }
  return exact;
}

ordered_json Vec3Json(float3 v) {
  return ordered_json::array({ShortestDecimal(v.x), ShortestDecimal(v.y), ShortestDecimal(v.z)});
}

// `target` relative to `dir` when it lies inside `dir` or below it, else absolute.
std::string PathForFile(const std::string& target, const std::string& dir) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::path t = fs::absolute(fs::path(target), ec);
  if (ec) return target;
  t = t.lexically_normal();
  fs::path d = fs::absolute(fs::path(dir.empty() ? "." : dir), ec);
  if (ec) return t.string();
  d = d.lexically_normal();
  if (!d.has_filename() && d.has_relative_path()) d = d.parent_path();  // "/a/b/" -> "/a/b"
  const fs::path rel = t.lexically_relative(d);
  if (!rel.empty() && *rel.begin() != ".." && rel.is_relative()) return rel.generic_string();
  return t.string();
}

ordered_json ToJson(const RigSpec& spec, const std::string& dir) {
  ordered_json root;
  root["format"] = kFormatName;
  root["version"] = kFormatVersion;
  ordered_json mesh;
  mesh["path"] = spec.mesh_path.empty() ? std::string() : PathForFile(spec.mesh_path, dir);
  if (!spec.mesh_name.empty()) mesh["name"] = spec.mesh_name;
  root["mesh"] = std::move(mesh);
  root["units"] = spec.units;

  ordered_json thickness;
  const ThicknessSpec& t = spec.thickness;
  switch (t.kind) {
    case ThicknessSpec::Kind::kConstant:
      thickness["type"] = "constant";
      thickness["value"] = ShortestDecimal(t.value);
      break;
    case ThicknessSpec::Kind::kPerVertex: {
      thickness["type"] = "per_vertex";
      ordered_json values = ordered_json::array();
      for (float h : t.per_vertex) values.push_back(ShortestDecimal(h));
      thickness["values"] = std::move(values);
      break;
    }
    case ThicknessSpec::Kind::kImage:
      thickness["type"] = "image";
      thickness["path"] = t.image_path.empty() ? std::string() : PathForFile(t.image_path, dir);
      thickness["min"] = ShortestDecimal(t.min);
      thickness["max"] = ShortestDecimal(t.max);
      break;
  }
  root["thickness"] = std::move(thickness);

  ordered_json muscles = ordered_json::array();
  for (const MuscleSpec& m : spec.muscles) {
    ordered_json j;
    j["name"] = m.name;
    j["type"] = MuscleTypeName(m.type);
    j["strength"] = ShortestDecimal(m.strength);
    if (m.type == MuscleType::kLinear) {
      j["attachment"] = Vec3Json(m.linear.attachment);
      j["insertion"] = Vec3Json(m.linear.insertion);
      j["zone_angle_deg"] = ShortestDegrees(m.linear.zone_angle);
      j["falloff_start"] = ShortestDecimal(m.linear.falloff_start);
      j["falloff_end"] = ShortestDecimal(m.linear.falloff_end);
    } else {
      j["attachment"] =
          ordered_json::array({Vec3Json(m.sheet.attachment[0]), Vec3Json(m.sheet.attachment[1])});
      j["insertion"] =
          ordered_json::array({Vec3Json(m.sheet.insertion[0]), Vec3Json(m.sheet.insertion[1])});
      j["length"] = ShortestDecimal(m.sheet.length);
      j["width"] = ShortestDecimal(m.sheet.width);
      j["falloff_start"] = ShortestDecimal(m.sheet.falloff_start);
    }
    const size_t i = muscles.size();
    if (i < spec.muscle_wrinkles.size() && spec.muscle_wrinkles[i]) {
      const MuscleWrinkleSpec& w = *spec.muscle_wrinkles[i];
      ordered_json wj;
      wj["lambda_w"] = ShortestDecimal(w.lambda_w);
      wj["count"] = w.count;
      wj["depth"] = ShortestDecimal(w.depth);
      wj["shape"] = ShortestDecimal(w.shape);
      // Only the attenuation parameter of the muscle's type (the other one is unused).
      if (m.type == MuscleType::kLinear)
        wj["phi_c_deg"] = ShortestDegrees(w.phi_c);
      else
        wj["h_c"] = ShortestDecimal(w.h_c);
      j["wrinkles"] = std::move(wj);
    }
    muscles.push_back(std::move(j));
  }
  root["muscles"] = std::move(muscles);

  if (!spec.curve_wrinkles.empty()) {
    ordered_json curves = ordered_json::array();
    for (const NamedCurveWrinkle& c : spec.curve_wrinkles) {
      ordered_json j;
      j["name"] = c.name;
      ordered_json control = ordered_json::array();
      for (const float2& p : c.spec.control)
        control.push_back(ordered_json::array({ShortestDecimal(p.x), ShortestDecimal(p.y)}));
      j["control"] = std::move(control);
      j["depth"] = ShortestDecimal(c.spec.depth);
      j["width"] = ShortestDecimal(c.spec.width);
      j["profile"] = CurveWrinkleProfileName(c.spec.profile);
      j["modulation"] = CurveWrinkleModulationName(c.spec.modulation);
      j["rest_amplitude"] = ShortestDecimal(c.spec.rest_amplitude);
      curves.push_back(std::move(j));
    }
    root["curve_wrinkles"] = std::move(curves);
  }

  const LayerSpec default_layers;
  const LayerSpec& l = spec.layers;
  if (l.thickness != default_layers.thickness ||
      l.muscle_wrinkles != default_layers.muscle_wrinkles ||
      l.curve_wrinkles != default_layers.curve_wrinkles) {
    ordered_json j;
    j["thickness"] = l.thickness;
    j["muscle_wrinkles"] = l.muscle_wrinkles;
    j["curve_wrinkles"] = l.curve_wrinkles;
    root["layers"] = std::move(j);
  }

  const RefinementSpec default_refinement;
  const RefinementSpec& r = spec.refinement;
  // `!(a == b)` so that a NaN edge fraction is written (and then refused by the check).
  if (r.enabled != default_refinement.enabled ||
      !(r.edge_fraction == default_refinement.edge_fraction)) {
    ordered_json j;
    j["enabled"] = r.enabled;
    j["edge_fraction"] = ShortestDecimal(r.edge_fraction);
    root["refinement"] = std::move(j);
  }
  return root;
}

bool ParseRigSpecImpl(std::string_view json_text, const std::string& base_dir, RigSpec* out,
                      Diagnostics* diag) {
  const std::string text = ReplaceOverflowingNumbers(json_text);
  DuplicateKeyTracker tracker;
  json root;
  try {
    json::parser_callback_t callback = [&tracker](int depth, json::parse_event_t event,
                                                  json& parsed) {
      return tracker(depth, event, parsed);
    };
    root = json::parse(text, callback, /*allow_exceptions=*/true, /*ignore_comments=*/false);
  } catch (const json::parse_error& e) {
    size_t line = 0, column = 0;
    LineColumn(text, e.byte, &line, &column);
    diag->Error("", "invalid JSON at line " + std::to_string(line) + ", column " +
                        std::to_string(column) + ": " + ParseErrorDetail(e.what()));
    return false;
  }
  const size_t errors_before = diag->ErrorCount();
  for (const std::string& p : tracker.duplicates)
    diag->Error(p, "duplicate key; expected each key once per object");

  RigSpec spec;
  RigChecker(base_dir, diag).CheckRoot(root, &spec);
  if (diag->ErrorCount() != errors_before) return false;
  *out = std::move(spec);
  return true;
}

}  // namespace

bool ParseRigSpec(std::string_view json_text, const std::string& base_dir, RigSpec* out,
                  Diagnostics* diag) {
  Diagnostics local;
  if (!diag) diag = &local;
  if (!out) {
    diag->Error("", "internal error: ParseRigSpec called without an output");
    return false;
  }
  try {
    return ParseRigSpecImpl(json_text, base_dir, out, diag);
  } catch (const std::exception& e) {
    diag->Error("", std::string("cannot read the rig: ") + e.what());
  } catch (...) {
    diag->Error("", "cannot read the rig: unknown error");
  }
  return false;
}

bool LoadRigSpec(const std::string& path, RigSpec* out, Diagnostics* diag) {
  Diagnostics local_fallback;
  if (!diag) diag = &local_fallback;
  std::string text;
  if (!ReadFile(path, &text, diag)) return false;
  Diagnostics local;
  RigSpec spec;
  const bool ok = ParseRigSpec(text, DirectoryOf(path), &spec, &local);
  diag->Append(local, path);
  if (!ok || !out) return false;
  spec.file = path;
  *out = std::move(spec);
  return true;
}

bool SaveRigSpec(const std::string& path, const RigSpec& spec, Diagnostics* diag) {
  Diagnostics local_fallback;
  if (!diag) diag = &local_fallback;
  try {
    const std::string dir = DirectoryOf(path);
    // `muscle_wrinkles` is parallel to `muscles`; a wrinkle block without its muscle is lost.
    for (size_t i = spec.muscles.size(); i < spec.muscle_wrinkles.size(); ++i) {
      if (!spec.muscle_wrinkles[i]) continue;
      diag->Error(path, "not saved: muscle_wrinkles[" + std::to_string(i) + "] has a wrinkle block "
                        "but the rig has only " + std::to_string(spec.muscles.size()) +
                        " muscles; expected muscle_wrinkles parallel to muscles");
      return false;
    }
    const std::string text =
        ToJson(spec, dir).dump(2, ' ', false, ordered_json::error_handler_t::strict) + "\n";
    // Refuse to write a file that would not load back (NaN, empty names, bad ranges, ...).
    Diagnostics check;
    RigSpec reread;
    if (!ParseRigSpec(text, dir, &reread, &check)) {
      diag->Append(check, path);
      diag->Error(path, "not saved: the rig does not validate (see the errors above)");
      return false;
    }
    return WriteFileAtomic(path, text, diag);
  } catch (const std::exception& e) {
    diag->Error(path, std::string("not saved: ") + e.what());
  } catch (...) {
    diag->Error(path, "not saved: unknown error");
  }
  return false;
}

}  // namespace mimetic

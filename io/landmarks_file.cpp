// io/landmarks_file.cpp: landmark files (docs/landmarks-format.md): the table of the format
// (io/json_reader.h checks it and generates assets/schema/mimetic-landmarks.schema.json from
// it), the scheme's counts, and writing.
#include "io/landmarks_file.h"

#include <cstdio>
#include <string>

#include <nlohmann/json.hpp>

#include "core/file_util.h"
#include "io/formats.h"
#include "io/json_reader.h"

namespace mimetic {
namespace {

using json = nlohmann::json;
using namespace json_reader;

// The points of the scheme: 68 in iBUG order ("ibug68", fitting/landmarks.h), millimetres.
const Object kLandmarkFile = {"a landmark file", {
    Enum("format", {"mimetic-landmarks"}).Required(),
    Integer("version", "the integer 1").Version(1, /*stops=*/false).Required(),
    Enum("scheme", {"ibug68"}, "\"ibug68\" (68 points, Multi-PIE / iBUG order)"),
    Enum("units", {"mm"}),
    Array("points",
          Array("", Number("", "a finite number (float range)").TypeText("a number"),
                "an array of 3 numbers [x, y, z]").Count(3),
          "an array of 68 [x, y, z]").About("68 points [x, y, z], mm"),
    Array("vertices",
          Integer("", "a vertex index >= 0, or -1 = unknown")
              .Min(-1).Below(9223372036854775808.0)
              .TypeText("an integer vertex index (>= 0, or -1 = unknown)"),
          "an array of 68 vertex indices (-1 = unknown)")
        .About("68 vertex indices into the mesh (-1 = unknown)")}};

const Format kLandmarksFormat = {
    .name = "mimetic-landmarks",
    .root = ObjectOf("", kLandmarkFile, "an object with \"format\": \"mimetic-landmarks\""),
    .wording = {.is_first = true, .unknown_key_in_owner = true},
    .title = "mimetic landmark file, version 1"};

// The count of an array of the scheme's points; false (reported) when it is not 68.
bool SchemeCount(Reader& r, const View& top, const std::string& key) {
  const json* v = top.Raw(key);
  if (!v || !v->is_array()) return false;
  if (v->size() == static_cast<size_t>(kIbug68Count)) return true;
  r.Error(key, "has " + std::to_string(v->size()) + " entries; expected 68 (ibug68)");
  return false;
}

}  // namespace

const json_reader::Format& LandmarksFileFormat() { return kLandmarksFormat; }

bool ParseLandmarks(const std::string& text, const std::string& where, Landmarks* out,
                    Diagnostics* diag) {
  Diagnostics local;
  if (!diag) diag = &local;
  return NoThrow(diag, where + ": internal error while reading the landmarks", [&] {
    Reader r(kLandmarksFormat, diag, where);
    if (!r.Parse(text)) return false;
    const View top = r.Check();
    if (!top.present() || !top.value()->is_object()) return false;
    Landmarks result;
    const bool has_points = top.Has("points"), has_vertices = top.Has("vertices");
    if (!has_points && !has_vertices)
      r.Error("", "neither \"points\" nor \"vertices\" given; expected at least one");
    if (SchemeCount(r, top, "points")) top.Read("points", &result.points);
    if (SchemeCount(r, top, "vertices") && top.Get("vertices")) {
      const json& vs = *top.Get("vertices");
      for (size_t i = 0; i < vs.size(); ++i) {
        const json& v = vs[i];
        result.vertex_indices.push_back(v.is_number_float() ? static_cast<int64_t>(v.get<double>())
                                                            : v.get<int64_t>());
        if (!has_points && result.vertex_indices.back() < 0)
          r.Error(Index("vertices", i), "is -1 (unknown) but no \"points\" are given; expected a "
                                        "vertex index or a points array");
      }
    }
    if (r.failed()) return false;
    if (out) *out = std::move(result);
    return true;
  });
}

bool LoadLandmarks(const std::string& path, Landmarks* out, Diagnostics* diag) {
  Diagnostics local;
  Diagnostics& d = diag ? *diag : local;
  std::string text;
  if (!ReadFile(path, &text, &d)) return false;
  return ParseLandmarks(text, path, out, &d);
}

std::string LandmarksToJson(const Landmarks& lm) {
  // Written by hand (not json::dump) to keep one point per line and short decimals.
  std::string s = "{\n  \"format\": \"mimetic-landmarks\",\n  \"version\": 1,\n";
  s += "  \"scheme\": \"" + (lm.scheme.empty() ? std::string("ibug68") : lm.scheme) + "\",\n";
  s += "  \"units\": \"mm\"";
  if (!lm.points.empty()) {
    s += ",\n  \"points\": [\n";
    for (size_t i = 0; i < lm.points.size(); ++i) {
      char buf[128];
      std::snprintf(buf, sizeof buf, "    [%.9g, %.9g, %.9g]%s\n", lm.points[i].x,
                    lm.points[i].y, lm.points[i].z, i + 1 < lm.points.size() ? "," : "");
      s += buf;
    }
    s += "  ]";
  }
  if (!lm.vertex_indices.empty()) {
    s += ",\n  \"vertices\": [";
    for (size_t i = 0; i < lm.vertex_indices.size(); ++i)
      s += (i ? ", " : "") + std::to_string(lm.vertex_indices[i]);
    s += "]";
  }
  s += "\n}\n";
  return s;
}

bool SaveLandmarks(const std::string& path, const Landmarks& lm, Diagnostics* diag) {
  Diagnostics local;
  Diagnostics& d = diag ? *diag : local;
  const size_t before = d.ErrorCount();
  if (lm.scheme != "ibug68")
    d.Error(path, "scheme \"" + lm.scheme + "\"; expected \"ibug68\"");
  if (lm.points.empty() && lm.vertex_indices.empty())
    d.Error(path, "no points and no vertex indices; expected 68 of either");
  if (!lm.points.empty() && lm.points.size() != static_cast<size_t>(kIbug68Count))
    d.Error(path, std::to_string(lm.points.size()) + " points; expected 68");
  if (!lm.vertex_indices.empty() && lm.vertex_indices.size() != static_cast<size_t>(kIbug68Count))
    d.Error(path, std::to_string(lm.vertex_indices.size()) + " vertex indices; expected 68");
  for (size_t i = 0; i < lm.points.size(); ++i)
    if (!IsFinite(lm.points[i]))
      d.Error(path + ": points[" + std::to_string(i) + "]", "not finite; expected numbers");
  for (size_t i = 0; i < lm.vertex_indices.size(); ++i)
    if (lm.vertex_indices[i] < -1 || (lm.points.empty() && lm.vertex_indices[i] < 0))
      d.Error(path + ": vertices[" + std::to_string(i) + "]",
              "is " + std::to_string(lm.vertex_indices[i]) +
                  "; expected a vertex index (-1 only together with points)");
  if (d.ErrorCount() != before) return false;
  return WriteFileAtomic(path, LandmarksToJson(lm), &d);
}

}  // namespace mimetic

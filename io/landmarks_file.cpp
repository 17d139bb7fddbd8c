// io/landmarks_file.cpp: landmark files (docs/landmarks-format.md).
#include "io/landmarks_file.h"

#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>

#include "core/file_util.h"

namespace mimetic {
namespace {

using json = nlohmann::json;



std::string TypeName(const json& j) {
  if (j.is_number_integer() || j.is_number_unsigned()) return "integer";
  if (j.is_number_float()) return "number";
  return j.type_name();
}

std::string Short(const json& j) {
  std::string s = j.dump();
  if (s.size() > 40) s = s.substr(0, 37) + "...";
  return s;
}

}  // namespace

bool ParseLandmarks(const std::string& text, const std::string& where, Landmarks* out,
                    Diagnostics* diag) {
  Diagnostics local;
  Diagnostics& d = diag ? *diag : local;
  const size_t errors_before = d.ErrorCount();
  const std::string pre = where.empty() ? "" : where + ": ";
  Landmarks result;
  result.scheme.clear();

  json root;
  try {
    root = json::parse(text);
  } catch (const json::parse_error& e) {
    d.Error(where, std::string("not valid JSON: ") + e.what() +
                       "; expected a landmark file (docs/landmarks-format.md)");
    return false;
  }
  if (!root.is_object()) {
    d.Error(where, "top level is " + TypeName(root) + "; expected an object with \"format\": "
                   "\"mimetic-landmarks\"");
    return false;
  }

  static const char* const kKeys[] = {"format", "version", "scheme", "units", "points",
                                      "vertices"};
  for (auto it = root.begin(); it != root.end(); ++it) {
    bool known = false;
    for (const char* k : kKeys) known = known || it.key() == k;
    if (!known)
      d.Error(pre + it.key(), "unknown key; expected one of format, version, scheme, units, "
                              "points, vertices");
  }

  // format
  if (!root.contains("format")) {
    d.Error(pre + "format", "missing; expected \"mimetic-landmarks\"");
  } else if (!root["format"].is_string() || root["format"].get<std::string>() != "mimetic-landmarks") {
    d.Error(pre + "format", "is " + Short(root["format"]) + "; expected \"mimetic-landmarks\"");
  }
  // version
  if (!root.contains("version")) {
    d.Error(pre + "version", "missing; expected 1");
  } else if (!root["version"].is_number_integer() && !root["version"].is_number_unsigned()) {
    d.Error(pre + "version", "is " + TypeName(root["version"]) + " " + Short(root["version"]) +
                                 "; expected the integer 1");
  } else if (root["version"].get<int64_t>() != 1) {
    d.Error(pre + "version", "is " + Short(root["version"]) +
                                 "; this reader supports version 1 only");
  }
  // scheme
  result.scheme = "ibug68";
  if (root.contains("scheme")) {
    const json& s = root["scheme"];
    if (!s.is_string()) {
      d.Error(pre + "scheme", "is " + TypeName(s) + "; expected the string \"ibug68\"");
    } else if (s.get<std::string>() != "ibug68") {
      d.Error(pre + "scheme", "is \"" + s.get<std::string>() +
                                  "\"; expected \"ibug68\" (68 points, Multi-PIE / iBUG order)");
    }
  }
  // units
  if (root.contains("units")) {
    const json& u = root["units"];
    if (!u.is_string() || u.get<std::string>() != "mm")
      d.Error(pre + "units", "is " + Short(u) + "; expected \"mm\"");
  }
  // points
  const bool has_points = root.contains("points");
  const bool has_vertices = root.contains("vertices");
  if (!has_points && !has_vertices)
    d.Error(where, "neither \"points\" nor \"vertices\" given; expected at least one");
  if (has_points) {
    const json& pts = root["points"];
    if (!pts.is_array()) {
      d.Error(pre + "points", "is " + TypeName(pts) + "; expected an array of 68 [x, y, z]");
    } else {
      if (pts.size() != static_cast<size_t>(kIbug68Count))
        d.Error(pre + "points", "has " + std::to_string(pts.size()) +
                                    " entries; expected 68 (ibug68)");
      for (size_t i = 0; i < pts.size(); ++i) {
        const std::string path = pre + "points[" + std::to_string(i) + "]";
        const json& p = pts[i];
        if (!p.is_array() || p.size() != 3) {
          d.Error(path, "is " + Short(p) + "; expected an array of 3 numbers [x, y, z]");
          continue;
        }
        float v[3] = {0, 0, 0};
        bool ok = true;
        for (int k = 0; k < 3; ++k) {
          const std::string cpath = path + "[" + std::to_string(k) + "]";
          if (!p[k].is_number()) {
            d.Error(cpath, "is " + TypeName(p[k]) + " " + Short(p[k]) + "; expected a number");
            ok = false;
            continue;
          }
          const double x = p[k].get<double>();
          v[k] = static_cast<float>(x);
          if (!std::isfinite(x) || !std::isfinite(v[k])) {
            d.Error(cpath, "is " + Short(p[k]) + "; expected a finite number (float range)");
            ok = false;
          }
        }
        if (ok) result.points.push_back({v[0], v[1], v[2]});
      }
      if (result.points.size() != static_cast<size_t>(kIbug68Count)) result.points.clear();
    }
  }
  // vertices
  if (has_vertices) {
    const json& vs = root["vertices"];
    if (!vs.is_array()) {
      d.Error(pre + "vertices", "is " + TypeName(vs) +
                                    "; expected an array of 68 vertex indices (-1 = unknown)");
    } else {
      if (vs.size() != static_cast<size_t>(kIbug68Count))
        d.Error(pre + "vertices", "has " + std::to_string(vs.size()) +
                                      " entries; expected 68 (ibug68)");
      for (size_t i = 0; i < vs.size(); ++i) {
        const std::string path = pre + "vertices[" + std::to_string(i) + "]";
        const json& v = vs[i];
        if (!v.is_number_integer() && !v.is_number_unsigned()) {
          d.Error(path, "is " + TypeName(v) + " " + Short(v) +
                            "; expected an integer vertex index (>= 0, or -1 = unknown)");
          continue;
        }
        if (v.is_number_unsigned() && v.get<uint64_t>() > static_cast<uint64_t>(INT64_MAX)) {
          d.Error(path, "is " + Short(v) + "; expected a vertex index below 2^63");
          continue;
        }
        const int64_t idx = v.get<int64_t>();
        if (idx < -1) {
          d.Error(path, "is " + std::to_string(idx) +
                            "; expected a vertex index >= 0, or -1 = unknown");
          continue;
        }
        result.vertex_indices.push_back(idx);
      }
      if (result.vertex_indices.size() != static_cast<size_t>(kIbug68Count))
        result.vertex_indices.clear();
      if (!has_points && !result.vertex_indices.empty()) {
        for (size_t i = 0; i < result.vertex_indices.size(); ++i)
          if (result.vertex_indices[i] < 0)
            d.Error(pre + "vertices[" + std::to_string(i) + "]",
                    "is -1 (unknown) but no \"points\" are given; expected a vertex index "
                    "or a points array");
      }
    }
  }

  if (d.ErrorCount() != errors_before) return false;
  if (out) *out = std::move(result);
  return true;
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

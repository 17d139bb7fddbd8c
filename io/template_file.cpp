// io/template_file.cpp: the muscle template file (docs/template-format.md): parse
// and validate. Every problem is recorded with its JSON path and what was expected; nothing
// throws out of this file (nlohmann::json exceptions are caught at the boundary).
#include "io/template_file.h"

#include "fitting/landmarks.h"

#include <cmath>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/file_util.h"

namespace mimetic {
namespace {

using json = nlohmann::json;

constexpr const char* kFormatName = "mimetic-muscle-template";
constexpr int kFormatVersion = 1;

// iBUG 68 mirror pairs (subject's right index, left index).
std::string Key(const std::string& path, const std::string& key) {
  return path.empty() ? key : path + "." + key;
}
std::string Index(const std::string& path, size_t i) {
  return path + "[" + std::to_string(i) + "]";
}

std::string Describe(const json& v) {
  switch (v.type()) {
    case json::value_t::null: return "null";
    case json::value_t::boolean: return "boolean";
    case json::value_t::number_integer:
    case json::value_t::number_unsigned:
    case json::value_t::number_float: return v.dump();
    case json::value_t::string: {
      std::string s = v.get<std::string>();
      if (s.size() > 40) s = s.substr(0, 40) + "...";
      return json(s).dump(-1, ' ', false, json::error_handler_t::replace);
    }
    case json::value_t::array: return "array of " + std::to_string(v.size()) + " elements";
    case json::value_t::object: return "object";
    default: return "unknown";
  }
}

std::string Num(float f) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", double(f));
  return buf;
}

bool EndsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

class Parser {
 public:
  explicit Parser(Diagnostics* diag) : diag_(diag) {}

  void Error(const std::string& where, const std::string& what) {
    diag_->Error(where, what);
    ++errors_;
  }
  size_t errors() const { return errors_; }

  void CheckKeys(const json& obj, const std::string& path, const std::vector<std::string>& allowed,
                 const std::string& what) {
    for (auto it = obj.begin(); it != obj.end(); ++it) {
      bool ok = false;
      for (const std::string& a : allowed) ok = ok || a == it.key();
      if (!ok) {
        std::string list;
        for (const std::string& a : allowed) list += (list.empty() ? "" : ", ") + a;
        Error(Key(path, it.key()), "unknown key in " + what + "; expected one of: " + list);
      }
    }
  }

  // A finite number that fits a float; `min_exclusive` / `min_inclusive` bounds.
  bool ReadFloat(const json& v, const std::string& path, const std::string& expect, float* out) {
    if (!v.is_number()) {
      Error(path, "expected " + expect + ", got " + Describe(v));
      return false;
    }
    const double d = v.get<double>();
    if (!std::isfinite(d) || std::fabs(d) > double(std::numeric_limits<float>::max())) {
      Error(path, "expected " + expect + ", got a number too large for a float");
      return false;
    }
    *out = float(d);
    return true;
  }
  bool ReadAtLeast(const json& v, const std::string& path, float lo, bool inclusive,
                   const std::string& expect, float* out) {
    float f = 0.f;
    if (!ReadFloat(v, path, expect, &f)) return false;
    if (inclusive ? !(f >= lo) : !(f > lo)) {
      Error(path, "expected " + expect + ", got " + Describe(v));
      return false;
    }
    *out = f;
    return true;
  }
  bool ReadFloat2(const json& v, const std::string& path, const std::string& expect, float2* out) {
    if (!v.is_array() || v.size() != 2) {
      Error(path, "expected " + expect + ", got " + Describe(v));
      return false;
    }
    float a = 0.f, b = 0.f;
    const bool ok = ReadFloat(v[0], Index(path, 0), "a finite number", &a) &
                    ReadFloat(v[1], Index(path, 1), "a finite number", &b);
    if (ok) *out = {a, b};
    return ok;
  }

  const json* Member(const json& obj, const std::string& path, const std::string& key,
                     const std::string& expect_if_missing) {
    const auto it = obj.find(key);
    if (it == obj.end()) {
      if (!expect_if_missing.empty())
        Error(Key(path, key), "missing; expected " + expect_if_missing);
      return nullptr;
    }
    return &*it;
  }

  // The required "name" of an object: a non-empty string (`example` shows one).
  void ReadName(const json& v, const std::string& path, const std::string& example,
                std::string* out) {
    const std::string expect = "a non-empty string such as \"" + example + "\"";
    if (const json* n = Member(v, path, "name", expect)) {
      if (!n->is_string() || n->get<std::string>().empty())
        Error(Key(path, "name"), "expected a non-empty string, got " + Describe(*n));
      else
        *out = n->get<std::string>();
    }
  }

  // `on_surface`: a curve wrinkle's control point, which lies in the skin: `depth` is optional
  // and must be 0 when given.
  bool ParsePoint(const json& v, const std::string& path, TemplatePoint* out,
                  bool on_surface = false) {
    const size_t before = errors_;
    if (!v.is_object()) {
      Error(path, std::string("expected a point object {\"landmarks\": [...], \"weights\": [...], "
                              "\"offset\": [dx, dy]") +
                      (on_surface ? "}" : ", \"depth\": d}") + ", got " + Describe(v));
      return false;
    }
    CheckKeys(v, path, {"landmarks", "weights", "offset", "depth"}, "a template point");
    out->landmarks.clear();
    out->weights.clear();
    if (const json* lm = Member(v, path, "landmarks",
                                "array of landmark indices (iBUG 68: integers 0..67)")) {
      const std::string lp = Key(path, "landmarks");
      if (!lm->is_array() || lm->empty()) {
        Error(lp, "expected a non-empty array of landmark indices (integers 0..67), got " +
                      Describe(*lm));
      } else {
        std::set<int> seen;
        for (size_t i = 0; i < lm->size(); ++i) {
          const json& e = (*lm)[i];
          const bool integral = e.is_number_integer() || e.is_number_unsigned();
          const long long k = integral ? e.get<long long>() : -1;
          if (!integral || k < 0 || k >= kTemplateLandmarkCount) {
            Error(Index(lp, i), "expected a landmark index, an integer in 0..67 (iBUG 68 order), got " +
                                    Describe(e));
            continue;
          }
          if (!seen.insert(int(k)).second) {
            Error(Index(lp, i), "landmark " + std::to_string(k) +
                                    " appears twice; expected each landmark once (use weights)");
            continue;
          }
          out->landmarks.push_back(int(k));
        }
      }
    }
    if (const json* w = Member(v, path, "weights", "")) {
      const std::string wp = Key(path, "weights");
      const size_t n = v.contains("landmarks") && v["landmarks"].is_array() ? v["landmarks"].size() : 0;
      if (!w->is_array() || w->size() != n) {
        Error(wp, "expected an array of " + std::to_string(n) +
                      " numbers >= 0 (one per landmark), got " + Describe(*w));
      } else {
        double sum = 0.0;
        bool all = true;
        for (size_t i = 0; i < w->size(); ++i) {
          float f = 0.f;
          if (ReadAtLeast((*w)[i], Index(wp, i), 0.f, true, "a number >= 0", &f)) {
            out->weights.push_back(f);
            sum += f;
          } else {
            all = false;
          }
        }
        if (all && !(sum > 0.0)) Error(wp, "weights sum to 0; expected at least one weight > 0");
      }
    }
    out->offset = {0.f, 0.f};
    if (const json* o = Member(v, path, "offset", ""))
      ReadFloat2(*o, Key(path, "offset"), "[dx, dy], two finite numbers (units of s)", &out->offset);
    out->depth = 0.f;
    if (on_surface) {
      if (const json* d = Member(v, path, "depth", "")) {
        float f = 0.f;
        if (ReadFloat(*d, Key(path, "depth"), "0 or no depth (a curve wrinkle lies in the skin)",
                      &f) && f != 0.f)
          Error(Key(path, "depth"), "a curve wrinkle's control point lies in the skin; expected "
                                    "0 or no depth, got " + Describe(*d));
      }
    } else if (const json* d = Member(v, path, "depth",
                                      "a number >= 0 (units of s under the surface)")) {
      ReadAtLeast(*d, Key(path, "depth"), 0.f, true,
                  "a number >= 0 (units of s under the surface)", &out->depth);
    }
    if (errors_ != before) return false;
    // Normalise the weights (default: equal).
    if (out->weights.empty()) out->weights.assign(out->landmarks.size(), 1.f);
    double sum = 0.0;
    for (float w : out->weights) sum += w;
    for (float& w : out->weights) w = float(w / sum);
    return true;
  }

  void ParseThickness(const json& v, TemplateThickness* out) {
    const std::string path = "thickness";
    if (!v.is_object()) {
      Error(path, "expected object {\"base\": ..., \"front\": [...], \"regions\": [...]}, got " +
                      Describe(v));
      return;
    }
    CheckKeys(v, path, {"base", "front", "regions"}, "thickness");
    if (const json* b = Member(v, path, "base", "a number >= 0 (units of s)"))
      ReadAtLeast(*b, Key(path, "base"), 0.f, true, "a number >= 0 (units of s)", &out->base);
    if (const json* f = Member(v, path, "front", "")) {
      float2 fr{out->front[0], out->front[1]};
      if (ReadFloat2(*f, Key(path, "front"), "[z0, z1], two numbers with z0 < z1 (units of s)",
                     &fr)) {
        if (!(fr.x < fr.y))
          Error(Key(path, "front"), "expected z0 < z1, got [" + Num(fr.x) + ", " + Num(fr.y) + "]");
        out->front[0] = fr.x;
        out->front[1] = fr.y;
      }
    }
    out->regions.clear();
    if (const json* r = Member(v, path, "regions", "")) {
      const std::string rp = Key(path, "regions");
      if (!r->is_array()) {
        Error(rp, "expected an array of regions, got " + Describe(*r));
        return;
      }
      for (size_t i = 0; i < r->size(); ++i) {
        const json& e = (*r)[i];
        const std::string ep = Index(rp, i);
        if (!e.is_object()) {
          Error(ep, "expected a region object {\"name\", \"center\", \"radius\", \"value\"}, got " +
                        Describe(e));
          continue;
        }
        CheckKeys(e, ep, {"name", "center", "radius", "value", "mirror"}, "a thickness region");
        const size_t before = errors_;
        ThicknessRegion region;
        if (const json* n = Member(e, ep, "name", "")) {
          if (!n->is_string()) Error(Key(ep, "name"), "expected a string, got " + Describe(*n));
          else region.name = n->get<std::string>();
        }
        if (const json* c = Member(e, ep, "center", "[x, y] (face frame, units of s)"))
          ReadFloat2(*c, Key(ep, "center"), "[x, y], two finite numbers (units of s)", &region.center);
        if (const json* c = Member(e, ep, "radius", "[sx, sy], two numbers > 0 (units of s)")) {
          if (ReadFloat2(*c, Key(ep, "radius"), "[sx, sy], two numbers > 0 (units of s)",
                         &region.radius) &&
              !(region.radius.x > 0.f && region.radius.y > 0.f))
            Error(Key(ep, "radius"), "expected two numbers > 0 (units of s), got " + Describe(*c));
        }
        if (const json* c = Member(e, ep, "value", "a number >= 0 (units of s)"))
          ReadAtLeast(*c, Key(ep, "value"), 0.f, true, "a number >= 0 (units of s)", &region.value);
        bool mirror = false;
        if (const json* m = Member(e, ep, "mirror", "")) {
          if (!m->is_boolean()) Error(Key(ep, "mirror"), "expected true or false, got " + Describe(*m));
          else mirror = m->get<bool>();
        }
        if (errors_ != before) continue;
        out->regions.push_back(region);
        if (mirror && region.center.x != 0.f) {
          region.center.x = -region.center.x;
          out->regions.push_back(region);
        }
      }
    }
  }

  void ParseMuscle(const json& v, const std::string& path, std::vector<TemplateMuscle>* out,
                   std::vector<std::string>* origin_paths) {
    if (!v.is_object()) {
      Error(path, "expected a muscle object, got " + Describe(v));
      return;
    }
    const size_t before = errors_;
    TemplateMuscle m;
    ReadName(v, path, "zygomaticus_major_L", &m.name);
    bool typed = false;
    if (const json* t = Member(v, path, "type", "\"linear\" or \"sheet\"")) {
      if (t->is_string() && t->get<std::string>() == "linear") {
        m.type = MuscleType::kLinear;
        typed = true;
      } else if (t->is_string() && t->get<std::string>() == "sheet") {
        m.type = MuscleType::kSheet;
        typed = true;
      } else {
        Error(Key(path, "type"), "expected \"linear\" or \"sheet\", got " + Describe(*t));
      }
    }
    const bool linear = m.type == MuscleType::kLinear;
    if (typed) {
      if (linear)
        CheckKeys(v, path, {"name", "type", "mirror", "strength", "attachment", "insertion",
                            "zone_angle_deg", "falloff_start", "falloff_end", "wrinkles"},
                  "a linear muscle");
      else
        CheckKeys(v, path, {"name", "type", "mirror", "strength", "attachment", "insertion",
                            "length", "width", "falloff_start", "wrinkles"},
                  "a sheet muscle");
    }
    bool mirror = false;
    if (const json* mm = Member(v, path, "mirror", "")) {
      if (!mm->is_boolean()) {
        Error(Key(path, "mirror"), "expected true or false, got " + Describe(*mm));
      } else {
        mirror = mm->get<bool>();
        if (mirror && !m.name.empty() && !EndsWith(m.name, "_L") && !EndsWith(m.name, "_R"))
          Error(Key(path, "mirror"), "a mirrored muscle's name must end in _L or _R (the copy "
                                     "gets the other suffix); got name \"" + m.name + "\"");
      }
    }
    if (const json* s = Member(v, path, "strength", "a number >= 0 (units of s)"))
      ReadAtLeast(*s, Key(path, "strength"), 0.f, true, "a number >= 0 (units of s)", &m.strength);
    if (typed) {
      for (int which = 0; which < 2; ++which) {
        const char* key = which == 0 ? "attachment" : "insertion";
        TemplatePoint* pts = which == 0 ? m.attachment : m.insertion;
        const std::string kp = Key(path, key);
        const json* p = Member(v, path, key, linear ? "a point object" : "an array of 2 point objects");
        if (!p) continue;
        if (linear) {
          ParsePoint(*p, kp, &pts[0]);
        } else if (!p->is_array() || p->size() != 2) {
          Error(kp, "expected an array of 2 point objects (the ends of the line), got " + Describe(*p));
        } else {
          ParsePoint((*p)[0], Index(kp, 0), &pts[0]);
          ParsePoint((*p)[1], Index(kp, 1), &pts[1]);
        }
      }
      if (linear) {
        if (const json* a = Member(v, path, "zone_angle_deg", "a number in (0, 180) (degrees)")) {
          if (ReadFloat(*a, Key(path, "zone_angle_deg"), "a number in (0, 180) (degrees)",
                        &m.zone_angle_deg) &&
              !(m.zone_angle_deg > 0.f && m.zone_angle_deg < 180.f))
            Error(Key(path, "zone_angle_deg"), "expected a number in (0, 180) (degrees), got " +
                                                   Describe(*a));
        }
        const json* rs = Member(v, path, "falloff_start", "a number > 0 (units of s)");
        const json* rf = Member(v, path, "falloff_end", "a number > falloff_start (units of s)");
        const bool have_rs = rs && ReadAtLeast(*rs, Key(path, "falloff_start"), 0.f, false,
                                               "a number > 0 (units of s)", &m.falloff_start);
        const bool have_rf = rf && ReadAtLeast(*rf, Key(path, "falloff_end"), 0.f, false,
                                               "a number > 0 (units of s)", &m.falloff_end);
        if (have_rs && have_rf && !(m.falloff_end > m.falloff_start))
          Error(Key(path, "falloff_end"), "expected a number > falloff_start (" +
                                              Num(m.falloff_start) + "), got " + Num(m.falloff_end));
      } else {
        const json* ls = Member(v, path, "length", "a number > 0 (units of s)");
        const json* ws = Member(v, path, "width", "a number > 0 (units of s)");
        const json* rs = Member(v, path, "falloff_start", "a number in (0, length) (units of s)");
        const bool have_ls = ls && ReadAtLeast(*ls, Key(path, "length"), 0.f, false,
                                               "a number > 0 (units of s)", &m.length);
        if (ws) ReadAtLeast(*ws, Key(path, "width"), 0.f, false, "a number > 0 (units of s)", &m.width);
        const bool have_rs = rs && ReadAtLeast(*rs, Key(path, "falloff_start"), 0.f, false,
                                               "a number in (0, length) (units of s)", &m.falloff_start);
        if (have_ls && have_rs && !(m.falloff_start < m.length))
          Error(Key(path, "falloff_start"), "expected a number in (0, length = " + Num(m.length) +
                                                "), got " + Num(m.falloff_start));
      }
      if (const json* w = Member(v, path, "wrinkles", "")) {
        MuscleWrinkleSpec spec;
        if (ParseWrinkles(*w, Key(path, "wrinkles"), v, m, &spec)) m.wrinkles = spec;
      }
    }
    if (errors_ != before) return;
    out->push_back(m);
    origin_paths->push_back(path);
    if (mirror) {
      TemplateMuscle c = m;
      c.name = m.name.substr(0, m.name.size() - 1) + (EndsWith(m.name, "_L") ? "R" : "L");
      for (TemplatePoint* p : {&c.attachment[0], &c.attachment[1], &c.insertion[0], &c.insertion[1]}) {
        for (int& l : p->landmarks) l = IbugMirrorLandmark(l);
        p->offset.x = -p->offset.x;
      }
      // Mirroring reverses the sheet lines' end order; keep each line's ends as given.
      out->push_back(c);
      origin_paths->push_back(path + " (mirrored as " + c.name + ")");
    }
  }

  // A muscle's wrinkle block (MODEL.md §6): the rig file's keys (docs/rig-format.md), lengths
  // in units of s. `m` holds what was read of the muscle; its zone angle / width bound the
  // attenuation key when they were read.
  bool ParseWrinkles(const json& v, const std::string& path, const json& muscle_json,
                     const TemplateMuscle& m, MuscleWrinkleSpec* out) {
    const bool linear = m.type == MuscleType::kLinear;
    const char* att = linear ? "\"phi_c_deg\"" : "\"h_c\"";
    if (!v.is_object()) {
      Error(path, std::string("expected a wrinkle object {\"lambda_w\": ..., \"count\": ..., "
                              "\"depth\": ..., \"shape\": ..., ") + att + ": ...}, got " +
                      Describe(v));
      return false;
    }
    const size_t before = errors_;
    const std::string wrong_key = linear ? "h_c" : "phi_c_deg";
    if (v.contains(wrong_key))
      Error(Key(path, wrong_key),
            linear ? std::string("\"h_c\" is for the wrinkles of a sheet muscle, and this is a "
                                 "linear muscle; expected \"phi_c_deg\" (degrees)")
                   : std::string("\"phi_c_deg\" is for the wrinkles of a linear muscle, and this "
                                 "is a sheet muscle; expected \"h_c\" (units of s)"));
    std::vector<std::string> allowed = {"lambda_w", "count", "depth", "shape"};
    allowed.push_back(linear ? "phi_c_deg" : "h_c");
    for (auto it = v.begin(); it != v.end(); ++it) {
      bool ok = it.key() == wrong_key;
      for (const std::string& a : allowed) ok = ok || a == it.key();
      if (ok) continue;
      std::string list;
      for (const std::string& a : allowed) list += (list.empty() ? "" : ", ") + a;
      Error(Key(path, it.key()), std::string("unknown key in the wrinkles of a ") +
                                     (linear ? "linear" : "sheet") + " muscle; expected one of: " + list);
    }
    MuscleWrinkleSpec spec;  // defaults for absent optional keys
    if (const json* lw = Member(v, path, "lambda_w", "")) {
      const std::string expect = std::string("a number in [0, 1) (start of the wrinkling region, "
                                             "fraction of ") + (linear ? "falloff_end" : "length") + ")";
      float f = 0.f;
      if (ReadFloat(*lw, Key(path, "lambda_w"), expect, &f)) {
        if (f >= 0.f && f < 1.f) spec.lambda_w = f;
        else Error(Key(path, "lambda_w"), "expected " + expect + ", got " + Describe(*lw));
      }
    }
    if (const json* n = Member(v, path, "count", "")) {
      const bool integral = n->is_number_integer() || n->is_number_unsigned();
      const long long k = integral ? n->get<long long>() : 0;
      if (!integral || k < 1 || k > 1000000)
        Error(Key(path, "count"), "expected an integer >= 1 (the number of wrinkles), got " +
                                      Describe(*n));
      else
        spec.count = int(k);
    }
    if (const json* d = Member(v, path, "depth", "a number >= 0 (k0, units of s)"))
      ReadAtLeast(*d, Key(path, "depth"), 0.f, true, "a number >= 0 (k0, units of s)", &spec.depth);
    if (const json* a = Member(v, path, "shape", ""))
      ReadFloat(*a, Key(path, "shape"), "a finite number (alpha)", &spec.shape);
    if (linear) {
      const bool have_zone = m.zone_angle_deg > 0.f && m.zone_angle_deg < 180.f &&
                             muscle_json.contains("zone_angle_deg");
      const std::string expect = have_zone ? "a number in [0, zone_angle_deg = " +
                                                 Num(m.zone_angle_deg) + ") (degrees)"
                                           : std::string("a number in [0, zone_angle_deg) (degrees)");
      if (const json* pc = Member(v, path, "phi_c_deg", "")) {
        float deg = 0.f;
        if (ReadFloat(*pc, Key(path, "phi_c_deg"), expect, &deg)) {
          if (deg >= 0.f && deg < 180.f && (!have_zone || deg < m.zone_angle_deg))
            spec.phi_c = deg * kPi / 180.f;
          else
            Error(Key(path, "phi_c_deg"), "expected " + expect + ", got " + Describe(*pc));
        }
      }
    } else {
      const bool have_width = m.width > 0.f;
      const std::string expect = have_width ? "a number in [0, width/2 = " + Num(0.5f * m.width) +
                                                  ") (units of s)"
                                            : std::string("a number in [0, width/2) (units of s)");
      if (const json* hc = Member(v, path, "h_c", "")) {
        float f = 0.f;
        if (ReadFloat(*hc, Key(path, "h_c"), expect, &f)) {
          if (f >= 0.f && (!have_width || f < 0.5f * m.width)) spec.h_c = f;
          else Error(Key(path, "h_c"), "expected " + expect + ", got " + Describe(*hc));
        }
      }
    }
    if (errors_ != before) return false;
    *out = spec;
    return true;
  }

  bool ReadChoice(const json& v, const std::string& path, const std::vector<std::string>& names,
                  size_t* out) {
    std::string list;
    for (const std::string& n : names) list += (list.empty() ? "\"" : ", \"") + n + "\"";
    if (v.is_string()) {
      for (size_t i = 0; i < names.size(); ++i)
        if (v.get<std::string>() == names[i]) return *out = i, true;
    }
    Error(path, "expected one of " + list + ", got " + Describe(v));
    return false;
  }

  // A curve wrinkle (MODEL.md §7-8) whose control points are template points on the skin.
  void ParseCurveWrinkle(const json& v, const std::string& path,
                         std::vector<TemplateCurveWrinkle>* out,
                         std::vector<std::string>* origin_paths) {
    if (!v.is_object()) {
      Error(path, "expected a curve wrinkle object {\"name\", \"control\", \"depth\", \"width\", "
                  "...}, got " + Describe(v));
      return;
    }
    const size_t before = errors_;
    CheckKeys(v, path, {"name", "mirror", "control", "depth", "width", "profile", "modulation",
                        "rest_amplitude"},
              "a curve wrinkle");
    TemplateCurveWrinkle c;
    ReadName(v, path, "nasolabial_L", &c.name);
    bool mirror = false;
    if (const json* mm = Member(v, path, "mirror", "")) {
      if (!mm->is_boolean()) {
        Error(Key(path, "mirror"), "expected true or false, got " + Describe(*mm));
      } else {
        mirror = mm->get<bool>();
        if (mirror && !c.name.empty() && !EndsWith(c.name, "_L") && !EndsWith(c.name, "_R"))
          Error(Key(path, "mirror"), "a mirrored curve wrinkle's name must end in _L or _R (the "
                                     "copy gets the other suffix); got name \"" + c.name + "\"");
      }
    }
    const std::string control_expect =
        "an array of 4 point objects (the cubic Bezier control points, on the skin)";
    if (const json* ctl = Member(v, path, "control", control_expect)) {
      const std::string cp = Key(path, "control");
      if (!ctl->is_array() || ctl->size() != 4) {
        Error(cp, "expected " + control_expect + ", got " + Describe(*ctl));
      } else {
        for (size_t k = 0; k < 4; ++k) ParsePoint((*ctl)[k], Index(cp, k), &c.control[k], true);
      }
    }
    if (const json* d = Member(v, path, "depth", "a number > 0 (units of s)"))
      ReadAtLeast(*d, Key(path, "depth"), 0.f, false, "a number > 0 (units of s)", &c.depth);
    if (const json* w = Member(v, path, "width", "a number > 0 (units of s)"))
      ReadAtLeast(*w, Key(path, "width"), 0.f, false, "a number > 0 (units of s)", &c.width);
    size_t choice = 0;
    if (const json* p = Member(v, path, "profile", ""))
      if (ReadChoice(*p, Key(path, "profile"), {"bando", "yang_zhang", "yang_zhang_exact"}, &choice))
        c.profile = choice == 0   ? CurveWrinkleProfile::kBando
                    : choice == 1 ? CurveWrinkleProfile::kYangZhang
                                  : CurveWrinkleProfile::kYangZhangExact;
    if (const json* m = Member(v, path, "modulation", ""))
      if (ReadChoice(*m, Key(path, "modulation"), {"directional", "area"}, &choice))
        c.modulation = choice == 0 ? CurveWrinkleModulation::kDirectional
                                   : CurveWrinkleModulation::kArea;
    if (const json* r = Member(v, path, "rest_amplitude", "")) {
      float f = 0.f;
      if (ReadFloat(*r, Key(path, "rest_amplitude"), "a number in [0, 1]", &f)) {
        if (f >= 0.f && f <= 1.f) c.rest_amplitude = f;
        else Error(Key(path, "rest_amplitude"), "expected a number in [0, 1], got " + Describe(*r));
      }
    }
    if (errors_ != before) return;
    out->push_back(c);
    origin_paths->push_back(path);
    if (mirror) {
      TemplateCurveWrinkle m = c;
      m.name = c.name.substr(0, c.name.size() - 1) + (EndsWith(c.name, "_L") ? "R" : "L");
      for (TemplatePoint& p : m.control) {
        for (int& l : p.landmarks) l = IbugMirrorLandmark(l);
        p.offset.x = -p.offset.x;
      }
      out->push_back(m);
      origin_paths->push_back(path + " (mirrored as " + m.name + ")");
    }
  }

  bool ParseRoot(const json& root, MuscleTemplate* out) {
    if (!root.is_object()) {
      Error("", "expected a JSON object {\"format\": \"mimetic-muscle-template\", ...}, got " +
                    Describe(root));
      return false;
    }
    // Version first: a newer file may use keys this build does not know.
    if (const json* ver = Member(root, "", "version", "the integer 1")) {
      if (!ver->is_number_integer() && !ver->is_number_unsigned()) {
        Error("version", "expected the integer 1, got " + Describe(*ver));
      } else if (ver->get<long long>() != kFormatVersion) {
        Error("version", "unsupported version " + ver->dump() + ": this build reads version 1");
        return false;
      }
    }
    if (const json* fmt = Member(root, "", "format", "\"mimetic-muscle-template\"")) {
      if (!fmt->is_string() || fmt->get<std::string>() != kFormatName)
        Error("format", std::string("expected \"") + kFormatName + "\", got " + Describe(*fmt));
    }
    CheckKeys(root, "", {"format", "version", "description", "thickness", "muscles",
                         "curve_wrinkles"},
              "a muscle template");
    if (const json* d = Member(root, "", "description", ""))
      if (!d->is_string()) Error("description", "expected a string, got " + Describe(*d));
    if (const json* t = Member(root, "", "thickness", "")) ParseThickness(*t, &out->thickness);
    std::vector<std::string> origin_paths;
    if (const json* ms = Member(root, "", "muscles", "a non-empty array of muscles")) {
      if (!ms->is_array() || ms->empty()) {
        Error("muscles", "expected a non-empty array of muscles, got " + Describe(*ms));
      } else {
        for (size_t i = 0; i < ms->size(); ++i)
          ParseMuscle((*ms)[i], Index("muscles", i), &out->muscles, &origin_paths);
      }
    }
    std::set<std::string> names;
    for (size_t i = 0; i < out->muscles.size(); ++i) {
      if (!names.insert(out->muscles[i].name).second)
        Error(origin_paths[i] + ".name", "duplicate muscle name \"" + out->muscles[i].name +
                                             "\"; expected unique names (mirrored copies count)");
    }
    std::vector<std::string> curve_paths;
    if (const json* cs = Member(root, "", "curve_wrinkles", "")) {
      if (!cs->is_array()) {
        Error("curve_wrinkles", "expected an array of curve wrinkles, got " + Describe(*cs));
      } else {
        for (size_t i = 0; i < cs->size(); ++i)
          ParseCurveWrinkle((*cs)[i], Index("curve_wrinkles", i), &out->curve_wrinkles, &curve_paths);
      }
    }
    std::set<std::string> curve_names;
    for (size_t i = 0; i < out->curve_wrinkles.size(); ++i) {
      if (!curve_names.insert(out->curve_wrinkles[i].name).second)
        Error(curve_paths[i] + ".name", "duplicate curve wrinkle name \"" +
                                            out->curve_wrinkles[i].name +
                                            "\"; expected unique names (mirrored copies count)");
    }
    return errors_ == 0;
  }

 private:
  Diagnostics* diag_;
  size_t errors_ = 0;
};

}  // namespace

bool ParseMuscleTemplate(std::string_view json_text, MuscleTemplate* out, Diagnostics* diag) {
  MuscleTemplate result;
  json root;
  try {
    root = json::parse(json_text.begin(), json_text.end());
  } catch (const json::exception& e) {
    std::string what = e.what();
    // "[json.exception.parse_error.101] parse error at line 3, column 5: ..." -> after "] ".
    const size_t cut = what.find("] ");
    if (cut != std::string::npos) what = what.substr(cut + 2);
    diag->Error("", "not valid JSON: " + what);
    return false;
  }
  Parser parser(diag);
  bool ok = false;
  try {
    ok = parser.ParseRoot(root, &result);
  } catch (const std::exception& e) {  // defensive: the checks above should prevent this
    diag->Error("", std::string("internal error while reading the template: ") + e.what());
    return false;
  }
  if (!ok) return false;
  result.file = out->file;
  *out = std::move(result);
  return true;
}

bool LoadMuscleTemplate(const std::string& path, MuscleTemplate* out, Diagnostics* diag) {
  std::string text;
  if (!ReadFile(path, &text, diag)) return false;
  Diagnostics local;
  MuscleTemplate t;
  const bool ok = ParseMuscleTemplate(text, &t, &local);
  diag->Append(local, path);
  if (!ok) return false;
  t.file = path;
  *out = std::move(t);
  return true;
}

}  // namespace mimetic

// viewer/core/rig_edit.cpp: see rig_edit.h.
#include "viewer/core/rig_edit.h"

#include <charconv>
#include <cmath>
#include <cstdlib>
#include <numbers>

#include "expressions/offline/activation_binding.h"

namespace mimetic::viewer {
namespace {

bool NeedSpec(const EditTarget& t, std::string* error) {
  if (t.rig_spec) return true;
  *error = "the rig has no editable spec (a compiled .mrig keeps none; open its .rig.json)";
  return false;
}

class SetMuscleSpec : public Command {
 public:
  SetMuscleSpec(uint32_t index, MuscleSpec muscle, std::optional<MuscleWrinkleSpec> wrinkles,
                std::string what)
      : index_(index), muscle_(std::move(muscle)), wrinkles_(wrinkles), what_(std::move(what)) {}
  std::string Describe() const override { return what_; }
  unsigned Touches() const override { return kEditRig; }
  bool Apply(const EditTarget& t, std::string* error) override {
    if (!NeedSpec(t, error)) return false;
    RigSpec& s = *t.rig_spec;
    if (index_ >= s.muscles.size()) {
      *error = "the rig has no muscle " + std::to_string(index_);
      return false;
    }
    before_ = s.muscles[index_];
    had_slot_ = index_ < s.muscle_wrinkles.size();
    before_wrinkles_ = had_slot_ ? s.muscle_wrinkles[index_] : std::nullopt;
    before_size_ = s.muscle_wrinkles.size();
    s.muscles[index_] = muscle_;
    if (wrinkles_ || had_slot_) {
      if (s.muscle_wrinkles.size() <= index_) s.muscle_wrinkles.resize(index_ + 1);
      s.muscle_wrinkles[index_] = wrinkles_;
    }
    return true;
  }
  void Revert(const EditTarget& t) override {
    RigSpec& s = *t.rig_spec;
    s.muscles[index_] = before_;
    if (had_slot_) s.muscle_wrinkles[index_] = before_wrinkles_;
    s.muscle_wrinkles.resize(before_size_);
  }

 private:
  uint32_t index_;
  MuscleSpec muscle_, before_;
  std::optional<MuscleWrinkleSpec> wrinkles_, before_wrinkles_;
  bool had_slot_ = false;
  size_t before_size_ = 0;
  std::string what_;
};

class SetCurveSpec : public Command {
 public:
  SetCurveSpec(uint32_t index, CurveWrinkleSpec curve, std::string what)
      : index_(index), curve_(curve), what_(std::move(what)) {}
  std::string Describe() const override { return what_; }
  unsigned Touches() const override { return kEditRig; }
  bool Apply(const EditTarget& t, std::string* error) override {
    if (!NeedSpec(t, error)) return false;
    if (index_ >= t.rig_spec->curve_wrinkles.size()) {
      *error = "the rig has no curve wrinkle " + std::to_string(index_);
      return false;
    }
    before_ = t.rig_spec->curve_wrinkles[index_].spec;
    t.rig_spec->curve_wrinkles[index_].spec = curve_;
    return true;
  }
  void Revert(const EditTarget& t) override { t.rig_spec->curve_wrinkles[index_].spec = before_; }

 private:
  uint32_t index_;
  CurveWrinkleSpec curve_, before_;
  std::string what_;
};

class SetField : public Command {
 public:
  SetField(uint32_t field, DirectionFieldSpec spec, std::string what)
      : field_(field), spec_(std::move(spec)), what_(std::move(what)) {}
  std::string Describe() const override { return what_; }
  unsigned Touches() const override { return kEditRig; }
  bool Apply(const EditTarget& t, std::string* error) override {
    if (!NeedSpec(t, error)) return false;
    if (!t.rig_spec->fine_scale || field_ > 1) {
      *error = "the rig has no fine_scale direction field " + std::to_string(field_);
      return false;
    }
    before_ = t.rig_spec->fine_scale->fields[field_];
    t.rig_spec->fine_scale->fields[field_] = spec_;
    return true;
  }
  void Revert(const EditTarget& t) override { t.rig_spec->fine_scale->fields[field_] = before_; }

 private:
  uint32_t field_;
  DirectionFieldSpec spec_, before_;
  std::string what_;
};

std::string Num(float f) {
  char buf[64];
  const auto res = std::to_chars(buf, buf + sizeof buf, f);
  return std::string(buf, res.ptr);
}

// A number word: anything strtof reads whole (nan and inf too: the checks below name them).
bool Word(const std::string& word, float* out) {
  char* end = nullptr;
  const float v = std::strtof(word.c_str(), &end);  // out of range: +-inf, refused by Check
  if (word.empty() || end != word.c_str() + word.size()) return false;
  *out = v;
  return true;
}

// Every word of `args` as a number; false with "WHERE: '...' is not a number" at the first
// that is not (`where` names the field).
bool Numbers(const std::vector<std::string>& args, const std::string& where,
             std::vector<float>* out, std::string* error) {
  out->clear();
  for (const std::string& a : args) {
    float v = 0.f;
    if (!Word(a, &v)) {
      *error = where + ": '" + a + "' is not a number";
      return false;
    }
    out->push_back(v);
  }
  return true;
}

std::string Joined(const std::vector<std::string>& args) {
  std::string out;
  for (const std::string& a : args) out += (out.empty() ? "" : " ") + a;
  return out;
}

std::string Joined(const std::vector<float>& values) {
  std::string out;
  for (float v : values) out += (out.empty() ? "" : " ") + Num(v);
  return out;
}

enum class Range { kAny, kNonNegative, kPositive, kUnit, kUnitOpen, kAngle };

bool InRange(float v, Range r) {
  if (!std::isfinite(v)) return false;
  switch (r) {
    case Range::kAny: return true;
    case Range::kNonNegative: return v >= 0.f;
    case Range::kPositive: return v > 0.f;
    case Range::kUnit: return v >= 0.f && v <= 1.f;
    case Range::kUnitOpen: return v >= 0.f && v < 1.f;
    case Range::kAngle: return v > 0.f && v < 180.f;
  }
  return false;
}

const char* RangeText(Range r) {
  switch (r) {
    case Range::kAny: return "a finite number";
    case Range::kNonNegative: return "a finite number >= 0";
    case Range::kPositive: return "a finite number > 0";
    case Range::kUnit: return "a number in [0, 1]";
    case Range::kUnitOpen: return "a number in [0, 1)";
    case Range::kAngle: return "an angle in (0, 180) degrees";
  }
  return "";
}

// Checks `values` against `count` and `range`: the message names `field`.
bool Check(const std::string& where, const std::string& field, const std::vector<float>& values,
           size_t count, Range range, std::string* error) {
  if (values.size() != count) {
    *error = where + ": " + field + ": expected " + std::to_string(count) +
             (count == 1 ? " value" : " values") + ", got " + std::to_string(values.size());
    return false;
  }
  for (float v : values)
    if (!InRange(v, range)) {
      *error = where + ": " + field + ": expected " + RangeText(range) + ", got " + Num(v);
      return false;
    }
  return true;
}

float Radians(float deg) { return float(double(deg) * std::numbers::pi / 180.0); }

// The muscle edits on numbers (words already read); `text` is what the Describe() shows.
CommandPtr MuscleValues(const RigSpec& spec, uint32_t m, const std::string& param,
                        const std::vector<float>& v, const std::string& text, std::string* error) {
  if (m >= spec.muscles.size()) {
    *error = "the rig has no muscle " + std::to_string(m);
    return nullptr;
  }
  MuscleSpec muscle = spec.muscles[m];
  std::optional<MuscleWrinkleSpec> wrinkles =
      m < spec.muscle_wrinkles.size() ? spec.muscle_wrinkles[m] : std::nullopt;
  const std::string where = "muscles[" + std::to_string(m) + "] " + muscle.name;
  const bool linear = muscle.type == MuscleType::kLinear;
  const auto point = [&](float3* line, bool is_linear) -> bool {
    if (is_linear) {
      if (!Check(where, param, v, 3, Range::kAny, error)) return false;
      *line = {v[0], v[1], v[2]};
      return true;
    }
    if (v.size() != 4 || !(v[0] == 0.f || v[0] == 1.f)) {
      *error = where + ": " + param + ": a sheet muscle's " + param +
               " is a line: expected I X Y Z with I = 0 or 1";
      return false;
    }
    const std::vector<float> xyz(v.begin() + 1, v.end());
    if (!Check(where, param, xyz, 3, Range::kAny, error)) return false;
    line[v[0] == 0.f ? 0 : 1] = {xyz[0], xyz[1], xyz[2]};
    return true;
  };
  const auto one = [&](float* field, Range range) -> bool {
    if (!Check(where, param, v, 1, range, error)) return false;
    *field = v[0];
    return true;
  };
  bool ok = false;
  if (param == "strength") {
    ok = one(&muscle.strength, Range::kNonNegative);
  } else if (param == "tangent_radius") {
    ok = one(&muscle.tangent_radius, Range::kNonNegative);
  } else if (param == "attachment") {
    ok = linear ? point(&muscle.linear.attachment, true) : point(muscle.sheet.attachment, false);
  } else if (param == "insertion") {
    ok = linear ? point(&muscle.linear.insertion, true) : point(muscle.sheet.insertion, false);
  } else if (param == "zone_angle" && linear) {
    float deg = 0.f;
    ok = one(&deg, Range::kAngle);
    if (ok) muscle.linear.zone_angle = Radians(deg);
  } else if (param == "falloff_start") {
    ok = one(linear ? &muscle.linear.falloff_start : &muscle.sheet.falloff_start, Range::kPositive);
  } else if (param == "falloff_end" && linear) {
    ok = one(&muscle.linear.falloff_end, Range::kPositive);
  } else if (param == "length" && !linear) {
    ok = one(&muscle.sheet.length, Range::kPositive);
  } else if (param == "width" && !linear) {
    ok = one(&muscle.sheet.width, Range::kPositive);
  } else if (param.rfind("wrinkles.", 0) == 0) {
    if (!wrinkles) {
      *error = where + ": " + param + ": the muscle has no wrinkle block (wrinkles on first)";
      return nullptr;
    }
    const std::string key = param.substr(9);
    if (key == "lambda_w") {
      ok = one(&wrinkles->lambda_w, Range::kUnitOpen);
    } else if (key == "count") {
      float n = 0.f;
      ok = one(&n, Range::kPositive);
      if (ok && (n != std::floor(n) || n < 1.f || n > 1000.f)) {
        *error = where + ": " + param + ": expected a whole number in [1, 1000], got " + Num(n);
        return nullptr;
      }
      if (ok) wrinkles->count = int(n);
    } else if (key == "depth") {
      ok = one(&wrinkles->depth, Range::kNonNegative);
    } else if (key == "shape") {
      ok = one(&wrinkles->shape, Range::kAny);
    } else if (key == "gate") {
      ok = one(&wrinkles->gate, Range::kUnit);
    } else if (key == "phi_c" && linear) {
      float deg = 0.f;
      ok = Check(where, param, v, 1, Range::kNonNegative, error);
      if (ok) wrinkles->phi_c = Radians(deg = v[0]);
    } else if (key == "h_c" && !linear) {
      ok = one(&wrinkles->h_c, Range::kNonNegative);
    } else {
      *error = where + ": no wrinkle parameter '" + key + "' for a " +
               (linear ? "linear" : "sheet") + " muscle; expected lambda_w, count, depth, shape, " +
               (linear ? "phi_c" : "h_c") + ", gate";
      return nullptr;
    }
  } else {
    *error = where + ": no parameter '" + param + "' for a " + (linear ? "linear" : "sheet") +
             " muscle; expected strength, falloff, motion, tangent_radius, attachment, insertion, " +
             (linear ? "zone_angle, falloff_start, falloff_end"
                     : "length, width, falloff_start") +
             ", wrinkles or wrinkles.FIELD";
    return nullptr;
  }
  if (!ok) return nullptr;
  return MakeSetMuscleSpec(m, std::move(muscle), wrinkles,
                           "muscle " + spec.muscles[m].name + " " + param + " " + text);
}

}  // namespace

CommandPtr MakeSetMuscleSpec(uint32_t index, MuscleSpec muscle,
                             std::optional<MuscleWrinkleSpec> wrinkles, std::string what) {
  return std::make_unique<SetMuscleSpec>(index, std::move(muscle), wrinkles, std::move(what));
}
CommandPtr MakeSetCurveWrinkleSpec(uint32_t index, CurveWrinkleSpec curve, std::string what) {
  return std::make_unique<SetCurveSpec>(index, curve, std::move(what));
}
CommandPtr MakeSetDirectionField(uint32_t field, DirectionFieldSpec spec, std::string what) {
  return std::make_unique<SetField>(field, std::move(spec), std::move(what));
}

// The index of the element called `name` in `items` (each has a `name`), or -1 with `error`
// saying "KIND NAME: the rig has no WHAT 'NAME'" and the closest names (or that there is none).
template <class T>
int FindNamedOrSay(const std::vector<T>& items, const std::string& name, const char* kind,
                   const char* what, std::string* error) {
  std::vector<std::string> names;
  for (size_t i = 0; i < items.size(); ++i) {
    if (items[i].name == name) return int(i);
    names.push_back(items[i].name);
  }
  *error = std::string(kind) + " " + name + ": the rig has no " + what + " '" + name + "'" +
           (names.empty() ? " (it has none)" : "; the closest: " + ClosestNames(names, name));
  return -1;
}

int FindSpecMuscle(const RigSpec& spec, const std::string& name) {
  for (size_t i = 0; i < spec.muscles.size(); ++i)
    if (spec.muscles[i].name == name) return int(i);
  return -1;
}
int FindSpecCurve(const RigSpec& spec, const std::string& name) {
  for (size_t i = 0; i < spec.curve_wrinkles.size(); ++i)
    if (spec.curve_wrinkles[i].name == name) return int(i);
  return -1;
}
int FindSpecField(const RigSpec& spec, const std::string& name) {
  if (!spec.fine_scale) return -1;
  for (int i = 0; i < 2; ++i)
    if (spec.fine_scale->fields[i].name == name) return i;
  if (name == "0" || name == "1") return name[0] - '0';
  return -1;
}

bool ParseCurveProfile(const std::string& text, CurveWrinkleProfile* out) {
  for (CurveWrinkleProfile p : {CurveWrinkleProfile::kBando, CurveWrinkleProfile::kYangZhang,
                                CurveWrinkleProfile::kYangZhangExact})
    if (text == CurveWrinkleProfileName(p)) return *out = p, true;
  return false;
}
bool ParseCurveModulation(const std::string& text, CurveWrinkleModulation* out) {
  for (CurveWrinkleModulation m : {CurveWrinkleModulation::kDirectional, CurveWrinkleModulation::kArea})
    if (text == CurveWrinkleModulationName(m)) return *out = m, true;
  return false;
}

CommandPtr MakeMuscleValueEdit(const RigSpec& spec, uint32_t muscle, const std::string& param,
                               const std::vector<float>& values, std::string* error) {
  return MuscleValues(spec, muscle, param, values, Joined(values), error);
}

CommandPtr MakeMuscleEdit(const RigSpec& spec, const std::string& name, const std::string& param,
                          const std::vector<std::string>& args, std::string* error) {
  const int m = FindNamedOrSay(spec.muscles, name, "muscle", "muscle", error);
  if (m < 0) return nullptr;
  const MuscleSpec& muscle = spec.muscles[size_t(m)];
  const std::string where = "muscles[" + std::to_string(m) + "] " + name;
  const std::string text = Joined(args);
  if (param == "falloff" || param == "motion") {
    MuscleSpec edited = muscle;
    bool ok = args.size() == 1;
    if (ok && param == "falloff") {
      ok = args[0] == "waters" || args[0] == "smooth";
      if (ok) edited.falloff = args[0] == "waters" ? MuscleFalloff::kWaters : MuscleFalloff::kSmooth;
    } else if (ok) {
      ok = args[0] == "chord" || args[0] == "tangent";
      if (ok) edited.motion = args[0] == "chord" ? MuscleMotion::kChord : MuscleMotion::kTangent;
    }
    if (!ok) {
      *error = where + ": " + param + ": expected " +
               (param == "falloff" ? "waters or smooth" : "chord or tangent") + ", got '" + text + "'";
      return nullptr;
    }
    return MakeSetMuscleSpec(uint32_t(m), std::move(edited),
                             size_t(m) < spec.muscle_wrinkles.size() ? spec.muscle_wrinkles[m]
                                                                      : std::nullopt,
                             "muscle " + name + " " + param + " " + text);
  }
  if (param == "wrinkles") {
    if (args.size() != 1 || (args[0] != "none" && args[0] != "on")) {
      *error = where + ": wrinkles: expected none or on, got '" + text + "'";
      return nullptr;
    }
    std::optional<MuscleWrinkleSpec> w =
        size_t(m) < spec.muscle_wrinkles.size() ? spec.muscle_wrinkles[m] : std::nullopt;
    if (args[0] == "none") {
      w.reset();
    } else if (!w) {
      w = MuscleWrinkleSpec{};
      w->depth = 0.1f * muscle.strength;  // a visible default: a tenth of the contraction
    }
    return MakeSetMuscleSpec(uint32_t(m), muscle, w, "muscle " + name + " wrinkles " + text);
  }
  std::vector<float> values;
  if (!Numbers(args, where + ": " + param, &values, error)) return nullptr;
  return MuscleValues(spec, uint32_t(m), param, values, text, error);
}

CommandPtr MakeCurvePointEdit(const RigSpec& spec, uint32_t c, int point, float2 uv,
                              std::string* error) {
  if (c >= spec.curve_wrinkles.size()) {
    *error = "the rig has no curve wrinkle " + std::to_string(c);
    return nullptr;
  }
  const std::string& name = spec.curve_wrinkles[c].name;
  const std::string where = "curve_wrinkles[" + std::to_string(c) + "] " + name;
  if (point < 0 || point > 3) {
    *error = where + ": point: expected a control point index 0 to 3, got " + std::to_string(point);
    return nullptr;
  }
  if (!std::isfinite(uv.x) || !std::isfinite(uv.y)) {
    *error = where + ": control[" + std::to_string(point) + "]: expected finite texture "
             "coordinates, got " + Num(uv.x) + " " + Num(uv.y);
    return nullptr;
  }
  CurveWrinkleSpec curve = spec.curve_wrinkles[c].spec;
  curve.control[point] = uv;
  return MakeSetCurveWrinkleSpec(c, curve, "curve " + name + " point " + std::to_string(point) +
                                               " " + Num(uv.x) + " " + Num(uv.y));
}

CommandPtr MakeCurveEdit(const RigSpec& spec, const std::string& name, const std::string& param,
                         const std::vector<std::string>& args, std::string* error) {
  const int c = FindNamedOrSay(spec.curve_wrinkles, name, "curve", "curve wrinkle", error);
  if (c < 0) return nullptr;
  const std::string where = "curve_wrinkles[" + std::to_string(c) + "] " + name;
  const std::string text = Joined(args);
  CurveWrinkleSpec curve = spec.curve_wrinkles[size_t(c)].spec;
  if (param == "profile" || param == "modulation") {
    const bool ok = args.size() == 1 && (param == "profile" ? ParseCurveProfile(args[0], &curve.profile)
                                                            : ParseCurveModulation(args[0], &curve.modulation));
    if (!ok) {
      *error = where + ": " + param + ": expected " +
               (param == "profile" ? "bando, yang_zhang or yang_zhang_exact" : "directional or area") +
               ", got '" + text + "'";
      return nullptr;
    }
    return MakeSetCurveWrinkleSpec(uint32_t(c), curve, "curve " + name + " " + param + " " + text);
  }
  std::vector<float> v;
  if (!Numbers(args, where + ": " + param, &v, error)) return nullptr;
  if (param == "point") {
    if (v.size() != 3 || v[0] != std::floor(v[0])) {
      *error = where + ": point: expected I U V (I a control point index 0 to 3)";
      return nullptr;
    }
    return MakeCurvePointEdit(spec, uint32_t(c), int(v[0]), {v[1], v[2]}, error);
  }
  bool ok = false;
  if (param == "depth") {
    ok = Check(where, param, v, 1, Range::kPositive, error) && (curve.depth = v[0], true);
  } else if (param == "width") {
    ok = Check(where, param, v, 1, Range::kPositive, error) && (curve.width = v[0], true);
  } else if (param == "rest_amplitude") {
    ok = Check(where, param, v, 1, Range::kUnit, error) && (curve.rest_amplitude = v[0], true);
  } else {
    *error = where + ": no parameter '" + param + "'; expected point, depth, width, profile, "
             "modulation or rest_amplitude";
    return nullptr;
  }
  if (!ok) return nullptr;
  return MakeSetCurveWrinkleSpec(uint32_t(c), curve, "curve " + name + " " + param + " " + text);
}

CommandPtr MakeDirectionEdit(const RigSpec& spec, size_t vertex_count, const std::string& field,
                             uint32_t vertex, const std::vector<std::string>& args,
                             std::string* error) {
  if (!spec.fine_scale) {
    *error = "direction " + field + ": the rig has no fine_scale block (docs/rig-format.md)";
    return nullptr;
  }
  const int f = FindSpecField(spec, field);
  if (f < 0) {
    *error = "direction " + field + ": no direction field '" + field + "'; expected " +
             spec.fine_scale->fields[0].name + ", " + spec.fine_scale->fields[1].name + ", 0 or 1";
    return nullptr;
  }
  const std::string where = "fine_scale.fields[" + std::to_string(f) + "] " +
                            spec.fine_scale->fields[f].name;
  if (vertex >= vertex_count) {
    *error = where + ": vertex: " + std::to_string(vertex) + " is not a vertex of the mesh (it has " +
             std::to_string(vertex_count) + ")";
    return nullptr;
  }
  DirectionFieldSpec edited = spec.fine_scale->fields[f];
  auto at = edited.anchors.end();
  for (auto it = edited.anchors.begin(); it != edited.anchors.end(); ++it)
    if (it->vertex == vertex) at = it;
  const std::string what = "direction " + spec.fine_scale->fields[f].name + " " +
                           std::to_string(vertex) + " " + Joined(args);
  if (args.size() == 1 && args[0] == "delete") {
    if (at == edited.anchors.end()) {
      *error = where + ": vertex " + std::to_string(vertex) + " has no direction vector to delete";
      return nullptr;
    }
    if (edited.anchors.size() == 1) {
      *error = where + ": the field's last direction vector cannot be deleted (a field needs one)";
      return nullptr;
    }
    edited.anchors.erase(at);
    return MakeSetDirectionField(uint32_t(f), std::move(edited), what);
  }
  std::vector<float> v;
  if (!Numbers(args, where + ": vector", &v, error)) return nullptr;
  if (v.size() != 4) {
    *error = where + ": expected DX DY DZ MAG or delete";
    return nullptr;
  }
  const std::vector<float> dir(v.begin(), v.begin() + 3);
  if (!Check(where, "vector", dir, 3, Range::kAny, error)) return nullptr;
  const float max_mag = MaxMagnitude(spec.fine_scale->parameters);
  if (!std::isfinite(v[3]) || v[3] <= 0.f || v[3] > max_mag) {
    *error = where + ": magnitude: expected a number in (0, " + Num(max_mag) + "] for these "
             "furrow parameters, got " + Num(v[3]);
    return nullptr;
  }
  const double len = std::sqrt(double(dir[0]) * dir[0] + double(dir[1]) * dir[1] + double(dir[2]) * dir[2]);
  if (!(len > 0.0)) {
    *error = where + ": vector: the direction must not be zero";
    return nullptr;
  }
  const double s = double(v[3]) / len;
  const float3 vec{float(dir[0] * s), float(dir[1] * s), float(dir[2] * s)};
  if (at != edited.anchors.end()) {
    at->vector = vec;
  } else {
    DirectionAnchor a;
    a.vertex = vertex;
    a.vector = vec;
    edited.anchors.push_back(a);
  }
  return MakeSetDirectionField(uint32_t(f), std::move(edited), what);
}

}  // namespace mimetic::viewer

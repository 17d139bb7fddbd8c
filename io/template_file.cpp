// io/template_file.cpp: the muscle template file (docs/template-format.md): parse and
// validate. The fields are declared once in the tables below (io/json_reader.h checks them and
// generates assets/schema/mimetic-muscle-template.schema.json from them); the rules between
// fields and the mirroring follow. Every problem is recorded with its JSON path and what was
// expected; nothing throws out of this file.
#include "io/template_file.h"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/file_util.h"
#include "core/strings.h"
#include "fitting/landmarks.h"
#include "io/formats.h"
#include "io/jaw_fields.h"
#include "io/json_reader.h"

namespace mimetic {
namespace {

using json = nlohmann::json;
using namespace json_reader;

constexpr const char* kFormatName = "mimetic-muscle-template";

// ---------------------------------------------------------------------------------------------
// The tables. Lengths are in units of s (docs/template-format.md, "Units").

// A point: weighted landmarks, an offset in the face plane, a depth under the skin.
const Field kLandmarks =
    Array("landmarks",
          Integer("", "a landmark index, an integer in 0..67 (iBUG 68 order)")
              .Min(0).Max(kTemplateLandmarkCount - 1),
          "a non-empty array of landmark indices (integers 0..67)")
        .NonEmpty().Required();
const Field kWeights = Array("weights", Number("").Min(0), "an array of numbers >= 0")
                           .About("one per landmark; default equal");
const Field kOffset = Numbers("offset", 2, "[dx, dy], two finite numbers (units of s)");
const Object kPoint = {"a template point", {
    kLandmarks, kWeights, kOffset,
    Number("depth").Min(0).Required().About("units of s under the surface")}};
// A curve wrinkle's control point lies in the skin.
const Object kSurfacePoint = {"a template point", {
    kLandmarks, kWeights, kOffset,
    Number("depth", "0 or no depth (a curve wrinkle's control point lies in the skin)")
        .Min(0).Max(0)}};
const std::string kPointExpect =
    "a point object {\"landmarks\": [...], \"weights\": [...], \"offset\": [dx, dy], "
    "\"depth\": d}";

const Object kRegion = {"a thickness region", {
    String("name"),
    Numbers("center", 2, "[x, y], two finite numbers (units of s)").Required()
        .About("face frame"),
    Array("radius", Number("").Above(0), "[sx, sy], two numbers > 0 (units of s)")
        .Count(2).Required(),
    Number("value").Min(0).Required().About("units of s"),
    Bool("mirror")}};
const Object kTensionRegion = {"a tension region", {
    String("name").NonEmpty().Required().About("such as \"glabella\" or \"crows_feet_L\""),
    Numbers("center", 2, "[x, y], two finite numbers (units of s)").Required()
        .About("face frame"),
    Array("radius", Number("").Above(0), "[sx, sy], two numbers > 0 (units of s)")
        .Count(2).Required(),
    Number("reference", "a number > 0 (a mean area compression)").Above(0)
        .About("c0 of the region's weight (docs/model.md §19); default 0.1"),
    Bool("mirror").About("also the copy mirrored across the midline, _L <-> _R")}};
const Object kDirectionAnchor = {"a fine-scale direction vector", {
    String("name").NonEmpty().Required().About("such as \"forehead\" or \"crows_feet_L\""),
    Numbers("at", 2, "[x, y], two finite numbers (units of s)").Required()
        .About("face frame; the fit takes the nearest forward-facing vertex"),
    Numbers("direction", 3, "[dx, dy, dz], three finite numbers, not all 0 (face frame)")
        .Required(),
    Number("magnitude", "a number in (0, 1]").Above(0).Max(1).Required()
        .About("000 eq. 1's m"),
    Bool("mirror").About("also the copy mirrored across the midline, _L <-> _R")}};
const Object kFineField = {"a fine-scale field", {
    String("name").NonEmpty().Required(),
    Array("vectors", ObjectOf("", kDirectionAnchor, "a direction vector object {\"name\", \"at\", "
                                                    "\"direction\", \"magnitude\"}"),
          "a non-empty array of direction vectors").NonEmpty().Required()}};
const Object kFineScale = {"fine_scale", {
    Array("fields", ObjectOf("", kFineField, "a field object {\"name\", \"vectors\"}"),
          "an array of 2 fields").Count(2).Required(),
    Number("rest_amplitude", "a number in [0, 1]").Min(0).Max(1)
        .About("r of M(s) (docs/model.md §23); default 0.5")}};
const Object kTemplateRefinement = {"refinement", {
    Number("falloff_error", "a number in [0, 1) (0 = off)").Min(0).Below(1)
        .About("the fitted rig's refinement.falloff_error (docs/model.md §11); default 0 = off")}};
const Object kThickness = {"thickness", {
    Number("base").Min(0).Required().About("units of s"),
    Numbers("front", 2, "[z0, z1], two numbers with z0 < z1 (units of s)"),
    Array("regions", ObjectOf("", kRegion, "a region object {\"name\", \"center\", \"radius\", "
                                           "\"value\"}"),
          "an array of regions")}};

// docs/model.md §6: the rig file's wrinkle block (docs/rig-format.md), lengths in units of s.
const Object kLinearWrinkles = MuscleWrinkleBlock(true, "units of s");
const Object kSheetWrinkles = MuscleWrinkleBlock(false, "units of s");

const Object kLinearMuscle = {"a linear muscle", {
    ObjectOf("attachment", kPoint, kPointExpect).Required(),
    ObjectOf("insertion", kPoint, kPointExpect).Required(),
    Number("zone_angle_deg", "a number in (0, 180) (degrees)").Above(0).Below(180).Required(),
    Number("falloff_start").Above(0).Required().About("Rs, units of s"),
    Number("falloff_end", "a finite number > falloff_start").Above(0).Required()
        .About("Rf, units of s"),
    ObjectOf("wrinkles", kLinearWrinkles, "a wrinkle object {\"lambda_w\": ..., \"count\": ..., "
             "\"depth\": ..., \"shape\": ..., \"phi_c_deg\": ...}")}};
Field Line(const char* key) {
  return Array(key, ObjectOf("", kPoint, kPointExpect),
               "an array of 2 point objects (the ends of the line)").Count(2).Required();
}
const Object kSheetMuscle = {"a sheet muscle", {
    Line("attachment"), Line("insertion"),
    Number("length").Above(0).Required().About("Ls, units of s"),
    Number("width").Above(0).Required().About("Ws, units of s"),
    Number("falloff_start", "a number in (0, length)").Above(0).Required()
        .About("Rs, units of s"),
    ObjectOf("wrinkles", kSheetWrinkles, "a wrinkle object {\"lambda_w\": ..., \"count\": ..., "
             "\"depth\": ..., \"shape\": ..., \"h_c\": ...}")}};
const Object kMuscle = {
    .owner = "a muscle",
    .fields = {
        String("name").NonEmpty().Required().About("such as \"zygomaticus_major_L\""),
        Enum("type", {"linear", "sheet"}, "\"linear\" or \"sheet\"").Required(),
        Bool("mirror").About("also the copy mirrored across the midline, _L <-> _R"),
        Number("strength").Min(0).Required().About("units of s"),
        Enum("falloff", {"waters", "smooth"}, "\"waters\" or \"smooth\"")
            .About("as in the rig file; default \"waters\""),
        Enum("motion", {"chord", "tangent"}, "\"chord\" or \"tangent\"")
            .About("as in the rig file; default \"chord\""),
        Number("tangent_radius").Min(0)
            .About("units of s; as in the rig file; default 0")},
    .variant_key = "type",
    .variants = {{"linear", &kLinearMuscle}, {"sheet", &kSheetMuscle}}};

// docs/model.md §7-8: a curve wrinkle whose control points are template points on the skin.
const Object kCurveWrinkle = {"a curve wrinkle", {
    String("name").NonEmpty().Required().About("such as \"nasolabial_L\""),
    Bool("mirror"),
    Array("control", ObjectOf("", kSurfacePoint, kPointExpect),
          "an array of 4 point objects (the cubic Bezier control points, on the skin)")
        .Count(4).Required(),
    Number("depth").Above(0).Required().About("units of s"),
    Number("width").Above(0).Required().About("units of s"),
    Enum("profile", {"bando", "yang_zhang", "yang_zhang_exact"}),
    Enum("modulation", {"directional", "area"}),
    Number("rest_amplitude").Min(0).Max(1)}};

// docs/model.md §18.
const Object kCondyle = {"a condyle", {
    kLandmarks, kWeights,
    Numbers("offset", 3, "[dx, dy, dz], three finite numbers (units of s, face frame)")
        .About("from the weighted landmark mean; no projection onto the surface")}};
const Object kJaw = {"the jaw", {
    ObjectOf("condyle", kCondyle, "a condyle object {\"landmarks\": [...], \"offset\": [dx, dy, dz]}")
        .Required().About("the subject's right condyle; the left one mirrors it"),
    Number("range_deg", "a number in (0, 90] (degrees)").Above(0).Max(90).Required(),
    Numbers("translation", 3, "[dx, dy, dz], three finite numbers (units of s, face frame)")
        .About("the condyles' glide at jaw = 1 (forward and down); default [0, 0, 0]"),
    Number("lip_blend_deg", "a number in (0, 45] (degrees)").Above(0).Max(45),
    Number("cheek_blend_deg", "a number in (0, 90] (degrees)").Above(0).Max(90),
    Number("cheek_drop_deg", "a number in [0, 45] (degrees)").Min(0).Max(45),
    Number("corner_fade", "a number in [0, 0.5] (a fraction of the mouth width)").Min(0).Max(0.5),
    Number("thickness_fade", "a number in [0, 1] (a fraction of the mouth width)").Min(0).Max(1),
    Numbers("back", 2, "[b0, b1], two numbers in [-1, 1] with b0 < b1 (fractions of the "
                       "hinge-to-mouth distance)"),
    Numbers("neck_deg", 2, "[n0, n1], two numbers in [0, 180] with n0 < n1 (degrees below the "
                           "lip line)")}};

const Object kTemplate = {"a muscle template", {
    Enum("format", {kFormatName}).Required(),
    Integer("version", "the integer 1").Version(1).Required(),
    String("description"),
    ObjectOf("thickness", kThickness, "object {\"base\": ..., \"front\": [...], \"regions\": [...]}"),
    Array("muscles", ObjectOf("", kMuscle, "a muscle object"), "a non-empty array of muscles")
        .NonEmpty().Required(),
    Array("curve_wrinkles", ObjectOf("", kCurveWrinkle, "a curve wrinkle object {\"name\", "
                                                        "\"control\", \"depth\", \"width\", ...}"),
          "an array of curve wrinkles"),
    ObjectOf("jaw", kJaw, "a jaw object {\"condyle\": ..., \"range_deg\": ..., ...}"),
    Array("tension_regions", ObjectOf("", kTensionRegion, "a tension region object {\"name\", "
                                                          "\"center\", \"radius\", ...}"),
          "an array of tension regions"),
    ObjectOf("fine_scale", kFineScale, "a fine_scale object {\"fields\": [...]}")
        .About("default fine-scale direction fields (docs/model.md §20)"),
    ObjectOf("refinement", kTemplateRefinement, "a refinement object {\"falloff_error\": ...}")
        .About("refinement the fitted rig asks for beyond its wrinkles'")}};

const Format kTemplateFormat = {
    .name = kFormatName,
    .root = ObjectOf("", kTemplate, "a JSON object {\"format\": \"mimetic-muscle-template\", ...}"),
    .wording = {.value_in_type_errors = true, .unknown_key_in_owner = true},
    .title = "mimetic muscle template, version 1"};

// ---------------------------------------------------------------------------------------------
// The rules between fields, and mirroring.

class TemplateRules {
 public:
  TemplateRules(Reader* reader, Diagnostics* diag) : r_(*reader), diag_(diag) {}

  void Root(const View& top, MuscleTemplate* out);

 private:
  bool Point(const View& p, TemplatePoint* out);
  void Thickness(const View& t, TemplateThickness* out);
  void Jaw(const View& j, MuscleTemplate* out);
  void Muscle(const View& m, std::vector<TemplateMuscle>* out, std::vector<std::string>* origins);
  void Curve(const View& c, std::vector<TemplateCurveWrinkle>* out,
             std::vector<std::string>* origins);
  // `mirror` is allowed only for a name ending in _L or _R; the name of the mirrored copy.
  bool Mirror(const View& v, const std::string& name, const std::string& kind, std::string* copy);
  void UniqueNames(const std::vector<std::string>& names, const std::vector<std::string>& origins,
                   const std::string& kind);

  Reader& r_;
  Diagnostics* diag_;
};

void TemplateRules::Root(const View& top, MuscleTemplate* out) {
  top.Read("description", &out->description);
  if (top.Has("thickness")) Thickness(top.Member("thickness"), &out->thickness);
  std::vector<std::string> origins, names;
  for (size_t i = 0; i < top.Size("muscles"); ++i)
    Muscle(top.Element("muscles", i), &out->muscles, &origins);
  for (const TemplateMuscle& m : out->muscles) names.push_back(m.name);
  UniqueNames(names, origins, "muscle");
  origins.clear();
  names.clear();
  for (size_t i = 0; i < top.Size("curve_wrinkles"); ++i)
    Curve(top.Element("curve_wrinkles", i), &out->curve_wrinkles, &origins);
  for (const TemplateCurveWrinkle& c : out->curve_wrinkles) names.push_back(c.name);
  UniqueNames(names, origins, "curve wrinkle");
  if (top.Has("jaw")) Jaw(top.Member("jaw"), out);
  origins.clear();
  names.clear();
  for (size_t i = 0; i < top.Size("tension_regions"); ++i) {
    const View e = top.Element("tension_regions", i);
    if (!e.ok()) continue;
    TemplateTensionRegion region;
    e.Read("name", &region.name);
    e.Read("center", &region.center);
    e.Read("radius", &region.radius);
    e.Read("reference", &region.reference);
    std::string copy;
    const bool mirror = Mirror(e, region.name, "tension region", &copy);
    out->tension_regions.push_back(region);
    origins.push_back(e.path());
    if (mirror) {
      region.name = copy;
      region.center.x = -region.center.x;
      region.mirrored_copy = true;
      out->tension_regions.push_back(region);
      origins.push_back(e.path() + " (mirrored as " + copy + ")");
    }
  }
  for (const TemplateTensionRegion& g : out->tension_regions) names.push_back(g.name);
  UniqueNames(names, origins, "tension region");
  top.Member("refinement").Read("falloff_error", &out->falloff_error);
  if (top.Has("fine_scale")) {
    const View f = top.Member("fine_scale");
    if (!f.ok()) return;
    TemplateFineScale fs;
    f.Read("rest_amplitude", &fs.rest_amplitude);
    for (size_t i = 0; i < 2 && i < f.Size("fields"); ++i) {
      const View field = f.Element("fields", i);
      field.Read("name", &fs.field_names[i]);
      origins.clear();
      names.clear();
      for (size_t k = 0; k < field.Size("vectors"); ++k) {
        const View e = field.Element("vectors", k);
        if (!e.ok()) continue;
        TemplateDirectionAnchor a;
        e.Read("name", &a.name);
        e.Read("at", &a.at);
        e.Read("direction", &a.direction);
        e.Read("magnitude", &a.magnitude);
        if (!(Length(a.direction) > 0.f)) {
          r_.Error(e.Path("direction"), "is [0, 0, 0]; expected a direction (not all 0)");
          continue;
        }
        std::string copy;
        const bool mirror = Mirror(e, a.name, "fine-scale direction vector", &copy);
        fs.fields[i].push_back(a);
        origins.push_back(e.path());
        if (mirror) {
          a.name = copy;
          a.at.x = -a.at.x;
          // The mirrored line (-dx, dy, dz), written with dx's sign kept when x dominates
          // (the same line), so that a pair does not cancel across the midline when the
          // fit interpolates the vectors.
          a.direction.x = -a.direction.x;
          if (std::fabs(a.direction.x) >= std::fmax(std::fabs(a.direction.y), std::fabs(a.direction.z)))
            a.direction = float3{-a.direction.x, -a.direction.y, -a.direction.z};
          a.mirrored_copy = true;
          fs.fields[i].push_back(a);
          origins.push_back(e.path() + " (mirrored as " + copy + ")");
        }
      }
      for (const TemplateDirectionAnchor& a : fs.fields[i]) names.push_back(a.name);
      UniqueNames(names, origins, "fine-scale direction vector");
    }
    out->fine_scale = std::move(fs);
  }
}

void TemplateRules::Jaw(const View& j, MuscleTemplate* out) {
  if (!j.present() || !j.value()->is_object()) return;
  TemplateJaw jaw;
  bool ok = j.ok();
  const View c = j.Member("condyle");
  TemplatePoint point;
  if (c.present() && c.value()->is_object()) {
    ok &= Point(c, &point);
    jaw.landmarks = point.landmarks;
    jaw.weights = point.weights;
    c.Read("offset", &jaw.offset);
  }
  ok = ReadJawShape(j, r_, &jaw) && ok;
  if (ok) out->jaw = std::move(jaw);
}

void TemplateRules::UniqueNames(const std::vector<std::string>& names,
                                const std::vector<std::string>& origins, const std::string& kind) {
  std::set<std::string> seen;
  for (size_t i = 0; i < names.size(); ++i)
    if (!seen.insert(names[i]).second)
      r_.Error(origins[i] + ".name", "duplicate " + kind + " name " + Quoted(names[i]) +
                                         "; expected unique names (mirrored copies count)");
}

bool TemplateRules::Mirror(const View& v, const std::string& name, const std::string& kind,
                           std::string* copy) {
  bool mirror = false;
  if (!v.Read("mirror", &mirror) || !mirror || name.empty()) return false;
  if (!EndsWith(name, "_L") && !EndsWith(name, "_R")) {
    r_.Error(v.Path("mirror"), "a mirrored " + kind + "'s name must end in _L or _R (the copy "
                               "gets the other suffix); got name " + Quoted(name));
    return false;
  }
  *copy = name.substr(0, name.size() - 1) + (EndsWith(name, "_L") ? "R" : "L");
  return true;
}

// Landmarks once each, one weight per landmark, weights normalised to sum 1 (default: equal).
bool TemplateRules::Point(const View& p, TemplatePoint* out) {
  const size_t before = diag_->ErrorCount();
  out->landmarks.clear();
  out->weights.clear();
  if (const json* lm = p.Get("landmarks")) {
    std::set<int> seen;
    for (size_t i = 0; i < lm->size(); ++i) {
      const int k = static_cast<int>((*lm)[i].get<double>());
      if (seen.insert(k).second) {
        out->landmarks.push_back(k);
      } else {
        r_.Error(Index(p.Path("landmarks"), i), "landmark " + std::to_string(k) +
                                                    " appears twice; expected each landmark "
                                                    "once (use weights)");
      }
    }
  }
  if (const json* w = p.Get("weights")) {
    const json* lm = p.Raw("landmarks");
    const size_t n = lm && lm->is_array() ? lm->size() : 0;
    if (w->size() != n) {
      r_.Expected(p.Path("weights"), "an array of " + std::to_string(n) +
                                         " numbers >= 0 (one per landmark)", *w);
    } else {
      double sum = 0.0;
      for (const json& e : *w) {
        out->weights.push_back(static_cast<float>(e.get<double>()));
        sum += out->weights.back();
      }
      if (!(sum > 0.0))
        r_.Error(p.Path("weights"), "weights sum to 0; expected at least one weight > 0");
    }
  }
  out->offset = {0.f, 0.f};
  p.Read("offset", &out->offset);
  out->depth = 0.f;
  p.Read("depth", &out->depth);
  if (!p.ok() || diag_->ErrorCount() != before) return false;
  if (out->weights.empty()) out->weights.assign(out->landmarks.size(), 1.f);
  double sum = 0.0;
  for (float w : out->weights) sum += w;
  for (float& w : out->weights) w = static_cast<float>(w / sum);
  return true;
}

void TemplateRules::Thickness(const View& t, TemplateThickness* out) {
  t.Read("base", &out->base);
  float2 front{out->front[0], out->front[1]};
  if (t.Read("front", &front)) {
    if (!(front.x < front.y))
      r_.Error(t.Path("front"), "expected z0 < z1, got [" + FormatFloat(front.x) + ", " +
                                    FormatFloat(front.y) + "]");
    out->front[0] = front.x;
    out->front[1] = front.y;
  }
  out->regions.clear();
  for (size_t i = 0; i < t.Size("regions"); ++i) {
    const View e = t.Element("regions", i);
    if (!e.ok()) continue;
    ThicknessRegion region;
    e.Read("name", &region.name);
    e.Read("center", &region.center);
    e.Read("radius", &region.radius);
    e.Read("value", &region.value);
    bool mirror = false;
    e.Read("mirror", &mirror);
    out->regions.push_back(region);
    if (mirror && region.center.x != 0.f) {
      region.center.x = -region.center.x;
      region.mirrored_copy = true;
      out->regions.push_back(region);
    }
  }
}

void TemplateRules::Muscle(const View& m, std::vector<TemplateMuscle>* out,
                           std::vector<std::string>* origins) {
  const size_t before = diag_->ErrorCount();
  TemplateMuscle t;
  m.Read("name", &t.name);
  std::string copy_name;
  const bool mirror = Mirror(m, t.name, "muscle", &copy_name);
  m.Read("strength", &t.strength);
  if (size_t choice = 0; m.Choice("falloff", &choice)) t.falloff = static_cast<MuscleFalloff>(choice);
  if (size_t choice = 0; m.Choice("motion", &choice)) {
    t.motion = static_cast<MuscleMotion>(choice);
    t.motion_given = true;
  }
  m.Read("tangent_radius", &t.tangent_radius);
  if (m.variant() == "linear") {
    t.type = MuscleType::kLinear;
    Point(m.Member("attachment"), &t.attachment[0]);
    Point(m.Member("insertion"), &t.insertion[0]);
    m.Read("zone_angle_deg", &t.zone_angle_deg);
    if (m.Read("falloff_start", &t.falloff_start) & m.Read("falloff_end", &t.falloff_end) &&
        !(t.falloff_end > t.falloff_start))
      r_.Error(m.Path("falloff_end"), "expected a number > falloff_start (" +
                                          FormatFloat(t.falloff_start) + "), got " +
                                          FormatFloat(t.falloff_end));
  } else if (m.variant() == "sheet") {
    t.type = MuscleType::kSheet;
    for (size_t k = 0; k < 2; ++k) {
      Point(m.Element("attachment", k), &t.attachment[k]);
      Point(m.Element("insertion", k), &t.insertion[k]);
    }
    m.Read("width", &t.width);
    const bool have_length = m.Read("length", &t.length);
    m.Read("falloff_start", &t.falloff_start);
    m.CheckBound("falloff_start", "length", have_length ? &t.length : nullptr);
  } else {
    return;
  }
  if (m.Has("wrinkles")) {
    MuscleWrinkleSpec spec;
    if (ReadMuscleWrinkles(m.Member("wrinkles"), m, t.type == MuscleType::kLinear, &spec))
      t.wrinkles = spec;
  }
  if (!m.ok() || diag_->ErrorCount() != before) return;
  out->push_back(t);
  origins->push_back(m.path());
  if (!mirror) return;
  TemplateMuscle c = t;
  c.name = copy_name;
  c.mirrored_copy = true;
  for (TemplatePoint* p : {&c.attachment[0], &c.attachment[1], &c.insertion[0], &c.insertion[1]}) {
    for (int& l : p->landmarks) l = IbugMirrorLandmark(l);
    p->offset.x = -p->offset.x;
  }
  // Mirroring reverses the sheet lines' end order; keep each line's ends as given.
  out->push_back(c);
  origins->push_back(m.path() + " (mirrored as " + c.name + ")");
}

void TemplateRules::Curve(const View& c, std::vector<TemplateCurveWrinkle>* out,
                          std::vector<std::string>* origins) {
  const size_t before = diag_->ErrorCount();
  TemplateCurveWrinkle t;
  c.Read("name", &t.name);
  std::string copy_name;
  const bool mirror = Mirror(c, t.name, "curve wrinkle", &copy_name);
  for (size_t k = 0; k < 4; ++k) Point(c.Element("control", k), &t.control[k]);
  c.Read("depth", &t.depth);
  c.Read("width", &t.width);
  size_t choice = 0;
  if (c.Choice("profile", &choice)) t.profile = static_cast<CurveWrinkleProfile>(choice);
  if (c.Choice("modulation", &choice)) t.modulation = static_cast<CurveWrinkleModulation>(choice);
  c.Read("rest_amplitude", &t.rest_amplitude);
  if (!c.ok() || diag_->ErrorCount() != before) return;
  out->push_back(t);
  origins->push_back(c.path());
  if (!mirror) return;
  TemplateCurveWrinkle m = t;
  m.name = copy_name;
  m.mirrored_copy = true;
  for (TemplatePoint& p : m.control) {
    for (int& l : p.landmarks) l = IbugMirrorLandmark(l);
    p.offset.x = -p.offset.x;
  }
  out->push_back(m);
  origins->push_back(c.path() + " (mirrored as " + m.name + ")");
}

}  // namespace

const json_reader::Format& TemplateFileFormat() { return kTemplateFormat; }

bool ParseMuscleTemplate(std::string_view json_text, MuscleTemplate* out, Diagnostics* diag) {
  Diagnostics local;
  if (!diag) diag = &local;
  return NoThrow(diag, "internal error while reading the template", [&] {
    Reader reader(kTemplateFormat, diag);
    if (!reader.Parse(json_text)) return false;
    const View top = reader.Check();
    if (reader.stopped()) return false;
    MuscleTemplate result;
    if (top.present() && top.value()->is_object()) TemplateRules(&reader, diag).Root(top, &result);
    if (reader.failed() || !out) return false;
    result.file = out->file;
    *out = std::move(result);
    return true;
  });
}

bool LoadMuscleTemplate(const std::string& path, MuscleTemplate* out, Diagnostics* diag) {
  MuscleTemplate t;
  const bool ok = ParseFile(path, diag, [&](const std::string& text, Diagnostics* local) {
    return ParseMuscleTemplate(text, &t, local);
  });
  if (!ok || !out) return false;
  t.file = path;
  *out = std::move(t);
  return true;
}

}  // namespace mimetic

// ---------------------------------------------------------------------------------------------
// Writing (calibrated templates, `mimetic calibrate`).

namespace mimetic {
namespace {

using ordered_json = nlohmann::ordered_json;

ordered_json PointJson(const TemplatePoint& p, bool with_depth) {
  ordered_json j;
  j["landmarks"] = p.landmarks;
  bool equal = true;
  for (float w : p.weights) equal &= std::fabs(w - p.weights[0]) < 1e-6f;
  if (!equal) {
    ordered_json w = ordered_json::array();
    for (float x : p.weights) w.push_back(TemplateDigits(x));
    j["weights"] = w;
  }
  if (p.offset.x != 0.f || p.offset.y != 0.f)
    j["offset"] = ordered_json::array({TemplateDigits(p.offset.x), TemplateDigits(p.offset.y)});
  if (with_depth) j["depth"] = TemplateDigits(p.depth);
  return j;
}

// Objects and arrays that fit in `width` columns go on one line; the rest one member a line.
void Pretty(const ordered_json& j, int indent, std::string* out) {
  const std::string flat = j.dump(-1, ' ', false, ordered_json::error_handler_t::replace);
  if ((!j.is_object() && !j.is_array()) || j.empty() || flat.size() + size_t(indent) <= 100) {
    // nlohmann's compact form has no spaces after ':' and ','; add them for reading.
    std::string spaced;
    bool in_string = false;
    for (size_t i = 0; i < flat.size(); ++i) {
      const char c = flat[i];
      spaced += c;
      if (c == '"' && (i == 0 || flat[i - 1] != '\\')) in_string = !in_string;
      if (!in_string && (c == ':' || c == ',')) spaced += ' ';
    }
    *out += spaced;
    return;
  }
  const std::string pad(size_t(indent + 2), ' ');
  *out += j.is_object() ? "{\n" : "[\n";
  size_t k = 0;
  for (auto it = j.begin(); it != j.end(); ++it, ++k) {
    *out += pad;
    if (j.is_object()) *out += ordered_json(it.key()).dump() + ": ";
    Pretty(*it, indent + 2, out);
    *out += k + 1 < j.size() ? ",\n" : "\n";
  }
  *out += std::string(size_t(indent), ' ') + (j.is_object() ? "}" : "]");
}

}  // namespace

std::string MuscleTemplateToJson(const MuscleTemplate& t) {
  ordered_json j;
  j["format"] = kFormatName;
  j["version"] = 1;
  if (!t.description.empty()) j["description"] = t.description;
  ordered_json th;
  th["base"] = TemplateDigits(t.thickness.base);
  th["front"] = ordered_json::array({TemplateDigits(t.thickness.front[0]), TemplateDigits(t.thickness.front[1])});
  ordered_json regions = ordered_json::array();
  for (size_t i = 0; i < t.thickness.regions.size(); ++i) {
    const ThicknessRegion& r = t.thickness.regions[i];
    if (r.mirrored_copy) continue;
    ordered_json e;
    if (!r.name.empty()) e["name"] = r.name;
    e["center"] = ordered_json::array({TemplateDigits(r.center.x), TemplateDigits(r.center.y)});
    e["radius"] = ordered_json::array({TemplateDigits(r.radius.x), TemplateDigits(r.radius.y)});
    e["value"] = TemplateDigits(r.value);
    if (i + 1 < t.thickness.regions.size() && t.thickness.regions[i + 1].mirrored_copy)
      e["mirror"] = true;
    regions.push_back(e);
  }
  if (!regions.empty()) th["regions"] = regions;
  j["thickness"] = th;
  ordered_json tension = ordered_json::array();
  for (size_t i = 0; i < t.tension_regions.size(); ++i) {
    const TemplateTensionRegion& g = t.tension_regions[i];
    if (g.mirrored_copy) continue;
    ordered_json e;
    e["name"] = g.name;
    e["center"] = ordered_json::array({TemplateDigits(g.center.x), TemplateDigits(g.center.y)});
    e["radius"] = ordered_json::array({TemplateDigits(g.radius.x), TemplateDigits(g.radius.y)});
    if (!(g.reference == kDefaultTensionReference)) e["reference"] = TemplateDigits(g.reference);
    if (i + 1 < t.tension_regions.size() && t.tension_regions[i + 1].mirrored_copy)
      e["mirror"] = true;
    tension.push_back(e);
  }
  ordered_json muscles = ordered_json::array();
  for (size_t i = 0; i < t.muscles.size(); ++i) {
    const TemplateMuscle& m = t.muscles[i];
    if (m.mirrored_copy) continue;
    const bool linear = m.type == MuscleType::kLinear;
    ordered_json e;
    e["name"] = m.name;
    e["type"] = MuscleTypeName(m.type);
    if (i + 1 < t.muscles.size() && t.muscles[i + 1].mirrored_copy) e["mirror"] = true;
    e["strength"] = TemplateDigits(m.strength);
    if (m.falloff != MuscleFalloff::kWaters) e["falloff"] = MuscleFalloffName(m.falloff);
    if (m.motion_given || m.motion != MuscleMotion::kChord)
      e["motion"] = MuscleMotionName(m.motion);
    if (m.tangent_radius != 0.f) e["tangent_radius"] = TemplateDigits(m.tangent_radius);
    if (linear) {
      e["attachment"] = PointJson(m.attachment[0], true);
      e["insertion"] = PointJson(m.insertion[0], true);
      e["zone_angle_deg"] = TemplateDigits(m.zone_angle_deg);
      e["falloff_start"] = TemplateDigits(m.falloff_start);
      e["falloff_end"] = TemplateDigits(m.falloff_end);
    } else {
      e["attachment"] = ordered_json::array({PointJson(m.attachment[0], true), PointJson(m.attachment[1], true)});
      e["insertion"] = ordered_json::array({PointJson(m.insertion[0], true), PointJson(m.insertion[1], true)});
      e["length"] = TemplateDigits(m.length);
      e["width"] = TemplateDigits(m.width);
      e["falloff_start"] = TemplateDigits(m.falloff_start);
    }
    if (m.wrinkles) {
      const MuscleWrinkleSpec& w = *m.wrinkles;
      ordered_json wj;
      wj["lambda_w"] = TemplateDigits(w.lambda_w);
      wj["count"] = w.count;
      wj["depth"] = TemplateDigits(w.depth);
      wj["shape"] = TemplateDigits(w.shape);
      if (linear && w.phi_c != 0.f) wj["phi_c_deg"] = TemplateDigits(w.phi_c * 180.0 / 3.14159265358979323846);
      if (!linear && w.h_c != 0.f) wj["h_c"] = TemplateDigits(w.h_c);
      if (w.gate != 0.f) wj["gate"] = TemplateDigits(w.gate);
      e["wrinkles"] = wj;
    }
    muscles.push_back(e);
  }
  j["muscles"] = muscles;
  ordered_json curves = ordered_json::array();
  for (size_t i = 0; i < t.curve_wrinkles.size(); ++i) {
    const TemplateCurveWrinkle& c = t.curve_wrinkles[i];
    if (c.mirrored_copy) continue;
    ordered_json e;
    e["name"] = c.name;
    if (i + 1 < t.curve_wrinkles.size() && t.curve_wrinkles[i + 1].mirrored_copy) e["mirror"] = true;
    ordered_json control = ordered_json::array();
    for (const TemplatePoint& p : c.control) control.push_back(PointJson(p, false));
    e["control"] = control;
    e["depth"] = TemplateDigits(c.depth);
    e["width"] = TemplateDigits(c.width);
    e["profile"] = CurveWrinkleProfileName(c.profile);
    e["modulation"] = CurveWrinkleModulationName(c.modulation);
    e["rest_amplitude"] = TemplateDigits(c.rest_amplitude);
    curves.push_back(e);
  }
  if (!curves.empty()) j["curve_wrinkles"] = curves;
  if (t.jaw) {
    const TemplateJaw& jw = *t.jaw;
    ordered_json c;
    c["landmarks"] = jw.landmarks;
    ordered_json w = ordered_json::array();
    for (float v : jw.weights) w.push_back(TemplateDigits(v));
    c["weights"] = w;
    c["offset"] = ordered_json::array({TemplateDigits(jw.offset.x), TemplateDigits(jw.offset.y), TemplateDigits(jw.offset.z)});
    ordered_json e;
    e["condyle"] = c;
    e["range_deg"] = TemplateDigits(jw.range_deg);
    e["translation"] = ordered_json::array({TemplateDigits(jw.translation.x), TemplateDigits(jw.translation.y),
                                            TemplateDigits(jw.translation.z)});
    e["lip_blend_deg"] = TemplateDigits(jw.lip_blend_deg);
    e["cheek_blend_deg"] = TemplateDigits(jw.cheek_blend_deg);
    e["cheek_drop_deg"] = TemplateDigits(jw.cheek_drop_deg);
    e["corner_fade"] = TemplateDigits(jw.corner_fade);
    e["thickness_fade"] = TemplateDigits(jw.thickness_fade);
    e["back"] = ordered_json::array({TemplateDigits(jw.back[0]), TemplateDigits(jw.back[1])});
    e["neck_deg"] = ordered_json::array({TemplateDigits(jw.neck_deg[0]), TemplateDigits(jw.neck_deg[1])});
    j["jaw"] = e;
  }
  if (!tension.empty()) j["tension_regions"] = tension;
  if (t.fine_scale) {
    ordered_json fields = ordered_json::array();
    for (int i = 0; i < 2; ++i) {  // (mirrored copies are not written: `mirror` makes them)
      const std::vector<TemplateDirectionAnchor>& v = t.fine_scale->fields[i];
      ordered_json vectors = ordered_json::array();
      for (size_t k = 0; k < v.size(); ++k) {
        if (v[k].mirrored_copy) continue;
        ordered_json e;
        e["name"] = v[k].name;
        e["at"] = ordered_json::array({TemplateDigits(v[k].at.x), TemplateDigits(v[k].at.y)});
        e["direction"] = ordered_json::array(
            {TemplateDigits(v[k].direction.x), TemplateDigits(v[k].direction.y), TemplateDigits(v[k].direction.z)});
        e["magnitude"] = TemplateDigits(v[k].magnitude);
        if (k + 1 < v.size() && v[k + 1].mirrored_copy) e["mirror"] = true;
        vectors.push_back(e);
      }
      ordered_json f;
      f["name"] = t.fine_scale->field_names[i];
      f["vectors"] = vectors;
      fields.push_back(f);
    }
    ordered_json fs;
    fs["fields"] = fields;
    if (!(t.fine_scale->rest_amplitude == 0.5f)) fs["rest_amplitude"] = TemplateDigits(t.fine_scale->rest_amplitude);
    j["fine_scale"] = fs;
  }
  if (!(t.falloff_error == 0.f)) {
    ordered_json r;
    r["falloff_error"] = TemplateDigits(t.falloff_error);
    j["refinement"] = r;
  }
  std::string out;
  Pretty(j, 0, &out);
  return out + "\n";
}

bool SaveMuscleTemplate(const std::string& path, const MuscleTemplate& t, Diagnostics* diag) {
  return WriteFileAtomic(path, MuscleTemplateToJson(t), diag);
}

}  // namespace mimetic

// io/rig_file.cpp: the rig file (docs/rig-format.md, version 1): parse, validate, save.
//
// The file holds what docs/model.md §2 (linear muscles), §3 (sheet muscles), §4 (skin thickness),
// §6 (muscle-derived wrinkles), §7-8 (curve wrinkles) and §11 (refinement) need. Angles are
// degrees in the file and radians in the spec structs. The fields are declared once in the
// tables below (io/json_reader.h checks them and generates assets/schema/mimetic-rig.schema.json
// from them); the rules between fields follow the tables. Every problem in the file is recorded
// in `Diagnostics` with its JSON path and what was expected; nothing throws out of this file.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <map>
#include <numbers>
#include <string>
#include <system_error>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/file_util.h"
#include "io/formats.h"
#include "io/jaw_fields.h"
#include "io/json_reader.h"
#include "io/rig_file.h"

namespace mimetic {
namespace {

using json = nlohmann::json;
using ordered_json = nlohmann::ordered_json;
using namespace json_reader;

constexpr const char* kFormatName = "mimetic-rig";
constexpr int kFormatVersion = 1;

// In MuscleFalloff's order.
const std::vector<std::string> kFalloffs = {"waters", "smooth"};
// In MuscleMotion's order.
const std::vector<std::string> kMotions = {"chord", "tangent"};
const std::vector<std::string> kProfiles = {
    CurveWrinkleProfileName(CurveWrinkleProfile::kBando),
    CurveWrinkleProfileName(CurveWrinkleProfile::kYangZhang),
    CurveWrinkleProfileName(CurveWrinkleProfile::kYangZhangExact)};
const std::vector<std::string> kModulations = {
    CurveWrinkleModulationName(CurveWrinkleModulation::kDirectional),
    CurveWrinkleModulationName(CurveWrinkleModulation::kArea)};

// ---------------------------------------------------------------------------------------------
// The tables.

// geometry/fingerprint.h: what ties per-vertex and texture-space data to the mesh.
const Object kFingerprint = {
    .owner = "mesh.fingerprint",
    .fields = {
        Integer("vertices", "an integer >= 1").Min(1).Required().About("the mesh's vertex count"),
        Integer("triangles", "an integer >= 0").Min(0).Required()
            .About("the mesh's triangle count"),
        String("index_hash", "a string of 16 lowercase hex digits (FNV-1a 64 of the indices)")
            .NonEmpty().Required(),
        Array("positions", Numbers("", 3), "array of up to 16 points [x, y, z]")
            .NonEmpty().Required()
            .About("positions of the sampled vertices floor(k (vertices - 1) / (n - 1))"),
        Array("uvs", Numbers("", 2, "array of 2 numbers [u, v]"),
              "array of [u, v], one per position")
            .About("texture coordinates of the sampled vertices; absent when the mesh has none")},
    .description = "The mesh the per-vertex and texture-space data were made for "
                   "(geometry/fingerprint.h); written by mimetic fit."};

const Object kMesh = {"mesh", {
    String("path", "non-empty string (.obj, .gltf or .glb file, relative to the rig file's "
                   "directory)").NonEmpty().Required(),
    String("name", "string (glTF mesh name)").About("glTF mesh name; absent = the first mesh"),
    ObjectOf("fingerprint", kFingerprint, "object {\"vertices\": ..., \"triangles\": ..., "
             "\"index_hash\": ..., \"positions\": [...], \"uvs\": [...]}")
        .About("the mesh the per-vertex and texture-space data were made for")}};

// docs/model.md §4: skin thickness h, mesh units; absent = constant 0.
const Object kConstantThickness = {"constant thickness", {
    Number("value").Min(0).Required().About("mesh units")}};
const Object kPerVertexThickness = {"per-vertex thickness", {
    Array("values", Number("").Min(0), "array of numbers >= 0, one per vertex of the mesh file")
        .Required().About("one value per vertex of the mesh file, in file order")}};
const Object kImageThickness = {"image thickness", {
    String("path", "non-empty string (grayscale image, relative to the rig file)")
        .NonEmpty().Required(),
    Number("min").Min(0).Required().About("thickness at black"),
    Number("max").Min(0).Required().About("thickness at white")}};
const Object kThickness = {
    .owner = "thickness",
    .fields = {Enum("type", {"constant", "per_vertex", "image"}).Required()},
    .variant_key = "type",
    .variants = {{"constant", &kConstantThickness},
                 {"per_vertex", &kPerVertexThickness},
                 {"image", &kImageThickness}},
    .description = "Subcutaneous skin thickness h in mesh units (docs/model.md §4). Absent = "
                   "constant 0; min <= max (reader check)."};

const Object kLinearWrinkles = MuscleWrinkleBlock(true, "mesh units");
const Object kSheetWrinkles = MuscleWrinkleBlock(false, "mesh units");

// docs/model.md §2: v1 (attachment), v2 (insertion), Omega, Rs, Rf.
const Object kLinearMuscle = {
    .owner = "a linear muscle",
    .fields = {
        Numbers("attachment", 3).Required().About("bone end, v1"),
        Numbers("insertion", 3).Required().About("skin end, v2"),
        Number("zone_angle_deg", "a number in (0, 180) (degrees)").Above(0).Below(180).Required(),
        Number("falloff_start").Above(0).Required().About("Rs, mesh units"),
        Number("falloff_end", "a finite number > falloff_start").Above(0).Required()
            .About("Rf, mesh units"),
        ObjectOf("wrinkles", kLinearWrinkles, "object {\"lambda_w\": ..., \"count\": ..., "
                 "\"depth\": ..., \"shape\": ..., \"phi_c_deg\": ...}")},
    .description = "Waters linear muscle (docs/model.md §2)."};

// docs/model.md §3: attachment line mA1 mA2, insertion line mI1 mI2, Ls, Ws, Rs.
Field Line(const char* key, const char* about) {
  return Array(key, Numbers("", 3), "array of 2 points (each an array of 3 numbers)")
      .Count(2).Required().About(about);
}
const Object kSheetMuscle = {
    .owner = "a sheet muscle",
    .fields = {
        Line("attachment", "the attachment line"), Line("insertion", "the insertion line"),
        Number("length").Above(0).Required().About("Ls, mesh units"),
        Number("width").Above(0).Required().About("Ws, mesh units"),
        Number("falloff_start", "a number in (0, length)").Above(0).Required()
            .About("Rs, mesh units"),
        ObjectOf("wrinkles", kSheetWrinkles, "object {\"lambda_w\": ..., \"count\": ..., "
                 "\"depth\": ..., \"shape\": ..., \"h_c\": ...}")},
    .description = "Waters sheet muscle (docs/model.md §3)."};

const Object kMuscle = {
    .owner = "a muscle",
    .fields = {
        String("name").NonEmpty().Required(),
        Enum("type", {"linear", "sheet"}, "\"linear\" or \"sheet\"").Required()
            .UnknownChoice("unknown muscle type {}; supported types: \"linear\", \"sheet\" "
                           "(sphincter muscles are not supported)"),
        Number("strength").Min(0).Required()
            .About("contraction at activation 1, mesh units"),
        Enum("falloff", kFalloffs, "\"waters\" or \"smooth\"")
            .About("how the influence reaches 0 at the zone's edges (docs/model.md §2-3); "
                   "default \"waters\""),
        Enum("motion", kMotions, "\"chord\" or \"tangent\"")
            .About("\"chord\": toward the attachment (Waters); \"tangent\": that motion "
                   "along the rest surface only (docs/model.md §2-3); default \"chord\""),
        Number("tangent_radius").Min(0)
            .About("mesh units; \"tangent\" only: the rest normals are averaged over a ball "
                   "this wide before the projection (docs/model.md §2-3); default 0, each "
                   "point's own normal")},
    .variant_key = "type",
    .variants = {{"linear", &kLinearMuscle}, {"sheet", &kSheetMuscle}},
    .description = "A muscle; names unique within the rig (reader check)."};

// docs/model.md §7-8.
const Object kCurveWrinkle = {
    .owner = "a curve wrinkle",
    .fields = {
        String("name").NonEmpty().Required(),
        Array("control", Numbers("", 2, "array of 2 numbers [u, v]"),
              "array of 4 points (cubic Bezier control points, each [u, v] in texture space)")
            .Count(4).Required(),
        Number("depth").Above(0).Required().About("mesh units"),
        Number("width").Above(0).Required().About("mesh units"),
        Enum("profile", kProfiles),
        Enum("modulation", kModulations),
        Number("rest_amplitude").Min(0).Max(1)},
    .description = "A curve wrinkle (docs/model.md §7-8); names unique (reader check)."};

// docs/model.md §1 steps 3-4; absent keys = true.
const Object kLayers = {"layers", {
    Bool("thickness").About("volume-preserving thickness (docs/model.md §4)"),
    Bool("muscle_wrinkles").About("muscle-derived wrinkles (docs/model.md §6)"),
    Bool("curve_wrinkles").About("curve wrinkles (docs/model.md §7-8)")}};

// docs/model.md §11.
const Object kRefinement = {"refinement", {
    Bool("enabled"),
    Number("edge_fraction", "a number in (0, 1] (fraction of the wrinkle width)").Above(0).Max(1),
    Number("falloff_error", "a number in [0, 1) (0 = off)").Min(0).Below(1)
        .About("largest error of a muscle's fall-off interpolated over one edge, as a fraction "
               "of its peak; 0 = off")}};

// docs/model.md §18: the jaw's hinge, range and weights.
const Object kJaw = {
    .owner = "jaw",
    .fields = {
        Array("condyles", Numbers("", 3),
              "array of 2 points (the subject's right, then left condyle, each [x, y, z])")
            .Count(2).Required()
            .About("the hinge axis runs through them; mesh units; the jaw opens by a positive "
                   "rotation about right -> left"),
        Number("range_deg", "a number in (0, 90] (degrees)").Above(0).Max(90).Required()
            .About("opening angle at jaw = 1"),
        Numbers("translation", 3, "array of 3 numbers [x, y, z] (mesh units)")
            .About("the condyles' glide at jaw = 1 (forward and down), added with the weight "
                   "after the turn; default [0, 0, 0]"),
        Numbers("mouth", 3, "array of 3 numbers [x, y, z] (between the lips on the midline)")
            .About("the lip line's point on the midline; required unless `weights` is given"),
        Number("mouth_width", "a number > 0 (mouth corner to corner, mesh units)").Above(0)
            .About("mouth corner to corner; required unless `weights` is given"),
        Number("lip_blend_deg", "a number in (0, 45] (degrees)").Above(0).Max(45)
            .About("blend half-width about the lip line between the mouth corners; default 2"),
        Number("cheek_blend_deg", "a number in (0, 90] (degrees)").Above(0).Max(90)
            .About("blend half-width a mouth width beyond the corners; default 12"),
        Number("cheek_drop_deg", "a number in [0, 45] (degrees)").Min(0).Max(45)
            .About("how far the blend's centre drops beyond the corners; default 0"),
        Number("corner_fade", "a number in [0, 0.5] (a fraction of the mouth width)").Min(0).Max(0.5)
            .About("where the lips' side term fades out before each mouth corner; default 0.2"),
        Number("thickness_fade", "a number in [0, 1] (a fraction of the mouth width)").Min(0).Max(1)
            .About("distance from the edge of a slit between the lips over which the skin's "
                   "thickness fades in (the lips carry no fat); 0 = off; default 0.3"),
        Numbers("back", 2, "array of 2 numbers [b0, b1] in [-1, 1], b0 < b1 (fractions of the "
                           "hinge-to-mouth distance)")
            .About("forward distance from the hinge where the weight fades in; default [0.2, 0.6]"),
        Numbers("neck_deg", 2, "array of 2 numbers [n0, n1] in [0, 180], n0 < n1 (degrees below "
                               "the lip line)")
            .About("angles about the hinge below the lip line where the weight fades out toward "
                   "the neck (1 above -n0, 0 below -n1); default [90, 180]"),
        Array("weights", Number("").Min(0).Max(1),
              "array of numbers in [0, 1], one per vertex of the mesh file")
            .About("explicit per-vertex jaw weights (file order); replace the region function")},
    .description = "The jaw (docs/model.md §18): a hinge through the condyles, an opening range "
                   "and a per-vertex weight, explicit or from the region parameters."};

// docs/model.md §24: the eyeballs the lids slide on.
const Object kEyeSphere = {
    .owner = "an eyeball",
    .fields = {
        Numbers("center", 3, "array of 3 numbers [x, y, z] (mesh units)").Required(),
        Number("radius", "a number > 0 (mesh units)").Above(0).Required()},
    .description = "An eyeball: a sphere (docs/model.md §24)."};
const Object kEyes = {
    .owner = "eyes",
    .fields = {
        Array("spheres", ObjectOf("", kEyeSphere, "object {\"center\": [...], \"radius\": ...}"),
              "array of eyeballs").NonEmpty().Required(),
        Numbers("band", 2, "array of 2 numbers [b0, b1], 0 <= b0 < b1 (mesh units from an "
                           "eyeball's surface)")
            .Required()
            .About("skin a muscle or the jaw moves slides on the nearest eyeball with weight 1 "
                   "within b0 of its surface, fading to 0 at b1")},
    .description = "The eyeballs the lids slide on (docs/model.md §24): moved skin near one "
                   "keeps its rest distance from the eyeball's centre."};

// docs/tension.md: a named per-vertex mask; EvaluateJob reports its weight per frame.
const Object kTensionRegion = {
    .owner = "a tension region",
    .fields = {
        String("name").NonEmpty().Required(),
        Number("reference", "a number > 0 (a mean area compression, 1 - r)").Above(0)
            .About("c0 of the region's weight 1 - exp(-C / c0) (docs/model.md §19); default 0.1"),
        Array("weights", Number("").Min(0).Max(1),
              "array of numbers in [0, 1], one per vertex of the mesh file (or of vertices)")
            .Required().About("the region's mask: one weight per vertex of the mesh file, in file "
                              "order; or, with vertices, one per listed vertex"),
        Array("vertices", Integer("").Min(0), "array of vertex indices, ascending")
            .About("the sparse form: the vertices (file order indices, ascending) that weights "
                   "lists, every other vertex at 0; the writer uses it when it is shorter")},
    .description = "A tension region (docs/tension.md); names unique among the regions (reader "
                   "check)."};

// docs/model.md §20-23: fine-scale wrinkle textures.
const Object kDirectionVector = {
    .owner = "a direction vector",
    .fields = {
        Integer("vertex", "an integer >= 0 (a vertex of the mesh file)").Min(0).Required(),
        Numbers("vector", 3, "array of 3 numbers [x, y, z] (mesh axes; length = magnitude)")
            .Required()
            .About("direction (projected onto the vertex's tangent plane) and magnitude (its "
                   "length: (0, 1] for bando2002, (0, 2] for bando2001)"),
        Number("weight", "a number > 0").Above(0)
            .About("lambda of 003 eq. 3.1 (inverse_distance only); default 1")},
    .description = "A user direction vector at a vertex (docs/model.md §20)."};
const Object kDirectionField = {
    .owner = "a direction field",
    .fields = {
        String("name").NonEmpty().Required(),
        Array("vectors", ObjectOf("", kDirectionVector, "object {\"vertex\": ..., \"vector\": [...]}"),
              "array of direction vectors").NonEmpty().Required()},
    .description = "One of the two direction fields (docs/model.md §20)."};
const Object kFineScaleMaps = {
    .owner = "fine_scale.maps",
    .fields = {
        Array("height", String("", "non-empty string (16-bit PNG, relative to the rig file)").NonEmpty(),
              "array of 2 paths (one height map per field)").Count(2),
        String("normal", "non-empty string (8-bit PNG, relative to the rig file)").NonEmpty()},
    .description = "The maps `mimetic texture` wrote (docs/model.md §22)."};
const Object kFineScale = {
    .owner = "fine_scale",
    .fields = {
        Array("fields", ObjectOf("", kDirectionField, "object (a direction field)"),
              "array of 2 direction fields").Count(2).Required(),
        Enum("interpolation", {"harmonic", "inverse_distance"})
            .About("000 §5.1 spring energy or 003 eq. 3.1; default \"harmonic\""),
        Enum("texture_space", {"auto", "uv", "planar", "cylindrical"})
            .About("the mesh's uvs or a projection (003 §3.2); default \"auto\" (uvs when the "
                   "mesh has them, else cylindrical)"),
        Bool("minimize_distortion").About("000 §4 harmonic smoothing of a projection; default false"),
        Enum("parameters", {"bando2002", "bando2001"})
            .About("000 eq. 1 or 003 eq. 5.1-5.6; default \"bando2002\""),
        Number("k_scale", "a number in (0, 16]").Above(0).Max(16)
            .About("003 length scale (bando2001 only); default 1"),
        Number("k_noise", "a number in [0, 1]").Min(0).Max(1).About("003 step 9; default 0"),
        Number("k_bump", "a number in [0, 64]").Min(0).Max(64).About("003 §4.1; default 1"),
        Number("rest_amplitude", "a number in [0, 1]").Min(0).Max(1)
            .About("r of M(s) (000 eq. 5) at rest; default 0.5"),
        ObjectOf("maps", kFineScaleMaps, "object {\"height\": [...], \"normal\": ...}")},
    .description = "Fine-scale wrinkle textures along two direction fields (docs/model.md "
                   "§20-23); vertices in range, vectors non-zero (reader check)."};
const std::string kReserved =
    "(reserved for a later version of the format; this build reads version 1)";
const Object kRig = {
    .owner = "",
    .fields = {
        Enum("format", {kFormatName}).Required(),
        Integer("version", "integer 1").Version(kFormatVersion).Required(),
        ObjectOf("mesh", kMesh, "object {\"path\": ..., \"name\": ...}").Required(),
        Enum("units", {"mm", "cm", "dm", "m", "in"}).Required()
            .About("unit of the mesh coordinates; every length in the file is in these units"),
        ObjectOf("thickness", kThickness,
                 "object {\"type\": \"constant\" | \"per_vertex\" | \"image\", ...}"),
        Array("muscles", ObjectOf("", kMuscle, "object (a muscle)"), "array of muscles")
            .Required().About("may be empty"),
        Array("curve_wrinkles", ObjectOf("", kCurveWrinkle, "object (a curve wrinkle)"),
              "array of curve wrinkles"),
        ObjectOf("layers", kLayers, "object {\"thickness\": true, \"muscle_wrinkles\": true, "
                                    "\"curve_wrinkles\": true}"),
        ObjectOf("refinement", kRefinement,
                 "object {\"enabled\": true, \"edge_fraction\": 0.25}"),
        ObjectOf("jaw", kJaw, "object {\"condyles\": [...], \"range_deg\": ..., ...}")
            .About("the jaw (docs/model.md §18); absent = none"),
        ObjectOf("eyes", kEyes, "object {\"spheres\": [...], \"band\": [b0, b1]}")
            .About("the eyeballs the lids slide on (docs/model.md §24); absent = none"),
        Array("tension_regions", ObjectOf("", kTensionRegion, "object (a tension region)"),
              "array of tension regions")
            .About("named masks whose per-frame weight engines blend wrinkle maps with "
                   "(docs/tension.md); absent = none"),
        ObjectOf("fine_scale", kFineScale, "object {\"fields\": [...], ...}")
            .About("fine-scale wrinkle textures (docs/model.md §20-23); absent = none")},
    .notes = {{"expressions", kReserved},
              {"wrinkles", "(muscle-derived wrinkles go inside each muscle: muscles[i].wrinkles)"}},
    .description = "A mimetic rig: mesh, units, skin thickness, Waters muscles with their "
                   "optional wrinkles, curve wrinkles, layer switches and refinement "
                   "(docs/rig-format.md). Rules between fields are checked by the reader only."};

const Format kRigFormat = {
    .name = kFormatName,
    .root = ObjectOf("", kRig, "the top-level value to be an object {\"format\": \"mimetic-rig\", "
                               "...}"),
    .title = "mimetic rig file, version 1"};

// ---------------------------------------------------------------------------------------------
// The rules between fields, on the checked document.

// Degrees in the file -> radians in the spec (zone angles and phi_c).
float DegreesToRadians(double deg) { return static_cast<float>(deg * std::numbers::pi / 180.0); }

class RigRules {
 public:
  RigRules(Reader* reader, const std::string& base_dir, Diagnostics* diag)
      : r_(*reader), base_dir_(base_dir), diag_(diag) {}

  void Root(const View& top, RigSpec* spec);

 private:
  // Reports `what` at `path`; returns false.
  bool Fail(const std::string& path, const std::string& what) {
    r_.Error(path, what);
    return false;
  }
  void Thickness(const View& t, ThicknessSpec* out);
  void Jaw(const View& j, RigSpec* spec);
  void Eyes(const View& e, RigSpec* spec);
  void FineScale(const View& f, RigSpec* spec);
  void Fingerprint(const View& f, MeshFingerprint* out);
  bool Muscle(const View& m, MuscleSpec* out, std::optional<MuscleWrinkleSpec>* wrinkles);
  bool Linear(const View& m, LinearMuscleSpec* out);
  bool Sheet(const View& m, SheetMuscleSpec* out);
  bool Wrinkles(const View& w, const View& m, const MuscleSpec& muscle, bool muscle_ok,
                MuscleWrinkleSpec* out);
  bool Curve(const View& c, NamedCurveWrinkle* out);

  Reader& r_;
  const std::string& base_dir_;
  Diagnostics* diag_;
};

// `name` unique among the names seen so far (`seen`: name -> index of its first use).
bool UniqueName(Reader& r, const std::string& name, const std::string& list, size_t i,
                const std::string& kind, const std::string& among,
                std::map<std::string, size_t>* seen) {
  if (name.empty()) return true;
  const auto [it, inserted] = seen->emplace(name, i);
  if (inserted) return true;
  r.Error(Key(Index(list, i), "name"), "duplicate " + kind + " name " + Quoted(name) +
                                           " (first used by " + Index(list, it->second) +
                                           "); expected a name unique " + among);
  return false;
}

void RigRules::Root(const View& top, RigSpec* spec) {
  const View mesh = top.Member("mesh");
  std::string s;
  if (mesh.Read("path", &s)) spec->mesh_path = JoinPath(base_dir_, s);
  mesh.Read("name", &spec->mesh_name);
  if (mesh.Has("fingerprint")) Fingerprint(mesh.Member("fingerprint"), &spec->mesh_fingerprint);
  top.Read("units", &spec->units);
  if (top.Has("thickness")) Thickness(top.Member("thickness"), &spec->thickness);

  std::map<std::string, size_t> muscle_names;
  for (size_t i = 0; i < top.Size("muscles"); ++i) {
    const View m = top.Element("muscles", i);
    MuscleSpec muscle;
    std::optional<MuscleWrinkleSpec> wrinkles;
    const bool ok = Muscle(m, &muscle, &wrinkles);
    UniqueName(r_, muscle.name, "muscles", i, "muscle", "within the rig", &muscle_names);
    if (ok) {
      spec->muscles.push_back(std::move(muscle));
      spec->muscle_wrinkles.push_back(wrinkles);
    }
  }
  std::map<std::string, size_t> curve_names;
  for (size_t i = 0; i < top.Size("curve_wrinkles"); ++i) {
    NamedCurveWrinkle curve;
    const bool ok = Curve(top.Element("curve_wrinkles", i), &curve);
    UniqueName(r_, curve.name, "curve_wrinkles", i, "curve wrinkle", "among the curve wrinkles",
               &curve_names);
    if (ok) spec->curve_wrinkles.push_back(std::move(curve));
  }
  const View layers = top.Member("layers");
  layers.Read("thickness", &spec->layers.thickness);
  layers.Read("muscle_wrinkles", &spec->layers.muscle_wrinkles);
  layers.Read("curve_wrinkles", &spec->layers.curve_wrinkles);
  const View refinement = top.Member("refinement");
  refinement.Read("enabled", &spec->refinement.enabled);
  refinement.Read("edge_fraction", &spec->refinement.edge_fraction);
  refinement.Read("falloff_error", &spec->refinement.falloff_error);
  if (top.Has("jaw")) Jaw(top.Member("jaw"), spec);
  if (top.Has("eyes")) Eyes(top.Member("eyes"), spec);
  std::map<std::string, size_t> region_names;
  for (size_t i = 0; i < top.Size("tension_regions"); ++i) {
    const View g = top.Element("tension_regions", i);
    TensionRegionSpec region;
    g.Read("name", &region.name);
    g.Read("reference", &region.reference);
    if (const json* weights = g.Get("weights"))
      for (const json& e : *weights)
        if (e.is_number()) region.weights.push_back(static_cast<float>(e.get<double>()));
    if (const json* vertices = g.Get("vertices")) {
      region.sparse = true;
      for (const json& e : *vertices)
        if (e.is_number()) region.vertices.push_back(static_cast<uint32_t>(e.get<double>()));
    }
    UniqueName(r_, region.name, "tension_regions", i, "tension region", "among the tension regions",
               &region_names);
    if (g.ok()) spec->tension_regions.push_back(std::move(region));
  }
  if (top.Has("fine_scale")) FineScale(top.Member("fine_scale"), spec);
}

void RigRules::FineScale(const View& f, RigSpec* spec) {
  if (!f.present() || !f.value()->is_object()) return;
  FineScaleSpec fs;
  bool ok = f.ok();
  for (size_t i = 0; i < f.Size("fields") && i < 2; ++i) {
    const View field = f.Element("fields", i);
    field.Read("name", &fs.fields[i].name);
    for (size_t k = 0; k < field.Size("vectors"); ++k) {
      const View v = field.Element("vectors", k);
      DirectionAnchor a;
      int64_t vertex = 0;
      if (v.Read("vertex", &vertex)) a.vertex = uint32_t(std::min<int64_t>(vertex, UINT32_MAX));
      v.Read("vector", &a.vector);
      v.Read("weight", &a.weight);
      if (v.ok() && !(Length(a.vector) > 1e-6f))
        ok = Fail(v.Path("vector"), "has zero length; expected a direction (its length is the "
                                    "magnitude, > 0)");
      ok = ok && v.ok();
      fs.fields[i].anchors.push_back(a);
    }
    ok = ok && field.ok();
  }
  std::string e;
  if (f.Read("interpolation", &e))
    fs.interpolation = e == "inverse_distance" ? FieldInterpolation::kInverseDistance
                                               : FieldInterpolation::kHarmonic;
  if (f.Read("texture_space", &e))
    fs.projection = e == "uv" ? TextureProjection::kUv
                  : e == "planar" ? TextureProjection::kPlanar
                  : e == "cylindrical" ? TextureProjection::kCylindrical
                                       : TextureProjection::kAuto;
  f.Read("minimize_distortion", &fs.minimize_distortion);
  if (f.Read("parameters", &e))
    fs.parameters = e == "bando2001" ? FurrowParameterSet::kBando2001 : FurrowParameterSet::kBando2002;
  f.Read("k_scale", &fs.k_scale);
  f.Read("k_noise", &fs.k_noise);
  f.Read("k_bump", &fs.k_bump);
  f.Read("rest_amplitude", &fs.rest_amplitude);
  const float top = MaxMagnitude(fs.parameters);
  for (size_t i = 0; i < 2; ++i)
    for (size_t k = 0; k < fs.fields[i].anchors.size(); ++k) {
      const float m = Length(fs.fields[i].anchors[k].vector);
      if (m > top * 1.0001f)
        ok = Fail(f.Element("fields", i).Element("vectors", k).Path("vector"),
                  "has magnitude " + FormatFloat(m) + "; expected at most " + FormatFloat(top) +
                      " for parameters " + (top > 1.f ? "\"bando2001\"" : "\"bando2002\""));
    }
  const View maps = f.Member("maps");
  if (const json* height = maps.Get("height"))
    for (size_t i = 0; i < height->size() && i < 2; ++i)
      if ((*height)[i].is_string())
        fs.height_maps[i] = JoinPath(base_dir_, (*height)[i].get<std::string>());
  std::string s;
  if (maps.Read("normal", &s)) fs.normal_map = JoinPath(base_dir_, s);
  if (ok) spec->fine_scale = std::move(fs);
}

void RigRules::Jaw(const View& j, RigSpec* spec) {
  if (!j.present() || !j.value()->is_object()) return;
  JawSpec jaw;
  bool ok = j.ok();
  std::vector<float3> condyles;
  if (j.Read("condyles", &condyles) && condyles.size() == 2) {
    jaw.condyles[0] = condyles[0];
    jaw.condyles[1] = condyles[1];
    if (!(Length(condyles[1] - condyles[0]) > 0.f))
      ok = Fail(j.Path("condyles"), "the two condyles coincide; expected two distinct points "
                                    "(the subject's right, then left condyle)");
  }
  ok = ReadJawShape(j, r_, &jaw) && ok;
  const bool explicit_weights = j.Has("weights");
  if (!explicit_weights) {
    if (!j.Has("mouth"))
      ok = Fail(j.Path("mouth"), "missing required key (jaw.weights is absent); expected a "
                                 "point [x, y, z] between the lips on the midline");
    if (!j.Has("mouth_width"))
      ok = Fail(j.Path("mouth_width"), "missing required key (jaw.weights is absent); expected "
                                       "a number > 0 (mouth corner to corner, mesh units)");
  }
  j.Read("mouth", &jaw.mouth);
  j.Read("mouth_width", &jaw.mouth_width);
  if (const json* weights = j.Get("weights"))
    for (const json& e : *weights) jaw.weights.push_back(static_cast<float>(e.get<double>()));
  if (ok && j.Has("mouth") && condyles.size() == 2 && !explicit_weights) {
    JawFrame frame;
    if (!MakeJawFrame(jaw, &frame))
      ok = Fail(j.Path("mouth"), "lies on the hinge axis through the condyles; expected a point "
                                 "in front of them, between the lips");
  }
  if (ok) spec->jaw = std::move(jaw);
}

void RigRules::Eyes(const View& e, RigSpec* spec) {
  if (!e.present() || !e.value()->is_object()) return;
  EyesSpec eyes;
  bool ok = e.ok();
  for (size_t i = 0; i < e.Size("spheres"); ++i) {
    const View s = e.Element("spheres", i);
    EyeSphere sphere;
    ok = s.ok() && ok;
    s.Read("center", &sphere.center);
    s.Read("radius", &sphere.radius);
    eyes.spheres.push_back(sphere);
  }
  if (const json* band = e.Get("band")) {
    eyes.band[0] = static_cast<float>((*band)[0].get<double>());
    eyes.band[1] = static_cast<float>((*band)[1].get<double>());
    if (!(eyes.band[0] >= 0.f && eyes.band[0] < eyes.band[1]))
      ok = Fail(e.Path("band"), "is [" + FormatFloat(eyes.band[0]) + ", " +
                                    FormatFloat(eyes.band[1]) + "]; expected [b0, b1] with "
                                    "0 <= b0 < b1 (mesh units from an eyeball's surface)");
  }
  if (ok) spec->eyes = std::move(eyes);
}

void RigRules::Fingerprint(const View& f, MeshFingerprint* out) {
  if (!f.ok()) return;
  MeshFingerprint fp;
  int64_t n = 0;
  if (f.Read("vertices", &n)) fp.vertices = uint64_t(n);
  if (f.Read("triangles", &n)) fp.triangles = uint64_t(n);
  std::string hash;
  if (f.Read("index_hash", &hash) && !ParseFingerprintHash(hash, &fp.index_hash)) {
    Fail(f.Path("index_hash"), "is " + Quoted(hash) + "; expected 16 lowercase hex digits");
    return;
  }
  f.Read("positions", &fp.positions);
  f.Read("uvs", &fp.uvs);
  if (fp.positions.size() > kFingerprintSamples) {
    Fail(f.Path("positions"), "has " + std::to_string(fp.positions.size()) +
                                  " entries; expected at most " +
                                  std::to_string(kFingerprintSamples));
    return;
  }
  if (fp.positions.size() > fp.vertices) {
    Fail(f.Path("positions"), "has " + std::to_string(fp.positions.size()) +
                                  " entries for a mesh of " + std::to_string(fp.vertices) +
                                  " vertices; expected at most one per vertex");
    return;
  }
  if (f.Has("uvs") && fp.uvs.size() != fp.positions.size()) {
    Fail(f.Path("uvs"), "has " + std::to_string(fp.uvs.size()) + " entries; expected one per "
                        "position (" + std::to_string(fp.positions.size()) + ")");
    return;
  }
  *out = std::move(fp);
}

void RigRules::Thickness(const View& t, ThicknessSpec* out) {
  if (t.variant() == "constant") {
    out->kind = ThicknessSpec::Kind::kConstant;
    t.Read("value", &out->value);
  } else if (t.variant() == "per_vertex") {
    out->kind = ThicknessSpec::Kind::kPerVertex;
    if (const json* values = t.Get("values"))
      for (const json& e : *values) out->per_vertex.push_back(static_cast<float>(e.get<double>()));
  } else if (t.variant() == "image") {
    out->kind = ThicknessSpec::Kind::kImage;
    std::string s;
    if (t.Read("path", &s)) out->image_path = JoinPath(base_dir_, s);
    if (t.Read("min", &out->min) & t.Read("max", &out->max) && out->min > out->max)
      Fail(t.path(), "min (" + FormatFloat(out->min) + ") > max (" + FormatFloat(out->max) +
                         "); expected min <= max");
  }
}

bool RigRules::Muscle(const View& m, MuscleSpec* out, std::optional<MuscleWrinkleSpec>* wrinkles) {
  m.Read("name", &out->name);
  m.Read("strength", &out->strength);
  if (size_t choice = 0; m.Choice("falloff", &choice)) out->falloff = static_cast<MuscleFalloff>(choice);
  if (size_t choice = 0; m.Choice("motion", &choice)) out->motion = static_cast<MuscleMotion>(choice);
  m.Read("tangent_radius", &out->tangent_radius);
  bool ok = m.ok();
  if (m.variant() == "linear") {
    out->type = MuscleType::kLinear;
    ok &= Linear(m, &out->linear);
  } else if (m.variant() == "sheet") {
    out->type = MuscleType::kSheet;
    ok &= Sheet(m, &out->sheet);
  } else {
    return false;
  }
  // docs/model.md §6: the optional wrinkle block, checked against the muscle's geometry.
  if (!m.Has("wrinkles")) return ok;
  MuscleWrinkleSpec spec;
  if (!Wrinkles(m.Member("wrinkles"), m, *out, ok, &spec)) return false;
  *wrinkles = spec;
  return ok;
}

bool RigRules::Linear(const View& m, LinearMuscleSpec* out) {
  bool ok = true;
  if (m.Read("attachment", &out->attachment) & m.Read("insertion", &out->insertion) &&
      out->attachment == out->insertion)
    ok = Fail(m.path(), "attachment equals insertion; expected two distinct points (the "
                        "muscle's axis runs from attachment to insertion)");
  double deg = 0.0;
  if (m.Read("zone_angle_deg", &deg)) {
    out->zone_angle = DegreesToRadians(deg);
    if (!(out->zone_angle > 0.f))  // a positive angle that rounds to 0 rad
    {
      r_.Expected(m.Path("zone_angle_deg"), m.FieldOf("zone_angle_deg")->Expect(),
                  *m.Raw("zone_angle_deg"));
      ok = false;
    }
  }
  if (m.Read("falloff_start", &out->falloff_start) & m.Read("falloff_end", &out->falloff_end) &&
      !(out->falloff_end > out->falloff_start))
    ok = Fail(m.Path("falloff_end"), "expected a number > falloff_start (" +
                                         FormatFloat(out->falloff_start) + "), got " +
                                         Describe(*m.Raw("falloff_end")));
  return ok;
}

// Two distinct points.
bool ReadLine(Reader& r, const View& m, const std::string& key, float3 out[2]) {
  std::vector<float3> points;
  if (!m.Read(key, &points)) return false;
  out[0] = points[0];
  out[1] = points[1];
  if (LengthSquared(out[1] - out[0]) > 0.f) return true;
  r.Error(m.Path(key), "the two points are equal; expected two distinct points (a line)");
  return false;
}

bool RigRules::Sheet(const View& m, SheetMuscleSpec* out) {
  bool ok = true;
  const bool have_a = ReadLine(r_, m, "attachment", out->attachment);
  const bool have_b = ReadLine(r_, m, "insertion", out->insertion);
  if (have_a && have_b) {
    const float3 mac = (out->attachment[0] + out->attachment[1]) * 0.5f;
    const float3 mic = (out->insertion[0] + out->insertion[1]) * 0.5f;
    if (!(LengthSquared(mic - mac) > 0.f))
      ok = Fail(m.path(), "zero-length fiber: the midpoints of the attachment and insertion "
                          "lines coincide; expected distinct midpoints (the central fiber runs "
                          "between them)");
  }
  m.Read("width", &out->width);
  const bool have_length = m.Read("length", &out->length);
  m.Read("falloff_start", &out->falloff_start);
  ok &= m.CheckBound("falloff_start", "length", have_length ? &out->length : nullptr);
  return ok && have_a && have_b;
}

// docs/model.md §6 (001 eq. 5-7, 12, 15). The attenuation parameter is bounded by the muscle's zone
// angle (linear) or half width (sheet) where those were read; `muscle_ok`: the whole muscle is
// valid, so the wrinkle module's own check can run too.
// docs/model.md §6 (001 eq. 5-7, 12, 15); `muscle_ok`: the whole muscle is valid, so the wrinkle
// module's own check can run too.
bool RigRules::Wrinkles(const View& w, const View& m, const MuscleSpec& muscle, bool muscle_ok,
                        MuscleWrinkleSpec* out) {
  MuscleWrinkleSpec spec;
  if (!ReadMuscleWrinkles(w, m, muscle.type == MuscleType::kLinear, &spec)) return false;
  *out = spec;
  if (!muscle_ok) return true;  // the muscle's own errors make the rig fail anyway
  // The wrinkle module's own check (same ranges; reported only if it is stricter than the above).
  return ValidateMuscleWrinkleSpec(spec, WrinkleGeometryOf(muscle), w.path(), diag_);
}

bool RigRules::Curve(const View& c, NamedCurveWrinkle* out) {
  c.Read("name", &out->name);
  if (!c.ok()) return false;
  CurveWrinkleSpec& spec = out->spec;
  std::vector<float2> control;
  c.Read("control", &control);
  std::copy(control.begin(), control.end(), spec.control);
  c.Read("depth", &spec.depth);
  c.Read("width", &spec.width);
  size_t choice = 0;
  if (c.Choice("profile", &choice)) spec.profile = static_cast<CurveWrinkleProfile>(choice);
  if (c.Choice("modulation", &choice)) spec.modulation = static_cast<CurveWrinkleModulation>(choice);
  c.Read("rest_amplitude", &spec.rest_amplitude);
  // The wrinkle module's own check (same ranges; reported only if it is stricter than the above).
  return ValidateCurveWrinkleSpec(spec, c.path(), diag_);
}

// ---------------------------------------------------------------------------------------------
// Writing.

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
  if (const MeshFingerprint& f = spec.mesh_fingerprint; !f.empty()) {
    ordered_json fp;
    fp["vertices"] = f.vertices;
    fp["triangles"] = f.triangles;
    fp["index_hash"] = FingerprintHashText(f.index_hash);
    ordered_json positions = ordered_json::array(), uvs = ordered_json::array();
    for (const float3& p : f.positions)
      positions.push_back({ShortestDecimal(p.x), ShortestDecimal(p.y), ShortestDecimal(p.z)});
    for (const float2& u : f.uvs) uvs.push_back({ShortestDecimal(u.x), ShortestDecimal(u.y)});
    fp["positions"] = std::move(positions);
    if (!f.uvs.empty()) fp["uvs"] = std::move(uvs);
    mesh["fingerprint"] = std::move(fp);
  }
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
    if (m.falloff != MuscleFalloff::kWaters) j["falloff"] = MuscleFalloffName(m.falloff);
    if (m.motion != MuscleMotion::kChord) j["motion"] = MuscleMotionName(m.motion);
    if (m.tangent_radius != 0.f) j["tangent_radius"] = ShortestDecimal(m.tangent_radius);
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
      if (w.gate != 0.f) wj["gate"] = ShortestDecimal(w.gate);
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

  const SkinLayers default_layers;
  const SkinLayers& l = spec.layers;
  if (l.thickness != default_layers.thickness ||
      l.muscle_wrinkles != default_layers.muscle_wrinkles ||
      l.curve_wrinkles != default_layers.curve_wrinkles) {
    ordered_json j;
    j["thickness"] = l.thickness;
    j["muscle_wrinkles"] = l.muscle_wrinkles;
    j["curve_wrinkles"] = l.curve_wrinkles;
    root["layers"] = std::move(j);
  }

  if (spec.jaw) {
    const JawSpec& jw = *spec.jaw;
    ordered_json j;
    j["condyles"] = ordered_json::array({Vec3Json(jw.condyles[0]), Vec3Json(jw.condyles[1])});
    j["range_deg"] = ShortestDecimal(jw.range_deg);
    if (!(jw.translation.x == 0.f && jw.translation.y == 0.f && jw.translation.z == 0.f))
      j["translation"] = Vec3Json(jw.translation);
    if (jw.weights.empty()) {
      j["mouth"] = Vec3Json(jw.mouth);
      j["mouth_width"] = ShortestDecimal(jw.mouth_width);
      j["lip_blend_deg"] = ShortestDecimal(jw.lip_blend_deg);
      j["cheek_blend_deg"] = ShortestDecimal(jw.cheek_blend_deg);
      j["cheek_drop_deg"] = ShortestDecimal(jw.cheek_drop_deg);
      j["corner_fade"] = ShortestDecimal(jw.corner_fade);
      j["thickness_fade"] = ShortestDecimal(jw.thickness_fade);
      j["back"] = ordered_json::array({ShortestDecimal(jw.back[0]), ShortestDecimal(jw.back[1])});
      j["neck_deg"] =
          ordered_json::array({ShortestDecimal(jw.neck_deg[0]), ShortestDecimal(jw.neck_deg[1])});
    } else {
      ordered_json w = ordered_json::array();
      for (float v : jw.weights) w.push_back(ShortestDecimal(v));
      j["weights"] = std::move(w);
      if (jw.mouth_width > 0.f) {  // the mouth still places the lips' thickness fade
        j["mouth"] = Vec3Json(jw.mouth);
        j["mouth_width"] = ShortestDecimal(jw.mouth_width);
        j["thickness_fade"] = ShortestDecimal(jw.thickness_fade);
      }
    }
    root["jaw"] = std::move(j);
  }

  if (spec.eyes) {
    ordered_json j, spheres = ordered_json::array();
    for (const EyeSphere& s : spec.eyes->spheres) {
      ordered_json sj;
      sj["center"] = Vec3Json(s.center);
      sj["radius"] = ShortestDecimal(s.radius);
      spheres.push_back(std::move(sj));
    }
    j["spheres"] = std::move(spheres);
    j["band"] = ordered_json::array(
        {ShortestDecimal(spec.eyes->band[0]), ShortestDecimal(spec.eyes->band[1])});
    root["eyes"] = std::move(j);
  }

  if (!spec.tension_regions.empty()) {
    ordered_json regions = ordered_json::array();
    for (const TensionRegionSpec& g : spec.tension_regions) {
      ordered_json j;
      j["name"] = g.name;
      if (!(g.reference == kDefaultTensionReference)) j["reference"] = ShortestDecimal(g.reference);
      // The sparse form when the region covers less than half the mesh (a face region of a
      // whole head: 4 MB dense for the sample head's nine regions, a tenth of that sparse).
      const size_t nonzero = size_t(std::count_if(g.weights.begin(), g.weights.end(),
                                                  [](float v) { return v != 0.f; }));
      ordered_json w = ordered_json::array(), idx = ordered_json::array();
      const bool sparse = g.sparse || 2 * nonzero < g.weights.size();
      if (g.sparse) {
        for (uint32_t v : g.vertices) idx.push_back(v);
        for (float v : g.weights) w.push_back(ShortestDecimal(v));
      } else if (sparse) {
        for (size_t v = 0; v < g.weights.size(); ++v)
          if (g.weights[v] != 0.f) {
            idx.push_back(v);
            w.push_back(ShortestDecimal(g.weights[v]));
          }
      } else {
        for (float v : g.weights) w.push_back(ShortestDecimal(v));
      }
      if (sparse) j["vertices"] = std::move(idx);
      j["weights"] = std::move(w);
      regions.push_back(std::move(j));
    }
    root["tension_regions"] = std::move(regions);
  }

  if (spec.fine_scale) {
    const FineScaleSpec& fs = *spec.fine_scale;
    const FineScaleSpec d;
    ordered_json j;
    ordered_json fields = ordered_json::array();
    for (const DirectionFieldSpec& field : fs.fields) {
      ordered_json fj;
      fj["name"] = field.name;
      ordered_json vectors = ordered_json::array();
      for (const DirectionAnchor& a : field.anchors) {
        ordered_json v;
        v["vertex"] = a.vertex;
        v["vector"] = Vec3Json(a.vector);
        if (!(a.weight == 1.f)) v["weight"] = ShortestDecimal(a.weight);
        vectors.push_back(std::move(v));
      }
      fj["vectors"] = std::move(vectors);
      fields.push_back(std::move(fj));
    }
    j["fields"] = std::move(fields);
    if (fs.interpolation != d.interpolation) j["interpolation"] = "inverse_distance";
    if (fs.projection != d.projection)
      j["texture_space"] = fs.projection == TextureProjection::kUv       ? "uv"
                           : fs.projection == TextureProjection::kPlanar ? "planar"
                                                                         : "cylindrical";
    if (fs.minimize_distortion) j["minimize_distortion"] = true;
    if (fs.parameters != d.parameters) j["parameters"] = "bando2001";
    if (!(fs.k_scale == d.k_scale)) j["k_scale"] = ShortestDecimal(fs.k_scale);
    if (!(fs.k_noise == d.k_noise)) j["k_noise"] = ShortestDecimal(fs.k_noise);
    if (!(fs.k_bump == d.k_bump)) j["k_bump"] = ShortestDecimal(fs.k_bump);
    if (!(fs.rest_amplitude == d.rest_amplitude)) j["rest_amplitude"] = ShortestDecimal(fs.rest_amplitude);
    if (!fs.height_maps[0].empty() || !fs.normal_map.empty()) {
      ordered_json maps;
      if (!fs.height_maps[0].empty())
        maps["height"] = ordered_json::array(
            {PathForFile(fs.height_maps[0], dir), PathForFile(fs.height_maps[1], dir)});
      if (!fs.normal_map.empty()) maps["normal"] = PathForFile(fs.normal_map, dir);
      j["maps"] = std::move(maps);
    }
    root["fine_scale"] = std::move(j);
  }

  const RefinementSpec default_refinement;
  const RefinementSpec& r = spec.refinement;
  // `!(a == b)` so that a NaN edge fraction is written (and then refused by the check).
  if (r.enabled != default_refinement.enabled ||
      !(r.edge_fraction == default_refinement.edge_fraction) ||
      !(r.falloff_error == default_refinement.falloff_error)) {
    ordered_json j;
    j["enabled"] = r.enabled;
    j["edge_fraction"] = ShortestDecimal(r.edge_fraction);
    if (!(r.falloff_error == default_refinement.falloff_error))
      j["falloff_error"] = ShortestDecimal(r.falloff_error);
    root["refinement"] = std::move(j);
  }
  return root;
}

bool ParseRigSpecImpl(std::string_view json_text, const std::string& base_dir, RigSpec* out,
                      Diagnostics* diag) {
  Reader reader(kRigFormat, diag);
  if (!reader.Parse(json_text)) return false;
  const View top = reader.Check();
  // A newer version may have keys and rules this build does not know: one error is enough.
  if (reader.stopped()) return false;
  RigSpec spec;
  if (top.present() && top.value()->is_object()) RigRules(&reader, base_dir, diag).Root(top, &spec);
  if (reader.failed()) return false;
  *out = std::move(spec);
  return true;
}

}  // namespace

const json_reader::Format& RigFileFormat() { return kRigFormat; }

json_reader::Object MuscleWrinkleBlock(bool linear, const std::string& unit) {
  using namespace json_reader;
  const std::string type = linear ? "linear" : "sheet";
  const std::string other = linear ? "sheet" : "linear";
  const std::string key = linear ? "phi_c_deg" : "h_c";
  const std::string other_key = linear ? "h_c" : "phi_c_deg";
  const std::string meaning =
      linear ? "degrees, where the attenuation across the zone starts"
             : unit + ", distance from the central fiber where the attenuation starts";
  Field attenuation =
      linear ? Number(key, "a number in [0, zone_angle_deg) (degrees)").Min(0).Below(180)
                   .About(meaning + "; < the muscle's zone_angle_deg (reader check)")
             : Number(key, "a number in [0, width/2) (" + unit + ")").Min(0)
                   .About(meaning + "; < the muscle's width / 2 (reader check)");
  return {
      .owner = "the wrinkles of a " + type + " muscle",
      .fields = {Number("lambda_w", "a number in [0, 1) (start of the wrinkling region, fraction "
                                    "of " + std::string(linear ? "falloff_end" : "length") + ")")
                     .Min(0).Below(1),
                 Integer("count").Min(1).About("n_w, wrinkles across the region; default 3"),
                 Number("depth").Min(0).Required().About("k0, " + unit),
                 Number("shape", "a finite number (alpha)"), attenuation.CrossField(),
                 Number("gate", "an activation in [0, 1] (0: no gate)").Min(0).Max(1)
                     .About("the muscle's activation at which its wrinkles reach full "
                            "amplitude (amplitude times smoothstep(0, gate, a)); default 0, "
                            "no gate: the amplitude follows the compression alone")},
      .notes = {{other_key, Quoted(other_key) + " is for the wrinkles of a " + other +
                                " muscle, and this is a " + type + " muscle; expected " +
                                Quoted(key) + " (" + meaning + ")",
                 true}},
      .description = "Wrinkles of a " + type + " muscle (docs/model.md §6; 001 eq. " +
                     (linear ? "5-7, 11-12" : "13-15") + ")."};
}

bool ReadMuscleWrinkles(const json_reader::View& w, const json_reader::View& m, bool linear,
                        MuscleWrinkleSpec* out) {
  MuscleWrinkleSpec spec;  // defaults for absent optional keys
  w.Read("lambda_w", &spec.lambda_w);
  w.Read("count", &spec.count);
  w.Read("depth", &spec.depth);
  w.Read("shape", &spec.shape);
  w.Read("gate", &spec.gate);
  bool ok = w.ok();
  float bound = 0.f;
  if (linear) {
    const bool have_zone = m.Read("zone_angle_deg", &bound) && DegreesToRadians(bound) > 0.f;
    ok &= w.CheckBound("phi_c_deg", "zone_angle_deg", have_zone ? &bound : nullptr);
    double deg = 0.0;
    if (w.Read("phi_c_deg", &deg)) spec.phi_c = DegreesToRadians(deg);
  } else {
    const bool have_width = m.Read("width", &bound);
    bound *= 0.5f;
    ok &= w.CheckBound("h_c", "width/2", have_width ? &bound : nullptr);
    w.Read("h_c", &spec.h_c);
  }
  if (ok) *out = spec;
  return ok;
}

bool ParseRigSpec(std::string_view json_text, const std::string& base_dir, RigSpec* out,
                  Diagnostics* diag) {
  Diagnostics local;
  if (!diag) diag = &local;
  if (!out) {
    diag->Error("", "internal error: ParseRigSpec called without an output");
    return false;
  }
  return NoThrow(diag, "cannot read the rig",
                 [&] { return ParseRigSpecImpl(json_text, base_dir, out, diag); });
}

bool LoadRigSpec(const std::string& path, RigSpec* out, Diagnostics* diag) {
  RigSpec spec;
  const bool ok = ParseFile(path, diag, [&](const std::string& text, Diagnostics* local) {
    return ParseRigSpec(text, DirectoryOf(path), &spec, local);
  });
  if (!ok || !out) return false;
  spec.file = path;
  *out = std::move(spec);
  return true;
}

std::string RigSpecText(const RigSpec& spec, const std::string& dir, std::string* error) {
  try {
    return ToJson(spec, dir).dump(2, ' ', false, ordered_json::error_handler_t::strict) + "\n";
  } catch (const std::exception& e) {
    if (error) *error = e.what();
  } catch (...) {
    if (error) *error = "unknown error";
  }
  return "";
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

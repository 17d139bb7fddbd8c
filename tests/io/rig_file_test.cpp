// tests/io/rig_file_test.cpp: the rig file loader, validator, saver and JSON schema
// (io/rig_file.cpp, docs/rig-format.md, assets/schema/mimetic-rig.schema.json).
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cstdlib>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

#include "io/rig_file.h"
#include "rig/offline/rig_spec.h"
#include "test_support.h"

namespace mimetic {
namespace {

namespace fs = std::filesystem;

// ---------------------------------------------------------------------------------------------
// Building blocks for rig texts.

const std::string kLinear =
    R"({"name": "zyg_L", "type": "linear", "strength": 4, "attachment": [0, 0, 0],
        "insertion": [10, 0, 0], "zone_angle_deg": 40, "falloff_start": 10, "falloff_end": 30})";
const std::string kSheet =
    R"({"name": "front_L", "type": "sheet", "strength": 3,
        "attachment": [[0, 0, 0], [10, 0, 0]], "insertion": [[0, 50, 0], [10, 50, 0]],
        "length": 50, "width": 40, "falloff_start": 20})";

// A valid rig with the given muscles array and extra top-level members.
std::string Doc(const std::string& muscles = "[" + kLinear + "]", const std::string& extra = "") {
  return R"({"format": "mimetic-rig", "version": 1, "mesh": {"path": "surface.obj"},
            "units": "mm", "muscles": )" +
         muscles + extra + "}";
}

// `text` with the first `from` replaced by `to` (the test fails when `from` is absent).
std::string Replace(std::string text, const std::string& from, const std::string& to) {
  const size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << "test setup: \"" << from << "\" not in " << text;
  if (at != std::string::npos) text.replace(at, from.size(), to);
  return text;
}

std::string Linear(const std::string& from, const std::string& to) {
  return Doc("[" + Replace(kLinear, from, to) + "]");
}
std::string Sheet(const std::string& from, const std::string& to) {
  return Doc("[" + Replace(kSheet, from, to) + "]");
}
std::string Top(const std::string& from, const std::string& to) { return Replace(Doc(), from, to); }
std::string Thickness(const std::string& thickness) {
  return Doc("[" + kLinear + "]", R"(, "thickness": )" + thickness);
}
// The linear (sheet) muscle above with the given wrinkle block (docs/model.md §6).
std::string LinearW(const std::string& wrinkles) {
  return Linear(R"("falloff_end": 30)", R"("falloff_end": 30, "wrinkles": )" + wrinkles);
}
std::string SheetW(const std::string& wrinkles) {
  return Sheet(R"("falloff_start": 20)", R"("falloff_start": 20, "wrinkles": )" + wrinkles);
}
// A curve wrinkle (docs/model.md §7-8) with only the required keys.
const std::string kCurve =
    R"({"name": "nasolabial_L", "control": [[0.1, 0.2], [0.2, 0.3], [0.3, 0.35], [0.4, 0.3]],
        "depth": 2, "width": 3})";
std::string Curves(const std::string& curves) {
  return Doc("[" + kLinear + "]", R"(, "curve_wrinkles": )" + curves);
}
std::string Curve(const std::string& from, const std::string& to) {
  return Curves("[" + Replace(kCurve, from, to) + "]");
}
// The base rig with one more top-level member, e.g. `"layers": {...}`.
std::string Extra(const std::string& member) { return Doc("[" + kLinear + "]", ", " + member); }
// A jaw block (docs/model.md §18) with only the required keys of the region form.
const std::string kJaw =
    R"({"condyles": [[-60, 0, -50], [60, 0, -50]], "range_deg": 20, "mouth": [0, 0, 10], "mouth_width": 40})";
std::string Jaw(const std::string& from, const std::string& to) {
  return Extra(R"("jaw": )" + Replace(kJaw, from, to));
}

// An eyes block (docs/model.md §24).
const std::string kEyes =
    R"({"spheres": [{"center": [-31, 0, 66], "radius": 12}, {"center": [31, 0, 66], "radius": 12}], "band": [2, 8]})";
std::string Eyes(const std::string& from, const std::string& to) {
  return Extra(R"("eyes": )" + Replace(kEyes, from, to));
}

TEST(RigJsonTest, BaseTextsAreValid) {
  for (const std::string& text :
       {Doc(), Doc("[" + kSheet + "]"), Doc("[]"), Thickness(R"({"type": "constant", "value": 3})"),
        LinearW(R"({"depth": 1, "phi_c_deg": 10})"), SheetW(R"({"depth": 1, "h_c": 5})"),
        LinearW(R"({"depth": 1, "gate": 1})"), SheetW(R"({"depth": 1, "gate": 0})"),
        Curves("[" + kCurve + "]"), Extra(R"("layers": {"thickness": false})"),
        Extra(R"("refinement": {"edge_fraction": 1})"), Extra(R"("jaw": )" + kJaw),
        Extra(R"("eyes": )" + kEyes),
        Extra(R"("tension_regions": [{"name": "glabella", "reference": 0.2, "weights": [0, 0.5, 1]}])")}) {
    RigSpec spec;
    Diagnostics diag;
    EXPECT_TRUE(ParseRigSpec(text, "", &spec, &diag)) << diag.Format() << text;
    EXPECT_EQ(diag.ErrorCount(), 0u);
  }
}

// ---------------------------------------------------------------------------------------------
// 1. Bad inputs: each text must be rejected with messages that name the JSON path and say what
// was expected (and what was got).

struct BadCase {
  const char* label;
  std::string text;
  std::vector<std::string> expected;  // substrings of Diagnostics::Format()
};

std::vector<BadCase> BadCases() {
  return {
      // "version": 1,, -- the second comma is the 15th character of line 2 (counted by hand).
      {"invalid JSON", "{\"format\": \"mimetic-rig\",\n \"version\": 1,,}",
       {"invalid JSON at line 2, column 15"}},
      {"empty text", "", {"invalid JSON at line 1, column 1"}},
      {"invalid UTF-8", "{\"format\": \"mimetic-rig\xff\"}",
       {"invalid JSON at line 1, column", "ill-formed UTF-8"}},
      // Doc() spans 3 lines; the "x" is on line 5, column 3.
      {"trailing garbage", Doc() + "\n\n  x", {"invalid JSON at line 5, column 3"}},
      {"root not object", "[1, 2]", {"expected the top-level value to be an object", "got array"}},
      {"missing format", Replace(Doc(), R"("format": "mimetic-rig", )", ""),
       {"error: format: missing required key; expected \"mimetic-rig\""}},
      {"wrong format", Top(R"("mimetic-rig")", R"("mimetic-face")"),
       {"format: expected \"mimetic-rig\", got \"mimetic-face\""}},
      {"missing version", Top(R"("version": 1, )", ""),
       {"version: missing required key; expected integer 1"}},
      {"version 2", Top(R"("version": 1)", R"("version": 2)"),
       {"version: unsupported version 2: this build reads version 1"}},
      {"version as string", Top(R"("version": 1)", R"("version": "1")"),
       {"version: expected integer 1, got string"}},
      {"tension weight above 1",
       Extra(R"("tension_regions": [{"name": "glabella", "weights": [0, 1.5]}])"),
       {"tension_regions[0].weights[1]", "1.5"}},
      {"tension region without weights", Extra(R"("tension_regions": [{"name": "glabella"}])"),
       {"tension_regions[0].weights: missing required key"}},
      {"tension reference 0",
       Extra(R"("tension_regions": [{"name": "a", "reference": 0, "weights": [1]}])"),
       {"tension_regions[0].reference"}},
      {"tension names repeat",
       Extra(R"("tension_regions": [{"name": "a", "weights": [1]}, {"name": "a", "weights": [1]}])"),
       {"tension_regions[1].name", "\"a\""}},
      {"version overflows", Top(R"("version": 1)", R"("version": 1e999)"),
       {"version: expected integer 1, got a number that overflows to infinity"}},
      {"version 1.5", Top(R"("version": 1)", R"("version": 1.5)"),
       {"version: expected integer 1, got 1.5"}},
      {"missing mesh", Top(R"("mesh": {"path": "surface.obj"},)", ""),
       {"mesh: missing required key"}},
      {"mesh not object", Top(R"({"path": "surface.obj"})", R"("surface.obj")"),
       {"mesh: expected object", "got string"}},
      {"mesh.path not string", Top(R"("path": "surface.obj")", R"("path": 7)"),
       {"mesh.path: expected non-empty string", "got number"}},
      {"mesh.path empty", Top(R"("path": "surface.obj")", R"("path": "")"),
       {"mesh.path: expected non-empty string", "got empty string"}},
      {"mesh.name not string", Top(R"("path": "surface.obj")", R"("path": "a.glb", "name": 3)"),
       {"mesh.name: expected string", "got number"}},
      {"unknown mesh key", Top(R"("path": "surface.obj")", R"("path": "a.obj", "scale": 2)"),
       {"mesh.scale: unknown key \"scale\"; allowed keys for mesh: path, name"}},
      {"bad units", Top(R"("units": "mm")", R"("units": "km")"),
       {R"(units: expected one of "mm", "cm", "dm", "m", "in", got "km")"}},
      {"missing units", Top(R"("units": "mm",)", ""), {"units: missing required key"}},
      {"unknown top-level key", Doc("[" + kLinear + "]", R"(, "colour": "red")"),
       {"colour: unknown key \"colour\"",
        "allowed keys: format, version, mesh, units, thickness, muscles, curve_wrinkles, layers, "
        "refinement"}},
      {"fine_scale not an object", Doc("[" + kLinear + "]", R"(, "fine_scale": [])"),
       {R"(fine_scale: expected object {"fields": [...], ...}, got array)"}},
      {"fine_scale with one field", Extra(R"("fine_scale": {"fields": [{"name": "a", "vectors": [{"vertex": 0, "vector": [1, 0, 0]}]}]})"),
       {"fine_scale.fields: expected array of 2 direction fields, got array of 1 elements"}},
      {"fine_scale zero vector", Extra(R"("fine_scale": {"fields": [{"name": "a", "vectors": [{"vertex": 0, "vector": [0, 0, 0]}]}, {"name": "b", "vectors": [{"vertex": 1, "vector": [0, 1, 0]}]}]})"),
       {"fine_scale.fields[0].vectors[0].vector: has zero length"}},
      {"fine_scale magnitude", Extra(R"("fine_scale": {"fields": [{"name": "a", "vectors": [{"vertex": 0, "vector": [1.5, 0, 0]}]}, {"name": "b", "vectors": [{"vertex": 1, "vector": [0, 1, 0]}]}]})"),
       {"fine_scale.fields[0].vectors[0].vector: has magnitude 1.5; expected at most 1"}},
      {"fine_scale negative vertex", Extra(R"("fine_scale": {"fields": [{"name": "a", "vectors": [{"vertex": -1, "vector": [1, 0, 0]}]}, {"name": "b", "vectors": [{"vertex": 1, "vector": [0, 1, 0]}]}]})"),
       {"fine_scale.fields[0].vectors[0].vertex"}},
      {"fine_scale bad interpolation", Extra(R"("fine_scale": {"fields": [{"name": "a", "vectors": [{"vertex": 0, "vector": [1, 0, 0]}]}, {"name": "b", "vectors": [{"vertex": 1, "vector": [0, 1, 0]}]}], "interpolation": "spline"})"),
       {"fine_scale.interpolation"}},
      {"reserved top-level key expressions", Extra(R"("expressions": {})"),
       {"expressions: unknown key \"expressions\" (reserved for a later version"}},
      {"top-level wrinkles", Doc("[" + kLinear + "]", R"(, "wrinkles": [])"),
       {"wrinkles: unknown key \"wrinkles\"",
        "muscle-derived wrinkles go inside each muscle: muscles[i].wrinkles"}},
      {"duplicate JSON key", Top(R"("path": "surface.obj")", R"("path": "a.obj", "path": "b.obj")"),
       {"mesh.path: duplicate key"}},
      {"muscles not an array", Doc(kLinear), {"muscles: expected array of muscles, got object"}},
      {"missing muscles", Replace(Doc(), R"(, "muscles": [)" + kLinear + "]", ""),
       {"muscles: missing required key"}},
      {"muscle not object", Doc("[3]"), {"muscles[0]: expected object (a muscle), got number"}},
      {"unknown muscle key", Linear(R"("strength": 4)", R"("strength": 4, "colour": 1)"),
       {"muscles[0].colour: unknown key \"colour\"",
        "allowed keys for a linear muscle: name, type, strength, falloff, motion, tangent_radius, "
        "attachment, insertion, "
        "zone_angle_deg, falloff_start, falloff_end, wrinkles"}},
      {"linear key on a sheet", Sheet(R"("width": 40)", R"("width": 40, "zone_angle_deg": 40)"),
       {"muscles[0].zone_angle_deg: unknown key", "allowed keys for a sheet muscle"}},
      {"missing name", Linear(R"("name": "zyg_L", )", ""),
       {"muscles[0].name: missing required key; expected non-empty string"}},
      {"empty name", Linear(R"("name": "zyg_L")", R"("name": "")"),
       {"muscles[0].name: expected non-empty string, got empty string"}},
      {"duplicate names", Doc("[" + kLinear + ", " + kLinear + "]"),
       {"muscles[1].name: duplicate muscle name \"zyg_L\" (first used by muscles[0])"}},
      {"missing type", Linear(R"("type": "linear", )", ""),
       {"muscles[0].type: missing required key"}},
      {"sphincter", Linear(R"("type": "linear")", R"("type": "sphincter")"),
       {"muscles[0].type: unknown muscle type \"sphincter\"",
        "supported types: \"linear\", \"sheet\"", "sphincter muscles are not supported"}},
      {"strength overflows (1e999)", Linear(R"("strength": 4)", R"("strength": 1e999)"),
       {"muscles[0].strength: expected a finite number >= 0", "overflows to infinity"}},
      {"strength overflows a float (1e300)", Linear(R"("strength": 4)", R"("strength": 1e300)"),
       {"muscles[0].strength: expected a finite number >= 0", "overflows to infinity"}},
      {"negative strength", Linear(R"("strength": 4)", R"("strength": -1)"),
       {"muscles[0].strength: expected a finite number >= 0, got -1"}},
      {"negative tangent_radius", Linear(R"("strength": 4)", R"("strength": 4, "tangent_radius": -0.5)"),
       {"muscles[0].tangent_radius: expected a finite number >= 0, got -0.5"}},
      {"tangent_radius string", Linear(R"("strength": 4)", R"("strength": 4, "tangent_radius": "wide")"),
       {"muscles[0].tangent_radius: expected a finite number >= 0, got string"}},
      {"strength boolean", Linear(R"("strength": 4)", R"("strength": true)"),
       {"muscles[0].strength: expected a finite number >= 0, got boolean"}},
      {"attachment string", Linear(R"("attachment": [0, 0, 0])", R"("attachment": "origin")"),
       {"muscles[0].attachment: expected array of 3 numbers, got string"}},
      {"attachment 2 numbers", Linear(R"("attachment": [0, 0, 0])", R"("attachment": [0, 0])"),
       {"muscles[0].attachment: expected array of 3 numbers, got array of 2 elements"}},
      {"attachment with null", Linear(R"("attachment": [0, 0, 0])", R"("attachment": [0, null, 0])"),
       {"muscles[0].attachment[1]: expected a finite number, got null"}},
      {"insertion overflows", Linear(R"("insertion": [10, 0, 0])", R"("insertion": [10, -1e999, 0])"),
       {"muscles[0].insertion[1]: expected a finite number", "overflows to infinity"}},
      {"attachment equals insertion", Linear(R"("insertion": [10, 0, 0])", R"("insertion": [0, 0, 0])"),
       {"muscles[0]: attachment equals insertion"}},
      {"zone angle 0", Linear(R"("zone_angle_deg": 40)", R"("zone_angle_deg": 0)"),
       {"muscles[0].zone_angle_deg: expected a number in (0, 180) (degrees), got 0"}},
      {"zone angle 200", Linear(R"("zone_angle_deg": 40)", R"("zone_angle_deg": 200)"),
       {"muscles[0].zone_angle_deg: expected a number in (0, 180) (degrees), got 200"}},
      {"zone angle string", Linear(R"("zone_angle_deg": 40)", R"("zone_angle_deg": "40")"),
       {"muscles[0].zone_angle_deg: expected a number in (0, 180) (degrees), got string"}},
      {"falloff_start 0", Linear(R"("falloff_start": 10)", R"("falloff_start": 0)"),
       {"muscles[0].falloff_start: expected a finite number > 0, got 0"}},
      {"falloff_end equals falloff_start", Linear(R"("falloff_end": 30)", R"("falloff_end": 10)"),
       {"muscles[0].falloff_end: expected a number > falloff_start (10), got 10"}},
      {"falloff_end below falloff_start", Linear(R"("falloff_end": 30)", R"("falloff_end": 5)"),
       {"muscles[0].falloff_end: expected a number > falloff_start (10), got 5"}},
      {"missing falloff_end", Linear(R"(, "falloff_end": 30)", ""),
       {"muscles[0].falloff_end: missing required key"}},
      {"sheet line with equal points",
       Sheet(R"("attachment": [[0, 0, 0], [10, 0, 0]])", R"("attachment": [[1, 2, 3], [1, 2, 3]])"),
       {"muscles[0].attachment: the two points are equal; expected two distinct points"}},
      {"sheet line of one point", Sheet(R"("attachment": [[0, 0, 0], [10, 0, 0]])", R"("attachment": [[0, 0, 0]])"),
       {"muscles[0].attachment: expected array of 2 points", "got array of 1 elements"}},
      {"sheet point wrong type",
       Sheet(R"("insertion": [[0, 50, 0], [10, 50, 0]])", R"("insertion": [[0, 50, 0], "x"])"),
       {"muscles[0].insertion[1]: expected array of 3 numbers, got string"}},
      {"sheet zero fiber",
       Sheet(R"("insertion": [[0, 50, 0], [10, 50, 0]])", R"("insertion": [[10, 0, 0], [0, 0, 0]])"),
       {"muscles[0]: zero-length fiber"}},
      {"sheet falloff_start = length", Sheet(R"("falloff_start": 20)", R"("falloff_start": 50)"),
       {"muscles[0].falloff_start: expected a number in (0, length = 50), got 50"}},
      {"sheet falloff_start > length", Sheet(R"("falloff_start": 20)", R"("falloff_start": 70)"),
       {"muscles[0].falloff_start: expected a number in (0, length = 50), got 70"}},
      {"sheet width 0", Sheet(R"("width": 40)", R"("width": 0)"),
       {"muscles[0].width: expected a finite number > 0, got 0"}},
      {"thickness unknown type", Thickness(R"({"type": "gradient", "value": 1})"),
       {R"(thickness.type: expected one of "constant", "per_vertex", "image", got "gradient")"}},
      {"thickness not object", Thickness("3"), {"thickness: expected object", "got number"}},
      {"thickness negative", Thickness(R"({"type": "constant", "value": -3})"),
       {"thickness.value: expected a finite number >= 0, got -3"}},
      {"thickness unknown key", Thickness(R"({"type": "constant", "value": 3, "values": [1]})"),
       {"thickness.values: unknown key \"values\"; allowed keys for constant thickness: type, value"}},
      {"per_vertex with a string", Thickness(R"({"type": "per_vertex", "values": [1, "2", 3]})"),
       {"thickness.values[1]: expected a finite number >= 0, got string"}},
      {"per_vertex not an array", Thickness(R"({"type": "per_vertex", "values": 1})"),
       {"thickness.values: expected array of numbers >= 0", "got number"}},
      {"image min > max", Thickness(R"({"type": "image", "path": "t.png", "min": 5, "max": 2})"),
       {"thickness: min (5) > max (2); expected min <= max"}},
      {"image missing path", Thickness(R"({"type": "image", "min": 0, "max": 2})"),
       {"thickness.path: missing required key"}},

      // Muscle wrinkles (docs/model.md §6).
      {"h_c on a linear muscle", LinearW(R"({"depth": 1, "h_c": 5})"),
       {"muscles[0].wrinkles.h_c: \"h_c\" is for the wrinkles of a sheet muscle, and this is a "
        "linear muscle; expected \"phi_c_deg\""}},
      {"phi_c_deg on a sheet muscle", SheetW(R"({"depth": 1, "phi_c_deg": 5})"),
       {"muscles[0].wrinkles.phi_c_deg: \"phi_c_deg\" is for the wrinkles of a linear muscle, "
        "and this is a sheet muscle; expected \"h_c\""}},
      {"phi_c_deg = zone angle", LinearW(R"({"depth": 1, "phi_c_deg": 40})"),
       {"muscles[0].wrinkles.phi_c_deg: expected a number in [0, zone_angle_deg = 40) (degrees), "
        "got 40"}},
      {"phi_c_deg > zone angle", LinearW(R"({"depth": 1, "phi_c_deg": 45.5})"),
       {"muscles[0].wrinkles.phi_c_deg: expected a number in [0, zone_angle_deg = 40) (degrees), "
        "got 45.5"}},
      {"phi_c_deg negative", LinearW(R"({"depth": 1, "phi_c_deg": -1})"),
       {"muscles[0].wrinkles.phi_c_deg: expected a number in [0, zone_angle_deg = 40)", "got -1"}},
      {"h_c = width/2", SheetW(R"({"depth": 1, "h_c": 20})"),
       {"muscles[0].wrinkles.h_c: expected a number in [0, width/2 = 20) (mesh units), got 20"}},
      {"h_c negative", SheetW(R"({"depth": 1, "h_c": -0.5})"),
       {"muscles[0].wrinkles.h_c: expected a number in [0, width/2 = 20) (mesh units), got -0.5"}},
      {"count 0", LinearW(R"({"depth": 1, "count": 0})"),
       {"muscles[0].wrinkles.count: expected an integer >= 1, got 0"}},
      {"count 2.5", LinearW(R"({"depth": 1, "count": 2.5})"),
       {"muscles[0].wrinkles.count: expected an integer >= 1, got 2.5"}},
      {"count string", LinearW(R"({"depth": 1, "count": "3"})"),
       {"muscles[0].wrinkles.count: expected an integer >= 1, got string"}},
      {"count too large for an int", LinearW(R"({"depth": 1, "count": 3e9})"),
       {"muscles[0].wrinkles.count: expected an integer >= 1, got 3000000000"}},
      {"lambda_w 1", LinearW(R"({"depth": 1, "lambda_w": 1})"),
       {"muscles[0].wrinkles.lambda_w: expected a number in [0, 1)", "got 1"}},
      {"lambda_w negative", SheetW(R"({"depth": 1, "lambda_w": -0.25})"),
       {"muscles[0].wrinkles.lambda_w: expected a number in [0, 1) (start of the wrinkling region, "
        "fraction of length), got -0.25"}},
      {"negative wrinkle depth", LinearW(R"({"depth": -1})"),
       {"muscles[0].wrinkles.depth: expected a finite number >= 0, got -1"}},
      {"missing wrinkle depth", LinearW(R"({"count": 2})"),
       {"muscles[0].wrinkles.depth: missing required key; expected a finite number >= 0"}},
      {"shape overflows", LinearW(R"({"depth": 1, "shape": 1e999})"),
       {"muscles[0].wrinkles.shape: expected a finite number (alpha)", "overflows to infinity"}},
      {"unknown wrinkle key", LinearW(R"({"depth": 1, "alpha": 2})"),
       {"muscles[0].wrinkles.alpha: unknown key \"alpha\"; allowed keys for the wrinkles of a "
        "linear muscle: lambda_w, count, depth, shape, phi_c_deg, gate"}},
      {"gate above 1", LinearW(R"({"depth": 1, "gate": 1.5})"),
       {"muscles[0].wrinkles.gate: expected an activation in [0, 1] (0: no gate), got 1.5"}},
      {"gate negative", SheetW(R"({"depth": 1, "gate": -0.25})"),
       {"muscles[0].wrinkles.gate: expected an activation in [0, 1] (0: no gate), got -0.25"}},
      {"gate a string", LinearW(R"({"depth": 1, "gate": "full"})"),
       {"muscles[0].wrinkles.gate: expected an activation in [0, 1] (0: no gate), got string"}},
      {"wrinkles not an object", LinearW("true"),
       {"muscles[0].wrinkles: expected object", "\"phi_c_deg\": ...}, got boolean"}},

      // Curve wrinkles (docs/model.md §7-8).
      {"curve_wrinkles not an array", Extra(R"("curve_wrinkles": )" + kCurve),
       {"curve_wrinkles: expected array of curve wrinkles, got object"}},
      {"curve wrinkle not an object", Curves("[\"nasolabial_L\"]"),
       {"curve_wrinkles[0]: expected object (a curve wrinkle), got string"}},
      {"duplicate curve names", Curves("[" + kCurve + ", " + kCurve + "]"),
       {"curve_wrinkles[1].name: duplicate curve wrinkle name \"nasolabial_L\" (first used by "
        "curve_wrinkles[0]); expected a name unique among the curve wrinkles"}},
      {"empty curve name", Curve(R"("name": "nasolabial_L")", R"("name": "")"),
       {"curve_wrinkles[0].name: expected non-empty string, got empty string"}},
      {"missing curve name", Curve(R"("name": "nasolabial_L", )", ""),
       {"curve_wrinkles[0].name: missing required key; expected non-empty string"}},
      {"3 control points", Curve(R"([[0.1, 0.2], [0.2, 0.3], [0.3, 0.35], [0.4, 0.3]])",
                                 R"([[0.1, 0.2], [0.2, 0.3], [0.3, 0.35]])"),
       {"curve_wrinkles[0].control: expected array of 4 points (cubic Bezier control points",
        "got array of 3 elements"}},
      {"control point with 3 numbers", Curve(R"([0.3, 0.35])", R"([0.3, 0.35, 0])"),
       {"curve_wrinkles[0].control[2]: expected array of 2 numbers [u, v], got array of 3 "
        "elements"}},
      {"control coordinate null", Curve(R"([0.2, 0.3])", R"([null, 0.3])"),
       {"curve_wrinkles[0].control[1][0]: expected a finite number, got null"}},
      {"control not an array", Curve(R"([[0.1, 0.2], [0.2, 0.3], [0.3, 0.35], [0.4, 0.3]])",
                                     R"("smile")"),
       {"curve_wrinkles[0].control: expected array of 4 points", "got string"}},
      {"unknown profile", Curve(R"("width": 3)", R"("width": 3, "profile": "gauss")"),
       {R"(curve_wrinkles[0].profile: expected one of "bando", "yang_zhang", )"
        R"("yang_zhang_exact", got "gauss")"}},
      {"unknown modulation", Curve(R"("width": 3)", R"("width": 3, "modulation": "length")"),
       {R"(curve_wrinkles[0].modulation: expected one of "directional", "area", got "length")"}},
      {"curve width 0", Curve(R"("width": 3)", R"("width": 0)"),
       {"curve_wrinkles[0].width: expected a finite number > 0, got 0"}},
      {"curve depth negative", Curve(R"("depth": 2)", R"("depth": -2)"),
       {"curve_wrinkles[0].depth: expected a finite number > 0, got -2"}},
      {"curve missing width", Curve(R"(, "width": 3)", ""),
       {"curve_wrinkles[0].width: missing required key; expected a finite number > 0"}},
      {"rest_amplitude 1.5", Curve(R"("width": 3)", R"("width": 3, "rest_amplitude": 1.5)"),
       {"curve_wrinkles[0].rest_amplitude: expected a number in [0, 1], got 1.5"}},
      {"unknown curve key", Curve(R"("width": 3)", R"("width": 3, "colour": 1)"),
       {"curve_wrinkles[0].colour: unknown key \"colour\"; allowed keys for a curve wrinkle: name, "
        "control, depth, width, profile, modulation, rest_amplitude"}},

      // Layers and refinement (docs/model.md §1, §11).
      {"layers.thickness \"yes\"", Extra(R"("layers": {"thickness": "yes"})"),
       {"layers.thickness: expected boolean (true or false), got \"yes\""}},
      {"layers.curve_wrinkles 0", Extra(R"("layers": {"curve_wrinkles": 0})"),
       {"layers.curve_wrinkles: expected boolean (true or false), got 0"}},
      {"layers not an object", Extra(R"("layers": true)"),
       {"layers: expected object {\"thickness\": true", "got boolean"}},
      {"unknown key in layers", Extra(R"("layers": {"fine_scale": false})"),
       {"layers.fine_scale: unknown key \"fine_scale\"; allowed keys for layers: thickness, "
        "muscle_wrinkles, curve_wrinkles"}},
      {"refinement.edge_fraction 0", Extra(R"("refinement": {"edge_fraction": 0})"),
       {"refinement.edge_fraction: expected a number in (0, 1] (fraction of the wrinkle width), "
        "got 0"}},
      {"refinement.edge_fraction 1.5", Extra(R"("refinement": {"edge_fraction": 1.5})"),
       {"refinement.edge_fraction: expected a number in (0, 1]", "got 1.5"}},
      {"refinement.enabled 1", Extra(R"("refinement": {"enabled": 1})"),
       {"refinement.enabled: expected boolean (true or false), got 1"}},
      {"unknown key in refinement", Extra(R"("refinement": {"levels": 2})"),
       {"refinement.levels: unknown key \"levels\"; allowed keys for refinement: enabled, "
        "edge_fraction, falloff_error"}},
      {"refinement.falloff_error -1", Extra(R"("refinement": {"falloff_error": -1})"),
       {"refinement.falloff_error: expected a number in [0, 1) (0 = off), got -1"}},
      {"refinement.falloff_error 1", Extra(R"("refinement": {"falloff_error": 1})"),
       {"refinement.falloff_error: expected a number in [0, 1) (0 = off), got 1"}},
      {"refinement.falloff_error text", Extra(R"("refinement": {"falloff_error": "fine"})"),
       {"refinement.falloff_error: expected a number in [0, 1) (0 = off), got string"}},
      // The jaw (docs/model.md §18).
      {"jaw not an object", Extra(R"("jaw": 3)"), {"jaw: expected object {\"condyles\""}},
      {"jaw without condyles", Extra(R"("jaw": {"range_deg": 20, "mouth": [0, 0, 10], "mouth_width": 40})"),
       {"jaw.condyles: missing required key; expected array of 2 points (the subject's right, "
        "then left condyle"}},
      {"jaw with one condyle", Jaw(R"("condyles": [[-60, 0, -50], [60, 0, -50]])", R"("condyles": [[-60, 0, -50]])"),
       {"jaw.condyles: expected array of 2 points", "got array of 1 elements"}},
      {"jaw condyle of 2 numbers", Jaw(R"([-60, 0, -50])", "[-60, 0]"),
       {"jaw.condyles[0]: expected array of 3 numbers"}},
      {"jaw condyles coincide", Jaw(R"([60, 0, -50])", "[-60, 0, -50]"),
       {"jaw.condyles: the two condyles coincide; expected two distinct points"}},
      {"jaw without range", Jaw(R"("range_deg": 20, )", ""),
       {"jaw.range_deg: missing required key; expected a number in (0, 90] (degrees)"}},
      {"jaw range 0", Jaw(R"("range_deg": 20)", R"("range_deg": 0)"),
       {"jaw.range_deg: expected a number in (0, 90] (degrees), got 0"}},
      {"jaw range 120", Jaw(R"("range_deg": 20)", R"("range_deg": 120)"),
       {"jaw.range_deg: expected a number in (0, 90] (degrees), got 120"}},
      {"jaw range string", Jaw(R"("range_deg": 20)", R"("range_deg": "wide")"),
       {"jaw.range_deg: expected a number in (0, 90] (degrees), got string"}},
      {"jaw without mouth", Jaw(R"("mouth": [0, 0, 10], )", ""),
       {"jaw.mouth: missing required key (jaw.weights is absent); expected a point [x, y, z]"}},
      {"jaw without mouth_width", Jaw(R"(, "mouth_width": 40)", ""),
       {"jaw.mouth_width: missing required key (jaw.weights is absent); expected a number > 0"}},
      {"jaw mouth_width 0", Jaw(R"("mouth_width": 40)", R"("mouth_width": 0)"),
       {"jaw.mouth_width: expected a number > 0 (mouth corner to corner, mesh units), got 0"}},
      {"jaw mouth on the axis", Jaw(R"("mouth": [0, 0, 10])", R"("mouth": [5, 0, -50])"),
       {"jaw.mouth: lies on the hinge axis through the condyles; expected a point in front of them"}},
      {"jaw lip_blend_deg 0", Jaw(R"("mouth_width": 40)", R"("mouth_width": 40, "lip_blend_deg": 0)"),
       {"jaw.lip_blend_deg: expected a number in (0, 45] (degrees), got 0"}},
      {"jaw cheek_blend_deg 100", Jaw(R"("mouth_width": 40)", R"("mouth_width": 40, "cheek_blend_deg": 100)"),
       {"jaw.cheek_blend_deg: expected a number in (0, 90] (degrees), got 100"}},
      {"jaw cheek_drop_deg -1", Jaw(R"("mouth_width": 40)", R"("mouth_width": 40, "cheek_drop_deg": -1)"),
       {"jaw.cheek_drop_deg: expected a number in [0, 45] (degrees), got -1"}},
      {"jaw corner_fade 0.6", Jaw(R"("mouth_width": 40)", R"("mouth_width": 40, "corner_fade": 0.6)"),
       {"jaw.corner_fade: expected a number in [0, 0.5] (a fraction of the mouth width), got 0.6"}},
      {"jaw thickness_fade 1.5", Jaw(R"("mouth_width": 40)", R"("mouth_width": 40, "thickness_fade": 1.5)"),
       {"jaw.thickness_fade: expected a number in [0, 1] (a fraction of the mouth width), got 1.5"}},
      {"jaw thickness_fade text", Jaw(R"("mouth_width": 40)", R"("mouth_width": 40, "thickness_fade": "x")"),
       {"jaw.thickness_fade: expected a number in [0, 1] (a fraction of the mouth width), got string"}},
      {"jaw back reversed", Jaw(R"("mouth_width": 40)", R"("mouth_width": 40, "back": [0.6, 0.2])"),
       {"jaw.back: is [0.6, 0.2]; expected [b0, b1] in [-1, 1] with b0 < b1"}},
      {"jaw back of 3", Jaw(R"("mouth_width": 40)", R"("mouth_width": 40, "back": [0, 0.2, 0.4])"),
       {"jaw.back: expected array of 2 numbers [b0, b1]", "got array of 3 elements"}},
      {"jaw weight 1.5", Jaw(R"("mouth_width": 40)", R"("mouth_width": 40, "weights": [0, 1.5])"),
       {"jaw.weights[1]: expected a number in [0, 1], got 1.5"}},
      {"jaw weight string", Jaw(R"("mouth_width": 40)", R"("mouth_width": 40, "weights": ["x"])"),
       {"jaw.weights[0]: expected a number in [0, 1], got string"}},
      {"unknown key in jaw", Jaw(R"("mouth_width": 40)", R"("mouth_width": 40, "hinge": [0, 0, 0])"),
       {"jaw.hinge: unknown key \"hinge\"; allowed keys for jaw: condyles, range_deg, translation, mouth"}},
      {"jaw translation of 2", Jaw(R"("mouth_width": 40)", R"("mouth_width": 40, "translation": [0, 1])"),
       {"jaw.translation: expected array of 3 numbers [x, y, z] (mesh units)", "got array of 2 elements"}},
      {"jaw translation string", Jaw(R"("mouth_width": 40)", R"("mouth_width": 40, "translation": "down")"),
       {"jaw.translation: expected array of 3 numbers [x, y, z] (mesh units), got string"}},
      {"jaw neck reversed", Jaw(R"("mouth_width": 40)", R"("mouth_width": 40, "neck_deg": [60, 20])"),
       {"jaw.neck_deg: is [60, 20]; expected [n0, n1] in [0, 180] with n0 < n1 (degrees below the lip line about the hinge)"}},
      {"jaw neck beyond 180", Jaw(R"("mouth_width": 40)", R"("mouth_width": 40, "neck_deg": [20, 200])"),
       {"jaw.neck_deg: is [20, 200]; expected [n0, n1] in [0, 180]"}},
      {"jaw neck of 1", Jaw(R"("mouth_width": 40)", R"("mouth_width": 40, "neck_deg": [20])"),
       {"jaw.neck_deg: expected array of 2 numbers [n0, n1]", "got array of 1 elements"}},
      // The eyeballs the lids slide on (docs/model.md §24).
      {"eyes not an object", Extra(R"("eyes": [1])"), {"eyes: expected object {\"spheres\""}},
      {"eyes without spheres", Eyes(R"("spheres": [{"center": [-31, 0, 66], "radius": 12}, {"center": [31, 0, 66], "radius": 12}], )", ""),
       {"eyes.spheres: missing required key; expected array of eyeballs"}},
      {"eyes with no sphere", Eyes(R"([{"center": [-31, 0, 66], "radius": 12}, {"center": [31, 0, 66], "radius": 12}])", "[]"),
       {"eyes.spheres: expected array of eyeballs", "got array of 0 elements"}},
      {"eyes radius 0", Eyes(R"("radius": 12})", R"("radius": 0})"),
       {"eyes.spheres[0].radius: expected a number > 0 (mesh units), got 0"}},
      {"eyes centre of 2", Eyes("[-31, 0, 66]", "[-31, 0]"),
       {"eyes.spheres[0].center: expected array of 3 numbers [x, y, z] (mesh units)", "got array of 2 elements"}},
      {"eyes sphere without centre", Eyes(R"("center": [31, 0, 66], )", ""),
       {"eyes.spheres[1].center: missing required key"}},
      {"eyes without band", Eyes(R"(, "band": [2, 8])", ""),
       {"eyes.band: missing required key; expected array of 2 numbers [b0, b1], 0 <= b0 < b1"}},
      {"eyes band reversed", Eyes("[2, 8]", "[8, 2]"),
       {"eyes.band: is [8, 2]; expected [b0, b1] with 0 <= b0 < b1 (mesh units from an eyeball's surface)"}},
      {"eyes band negative", Eyes("[2, 8]", "[-1, 8]"), {"eyes.band: is [-1, 8]; expected [b0, b1] with 0 <= b0 < b1"}},
      {"eyes band of 3", Eyes("[2, 8]", "[2, 8, 9]"),
       {"eyes.band: expected array of 2 numbers [b0, b1]", "got array of 3 elements"}},
      {"unknown key in eyes", Eyes(R"("band")", R"("hold": 1, "band")"),
       {"eyes.hold: unknown key \"hold\"; allowed keys for eyes: spheres, band"}},
  };
}

TEST(RigJsonTest, EyesParseToTheNumbersWrittenAndWriteBack) {
  RigSpec spec;
  Diagnostics diag;
  ASSERT_TRUE(ParseRigSpec(Extra(R"("eyes": )" + kEyes), "", &spec, &diag)) << diag.Format();
  ASSERT_TRUE(spec.eyes.has_value());
  ASSERT_EQ(spec.eyes->spheres.size(), 2u);
  EXPECT_EQ(spec.eyes->spheres[0].center.x, -31.f);
  EXPECT_EQ(spec.eyes->spheres[1].center.x, 31.f);
  EXPECT_EQ(spec.eyes->spheres[1].center.z, 66.f);
  EXPECT_EQ(spec.eyes->spheres[1].radius, 12.f);
  EXPECT_EQ(spec.eyes->band[0], 2.f);
  EXPECT_EQ(spec.eyes->band[1], 8.f);
  RigSpec again;
  ASSERT_TRUE(ParseRigSpec(RigSpecText(spec, ""), "", &again, &diag)) << diag.Format();
  ASSERT_TRUE(again.eyes.has_value());
  EXPECT_EQ(again.eyes->spheres[0].center.x, -31.f);
  EXPECT_EQ(again.eyes->spheres[1].radius, 12.f);
  EXPECT_EQ(again.eyes->band[1], 8.f);
  RigSpec none;
  ASSERT_TRUE(ParseRigSpec(Doc(), "", &none, &diag));
  EXPECT_FALSE(none.eyes.has_value());
  EXPECT_EQ(RigSpecText(none, "").find("\"eyes\""), std::string::npos);
}

TEST(RigJsonTest, BadInputsAreRejectedWithPathAndExpectation) {
  const std::vector<BadCase> cases = BadCases();
  ASSERT_GE(cases.size(), 65u + 15u);
  for (const BadCase& c : cases) {
    SCOPED_TRACE(c.label);
    RigSpec spec;
    spec.units = "sentinel";
    Diagnostics diag;
    EXPECT_FALSE(ParseRigSpec(c.text, "", &spec, &diag)) << c.text;
    EXPECT_TRUE(diag.HasErrors());
    EXPECT_EQ(spec.units, "sentinel") << "the output must be left alone on failure";
    const std::string formatted = diag.Format();
    EXPECT_EQ(formatted.find('\xff'), std::string::npos) << "messages must be valid UTF-8";
    for (const std::string& needle : c.expected)
      EXPECT_NE(formatted.find(needle), std::string::npos)
          << "expected \"" << needle << "\" in:\n" << formatted << "for:\n" << c.text;
  }
}

TEST(RigJsonTest, WrinkleSectionBadInputsGiveOneMessageEach) {
  // The loader's own checks and the wrinkle module's validators must not both report a problem.
  size_t checked = 0;
  for (const BadCase& c : BadCases()) {
    const std::string& first = c.expected.front();
    const bool new_section = first.rfind("muscles[0].wrinkles", 0) == 0 ||
                             first.rfind("curve_wrinkles", 0) == 0 ||
                             first.rfind("layers", 0) == 0 || first.rfind("refinement", 0) == 0;
    if (!new_section) continue;
    SCOPED_TRACE(c.label);
    RigSpec spec;
    Diagnostics diag;
    EXPECT_FALSE(ParseRigSpec(c.text, "", &spec, &diag));
    EXPECT_EQ(diag.ErrorCount(), 1u) << diag.Format();
    ++checked;
  }
  EXPECT_GE(checked, 40u);
}

TEST(RigJsonTest, LabelsAreDistinct) {
  const std::vector<BadCase> cases = BadCases();
  for (size_t i = 0; i < cases.size(); ++i)
    for (size_t j = i + 1; j < cases.size(); ++j) {
      EXPECT_NE(std::string(cases[i].label), cases[j].label);
      EXPECT_NE(cases[i].text, cases[j].text) << cases[i].label << " / " << cases[j].label;
    }
}

TEST(RigJsonTest, UnsupportedVersionIsTheOnlyError) {
  // A newer file may use keys this build does not know; they are not reported one by one.
  RigSpec spec;
  Diagnostics diag;
  const std::string text = Doc("[" + kLinear + "]", R"(, "wrinkles": [])");
  EXPECT_FALSE(ParseRigSpec(Replace(text, R"("version": 1)", R"("version": 2)"), "", &spec, &diag));
  EXPECT_EQ(diag.ErrorCount(), 1u) << diag.Format();
}

TEST(RigJsonTest, NullOutputsDoNotCrash) {
  Diagnostics diag;
  EXPECT_FALSE(ParseRigSpec(Doc(), "", nullptr, &diag));
  EXPECT_TRUE(diag.HasErrors());
  RigSpec spec;
  EXPECT_TRUE(ParseRigSpec(Doc(), "", &spec, nullptr));
  EXPECT_FALSE(ParseRigSpec("[", "", &spec, nullptr));
}

TEST(RigJsonTest, DeepNestingAndHugeInputDoNotCrash) {
  RigSpec spec;
  Diagnostics diag;
  const std::string deep = std::string(100000, '[') + std::string(100000, ']');
  EXPECT_FALSE(ParseRigSpec(deep, "", &spec, &diag));
  EXPECT_TRUE(diag.Contains("expected the top-level value to be an object"));

  // 1000 bad per-vertex values: the first 20 are listed, the rest summed up in one line.
  std::string values = "[";
  for (int i = 0; i < 1000; ++i) values += std::string(i ? ", " : "") + "\"x\"";
  values += "]";
  diag.Clear();
  EXPECT_FALSE(ParseRigSpec(Thickness(R"({"type": "per_vertex", "values": )" + values + "}"), "",
                            &spec, &diag));
  EXPECT_EQ(diag.ErrorCount(), 21u);
  EXPECT_TRUE(diag.Contains("980 more invalid elements not listed"));
}

// ---------------------------------------------------------------------------------------------
// 2. Every problem is reported, not only the first.

TEST(RigJsonTest, ThreeDistinctErrorsAreAllReported) {
  std::string text = Doc("[" + kLinear + ", " + kSheet + "]");
  text = Replace(text, R"("units": "mm")", R"("units": "furlong")");       // error 1
  text = Replace(text, R"("zone_angle_deg": 40)", R"("zone_angle_deg": 200)");  // error 2
  text = Replace(text, R"("width": 40)", R"("width": -4)");                    // error 3
  RigSpec spec;
  Diagnostics diag;
  EXPECT_FALSE(ParseRigSpec(text, "", &spec, &diag));
  EXPECT_EQ(diag.ErrorCount(), 3u) << diag.Format();
  EXPECT_TRUE(diag.Contains("got \"furlong\""));
  EXPECT_TRUE(diag.Contains("muscles[0].zone_angle_deg"));
  EXPECT_TRUE(diag.Contains("muscles[1].width"));
}

TEST(RigJsonTest, ErrorsInTheWrinkleSectionsAreAllReported) {
  // One error in each new section, and two in one curve: five messages.
  std::string text = Doc("[" + kLinear + ", " + kSheet + "]",
                         R"(, "curve_wrinkles": [)" + kCurve + R"(],
                         "layers": {"thickness": "no"}, "refinement": {"edge_fraction": 2})");
  text = Replace(text, R"("falloff_end": 30)",
                 R"("falloff_end": 30, "wrinkles": {"depth": 1, "count": 0})");   // error 1
  text = Replace(text, R"("width": 3)", R"("width": 0, "profile": "sine")");      // errors 2, 3
  RigSpec spec;
  Diagnostics diag;
  EXPECT_FALSE(ParseRigSpec(text, "", &spec, &diag));
  EXPECT_EQ(diag.ErrorCount(), 5u) << diag.Format();
  EXPECT_TRUE(diag.Contains("muscles[0].wrinkles.count"));
  EXPECT_TRUE(diag.Contains("curve_wrinkles[0].width"));
  EXPECT_TRUE(diag.Contains("curve_wrinkles[0].profile"));
  EXPECT_TRUE(diag.Contains("layers.thickness"));
  EXPECT_TRUE(diag.Contains("refinement.edge_fraction"));
}

TEST(RigJsonTest, WrinklesOfABadMuscleAreStillChecked) {
  // The muscle's zone angle is bad, so phi_c_deg cannot be compared with it, but its other
  // wrinkle keys are still checked; phi_c_deg 170 is only bounded by 180.
  RigSpec spec;
  Diagnostics diag;
  std::string text = LinearW(R"({"depth": -1, "phi_c_deg": 170})");
  text = Replace(text, R"("zone_angle_deg": 40)", R"("zone_angle_deg": 0)");
  EXPECT_FALSE(ParseRigSpec(text, "", &spec, &diag));
  EXPECT_EQ(diag.ErrorCount(), 2u) << diag.Format();
  EXPECT_TRUE(diag.Contains("muscles[0].zone_angle_deg"));
  EXPECT_TRUE(diag.Contains("muscles[0].wrinkles.depth"));
}

// ---------------------------------------------------------------------------------------------
// 3. A valid file parses to exactly the numbers written.

const char* kValidRig = R"({
  "format": "mimetic-rig",
  "version": 1,
  "mesh": { "path": "meshes/surface.obj", "name": "Head" },
  "units": "cm",
  "thickness": { "type": "image", "path": "thickness.png", "min": 0.5, "max": 2.25 },
  "muscles": [
    { "name": "zygomatic_major_L", "type": "linear", "strength": 4.0,
      "attachment": [1.5, -2.25, 30.125], "insertion": [0.1, 7, -8],
      "zone_angle_deg": 40, "falloff_start": 10, "falloff_end": 30.5 },
    { "name": "frontalis_inner_L", "type": "sheet", "strength": 3.0,
      "attachment": [[-10, 20, 5], [10, 20, 5]], "insertion": [[-12, 70, 9], [12, 70, 9]],
      "length": 50, "width": 40, "falloff_start": 20 }
  ]
})";

void ExpectVec(float3 v, float x, float y, float z) {
  EXPECT_EQ(v.x, x);
  EXPECT_EQ(v.y, y);
  EXPECT_EQ(v.z, z);
}

TEST(RigJsonTest, ValidFileParsesToTheNumbersWritten) {
  RigSpec spec;
  Diagnostics diag;
  ASSERT_TRUE(ParseRigSpec(kValidRig, "/data/rigs", &spec, &diag)) << diag.Format();
  EXPECT_TRUE(diag.empty());
  EXPECT_EQ(spec.file, "");
  EXPECT_EQ(spec.mesh_path, "/data/rigs/meshes/surface.obj");
  EXPECT_EQ(spec.mesh_name, "Head");
  EXPECT_EQ(spec.units, "cm");
  EXPECT_EQ(spec.thickness.kind, ThicknessSpec::Kind::kImage);
  EXPECT_EQ(spec.thickness.image_path, "/data/rigs/thickness.png");
  EXPECT_EQ(spec.thickness.min, 0.5f);
  EXPECT_EQ(spec.thickness.max, 2.25f);
  ASSERT_EQ(spec.muscles.size(), 2u);

  const MuscleSpec& lin = spec.muscles[0];
  EXPECT_EQ(lin.name, "zygomatic_major_L");
  EXPECT_EQ(lin.type, MuscleType::kLinear);
  EXPECT_EQ(lin.strength, 4.f);
  ExpectVec(lin.linear.attachment, 1.5f, -2.25f, 30.125f);
  ExpectVec(lin.linear.insertion, 0.1f, 7.f, -8.f);
  // 40 degrees = 40 * pi / 180 = 2 pi / 9 = 0.6981317007977318 rad.
  EXPECT_FLOAT_EQ(lin.linear.zone_angle, static_cast<float>(40.0 * std::numbers::pi / 180.0));
  EXPECT_NEAR(lin.linear.zone_angle, 0.6981317007977318, 1e-7);
  EXPECT_EQ(lin.linear.falloff_start, 10.f);
  EXPECT_EQ(lin.linear.falloff_end, 30.5f);

  const MuscleSpec& sheet = spec.muscles[1];
  EXPECT_EQ(sheet.name, "frontalis_inner_L");
  EXPECT_EQ(sheet.type, MuscleType::kSheet);
  EXPECT_EQ(sheet.strength, 3.f);
  ExpectVec(sheet.sheet.attachment[0], -10.f, 20.f, 5.f);
  ExpectVec(sheet.sheet.attachment[1], 10.f, 20.f, 5.f);
  ExpectVec(sheet.sheet.insertion[0], -12.f, 70.f, 9.f);
  ExpectVec(sheet.sheet.insertion[1], 12.f, 70.f, 9.f);
  EXPECT_EQ(sheet.sheet.length, 50.f);
  EXPECT_EQ(sheet.sheet.width, 40.f);
  EXPECT_EQ(sheet.sheet.falloff_start, 20.f);
}

TEST(RigJsonTest, PathsResolveAgainstTheBaseDirectory) {
  RigSpec spec;
  Diagnostics diag;
  ASSERT_TRUE(ParseRigSpec(kValidRig, "", &spec, &diag)) << diag.Format();
  EXPECT_EQ(spec.mesh_path, "meshes/surface.obj");  // "" = relative to the current directory
  EXPECT_EQ(spec.thickness.image_path, "thickness.png");
  ASSERT_TRUE(ParseRigSpec(kValidRig, "rigs/", &spec, &diag));
  EXPECT_EQ(spec.mesh_path, "rigs/meshes/surface.obj");
  const std::string absolute =
      Replace(kValidRig, R"("meshes/surface.obj")", R"("/abs/surface.obj")");
  ASSERT_TRUE(ParseRigSpec(absolute, "/data/rigs", &spec, &diag));
  EXPECT_EQ(spec.mesh_path, "/abs/surface.obj");
}

const char* kValidWrinkleRig = R"({
  "format": "mimetic-rig",
  "version": 1,
  "mesh": { "path": "surface.obj" },
  "units": "mm",
  "muscles": [
    { "name": "zygomatic_major_L", "type": "linear", "strength": 4.0,
      "attachment": [0, 0, 0], "insertion": [10, 0, 0],
      "zone_angle_deg": 40, "falloff_start": 10, "falloff_end": 30,
      "wrinkles": { "lambda_w": 0.625, "count": 4, "depth": 1.5, "shape": -0.75,
                    "phi_c_deg": 10 } },
    { "name": "frontalis_inner_L", "type": "sheet", "strength": 3.0,
      "attachment": [[0, 0, 0], [10, 0, 0]], "insertion": [[0, 50, 0], [10, 50, 0]],
      "length": 50, "width": 40, "falloff_start": 20,
      "wrinkles": { "lambda_w": 0.25, "count": 6, "depth": 0.5, "shape": 2, "h_c": 5.5 } },
    { "name": "buccinator_L", "type": "linear", "strength": 1,
      "attachment": [0, 0, 0], "insertion": [0, 10, 0],
      "zone_angle_deg": 30, "falloff_start": 5, "falloff_end": 20,
      "wrinkles": { "depth": 0.25 } }
  ],
  "curve_wrinkles": [
    { "name": "nasolabial_L", "control": [[0.125, 0.5], [0.25, 0.375], [0.375, 0.25], [0.5, 0.125]],
      "depth": 2.0, "width": 3.0, "profile": "yang_zhang", "modulation": "area",
      "rest_amplitude": 0.75 },
    { "name": "crow_L", "control": [[-1, 2], [3, -4], [0.1, 0.2], [1e-3, 7]],
      "depth": 0.5, "width": 1.25 },
    { "name": "brow_L", "control": [[0, 0], [0, 1], [1, 1], [1, 0]],
      "depth": 1, "width": 1, "profile": "yang_zhang_exact", "modulation": "directional",
      "rest_amplitude": 1 }
  ],
  "layers": { "thickness": false, "muscle_wrinkles": true, "curve_wrinkles": false },
  "refinement": { "enabled": false, "edge_fraction": 0.5 }
})";

void ExpectControl(const CurveWrinkleSpec& c, std::vector<float> xy) {
  ASSERT_EQ(xy.size(), 8u);
  for (int k = 0; k < 4; ++k) {
    EXPECT_EQ(c.control[k].x, xy[2 * k]) << k;
    EXPECT_EQ(c.control[k].y, xy[2 * k + 1]) << k;
  }
}

TEST(RigJsonTest, ValidWrinkleFileParsesToTheNumbersWritten) {
  RigSpec spec;
  Diagnostics diag;
  ASSERT_TRUE(ParseRigSpec(kValidWrinkleRig, "", &spec, &diag)) << diag.Format();
  EXPECT_TRUE(diag.empty()) << diag.Format();
  ASSERT_EQ(spec.muscles.size(), 3u);
  ASSERT_EQ(spec.muscle_wrinkles.size(), 3u);
  ASSERT_TRUE(spec.muscle_wrinkles[0].has_value());
  ASSERT_TRUE(spec.muscle_wrinkles[1].has_value());
  ASSERT_TRUE(spec.muscle_wrinkles[2].has_value());

  const MuscleWrinkleSpec& lin = *spec.muscle_wrinkles[0];
  EXPECT_EQ(lin.lambda_w, 0.625f);
  EXPECT_EQ(lin.count, 4);
  EXPECT_EQ(lin.depth, 1.5f);
  EXPECT_EQ(lin.shape, -0.75f);
  // 10 degrees = pi / 18 = 0.17453292519943295 rad (rounded to a float once).
  EXPECT_EQ(lin.phi_c, static_cast<float>(std::numbers::pi / 18.0));
  EXPECT_NEAR(lin.phi_c, 0.17453292519943295, 1e-8);
  EXPECT_EQ(lin.h_c, 0.f);

  const MuscleWrinkleSpec& sheet = *spec.muscle_wrinkles[1];
  EXPECT_EQ(sheet.lambda_w, 0.25f);
  EXPECT_EQ(sheet.count, 6);
  EXPECT_EQ(sheet.depth, 0.5f);
  EXPECT_EQ(sheet.shape, 2.f);
  EXPECT_EQ(sheet.h_c, 5.5f);
  EXPECT_EQ(sheet.phi_c, 0.f);

  // Only depth given: the documented defaults lambda_w 0.5, count 3, shape 0, phi_c_deg 0.
  const MuscleWrinkleSpec& defaults = *spec.muscle_wrinkles[2];
  EXPECT_EQ(defaults.lambda_w, 0.5f);
  EXPECT_EQ(defaults.count, 3);
  EXPECT_EQ(defaults.depth, 0.25f);
  EXPECT_EQ(defaults.shape, 0.f);
  EXPECT_EQ(defaults.phi_c, 0.f);

  ASSERT_EQ(spec.curve_wrinkles.size(), 3u);
  const NamedCurveWrinkle& c0 = spec.curve_wrinkles[0];
  EXPECT_EQ(c0.name, "nasolabial_L");
  ExpectControl(c0.spec, {0.125f, 0.5f, 0.25f, 0.375f, 0.375f, 0.25f, 0.5f, 0.125f});
  EXPECT_EQ(c0.spec.depth, 2.f);
  EXPECT_EQ(c0.spec.width, 3.f);
  EXPECT_EQ(c0.spec.profile, CurveWrinkleProfile::kYangZhang);
  EXPECT_EQ(c0.spec.modulation, CurveWrinkleModulation::kArea);
  EXPECT_EQ(c0.spec.rest_amplitude, 0.75f);
  // Defaults: Bando profile, directional modulation, rest amplitude 0.
  const NamedCurveWrinkle& c1 = spec.curve_wrinkles[1];
  EXPECT_EQ(c1.name, "crow_L");
  ExpectControl(c1.spec, {-1.f, 2.f, 3.f, -4.f, 0.1f, 0.2f, 1e-3f, 7.f});
  EXPECT_EQ(c1.spec.depth, 0.5f);
  EXPECT_EQ(c1.spec.width, 1.25f);
  EXPECT_EQ(c1.spec.profile, CurveWrinkleProfile::kBando);
  EXPECT_EQ(c1.spec.modulation, CurveWrinkleModulation::kDirectional);
  EXPECT_EQ(c1.spec.rest_amplitude, 0.f);
  const NamedCurveWrinkle& c2 = spec.curve_wrinkles[2];
  EXPECT_EQ(c2.name, "brow_L");
  EXPECT_EQ(c2.spec.profile, CurveWrinkleProfile::kYangZhangExact);
  EXPECT_EQ(c2.spec.modulation, CurveWrinkleModulation::kDirectional);
  EXPECT_EQ(c2.spec.rest_amplitude, 1.f);

  EXPECT_FALSE(spec.layers.thickness);
  EXPECT_TRUE(spec.layers.muscle_wrinkles);
  EXPECT_FALSE(spec.layers.curve_wrinkles);
  EXPECT_FALSE(spec.refinement.enabled);
  EXPECT_EQ(spec.refinement.edge_fraction, 0.5f);
}

TEST(RigJsonTest, WrinkleSectionDefaults) {
  RigSpec spec;
  Diagnostics diag;
  ASSERT_TRUE(ParseRigSpec(Doc("[" + kLinear + ", " + kSheet + "]"), "", &spec, &diag))
      << diag.Format();
  // muscle_wrinkles is always parallel to muscles; no block = nullopt.
  ASSERT_EQ(spec.muscle_wrinkles.size(), 2u);
  EXPECT_FALSE(spec.muscle_wrinkles[0].has_value());
  EXPECT_FALSE(spec.muscle_wrinkles[1].has_value());
  EXPECT_TRUE(spec.curve_wrinkles.empty());
  EXPECT_TRUE(spec.layers.thickness);
  EXPECT_TRUE(spec.layers.muscle_wrinkles);
  EXPECT_TRUE(spec.layers.curve_wrinkles);
  EXPECT_TRUE(spec.refinement.enabled);
  EXPECT_EQ(spec.refinement.edge_fraction, 0.25f);

  // Only the sheet muscle has wrinkles: index 1 is set, index 0 is not.
  ASSERT_TRUE(ParseRigSpec(Doc("[" + kLinear + ", " +
                               Replace(kSheet, R"("falloff_start": 20)",
                                       R"("falloff_start": 20, "wrinkles": {"depth": 2})") +
                               "]"),
                           "", &spec, &diag))
      << diag.Format();
  ASSERT_EQ(spec.muscle_wrinkles.size(), 2u);
  EXPECT_FALSE(spec.muscle_wrinkles[0].has_value());
  ASSERT_TRUE(spec.muscle_wrinkles[1].has_value());
  EXPECT_EQ(spec.muscle_wrinkles[1]->depth, 2.f);
  EXPECT_EQ(spec.muscle_wrinkles[1]->h_c, 0.f);

  // Partial layers / refinement objects keep the defaults of the keys left out.
  ASSERT_TRUE(ParseRigSpec(Extra(R"("layers": {"muscle_wrinkles": false},
                                    "refinement": {"edge_fraction": 1})"),
                           "", &spec, &diag))
      << diag.Format();
  EXPECT_TRUE(spec.layers.thickness);
  EXPECT_FALSE(spec.layers.muscle_wrinkles);
  EXPECT_TRUE(spec.layers.curve_wrinkles);
  EXPECT_TRUE(spec.refinement.enabled);
  EXPECT_EQ(spec.refinement.edge_fraction, 1.f);
  // A whole-number float is an integer count (as in JSON Schema); h_c just under width/2 is fine.
  ASSERT_TRUE(ParseRigSpec(SheetW(R"({"depth": 1, "count": 2.0, "h_c": 19.5})"), "", &spec, &diag))
      << diag.Format();
  EXPECT_EQ(spec.muscle_wrinkles[0]->count, 2);
  EXPECT_EQ(spec.muscle_wrinkles[0]->h_c, 19.5f);
  EXPECT_TRUE(diag.empty()) << diag.Format();
}

TEST(RigJsonTest, DefaultsAndOtherThicknessKinds) {
  RigSpec spec;
  Diagnostics diag;
  ASSERT_TRUE(ParseRigSpec(Doc("[]"), "", &spec, &diag)) << diag.Format();
  EXPECT_EQ(spec.thickness.kind, ThicknessSpec::Kind::kConstant);
  EXPECT_EQ(spec.thickness.value, 0.f);
  EXPECT_EQ(spec.mesh_name, "");
  EXPECT_TRUE(spec.muscles.empty());

  ASSERT_TRUE(ParseRigSpec(Thickness(R"({"type": "constant", "value": 3})"), "", &spec, &diag));
  EXPECT_EQ(spec.thickness.kind, ThicknessSpec::Kind::kConstant);
  EXPECT_EQ(spec.thickness.value, 3.f);

  ASSERT_TRUE(ParseRigSpec(Thickness(R"({"type": "per_vertex", "values": [0, 1.5, 0.25]})"), "",
                           &spec, &diag));
  EXPECT_EQ(spec.thickness.kind, ThicknessSpec::Kind::kPerVertex);
  EXPECT_EQ(spec.thickness.per_vertex, (std::vector<float>{0.f, 1.5f, 0.25f}));
  EXPECT_TRUE(diag.empty()) << diag.Format();
}

// ---------------------------------------------------------------------------------------------
// 4. Save / load.

RigSpec SampleSpec(const std::string& dir) {
  RigSpec spec;
  spec.mesh_path = dir + "/surface.glb";
  spec.mesh_name = "face";
  spec.units = "in";
  MuscleSpec lin;
  lin.name = "zygomatic_major_L";
  lin.type = MuscleType::kLinear;
  lin.strength = 0.1f;
  lin.linear.attachment = {1.f / 3.f, -2.5e-7f, 123456.78f};
  lin.linear.insertion = {0.3f, 0.2f, -0.7f};
  lin.linear.zone_angle = 0.7f;  // radians, not a round number of degrees
  lin.linear.falloff_start = 1.f / 7.f;
  lin.linear.falloff_end = 2.9f;
  MuscleSpec sheet;
  sheet.name = "frontalis_inner_L";
  sheet.type = MuscleType::kSheet;
  sheet.strength = 3.3f;
  sheet.sheet.attachment[0] = {-1.1f, 2.2f, 3.3f};
  sheet.sheet.attachment[1] = {1.1f, 2.2f, 3.3f};
  sheet.sheet.insertion[0] = {-1.2f, 7.1f, 0.9f};
  sheet.sheet.insertion[1] = {1.2f, 7.1f, 0.9f};
  sheet.sheet.length = 5.1f;
  sheet.sheet.width = 4.3f;
  sheet.sheet.falloff_start = 2.05f;
  sheet.falloff = MuscleFalloff::kSmooth;
  sheet.motion = MuscleMotion::kTangent;
  sheet.tangent_radius = 2.f / 3.f;  // not a round number in decimal
  spec.muscles = {lin, sheet};
  return spec;
}

// SampleSpec with a wrinkle block on each muscle, three curve wrinkles and non-default layers
// and refinement.
RigSpec SampleWrinkleSpec(const std::string& dir) {
  RigSpec spec = SampleSpec(dir);
  MuscleWrinkleSpec lw;
  lw.lambda_w = 0.3f;
  lw.count = 7;
  lw.depth = 1.f / 3.f;
  lw.shape = -0.1f;
  lw.phi_c = 0.1f;  // radians, below the zone angle 0.7, not a round number of degrees
  lw.gate = 0.35f;  // the sheet's stays 0: no gate, and no key in the file
  MuscleWrinkleSpec sw;
  sw.lambda_w = 0.f;
  sw.count = 1;
  sw.depth = 0.f;
  sw.shape = 2.5f;
  sw.h_c = 2.1f;  // < width/2 = 2.15
  spec.muscle_wrinkles = {lw, sw};
  NamedCurveWrinkle a;
  a.name = "nasolabial_L";
  a.spec.control[0] = {0.1f, 0.2f};
  a.spec.control[1] = {1.f / 3.f, -2.5e-7f};
  a.spec.control[2] = {0.7f, 0.45f};
  a.spec.control[3] = {0.9f, 123.456f};
  a.spec.depth = 0.2f;
  a.spec.width = 0.35f;
  a.spec.profile = CurveWrinkleProfile::kYangZhangExact;
  a.spec.modulation = CurveWrinkleModulation::kArea;
  a.spec.rest_amplitude = 0.3f;
  NamedCurveWrinkle b = a;
  b.name = "forehead_1";
  b.spec.profile = CurveWrinkleProfile::kBando;
  b.spec.modulation = CurveWrinkleModulation::kDirectional;
  b.spec.rest_amplitude = 1.f;
  NamedCurveWrinkle c = a;
  c.name = "forehead_2";
  c.spec.profile = CurveWrinkleProfile::kYangZhang;
  c.spec.rest_amplitude = 0.f;
  spec.curve_wrinkles = {a, b, c};
  spec.layers.thickness = false;
  spec.layers.curve_wrinkles = false;
  spec.refinement.enabled = false;
  spec.refinement.edge_fraction = 0.1f;
  return spec;
}

void ExpectSameSpec(const RigSpec& a, const RigSpec& b) {
  EXPECT_EQ(a.file, b.file);
  EXPECT_EQ(a.mesh_path, b.mesh_path);
  EXPECT_EQ(a.mesh_name, b.mesh_name);
  EXPECT_EQ(a.units, b.units);
  EXPECT_EQ(a.thickness.kind, b.thickness.kind);
  EXPECT_EQ(a.thickness.value, b.thickness.value);
  EXPECT_EQ(a.thickness.per_vertex, b.thickness.per_vertex);
  EXPECT_EQ(a.thickness.image_path, b.thickness.image_path);
  EXPECT_EQ(a.thickness.min, b.thickness.min);
  EXPECT_EQ(a.thickness.max, b.thickness.max);
  ASSERT_EQ(a.muscles.size(), b.muscles.size());
  for (size_t i = 0; i < a.muscles.size(); ++i) {
    const MuscleSpec& x = a.muscles[i];
    const MuscleSpec& y = b.muscles[i];
    SCOPED_TRACE(x.name);
    EXPECT_EQ(x.name, y.name);
    EXPECT_EQ(x.type, y.type);
    EXPECT_EQ(x.strength, y.strength);
    EXPECT_EQ(x.falloff, y.falloff);
    EXPECT_EQ(x.motion, y.motion);
    EXPECT_EQ(x.tangent_radius, y.tangent_radius);
    if (x.type == MuscleType::kLinear) {
      EXPECT_EQ(x.linear.attachment, y.linear.attachment);
      EXPECT_EQ(x.linear.insertion, y.linear.insertion);
      EXPECT_EQ(x.linear.zone_angle, y.linear.zone_angle);
      EXPECT_EQ(x.linear.falloff_start, y.linear.falloff_start);
      EXPECT_EQ(x.linear.falloff_end, y.linear.falloff_end);
    } else {
      for (int k = 0; k < 2; ++k) {
        EXPECT_EQ(x.sheet.attachment[k], y.sheet.attachment[k]);
        EXPECT_EQ(x.sheet.insertion[k], y.sheet.insertion[k]);
      }
      EXPECT_EQ(x.sheet.length, y.sheet.length);
      EXPECT_EQ(x.sheet.width, y.sheet.width);
      EXPECT_EQ(x.sheet.falloff_start, y.sheet.falloff_start);
    }
    // An empty muscle_wrinkles vector means no muscle has wrinkles.
    const bool xw = i < a.muscle_wrinkles.size() && a.muscle_wrinkles[i].has_value();
    const bool yw = i < b.muscle_wrinkles.size() && b.muscle_wrinkles[i].has_value();
    EXPECT_EQ(xw, yw);
    if (xw && yw) {
      const MuscleWrinkleSpec& p = *a.muscle_wrinkles[i];
      const MuscleWrinkleSpec& q = *b.muscle_wrinkles[i];
      EXPECT_EQ(p.lambda_w, q.lambda_w);
      EXPECT_EQ(p.count, q.count);
      EXPECT_EQ(p.depth, q.depth);
      EXPECT_EQ(p.shape, q.shape);
      EXPECT_EQ(p.phi_c, q.phi_c);
      EXPECT_EQ(p.h_c, q.h_c);
      EXPECT_EQ(p.gate, q.gate);
    }
  }
  ASSERT_EQ(a.curve_wrinkles.size(), b.curve_wrinkles.size());
  for (size_t i = 0; i < a.curve_wrinkles.size(); ++i) {
    const NamedCurveWrinkle& x = a.curve_wrinkles[i];
    const NamedCurveWrinkle& y = b.curve_wrinkles[i];
    SCOPED_TRACE(x.name);
    EXPECT_EQ(x.name, y.name);
    for (int k = 0; k < 4; ++k) {
      EXPECT_EQ(x.spec.control[k].x, y.spec.control[k].x);
      EXPECT_EQ(x.spec.control[k].y, y.spec.control[k].y);
    }
    EXPECT_EQ(x.spec.depth, y.spec.depth);
    EXPECT_EQ(x.spec.width, y.spec.width);
    EXPECT_EQ(x.spec.profile, y.spec.profile);
    EXPECT_EQ(x.spec.modulation, y.spec.modulation);
    EXPECT_EQ(x.spec.rest_amplitude, y.spec.rest_amplitude);
  }
  EXPECT_EQ(a.layers.thickness, b.layers.thickness);
  EXPECT_EQ(a.layers.muscle_wrinkles, b.layers.muscle_wrinkles);
  EXPECT_EQ(a.layers.curve_wrinkles, b.layers.curve_wrinkles);
  EXPECT_EQ(a.refinement.enabled, b.refinement.enabled);
  EXPECT_EQ(a.refinement.edge_fraction, b.refinement.edge_fraction);
}

std::string ReadText(const std::string& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

std::vector<std::string> ListDir(const std::string& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

TEST(RigJsonTest, SaveLoadRoundTripForEveryThicknessKind) {
  const std::string dir = test::TempDir();
  for (int kind = 0; kind < 3; ++kind) {
    SCOPED_TRACE(kind);
    RigSpec spec = SampleSpec(dir);
    if (kind == 0) {
      spec.thickness.kind = ThicknessSpec::Kind::kConstant;
      spec.thickness.value = 0.3f;
    } else if (kind == 1) {
      spec.thickness.kind = ThicknessSpec::Kind::kPerVertex;
      spec.thickness.per_vertex = {0.f, 0.1f, 1e-3f, 7.77f, 3.4e38f};
    } else {
      spec.thickness.kind = ThicknessSpec::Kind::kImage;
      spec.thickness.image_path = dir + "/maps/thickness.png";
      spec.thickness.min = 0.2f;
      spec.thickness.max = 0.2f;  // min == max is allowed
    }
    const std::string path = dir + "/rig" + std::to_string(kind) + ".rig.json";
    spec.file = path;
    Diagnostics diag;
    ASSERT_TRUE(SaveRigSpec(path, spec, &diag)) << diag.Format();
    RigSpec loaded;
    ASSERT_TRUE(LoadRigSpec(path, &loaded, &diag)) << diag.Format();
    EXPECT_TRUE(diag.empty()) << diag.Format();
    ExpectSameSpec(spec, loaded);
  }
  // Atomic save: only the three rig files are there, no temporary file left behind.
  EXPECT_EQ(ListDir(dir), (std::vector<std::string>{"rig0.rig.json", "rig1.rig.json",
                                                     "rig2.rig.json"}));
  // The image path inside the rig's directory is written relative to it.
  EXPECT_NE(ReadText(dir + "/rig2.rig.json").find(R"("path": "maps/thickness.png")"),
            std::string::npos);
}

TEST(RigJsonTest, FineScaleParsesToTheNumbersWrittenAndRoundTrips) {
  const std::string dir = test::TempDir();
  const std::string text = Extra(R"("fine_scale": {
      "fields": [{"name": "across", "vectors": [{"vertex": 3, "vector": [0.5, 0, 0]},
                                                 {"vertex": 7, "vector": [0, 0.25, 0], "weight": 2}]},
                 {"name": "along", "vectors": [{"vertex": 1, "vector": [0, 1.5, 0]}]}],
      "interpolation": "inverse_distance", "texture_space": "planar",
      "minimize_distortion": true, "parameters": "bando2001", "k_scale": 2, "k_noise": 0.1,
      "k_bump": 4, "rest_amplitude": 0.25,
      "maps": {"height": ["maps/h1.png", "maps/h2.png"], "normal": "maps/n.png"}})");
  RigSpec spec;
  Diagnostics diag;
  ASSERT_TRUE(ParseRigSpec(text, dir, &spec, &diag)) << diag.Format();
  ASSERT_TRUE(spec.fine_scale.has_value());
  const FineScaleSpec& f = *spec.fine_scale;
  EXPECT_EQ(f.fields[0].name, "across");
  ASSERT_EQ(f.fields[0].anchors.size(), 2u);
  EXPECT_EQ(f.fields[0].anchors[1].vertex, 7u);
  EXPECT_FLOAT_EQ(f.fields[0].anchors[1].vector.y, 0.25f);
  EXPECT_FLOAT_EQ(f.fields[0].anchors[1].weight, 2.f);
  EXPECT_FLOAT_EQ(f.fields[1].anchors[0].vector.y, 1.5f);  // bando2001 allows up to 2
  EXPECT_EQ(f.interpolation, FieldInterpolation::kInverseDistance);
  EXPECT_EQ(f.projection, TextureProjection::kPlanar);
  EXPECT_TRUE(f.minimize_distortion);
  EXPECT_EQ(f.parameters, FurrowParameterSet::kBando2001);
  EXPECT_FLOAT_EQ(f.k_scale, 2.f);
  EXPECT_FLOAT_EQ(f.k_noise, 0.1f);
  EXPECT_FLOAT_EQ(f.k_bump, 4.f);
  EXPECT_FLOAT_EQ(f.rest_amplitude, 0.25f);
  EXPECT_EQ(f.height_maps[1], (fs::path(dir) / "maps/h2.png").lexically_normal().string());
  EXPECT_EQ(f.normal_map, (fs::path(dir) / "maps/n.png").lexically_normal().string());
  // Save, load, save: the same text; the map paths stay relative.
  spec.mesh_path = dir + "/surface.obj";
  const std::string path = dir + "/fine.rig.json", path2 = dir + "/fine2.rig.json";
  ASSERT_TRUE(SaveRigSpec(path, spec, &diag)) << diag.Format();
  RigSpec loaded;
  ASSERT_TRUE(LoadRigSpec(path, &loaded, &diag)) << diag.Format();
  ASSERT_TRUE(loaded.fine_scale.has_value());
  EXPECT_EQ(loaded.fine_scale->normal_map, f.normal_map);
  ASSERT_TRUE(SaveRigSpec(path2, loaded, &diag)) << diag.Format();
  EXPECT_EQ(ReadText(path), ReadText(path2));
  EXPECT_NE(ReadText(path).find(R"("normal": "maps/n.png")"), std::string::npos) << ReadText(path);
  // Defaults.
  RigSpec plain;
  ASSERT_TRUE(ParseRigSpec(Extra(R"("fine_scale": {"fields": [{"name": "a", "vectors": [{"vertex": 0, "vector": [1, 0, 0]}]}, {"name": "b", "vectors": [{"vertex": 1, "vector": [0, 1, 0]}]}]})"),
                           dir, &plain, &diag)) << diag.Format();
  EXPECT_EQ(plain.fine_scale->interpolation, FieldInterpolation::kHarmonic);
  EXPECT_EQ(plain.fine_scale->projection, TextureProjection::kAuto);
  EXPECT_EQ(plain.fine_scale->parameters, FurrowParameterSet::kBando2002);
  EXPECT_FLOAT_EQ(plain.fine_scale->rest_amplitude, 0.5f);
  EXPECT_FLOAT_EQ(plain.fine_scale->k_bump, 1.f);
  EXPECT_TRUE(plain.fine_scale->normal_map.empty());
}

TEST(RigJsonTest, SaveLoadRoundTripWithWrinklesLayersAndRefinement) {
  const std::string dir = test::TempDir();
  RigSpec spec = SampleWrinkleSpec(dir);
  const std::string path = dir + "/wrinkles.rig.json";
  spec.file = path;
  Diagnostics diag;
  ASSERT_TRUE(SaveRigSpec(path, spec, &diag)) << diag.Format();
  RigSpec loaded;
  ASSERT_TRUE(LoadRigSpec(path, &loaded, &diag)) << diag.Format();
  EXPECT_TRUE(diag.empty()) << diag.Format();
  ExpectSameSpec(spec, loaded);
  // Saving the loaded spec again gives the same text.
  const std::string path2 = dir + "/again.rig.json";
  ASSERT_TRUE(SaveRigSpec(path2, loaded, &diag)) << diag.Format();
  EXPECT_EQ(ReadText(path), ReadText(path2));

  // One muscle without wrinkles; an empty muscle_wrinkles vector means none at all.
  spec.muscle_wrinkles[0].reset();
  ASSERT_TRUE(SaveRigSpec(path, spec, &diag)) << diag.Format();
  ASSERT_TRUE(LoadRigSpec(path, &loaded, &diag)) << diag.Format();
  ExpectSameSpec(spec, loaded);
  spec.muscle_wrinkles.clear();
  ASSERT_TRUE(SaveRigSpec(path, spec, &diag)) << diag.Format();
  ASSERT_TRUE(LoadRigSpec(path, &loaded, &diag)) << diag.Format();
  ExpectSameSpec(spec, loaded);
  EXPECT_EQ(loaded.muscle_wrinkles.size(), 2u);
  EXPECT_EQ(ReadText(path).find("\"wrinkles\""), std::string::npos) << ReadText(path);
}

TEST(RigJsonTest, SavedWrinkleTextHasTheDocumentedLayout) {
  const std::string dir = test::TempDir();
  RigSpec spec = SampleWrinkleSpec(dir);
  spec.muscle_wrinkles[0]->phi_c = static_cast<float>(12.0 * std::numbers::pi / 180.0);
  const std::string path = dir + "/head.rig.json";
  Diagnostics diag;
  ASSERT_TRUE(SaveRigSpec(path, spec, &diag)) << diag.Format();
  const std::string text = ReadText(path);
  const char* keys[] = {"\n  \"muscles\": [",
                        "\"name\": \"zygomatic_major_L\"",
                        "\"falloff_end\": 2.9",
                        "\n      \"wrinkles\": {",
                        "\n        \"lambda_w\": 0.3",
                        "\"count\": 7,",
                        "\"depth\": 0.33333334",
                        "\"shape\": -0.1",
                        "\"phi_c_deg\": 12.0",
                        "\"gate\": 0.35",
                        "\"name\": \"frontalis_inner_L\"",
                        "\"falloff_start\": 2.05",
                        "\"wrinkles\": {",
                        "\"lambda_w\": 0.0",
                        "\"count\": 1,",
                        "\"shape\": 2.5",
                        "\"h_c\": 2.1",
                        "\n  \"curve_wrinkles\": [",
                        "\"name\": \"nasolabial_L\"",
                        "\"control\": [",
                        "0.1,",
                        "123.456",
                        "\"depth\": 0.2",
                        "\"width\": 0.35",
                        "\"profile\": \"yang_zhang_exact\"",
                        "\"modulation\": \"area\"",
                        "\"rest_amplitude\": 0.3",
                        "\"name\": \"forehead_1\"",
                        "\"profile\": \"bando\"",
                        "\"modulation\": \"directional\"",
                        "\"name\": \"forehead_2\"",
                        "\"profile\": \"yang_zhang\"",
                        "\n  \"layers\": {",
                        "\"thickness\": false",
                        "\"muscle_wrinkles\": true",
                        "\"curve_wrinkles\": false",
                        "\n  \"refinement\": {",
                        "\"enabled\": false",
                        "\"edge_fraction\": 0.1"};
  size_t at = 0;
  for (const char* key : keys) {
    const size_t found = text.find(key, at);
    EXPECT_NE(found, std::string::npos) << "missing or out of order: " << key << "\n" << text;
    if (found != std::string::npos) at = found;
  }
  // The attenuation key of the other muscle type is not written.
  EXPECT_EQ(text.find("\"h_c\""), text.rfind("\"h_c\""));
  EXPECT_EQ(text.find("\"phi_c_deg\""), text.rfind("\"phi_c_deg\""));
  // Nor a gate of 0 (no gate, the default): only the linear muscle's.
  EXPECT_EQ(text.find("\"gate\""), text.rfind("\"gate\""));
  EXPECT_EQ(text.find("0000000"), std::string::npos) << text;

  // Defaults are not written: no curve_wrinkles, layers or refinement block.
  RigSpec plain = SampleSpec(dir);
  ASSERT_TRUE(SaveRigSpec(path, plain, &diag)) << diag.Format();
  const std::string plain_text = ReadText(path);
  EXPECT_EQ(plain_text.find("curve_wrinkles"), std::string::npos) << plain_text;
  EXPECT_EQ(plain_text.find("layers"), std::string::npos) << plain_text;
  EXPECT_EQ(plain_text.find("refinement"), std::string::npos) << plain_text;
  EXPECT_EQ(plain_text.find("wrinkles"), std::string::npos) << plain_text;
  // Any one switch off, or another edge fraction, writes the block.
  plain.layers.muscle_wrinkles = false;
  ASSERT_TRUE(SaveRigSpec(path, plain, &diag)) << diag.Format();
  EXPECT_NE(ReadText(path).find("\"muscle_wrinkles\": false"), std::string::npos);
  EXPECT_EQ(ReadText(path).find("refinement"), std::string::npos);
  plain.layers = SkinLayers();
  plain.refinement.edge_fraction = 0.5f;
  ASSERT_TRUE(SaveRigSpec(path, plain, &diag)) << diag.Format();
  EXPECT_NE(ReadText(path).find("\"edge_fraction\": 0.5"), std::string::npos);
  EXPECT_NE(ReadText(path).find("\"enabled\": true"), std::string::npos);
  EXPECT_EQ(ReadText(path).find("layers"), std::string::npos);
  EXPECT_EQ(ReadText(path).find("falloff_error"), std::string::npos);  // 0: not written
  // A fall-off slope alone writes the block, and reads back.
  plain.refinement = RefinementSpec();
  plain.refinement.falloff_error = 0.005f;
  ASSERT_TRUE(SaveRigSpec(path, plain, &diag)) << diag.Format();
  EXPECT_NE(ReadText(path).find("\"falloff_error\": 0.005"), std::string::npos);
  RigSpec back;
  ASSERT_TRUE(ParseRigSpec(ReadText(path), "", &back, &diag)) << diag.Format();
  EXPECT_EQ(back.refinement.falloff_error, 0.005f);
  EXPECT_EQ(back.refinement.edge_fraction, 0.25f);
}

TEST(RigJsonTest, SaveRefusesBadWrinkles) {
  const std::string dir = test::TempDir();
  const std::string path = dir + "/head.rig.json";
  {
    RigSpec spec = SampleWrinkleSpec(dir);
    spec.muscle_wrinkles[0]->phi_c = 0.7f;  // = the zone angle
    spec.muscle_wrinkles[1]->count = 0;
    spec.curve_wrinkles[2].name = spec.curve_wrinkles[0].name;
    spec.curve_wrinkles[1].spec.width = std::nanf("");
    spec.refinement.edge_fraction = 0.f;
    Diagnostics diag;
    EXPECT_FALSE(SaveRigSpec(path, spec, &diag));
    EXPECT_TRUE(diag.Contains("muscles[0].wrinkles.phi_c_deg")) << diag.Format();
    EXPECT_TRUE(diag.Contains("muscles[1].wrinkles.count")) << diag.Format();
    EXPECT_NE(diag.Format().find("curve_wrinkles[2].name: duplicate curve wrinkle name"),
              std::string::npos)
        << diag.Format();
    EXPECT_TRUE(diag.Contains("curve_wrinkles[1].width")) << diag.Format();
    EXPECT_TRUE(diag.Contains("refinement.edge_fraction")) << diag.Format();
    EXPECT_TRUE(diag.Contains("not saved")) << diag.Format();
  }
  {
    // A wrinkle block beyond the last muscle would be lost.
    RigSpec spec = SampleWrinkleSpec(dir);
    spec.muscle_wrinkles.push_back(MuscleWrinkleSpec());
    Diagnostics diag;
    EXPECT_FALSE(SaveRigSpec(path, spec, &diag));
    EXPECT_TRUE(diag.Contains("muscle_wrinkles[2]")) << diag.Format();
    // An extra empty entry is harmless.
    spec.muscle_wrinkles.back().reset();
    diag.Clear();
    EXPECT_TRUE(SaveRigSpec(path, spec, &diag)) << diag.Format();
  }
  EXPECT_EQ(ListDir(dir), std::vector<std::string>{"head.rig.json"});
}

TEST(RigJsonTest, SavedTextHasTheDocumentedLayout) {
  const std::string dir = test::TempDir();
  RigSpec spec = SampleSpec(dir);
  spec.muscles[0].linear.zone_angle = static_cast<float>(40.0 * std::numbers::pi / 180.0);
  spec.muscles[0].strength = 4.f;
  spec.thickness.value = 3.f;
  const std::string path = dir + "/head.rig.json";
  Diagnostics diag;
  ASSERT_TRUE(SaveRigSpec(path, spec, &diag)) << diag.Format();
  const std::string text = ReadText(path);
  // Key order as in docs/rig-format.md, two-space indentation.
  const char* keys[] = {"\n  \"format\": \"mimetic-rig\"", "\n  \"version\": 1",
                        "\n  \"mesh\": {",                  "\n    \"path\": \"surface.glb\"",
                        "\n    \"name\": \"face\"",         "\n  \"units\": \"in\"",
                        "\n  \"thickness\": {",             "\"type\": \"constant\"",
                        "\"value\": 3.0",                   "\n  \"muscles\": [",
                        "\"name\": \"zygomatic_major_L\"",  "\"type\": \"linear\"",
                        "\"strength\": 4.0",                "\"attachment\"",
                        "\"insertion\"",                    "\"zone_angle_deg\": 40.0",
                        "\"falloff_start\"",                "\"falloff_end\"",
                        "\"name\": \"frontalis_inner_L\"",  "\"type\": \"sheet\"",
                        "\"length\": 5.1",                  "\"width\": 4.3",
                        "\"falloff_start\": 2.05"};
  size_t at = 0;
  for (const char* key : keys) {
    const size_t found = text.find(key, at);
    EXPECT_NE(found, std::string::npos) << "missing or out of order: " << key << "\n" << text;
    if (found != std::string::npos) at = found;
  }
  // Floats are written in their shortest form: 0.1f as 0.1.
  EXPECT_NE(text.find("\"strength\": 3.3"), std::string::npos) << text;
  EXPECT_EQ(text.find("0000000"), std::string::npos) << text;
}

TEST(RigJsonTest, MeshPathIsRelativeInsideAndAbsoluteOutside) {
  const std::string dir = test::TempDir();
  fs::create_directories(dir + "/rigs/sub");
  struct Case {
    std::string mesh;
    std::string written;
  } cases[] = {
      {dir + "/rigs/surface.obj", "surface.obj"},
      {dir + "/rigs/sub/surface.obj", "sub/surface.obj"},
      {dir + "/rigs/./sub/../surface.obj", "surface.obj"},
      {dir + "/other/surface.obj", dir + "/other/surface.obj"},
      {"/elsewhere/surface.obj", "/elsewhere/surface.obj"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.mesh);
    RigSpec spec = SampleSpec(dir);
    spec.mesh_path = c.mesh;
    const std::string path = dir + "/rigs/r.rig.json";
    Diagnostics diag;
    ASSERT_TRUE(SaveRigSpec(path, spec, &diag)) << diag.Format();
    EXPECT_NE(ReadText(path).find("\"path\": \"" + c.written + "\""), std::string::npos)
        << ReadText(path);
    RigSpec loaded;
    ASSERT_TRUE(LoadRigSpec(path, &loaded, &diag)) << diag.Format();
    EXPECT_EQ(fs::path(loaded.mesh_path).lexically_normal(), fs::path(c.mesh).lexically_normal());
  }
}

TEST(RigJsonTest, SaveToUnwritableDirectoryReportsAnError) {
  const std::string dir = test::TempDir();
  RigSpec spec = SampleSpec(dir);
  Diagnostics diag;
  const std::string path = dir + "/no/such/dir/head.rig.json";
  EXPECT_FALSE(SaveRigSpec(path, spec, &diag));
  EXPECT_TRUE(diag.HasErrors());
  EXPECT_TRUE(diag.Contains("cannot write")) << diag.Format();
  EXPECT_FALSE(fs::exists(path));
  EXPECT_TRUE(ListDir(dir).empty());
}

TEST(RigJsonTest, SaveRefusesARigThatWouldNotLoad) {
  const std::string dir = test::TempDir();
  RigSpec spec = SampleSpec(dir);
  spec.muscles[1].strength = std::nanf("");
  spec.muscles[0].name = spec.muscles[1].name;
  Diagnostics diag;
  const std::string path = dir + "/head.rig.json";
  EXPECT_FALSE(SaveRigSpec(path, spec, &diag));
  EXPECT_TRUE(diag.Contains("muscles[1].strength")) << diag.Format();
  EXPECT_TRUE(diag.Contains("duplicate muscle name")) << diag.Format();
  EXPECT_TRUE(diag.Contains("not saved")) << diag.Format();
  EXPECT_TRUE(ListDir(dir).empty());
}

TEST(RigJsonTest, LoadReportsMissingFileAndPrefixesErrorsWithThePath) {
  const std::string dir = test::TempDir();
  RigSpec spec;
  Diagnostics diag;
  EXPECT_FALSE(LoadRigSpec(dir + "/missing.rig.json", &spec, &diag));
  EXPECT_TRUE(diag.Contains("cannot open")) << diag.Format();

  const std::string path = dir + "/bad.rig.json";
  std::ofstream(path) << Linear(R"("strength": 4)", R"("strength": -1)");
  diag.Clear();
  EXPECT_FALSE(LoadRigSpec(path, &spec, &diag));
  EXPECT_NE(diag.Format().find("error: " + path + ": muscles[0].strength: expected a finite "
                               "number >= 0, got -1"),
            std::string::npos)
      << diag.Format();
}

// ---------------------------------------------------------------------------------------------
// 5. Every example rig in the repository validates.

std::vector<std::string> ExampleRigs() {
  std::vector<std::string> found;
  for (const char* sub : {"assets", "tests/data"}) {
    const fs::path root = fs::path(test::SourceDir()) / sub;
    std::error_code ec;
    if (!fs::is_directory(root, ec)) continue;
    for (auto it = fs::recursive_directory_iterator(root, ec);
         !ec && it != fs::recursive_directory_iterator(); it.increment(ec)) {
      const std::string name = it->path().filename().string();
      if (it->is_regular_file(ec) && name.size() > 9 &&
          name.compare(name.size() - 9, 9, ".rig.json") == 0)
        found.push_back(it->path().string());
    }
  }
  std::sort(found.begin(), found.end());
  return found;
}

TEST(RigJsonTest, EveryExampleRigValidates) {
  const std::vector<std::string> rigs = ExampleRigs();
  if (fs::exists(fs::path(test::SourceDir()) / "assets/surface/surface.rig.json")) {
    EXPECT_FALSE(rigs.empty());
  }
  for (const std::string& path : rigs) {
    SCOPED_TRACE(path);
    RigSpec spec;
    Diagnostics diag;
    EXPECT_TRUE(LoadRigSpec(path, &spec, &diag)) << diag.Format();
    EXPECT_EQ(diag.ErrorCount(), 0u);
    EXPECT_EQ(spec.file, path);
  }
  std::printf("validated %zu example rig(s)\n", rigs.size());
}

TEST(RigJsonTest, DocumentationExampleValidates) {
  const std::string doc = ReadText(test::SourceDir() + "/docs/rig-format.md");
  const size_t start = doc.find("```json\n");
  ASSERT_NE(start, std::string::npos) << "docs/rig-format.md has no ```json example";
  const size_t end = doc.find("```", start + 8);
  ASSERT_NE(end, std::string::npos);
  RigSpec spec;
  Diagnostics diag;
  EXPECT_TRUE(ParseRigSpec(doc.substr(start + 8, end - start - 8), "", &spec, &diag))
      << diag.Format();
  EXPECT_EQ(spec.muscles.size(), 2u);
  // The example shows every section: wrinkles on both muscles, a curve wrinkle, layers and
  // refinement.
  ASSERT_EQ(spec.muscle_wrinkles.size(), 2u);
  EXPECT_TRUE(spec.muscle_wrinkles[0].has_value());
  EXPECT_TRUE(spec.muscle_wrinkles[1].has_value());
  EXPECT_FALSE(spec.curve_wrinkles.empty());
  const std::string example = doc.substr(start, end - start);
  for (const char* key : {"\"layers\"", "\"refinement\"", "\"phi_c_deg\"", "\"h_c\"",
                          "\"profile\"", "\"modulation\"", "\"rest_amplitude\""})
    EXPECT_NE(example.find(key), std::string::npos) << key;
}

// ---------------------------------------------------------------------------------------------
// 6. The JSON schema agrees with the loader on examples and on a few bad files.

bool HavePythonJsonschema() {
  return std::system("python3 -c 'import jsonschema' >/dev/null 2>&1") == 0;
}

std::string RunCommand(const std::string& cmd) {
  std::string out;
  FILE* pipe = ::popen(cmd.c_str(), "r");
  if (!pipe) return out;
  char buf[4096];
  size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, pipe)) > 0) out.append(buf, n);
  ::pclose(pipe);
  return out;
}

TEST(RigJsonTest, JawParsesAndRoundTripsInBothForms) {
  RigSpec spec;
  Diagnostics diag;
  ASSERT_TRUE(ParseRigSpec(Jaw(R"("mouth_width": 40)",
                               R"("mouth_width": 40, "lip_blend_deg": 3, "back": [0.1, 0.5], )"
                               R"("translation": [0, -4, 2.5], "neck_deg": [25, 55], "thickness_fade": 0.2)"),
                           "", &spec, &diag))
      << diag.Format();
  ASSERT_TRUE(spec.jaw.has_value());
  ExpectVec(spec.jaw->condyles[0], -60, 0, -50);
  ExpectVec(spec.jaw->condyles[1], 60, 0, -50);
  ExpectVec(spec.jaw->mouth, 0, 0, 10);
  EXPECT_EQ(spec.jaw->range_deg, 20.f);
  EXPECT_EQ(spec.jaw->mouth_width, 40.f);
  EXPECT_EQ(spec.jaw->lip_blend_deg, 3.f);
  EXPECT_EQ(spec.jaw->cheek_blend_deg, JawSpec().cheek_blend_deg);  // default
  EXPECT_EQ(spec.jaw->back[0], 0.1f);
  EXPECT_EQ(spec.jaw->back[1], 0.5f);
  ExpectVec(spec.jaw->translation, 0, -4, 2.5);
  EXPECT_EQ(spec.jaw->neck_deg[0], 25.f);
  EXPECT_EQ(spec.jaw->neck_deg[1], 55.f);
  EXPECT_EQ(spec.jaw->thickness_fade, 0.2f);
  EXPECT_TRUE(spec.jaw->weights.empty());
  const std::string dir = test::TempDir();
  for (bool explicit_weights : {false, true}) {
    if (explicit_weights) spec.jaw->weights = {0.f, 0.25f, 1.f};
    const std::string path = dir + "/jaw.rig.json";
    spec.file = path;
    spec.mesh_path = dir + "/surface.obj";
    ASSERT_TRUE(SaveRigSpec(path, spec, &diag)) << diag.Format();
    RigSpec loaded;
    ASSERT_TRUE(LoadRigSpec(path, &loaded, &diag)) << diag.Format();
    ASSERT_TRUE(loaded.jaw.has_value());
    ExpectVec(loaded.jaw->condyles[1], 60, 0, -50);
    EXPECT_EQ(loaded.jaw->range_deg, 20.f);
    EXPECT_EQ(loaded.jaw->weights, spec.jaw->weights);
    ExpectVec(loaded.jaw->translation, 0, -4, 2.5);
    // The mouth is kept beside explicit weights too: it places the lips' thickness fade.
    ExpectVec(loaded.jaw->mouth, 0, 0, 10);
    EXPECT_EQ(loaded.jaw->mouth_width, 40.f);
    EXPECT_EQ(loaded.jaw->thickness_fade, 0.2f);
    if (!explicit_weights) {
      EXPECT_EQ(loaded.jaw->neck_deg[0], 25.f);
      EXPECT_EQ(loaded.jaw->neck_deg[1], 55.f);
      ExpectVec(loaded.jaw->mouth, 0, 0, 10);
      EXPECT_EQ(loaded.jaw->lip_blend_deg, 3.f);
      EXPECT_EQ(loaded.jaw->back[1], 0.5f);
    }
  }
}

// Tension regions in both forms: a region on fewer than half the vertices is saved sparse
// ("vertices" + one weight each), a wider one dense (one weight per vertex); both read back to
// what was saved; a sparse region given by hand parses as written.
TEST(RigJsonTest, TensionRegionsSaveSparseWhenShorterAndRoundTrip) {
  RigSpec spec;
  Diagnostics diag;
  ASSERT_TRUE(ParseRigSpec(Extra(R"("tension_regions": [{"name": "a", "vertices": [1, 4], )"
                                 R"("weights": [0.5, 1]}])"),
                           "", &spec, &diag))
      << diag.Format();
  ASSERT_EQ(spec.tension_regions.size(), 1u);
  EXPECT_TRUE(spec.tension_regions[0].sparse);
  EXPECT_EQ(spec.tension_regions[0].vertices, (std::vector<uint32_t>{1, 4}));
  EXPECT_EQ(spec.tension_regions[0].weights, (std::vector<float>{0.5f, 1.f}));
  TensionRegionSpec narrow{"narrow", 0.2f, {0.f, 0.f, 0.75f, 0.f, 0.f, 0.f, 0.25f, 0.f}};
  TensionRegionSpec wide{"wide", 0.1f, {0.f, 1.f, 1.f, 1.f, 0.5f, 0.f, 0.f, 1.f}};
  TensionRegionSpec none{"none", 0.1f, std::vector<float>(8, 0.f)};
  spec.tension_regions = {narrow, wide, none};
  const std::string dir = test::TempDir();
  const std::string path = dir + "/regions.rig.json";
  spec.file = path;
  spec.mesh_path = dir + "/surface.obj";
  ASSERT_TRUE(SaveRigSpec(path, spec, &diag)) << diag.Format();
  const nlohmann::json j = nlohmann::json::parse(std::ifstream(path));
  const nlohmann::json& regions = j["tension_regions"];
  ASSERT_EQ(regions.size(), 3u);
  EXPECT_EQ(regions[0]["vertices"], (std::vector<int>{2, 6}));
  EXPECT_EQ(regions[0]["weights"], (std::vector<double>{0.75, 0.25}));
  EXPECT_FALSE(regions[1].contains("vertices"));  // 5 of 8 non-zero: dense is shorter
  EXPECT_EQ(regions[1]["weights"].size(), 8u);
  EXPECT_EQ(regions[2]["vertices"].size(), 0u);   // all zero: sparse and empty
  RigSpec loaded;
  ASSERT_TRUE(LoadRigSpec(path, &loaded, &diag)) << diag.Format();
  ASSERT_EQ(loaded.tension_regions.size(), 3u);
  EXPECT_TRUE(loaded.tension_regions[0].sparse);
  EXPECT_EQ(loaded.tension_regions[0].vertices, (std::vector<uint32_t>{2, 6}));
  EXPECT_EQ(loaded.tension_regions[0].weights, (std::vector<float>{0.75f, 0.25f}));
  EXPECT_FALSE(loaded.tension_regions[1].sparse);
  EXPECT_EQ(loaded.tension_regions[1].weights, wide.weights);
  EXPECT_TRUE(loaded.tension_regions[2].sparse);
  EXPECT_TRUE(loaded.tension_regions[2].weights.empty());
}

TEST(RigJsonTest, SchemaAgreesWithTheLoader) {
  if (!HavePythonJsonschema()) {
    // tools/install-deps.sh installs it: under CI a missing validator is a failure, not a skip.
    if (std::getenv("CI")) FAIL() << "python3 with jsonschema is not installed (CI=true)";
    GTEST_SKIP() << "python3 with jsonschema is not installed";
  }
  const std::string schema = test::SourceDir() + "/assets/schema/mimetic-rig.schema.json";
  ASSERT_TRUE(fs::exists(schema));
  const std::string dir = test::TempDir();
  const std::string script = dir + "/check.py";
  std::ofstream(script) << R"(import json, sys, jsonschema
schema = json.load(open(sys.argv[1]))
jsonschema.Draft7Validator.check_schema(schema)
validator = jsonschema.Draft7Validator(schema)
for path in sys.argv[2:]:
    errors = list(validator.iter_errors(json.load(open(path))))
    print(("INVALID " if errors else "VALID ") + path)
)";

  // Files the loader accepts: the example rigs, the inline ones above, a saved one.
  std::vector<std::string> good = ExampleRigs();
  const std::vector<std::string> good_texts = {
      kValidRig, Doc(), Doc("[" + kSheet + "]"), Doc("[]"),
      Thickness(R"({"type": "per_vertex", "values": [0, 1.5]})"),
      Thickness(R"({"type": "constant", "value": 2})"),
      kValidWrinkleRig,
      LinearW(R"({"depth": 1})"),
      LinearW(R"({"depth": 0, "count": 2.0, "lambda_w": 0, "shape": -3, "phi_c_deg": 0})"),
      SheetW(R"({"depth": 1, "h_c": 0})"),
      Curves("[" + kCurve + "]"),
      Curve(R"("width": 3)", R"("width": 3, "rest_amplitude": 1, "profile": "yang_zhang")"),
      Curves("[]"),
      Extra(R"("layers": {})"),
      Extra(R"("refinement": {"enabled": false, "edge_fraction": 1})")};
  // Files the loader rejects, each for a reason the schema can express.
  const std::vector<std::string> bad_texts = {
      Doc("[" + kLinear + "]", R"(, "colour": "red")"),
      Linear(R"("strength": 4)", R"("strength": 4, "colour": 1)"),
      Linear(R"("attachment": [0, 0, 0])", R"("attachment": "origin")"),
      Linear(R"("attachment": [0, 0, 0])", R"("attachment": [0, 0])"),
      Linear(R"("zone_angle_deg": 40)", R"("zone_angle_deg": 200)"),
      Linear(R"("type": "linear")", R"("type": "sphincter")"),
      Linear(R"("strength": 4)", R"("strength": -1)"),
      Linear(R"("strength": 4)", R"("strength": 1e999)"),
      Sheet(R"("width": 40)", R"("width": 40, "zone_angle_deg": 40)"),
      Top(R"("version": 1)", R"("version": 2)"),
      Top(R"("units": "mm")", R"("units": "km")"),
      Top(R"("path": "surface.obj")", R"("path": "")"),
      Thickness(R"({"type": "gradient", "value": 1})"),
      Thickness(R"({"type": "per_vertex", "values": [1, "2"]})"),
      Doc(kLinear),
      // The wrinkle sections (the cross-field rules, phi_c_deg < zone_angle_deg, h_c < width/2
      // and unique names, are the loader's alone).
      Doc("[" + kLinear + "]", R"(, "wrinkles": [])"),
      Doc("[" + kLinear + "]", R"(, "fine_scale": [])"),
      LinearW(R"({"depth": 1, "h_c": 5})"),
      SheetW(R"({"depth": 1, "phi_c_deg": 5})"),
      LinearW(R"({"depth": 1, "phi_c_deg": 180})"),
      LinearW(R"({"depth": 1, "count": 0})"),
      LinearW(R"({"depth": 1, "count": 2.5})"),
      LinearW(R"({"depth": 1, "lambda_w": 1})"),
      LinearW(R"({"depth": -1})"),
      LinearW(R"({"count": 2})"),
      LinearW(R"({"depth": 1, "alpha": 2})"),
      SheetW(R"({"depth": 1, "h_c": -1})"),
      Extra(R"("curve_wrinkles": )" + kCurve),
      Curve(R"("name": "nasolabial_L")", R"("name": "")"),
      Curve(R"([[0.1, 0.2], [0.2, 0.3], [0.3, 0.35], [0.4, 0.3]])",
            R"([[0.1, 0.2], [0.2, 0.3], [0.3, 0.35]])"),
      Curve(R"([0.3, 0.35])", R"([0.3, 0.35, 0])"),
      Curve(R"("width": 3)", R"("width": 3, "profile": "gauss")"),
      Curve(R"("width": 3)", R"("width": 3, "modulation": "length")"),
      Curve(R"("width": 3)", R"("width": 0)"),
      Curve(R"("width": 3)", R"("width": 3, "rest_amplitude": 1.5)"),
      Curve(R"("width": 3)", R"("width": 3, "colour": 1)"),
      Curve(R"(, "width": 3)", ""),
      Extra(R"("layers": {"thickness": "yes"})"),
      Extra(R"("layers": {"fine_scale": false})"),
      Extra(R"("refinement": {"edge_fraction": 0})"),
      Extra(R"("refinement": {"edge_fraction": 1.5})"),
      Extra(R"("refinement": {"enabled": 1})"),
      Extra(R"("refinement": {"levels": 2})")};
  std::vector<std::string> bad;
  std::vector<std::string> all_texts = good_texts;
  all_texts.insert(all_texts.end(), bad_texts.begin(), bad_texts.end());
  for (size_t i = 0; i < all_texts.size(); ++i) {
    const std::string path = dir + "/t" + std::to_string(i) + ".rig.json";
    std::ofstream(path) << all_texts[i];
    // The loader's verdict first, so that the schema is compared against it.
    RigSpec spec;
    Diagnostics diag;
    const bool loads = ParseRigSpec(all_texts[i], "", &spec, &diag);
    EXPECT_EQ(loads, i < good_texts.size()) << all_texts[i] << diag.Format();
    (i < good_texts.size() ? good : bad).push_back(path);
  }
  RigSpec saved = SampleSpec(dir);
  Diagnostics diag;
  ASSERT_TRUE(SaveRigSpec(dir + "/saved.rig.json", saved, &diag)) << diag.Format();
  good.push_back(dir + "/saved.rig.json");
  ASSERT_TRUE(SaveRigSpec(dir + "/saved_wrinkles.rig.json", SampleWrinkleSpec(dir), &diag))
      << diag.Format();
  good.push_back(dir + "/saved_wrinkles.rig.json");

  std::string cmd = "python3 '" + script + "' '" + schema + "'";
  for (const std::string& p : good) cmd += " '" + p + "'";
  for (const std::string& p : bad) cmd += " '" + p + "'";
  const std::string out = "\n" + RunCommand(cmd + " 2>&1");
  for (const std::string& p : good)
    EXPECT_NE(out.find("\nVALID " + p + "\n"), std::string::npos) << p << "\n" << ReadText(p) << out;
  for (const std::string& p : bad)
    EXPECT_NE(out.find("\nINVALID " + p + "\n"), std::string::npos) << p << "\n" << ReadText(p) << out;
}

}  // namespace
}  // namespace mimetic

namespace mimetic {
namespace {

TEST(RigJsonTest, MuscleFalloffKinds) {
  // docs/rig-format.md: "falloff" is "waters" (the default) or "smooth".
  RigSpec spec;
  Diagnostics diag;
  ASSERT_TRUE(ParseRigSpec(Doc(), "", &spec, &diag)) << diag.Format();
  EXPECT_EQ(spec.muscles[0].falloff, MuscleFalloff::kWaters);
  ASSERT_TRUE(ParseRigSpec(Linear(R"("strength": 4)", R"("strength": 4, "falloff": "smooth")"), "",
                           &spec, &diag))
      << diag.Format();
  EXPECT_EQ(spec.muscles[0].falloff, MuscleFalloff::kSmooth);
  ASSERT_TRUE(ParseRigSpec(Sheet(R"("strength": 3)", R"("strength": 3, "falloff": "waters")"), "",
                           &spec, &diag));
  EXPECT_EQ(spec.muscles[0].falloff, MuscleFalloff::kWaters);
  Diagnostics bad;
  EXPECT_FALSE(ParseRigSpec(Linear(R"("strength": 4)", R"("strength": 4, "falloff": "cubic")"), "",
                            &spec, &bad));
  EXPECT_TRUE(bad.Contains("\"waters\" or \"smooth\"")) << bad.Format();
  EXPECT_NE(bad.Format().find("muscles[0].falloff"), std::string::npos) << bad.Format();
  // Saved and read back; a Waters muscle is written without the key (older readers agree).
  spec = {};
  ASSERT_TRUE(ParseRigSpec(Linear(R"("strength": 4)", R"("strength": 4, "falloff": "smooth")"),
                           "", &spec, &diag));
  const std::string dir = test::TempDir();
  spec.file = dir + "/f.rig.json";
  ASSERT_TRUE(SaveRigSpec(spec.file, spec, &diag)) << diag.Format();
  RigSpec back;
  ASSERT_TRUE(LoadRigSpec(spec.file, &back, &diag)) << diag.Format();
  EXPECT_EQ(back.muscles[0].falloff, MuscleFalloff::kSmooth);
  back.muscles[0].falloff = MuscleFalloff::kWaters;
  ASSERT_TRUE(SaveRigSpec(spec.file, back, &diag));
  std::ifstream in(spec.file);
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  EXPECT_EQ(text.find("falloff\""), std::string::npos) << text;
}

}  // namespace
}  // namespace mimetic

namespace mimetic {
namespace {

// mesh.fingerprint (geometry/fingerprint.h, issue 11): saved and read back exactly; a bad one
// is reported with its path.
TEST(RigJsonTest, MeshFingerprintRoundTripAndBadInputs) {
  const std::string dir = test::TempDir();
  RigSpec spec;
  spec.mesh_path = dir + "/head.glb";
  spec.units = "mm";
  spec.thickness.kind = ThicknessSpec::Kind::kPerVertex;
  spec.thickness.per_vertex = {0.5f, 1.f, 2.f};
  spec.mesh_fingerprint.vertices = 3;
  spec.mesh_fingerprint.triangles = 1;
  spec.mesh_fingerprint.index_hash = 0x0123456789abcdefull;
  spec.mesh_fingerprint.positions = {{0.1f, -2.f, 3e3f}, {1.f, 0.f, 0.f}, {0.f, 1.f, 0.f}};
  spec.mesh_fingerprint.uvs = {{0.f, 0.f}, {1.f, 0.f}, {0.25f, 0.75f}};
  const std::string path = dir + "/f.rig.json";
  Diagnostics diag;
  ASSERT_TRUE(SaveRigSpec(path, spec, &diag)) << diag.Format();
  const std::string text = ReadText(path);
  EXPECT_NE(text.find(R"("index_hash": "0123456789abcdef")"), std::string::npos) << text;
  RigSpec loaded;
  ASSERT_TRUE(LoadRigSpec(path, &loaded, &diag)) << diag.Format();
  const MeshFingerprint& f = loaded.mesh_fingerprint;
  EXPECT_EQ(f.vertices, 3u);
  EXPECT_EQ(f.triangles, 1u);
  EXPECT_EQ(f.index_hash, 0x0123456789abcdefull);
  ASSERT_EQ(f.positions.size(), 3u);
  EXPECT_EQ(f.positions[0], (float3{0.1f, -2.f, 3e3f}));
  ASSERT_EQ(f.uvs.size(), 3u);
  EXPECT_EQ(f.uvs[2].y, 0.75f);
  // Without a fingerprint (files before it): none written, none read.
  spec.mesh_fingerprint = {};
  ASSERT_TRUE(SaveRigSpec(path, spec, &diag)) << diag.Format();
  EXPECT_EQ(ReadText(path).find("fingerprint"), std::string::npos);

  const std::string fp = R"("fingerprint": {"vertices": 3, "triangles": 1, "index_hash": "0123456789abcdef", "positions": [[0, 0, 0], [1, 0, 0]]})";
  auto doc = [&](const std::string& from, const std::string& to) {
    return Top(R"("mesh": {"path": "surface.obj"})",
               R"("mesh": {"path": "surface.obj", )" + Replace(fp, from, to) + "}");
  };
  {
    RigSpec s;
    Diagnostics d;
    EXPECT_TRUE(ParseRigSpec(doc("", ""), "", &s, &d)) << d.Format();
    EXPECT_EQ(s.mesh_fingerprint.positions.size(), 2u);
  }
  const std::vector<std::pair<std::string, std::string>> bad = {
      {doc("0123456789abcdef", "0123456789ABCDEF"),
       "mesh.fingerprint.index_hash: is \"0123456789ABCDEF\"; expected 16 lowercase hex digits"},
      {doc("\"vertices\": 3", "\"vertices\": 0"), "mesh.fingerprint.vertices"},
      {doc("\"vertices\": 3", "\"vertices\": 1"),
       "mesh.fingerprint.positions: has 2 entries for a mesh of 1 vertices"},
      {doc("[[0, 0, 0], [1, 0, 0]]", "[[0, 0, 0], [1, 0, 0]], \"uvs\": [[0, 0]]"),
       "mesh.fingerprint.uvs: has 1 entries; expected one per position (2)"},
      {doc(", \"triangles\": 1", ""), "mesh.fingerprint.triangles"},
  };
  for (const auto& [text_in, expect] : bad) {
    RigSpec s;
    Diagnostics d;
    EXPECT_FALSE(ParseRigSpec(text_in, "", &s, &d)) << text_in;
    EXPECT_NE(d.Format().find(expect), std::string::npos) << expect << "\n" << d.Format();
  }
}

}  // namespace
}  // namespace mimetic

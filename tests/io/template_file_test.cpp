// Muscle template loader (docs/template-format.md): bad-input table, mirroring, the default
// template, and the thickness blend against hand-computed values.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "fitting/muscle_template.h"
#include "io/template_file.h"
#include "test_support.h"

namespace mimetic {
namespace {

// A valid template with one linear and one sheet muscle; cases below edit its text.
const std::string kValid = R"({
  "format": "mimetic-muscle-template", "version": 1,
  "thickness": {"base": 0.03, "front": [-1, -0.5],
                "regions": [{"name": "cheek", "center": [0.3, -0.5], "radius": [0.1, 0.2], "value": 0.09, "mirror": true}]},
  "muscles": [
    {"name": "zyg_L", "type": "linear", "mirror": true, "strength": 0.08,
     "attachment": {"landmarks": [45], "offset": [0.08, -0.22], "depth": 0.08},
     "insertion": {"landmarks": [54, 48], "weights": [3, 1], "depth": 0.02},
     "zone_angle_deg": 25, "falloff_start": 0.5, "falloff_end": 0.8,
     "wrinkles": {"depth": 0.012, "phi_c_deg": 10}},
    {"name": "front", "type": "sheet", "strength": 0.1,
     "attachment": [{"landmarks": [22], "offset": [0, 0.6], "depth": 0.03},
                    {"landmarks": [24], "offset": [0, 0.6], "depth": 0.03}],
     "insertion": [{"landmarks": [22], "depth": 0.01}, {"landmarks": [24], "depth": 0.01}],
     "length": 0.8, "width": 0.36, "falloff_start": 0.6,
     "wrinkles": {"lambda_w": 0.2, "count": 4, "depth": 0.01, "shape": 0.5, "h_c": 0.05, "gate": 0.6}}
  ],
  "curve_wrinkles": [
    {"name": "fold_L", "mirror": true,
     "control": [{"landmarks": [35], "offset": [0.05, 0.08]}, {"landmarks": [35], "offset": [0.1, -0.06]},
                 {"landmarks": [54], "offset": [0.06, 0.1]}, {"landmarks": [54], "offset": [0.07, -0.04], "depth": 0}],
     "depth": 0.04, "width": 0.05, "modulation": "area", "rest_amplitude": 0.2}
  ]
})";

std::string Replace(std::string s, const std::string& from, const std::string& to) {
  const size_t at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) s.replace(at, from.size(), to);
  return s;
}

TEST(MuscleTemplate, TensionRegionsParseMirrorAndRoundTrip) {
  const std::string text = Replace(kValid, R"(  "curve_wrinkles": [)",
                                   R"(  "tension_regions": [
    {"name": "glabella", "center": [0, 0.3], "radius": [0.1, 0.08], "reference": 0.2},
    {"name": "crows_feet_L", "center": [0.55, 0.05], "radius": [0.08, 0.1], "mirror": true}],
  "curve_wrinkles": [)");
  MuscleTemplate t;
  Diagnostics diag;
  ASSERT_TRUE(ParseMuscleTemplate(text, &t, &diag)) << diag.Format();
  ASSERT_EQ(t.tension_regions.size(), 3u);
  EXPECT_EQ(t.tension_regions[2].name, "crows_feet_R");
  EXPECT_FLOAT_EQ(t.tension_regions[2].center.x, -0.55f);
  EXPECT_FLOAT_EQ(t.tension_regions[0].reference, 0.2f);
  EXPECT_FLOAT_EQ(t.tension_regions[1].reference, kDefaultTensionReference);
  // The weight at a face-frame point, by hand: at the centre in front of the fade 1; one
  // radius off in x exp(-1/2); behind the fade (z below front[0] = -1) 0; far away 0 (cut).
  const TemplateTensionRegion& g = t.tension_regions[0];
  EXPECT_FLOAT_EQ(EvaluateTensionRegion(g, t.thickness.front, {0.f, 0.3f, 0.f}), 1.f);
  EXPECT_NEAR(EvaluateTensionRegion(g, t.thickness.front, {0.1f, 0.3f, 0.f}), std::exp(-0.5),
              1e-6);
  EXPECT_EQ(EvaluateTensionRegion(g, t.thickness.front, {0.f, 0.3f, -2.f}), 0.f);
  EXPECT_EQ(EvaluateTensionRegion(g, t.thickness.front, {0.5f, 0.3f, 0.f}), 0.f);
  MuscleTemplate again;
  ASSERT_TRUE(ParseMuscleTemplate(MuscleTemplateToJson(t), &again, &diag)) << diag.Format();
  ASSERT_EQ(again.tension_regions.size(), 3u);
  EXPECT_EQ(again.tension_regions[2].name, "crows_feet_R");
  // Bad definitions name the path.
  for (const auto& [from, to, message] : std::vector<std::array<std::string, 3>>{
           {R"("radius": [0.1, 0.08])", R"("radius": [0, 0.08])", "tension_regions[0].radius"},
           {R"("name": "crows_feet_L")", R"("name": "crows_feet")", "must end in _L or _R"},
           {R"("name": "crows_feet_L")", R"("name": "glabella")", "duplicate tension region name"},
           {R"("reference": 0.2)", R"("reference": -1)", "tension_regions[0].reference"}}) {
    MuscleTemplate bad;
    Diagnostics d;
    EXPECT_FALSE(ParseMuscleTemplate(Replace(text, from, to), &bad, &d)) << to;
    EXPECT_NE(d.Format().find(message), std::string::npos) << d.Format();
  }
}

TEST(MuscleTemplate, ValidTextParsesWithMirroringAndNormalisedWeights) {
  MuscleTemplate t;
  Diagnostics diag;
  ASSERT_TRUE(ParseMuscleTemplate(kValid, &t, &diag)) << diag.Format();
  ASSERT_EQ(t.muscles.size(), 3u);
  EXPECT_EQ(t.muscles[0].name, "zyg_L");
  EXPECT_EQ(t.muscles[1].name, "zyg_R");
  EXPECT_EQ(t.muscles[2].name, "front");
  const TemplateMuscle& r = t.muscles[1];
  // Mirror: 45 <-> 36, 54 <-> 48, dx negated.
  EXPECT_EQ(r.attachment[0].landmarks, (std::vector<int>{36}));
  EXPECT_EQ(r.insertion[0].landmarks, (std::vector<int>{48, 54}));
  EXPECT_FLOAT_EQ(r.attachment[0].offset.x, -0.08f);
  EXPECT_FLOAT_EQ(r.attachment[0].offset.y, -0.22f);
  EXPECT_FLOAT_EQ(t.muscles[0].insertion[0].weights[0], 0.75f);
  EXPECT_FLOAT_EQ(t.muscles[0].insertion[0].weights[1], 0.25f);
  EXPECT_FLOAT_EQ(t.muscles[2].insertion[0].weights[0], 1.f);  // default: equal
  EXPECT_FLOAT_EQ(t.muscles[2].insertion[0].offset.x, 0.f);   // default offset
  EXPECT_EQ(t.muscles[2].type, MuscleType::kSheet);
  ASSERT_EQ(t.thickness.regions.size(), 2u);  // mirrored region
  EXPECT_FLOAT_EQ(t.thickness.regions[1].center.x, -0.3f);
}

TEST(MuscleTemplate, WrinkleBlocksAndCurveWrinklesParseMirrorAndDefault) {
  MuscleTemplate t;
  Diagnostics diag;
  ASSERT_TRUE(ParseMuscleTemplate(kValid, &t, &diag)) << diag.Format();
  ASSERT_EQ(t.muscles.size(), 3u);
  // Linear block: absent keys take the rig file's defaults; phi_c in radians.
  for (int i : {0, 1}) {  // the mirrored copy carries the block too
    ASSERT_TRUE(t.muscles[size_t(i)].wrinkles.has_value()) << i;
    const MuscleWrinkleSpec& w = *t.muscles[size_t(i)].wrinkles;
    EXPECT_FLOAT_EQ(w.lambda_w, 0.5f);
    EXPECT_EQ(w.count, 3);
    EXPECT_FLOAT_EQ(w.depth, 0.012f);
    EXPECT_FLOAT_EQ(w.shape, 0.f);
    EXPECT_NEAR(w.phi_c, 10.f * 3.14159265f / 180.f, 1e-6f);
  }
  const MuscleWrinkleSpec& sw = *t.muscles[2].wrinkles;
  EXPECT_FLOAT_EQ(sw.lambda_w, 0.2f);
  EXPECT_EQ(sw.count, 4);
  EXPECT_FLOAT_EQ(sw.depth, 0.01f);
  EXPECT_FLOAT_EQ(sw.shape, 0.5f);
  EXPECT_FLOAT_EQ(sw.h_c, 0.05f);
  EXPECT_FLOAT_EQ(sw.gate, 0.6f);  // and the linear block's default: no gate
  EXPECT_EQ(t.muscles[0].wrinkles->gate, 0.f);
  // Curve: mirrored (35 <-> 31, 54 <-> 48, dx negated), defaults, depth 0 on the skin.
  ASSERT_EQ(t.curve_wrinkles.size(), 2u);
  const TemplateCurveWrinkle& l = t.curve_wrinkles[0];
  const TemplateCurveWrinkle& r = t.curve_wrinkles[1];
  EXPECT_EQ(l.name, "fold_L");
  EXPECT_EQ(r.name, "fold_R");
  EXPECT_EQ(l.control[0].landmarks, (std::vector<int>{35}));
  EXPECT_EQ(r.control[0].landmarks, (std::vector<int>{31}));
  EXPECT_EQ(r.control[3].landmarks, (std::vector<int>{48}));
  EXPECT_FLOAT_EQ(r.control[1].offset.x, -0.1f);
  EXPECT_FLOAT_EQ(r.control[1].offset.y, -0.06f);
  for (const TemplatePoint& p : l.control) EXPECT_FLOAT_EQ(p.depth, 0.f);
  EXPECT_FLOAT_EQ(l.depth, 0.04f);
  EXPECT_FLOAT_EQ(l.width, 0.05f);
  EXPECT_EQ(l.profile, CurveWrinkleProfile::kBando);  // default
  EXPECT_EQ(l.modulation, CurveWrinkleModulation::kArea);
  EXPECT_FLOAT_EQ(r.rest_amplitude, 0.2f);
}

struct BadCase {
  const char* name;
  std::string text;
  std::vector<std::string> expect;  // substrings of the diagnostics (where or what)
};

// kValid with a jaw block (docs/template-format.md) carrying `extra` keys.
std::string WithJaw(const std::string& extra) {
  return Replace(kValid, "\"curve_wrinkles\": [",
                 R"("jaw": {"condyle": {"landmarks": [0], "offset": [0.1, -0.3, -0.4]}, )"
                 R"("range_deg": 5, )" + extra + "},\n  \"curve_wrinkles\": [");
}

TEST(MuscleTemplate, JawWithGlideAndNeckParses) {
  MuscleTemplate t;
  Diagnostics diag;
  ASSERT_TRUE(ParseMuscleTemplate(WithJaw(R"("translation": [0, -0.25, -0.2], "neck_deg": [26, 56], )"
                                          R"("thickness_fade": 0.45)"),
                                  &t, &diag))
      << diag.Format();
  ASSERT_TRUE(t.jaw.has_value());
  EXPECT_EQ(t.jaw->range_deg, 5.f);
  EXPECT_EQ(t.jaw->translation.y, -0.25f);
  EXPECT_EQ(t.jaw->translation.z, -0.2f);
  EXPECT_EQ(t.jaw->neck_deg[0], 26.f);
  EXPECT_EQ(t.jaw->neck_deg[1], 56.f);
  EXPECT_EQ(t.jaw->thickness_fade, 0.45f);
  MuscleTemplate none;
  ASSERT_TRUE(ParseMuscleTemplate(WithJaw(R"("lip_blend_deg": 1)"), &none, &diag)) << diag.Format();
  EXPECT_EQ(none.jaw->translation.y, 0.f);  // defaults: no glide, no neck fade in front
  EXPECT_EQ(none.jaw->neck_deg[0], 90.f);
  EXPECT_EQ(none.jaw->neck_deg[1], 180.f);
  EXPECT_EQ(none.jaw->thickness_fade, 0.3f);  // the lips' fade is on by default
}

TEST(MuscleTemplate, BadInputTable) {
  const std::vector<BadCase> cases = {
      {"not json", "{\"format\": ", {"not valid JSON"}},
      {"not an object", "[1, 2]", {"expected a JSON object"}},
      {"wrong format", Replace(kValid, "\"mimetic-muscle-template\"", "\"mimetic-rig\""),
       {"format", "expected \"mimetic-muscle-template\""}},
      {"newer version", Replace(kValid, "\"version\": 1", "\"version\": 2"),
       {"unsupported version 2"}},
      {"unknown top key", Replace(kValid, "\"version\": 1,", "\"version\": 1, \"colour\": 3,"),
       {"colour", "unknown key"}},
      {"negative falloff slope",
       Replace(kValid, "\"version\": 1,", "\"version\": 1, \"refinement\": {\"falloff_error\": -0.3},"),
       {"refinement.falloff_error", "a number in [0, 1) (0 = off)", "-0.3"}},
      {"unknown refinement key",
       Replace(kValid, "\"version\": 1,", "\"version\": 1, \"refinement\": {\"edge_fraction\": 0.3},"),
       {"refinement.edge_fraction", "unknown key"}},
      {"no muscles", Replace(kValid, "\"muscles\": [", "\"muscles\": [], \"x\": ["),
       {"muscles", "non-empty array"}},
      {"bad type", Replace(kValid, "\"type\": \"linear\"", "\"type\": \"ring\""),
       {"muscles[0].type", "\"linear\" or \"sheet\""}},
      {"landmark out of range", Replace(kValid, "\"landmarks\": [45]", "\"landmarks\": [68]"),
       {"muscles[0].attachment.landmarks[0]", "0..67"}},
      {"landmark repeated", Replace(kValid, "[54, 48]", "[54, 54]"),
       {"muscles[0].insertion.landmarks[1]", "appears twice"}},
      {"weights count", Replace(kValid, "\"weights\": [3, 1]", "\"weights\": [3]"),
       {"muscles[0].insertion.weights", "array of 2 numbers"}},
      {"weights zero", Replace(kValid, "\"weights\": [3, 1]", "\"weights\": [0, 0]"),
       {"weights sum to 0"}},
      {"negative depth", Replace(kValid, "\"depth\": 0.08", "\"depth\": -0.08"),
       {"muscles[0].attachment.depth", ">= 0"}},
      {"missing depth", Replace(kValid, ", \"depth\": 0.02}", "}"),
       {"muscles[0].insertion.depth", "missing"}},
      {"offset shape", Replace(kValid, "\"offset\": [0.08, -0.22]", "\"offset\": [0.08]"),
       {"muscles[0].attachment.offset", "[dx, dy]"}},
      {"zone angle", Replace(kValid, "\"zone_angle_deg\": 25", "\"zone_angle_deg\": 190"),
       {"zone_angle_deg", "(0, 180)"}},
      {"falloff order", Replace(kValid, "\"falloff_end\": 0.8", "\"falloff_end\": 0.4"),
       {"falloff_end", "> falloff_start"}},
      {"sheet falloff beyond length", Replace(kValid, "\"falloff_start\": 0.6", "\"falloff_start\": 0.9"),
       {"muscles[1].falloff_start", "(0, length"}},
      {"sheet with one insertion",
       Replace(kValid, "[{\"landmarks\": [22], \"depth\": 0.01}, {\"landmarks\": [24], \"depth\": 0.01}]",
               "{\"landmarks\": [22], \"depth\": 0.01}"),
       {"muscles[1].insertion", "array of 2 point objects"}},
      {"linear key on a sheet", Replace(kValid, "\"length\": 0.8,", "\"length\": 0.8, \"zone_angle_deg\": 20,"),
       {"muscles[1].zone_angle_deg", "unknown key in a sheet muscle"}},
      {"mirror without suffix", Replace(kValid, "\"name\": \"zyg_L\"", "\"name\": \"zyg\""),
       {"muscles[0].mirror", "_L or _R"}},
      {"duplicate via mirror", Replace(kValid, "\"name\": \"front\"", "\"name\": \"zyg_R\""),
       {"duplicate muscle name \"zyg_R\""}},
      {"negative strength", Replace(kValid, "\"strength\": 0.1", "\"strength\": -1"),
       {"muscles[1].strength", ">= 0"}},
      {"overflowing number", Replace(kValid, "\"strength\": 0.1", "\"strength\": 1e300"),
       {"muscles[1].strength", "too large for a float"}},
      {"thickness front order", Replace(kValid, "\"front\": [-1, -0.5]", "\"front\": [0, -0.5]"),
       {"thickness.front", "z0 < z1"}},
      {"thickness radius", Replace(kValid, "\"radius\": [0.1, 0.2]", "\"radius\": [0, 0.2]"),
       {"thickness.regions[0].radius", "> 0"}},
      {"thickness value type", Replace(kValid, "\"value\": 0.09", "\"value\": \"thick\""),
       {"thickness.regions[0].value", "got \"thick\""}},
      // Muscle wrinkle blocks (docs/template-format.md, "Wrinkles").
      {"wrinkles not an object", Replace(kValid, "\"wrinkles\": {\"depth\": 0.012, \"phi_c_deg\": 10}",
                                         "\"wrinkles\": 3"),
       {"muscles[0].wrinkles", "expected a wrinkle object"}},
      {"wrinkles without depth", Replace(kValid, "{\"depth\": 0.012, \"phi_c_deg\": 10}", "{\"phi_c_deg\": 10}"),
       {"muscles[0].wrinkles.depth", "missing"}},
      {"wrinkles negative depth", Replace(kValid, "\"depth\": 0.012,", "\"depth\": -0.012,"),
       {"muscles[0].wrinkles.depth", ">= 0"}},
      {"wrinkles lambda_w 1", Replace(kValid, "\"lambda_w\": 0.2", "\"lambda_w\": 1"),
       {"muscles[1].wrinkles.lambda_w", "[0, 1)"}},
      {"wrinkles count 0", Replace(kValid, "\"count\": 4", "\"count\": 0"),
       {"muscles[1].wrinkles.count", "integer >= 1"}},
      {"wrinkles count fractional", Replace(kValid, "\"count\": 4", "\"count\": 2.5"),
       {"muscles[1].wrinkles.count", "integer >= 1"}},
      {"wrinkles shape type", Replace(kValid, "\"shape\": 0.5", "\"shape\": \"sharp\""),
       {"muscles[1].wrinkles.shape", "finite number"}},
      {"phi_c beyond the zone angle", Replace(kValid, "\"phi_c_deg\": 10", "\"phi_c_deg\": 30"),
       {"muscles[0].wrinkles.phi_c_deg", "zone_angle_deg = 25"}},
      {"h_c on a linear muscle", Replace(kValid, "\"phi_c_deg\": 10", "\"h_c\": 0.01"),
       {"muscles[0].wrinkles.h_c", "sheet muscle"}},
      {"phi_c on a sheet muscle", Replace(kValid, "\"h_c\": 0.05", "\"phi_c_deg\": 5"),
       {"muscles[1].wrinkles.phi_c_deg", "linear muscle"}},
      {"h_c beyond half the width", Replace(kValid, "\"h_c\": 0.05", "\"h_c\": 0.2"),
       {"muscles[1].wrinkles.h_c", "width/2 = 0.18"}},
      {"unknown wrinkle key", Replace(kValid, "\"count\": 4,", "\"count\": 4, \"period\": 2,"),
       {"muscles[1].wrinkles.period", "unknown key"}},
      // Curve wrinkles.
      {"curve_wrinkles not an array", Replace(kValid, "\"curve_wrinkles\": [", "\"curve_wrinkles\": 1, \"x\": ["),
       {"curve_wrinkles", "expected an array of curve wrinkles"}},
      {"curve control count",
       Replace(kValid, ", {\"landmarks\": [54], \"offset\": [0.07, -0.04], \"depth\": 0}]", "]"),
       {"curve_wrinkles[0].control", "array of 4 point objects"}},
      {"curve control depth", Replace(kValid, "\"offset\": [0.07, -0.04], \"depth\": 0}",
                                      "\"offset\": [0.07, -0.04], \"depth\": 0.01}"),
       {"curve_wrinkles[0].control[3].depth", "lies in the skin"}},
      {"curve control landmark", Replace(kValid, "{\"landmarks\": [35], \"offset\": [0.1, -0.06]}",
                                         "{\"landmarks\": [99], \"offset\": [0.1, -0.06]}"),
       {"curve_wrinkles[0].control[1].landmarks[0]", "0..67"}},
      {"curve missing width", Replace(kValid, "\"width\": 0.05, ", ""),
       {"curve_wrinkles[0].width", "missing"}},
      {"curve zero depth", Replace(kValid, "\"depth\": 0.04,", "\"depth\": 0,"),
       {"curve_wrinkles[0].depth", "> 0"}},
      {"curve profile", Replace(kValid, "\"modulation\": \"area\"", "\"modulation\": \"area\", \"profile\": \"gauss\""),
       {"curve_wrinkles[0].profile", "\"bando\", \"yang_zhang\", \"yang_zhang_exact\""}},
      {"curve modulation", Replace(kValid, "\"modulation\": \"area\"", "\"modulation\": \"strain\""),
       {"curve_wrinkles[0].modulation", "\"directional\", \"area\""}},
      {"curve rest amplitude", Replace(kValid, "\"rest_amplitude\": 0.2", "\"rest_amplitude\": 1.5"),
       {"curve_wrinkles[0].rest_amplitude", "[0, 1]"}},
      {"curve mirror without suffix", Replace(kValid, "\"name\": \"fold_L\"", "\"name\": \"fold\""),
       {"curve_wrinkles[0].mirror", "_L or _R"}},
      {"curve unknown key", Replace(kValid, "\"name\": \"fold_L\",", "\"name\": \"fold_L\", \"colour\": 1,"),
       {"curve_wrinkles[0].colour", "unknown key in a curve wrinkle"}},
      {"curve duplicate via mirror",
       Replace(kValid, "\"curve_wrinkles\": [",
               "\"curve_wrinkles\": [{\"name\": \"fold_R\", \"control\": [{\"landmarks\": [1]}, "
               "{\"landmarks\": [2]}, {\"landmarks\": [3]}, {\"landmarks\": [4]}], \"depth\": 0.01, "
               "\"width\": 0.01},"),
       {"duplicate curve wrinkle name \"fold_R\""}},
      // The jaw (docs/template-format.md, `jaw`).
      {"jaw translation of 2", WithJaw(R"("translation": [0, -0.2])"),
       {"jaw.translation", "[dx, dy, dz], three finite numbers (units of s, face frame)"}},
      {"jaw neck reversed", WithJaw(R"("neck_deg": [60, 20])"),
       {"jaw.neck_deg", "is [60, 20]; expected [n0, n1] in [0, 180] with n0 < n1"}},
      {"jaw neck beyond 180", WithJaw(R"("neck_deg": [20, 190])"),
       {"jaw.neck_deg", "is [20, 190]; expected [n0, n1] in [0, 180]"}},
      {"jaw back reversed", WithJaw(R"("back": [0.6, 0.2])"),
       {"jaw.back", "is [0.6, 0.2]; expected [b0, b1] in [-1, 1] with b0 < b1 (fractions of "
                    "the hinge-to-mouth distance)"}},
      {"jaw back below -1", WithJaw(R"("back": [-1.5, 0.2])"), {"jaw.back", "is [-1.5, 0.2]"}},
      {"jaw thickness_fade -0.1", WithJaw(R"("thickness_fade": -0.1)"),
       {"jaw.thickness_fade", "a number in [0, 1] (a fraction of the mouth width)", "-0.1"}},
      {"jaw without range", Replace(WithJaw(R"("lip_blend_deg": 1)"), R"("range_deg": 5, )", ""),
       {"jaw.range_deg", "missing"}},
  };
  ASSERT_GE(cases.size(), 12u);
  for (const BadCase& c : cases) {
    MuscleTemplate t;
    Diagnostics diag;
    EXPECT_FALSE(ParseMuscleTemplate(c.text, &t, &diag)) << c.name;
    EXPECT_TRUE(diag.HasErrors()) << c.name;
    for (const std::string& e : c.expect) EXPECT_TRUE(diag.Contains(e)) << c.name << ": wanted '" << e << "' in\n" << diag.Format();
  }
}

TEST(MuscleTemplate, ReportsEveryProblemNotOnlyTheFirst) {
  std::string text = Replace(kValid, "\"zone_angle_deg\": 25", "\"zone_angle_deg\": -5");
  text = Replace(text, "\"width\": 0.36", "\"width\": 0");
  text = Replace(text, "\"base\": 0.03", "\"base\": -1");
  MuscleTemplate t;
  Diagnostics diag;
  EXPECT_FALSE(ParseMuscleTemplate(text, &t, &diag));
  EXPECT_EQ(diag.ErrorCount(), 3u) << diag.Format();
  EXPECT_TRUE(diag.Contains("muscles[0].zone_angle_deg"));
  EXPECT_TRUE(diag.Contains("muscles[1].width"));
  EXPECT_TRUE(diag.Contains("thickness.base"));
}

TEST(MuscleTemplate, LoadReportsMissingFileAndPrefixesTheFileName) {
  MuscleTemplate t;
  Diagnostics diag;
  EXPECT_FALSE(LoadMuscleTemplate("/nonexistent/x.template.json", &t, &diag));
  EXPECT_TRUE(diag.Contains("cannot open")) << diag.Format();
}

TEST(MuscleTemplate, DefaultTemplateHasTheZhangAndBandoMusclesOnBothSides) {
  MuscleTemplate t;
  Diagnostics diag;
  ASSERT_TRUE(LoadMuscleTemplate(test::SourceDir() + "/assets/head/default.template.json", &t, &diag))
      << diag.Format();
  EXPECT_TRUE(diag.empty()) << diag.Format();
  const char* names[] = {"frontalis_inner", "frontalis_major", "frontalis_outer",
                         "corrugator_supercilii", "procerus", "nasalis",
                         "levator_labii_alaeque_nasi", "zygomaticus_minor", "zygomaticus_major",
                         "risorius", "depressor_anguli_oris", "mentalis",
                         "levator_labii_superioris", "depressor_labii_inferioris", "buccinator",
                         "platysma", "orbicularis_oculi_lateral"};
  ASSERT_EQ(t.muscles.size(), 34u);
  for (const char* n : names) {
    for (const char* side : {"_L", "_R"}) {
      bool found = false;
      for (const TemplateMuscle& m : t.muscles) {
        if (m.name != std::string(n) + side) continue;
        found = true;
        const bool sheet = std::string(n).rfind("frontalis", 0) == 0 || std::string(n) == "platysma";
        EXPECT_EQ(m.type, sheet ? MuscleType::kSheet : MuscleType::kLinear) << m.name;
        EXPECT_GT(m.strength, 0.f) << m.name;
        // The default template uses the C1 fall-off (docs/model.md §2-3).
        EXPECT_EQ(m.falloff, MuscleFalloff::kSmooth) << m.name;
      }
      EXPECT_TRUE(found) << n << side;
    }
  }
  // Left-side insertions lie on the subject's left (+x offsets or left landmarks).
}

TEST(TemplateThickness, NormalisedGaussianBlendKnownAnswers) {
  TemplateThickness t;
  t.base = 0.03f;
  t.front[0] = -1.f;
  t.front[1] = -0.5f;
  t.regions.push_back({"a", {0.f, 0.5f}, {0.2f, 0.1f}, 0.01f});
  const float w0 = std::exp(-2.f);
  // At the centre, in front: g = 1 -> (w0 * base + v) / (w0 + 1).
  EXPECT_NEAR(EvaluateTemplateThickness(t, {0.f, 0.5f, 0.f}), (w0 * 0.03f + 0.01f) / (w0 + 1.f), 1e-7f);
  // One radius away in x: g = exp(-1/2).
  const float g = std::exp(-0.5f);
  EXPECT_NEAR(EvaluateTemplateThickness(t, {0.2f, 0.5f, 0.f}), (w0 * 0.03f + g * 0.01f) / (w0 + g), 1e-7f);
  // Behind the face (z <= front[0]) the region does not apply: base.
  EXPECT_NEAR(EvaluateTemplateThickness(t, {0.f, 0.5f, -2.f}), 0.03f, 1e-7f);
  // Halfway through the fade, smoothstep(0.5) = 0.5.
  EXPECT_NEAR(EvaluateTemplateThickness(t, {0.f, 0.5f, -0.75f}), (w0 * 0.03f + 0.5f * 0.01f) / (w0 + 0.5f), 1e-7f);
  // Far away: base.
  EXPECT_NEAR(EvaluateTemplateThickness(t, {5.f, 5.f, 0.f}), 0.03f, 1e-6f);
}

}  // namespace
}  // namespace mimetic

namespace mimetic {
namespace {

TEST(MuscleTemplate, FalloffIsReadAndMirroredCopiesShareIt) {
  MuscleTemplate t;
  Diagnostics diag;
  ASSERT_TRUE(ParseMuscleTemplate(kValid, &t, &diag)) << diag.Format();
  for (const TemplateMuscle& m : t.muscles) EXPECT_EQ(m.falloff, MuscleFalloff::kWaters);
  const std::string smooth =
      Replace(kValid, R"("mirror": true, "strength": 0.08,)",
              R"("mirror": true, "strength": 0.08, "falloff": "smooth",)");
  ASSERT_TRUE(ParseMuscleTemplate(smooth, &t, &diag)) << diag.Format();
  int smooth_count = 0;
  for (const TemplateMuscle& m : t.muscles)
    if (m.falloff == MuscleFalloff::kSmooth) {
      ++smooth_count;
      EXPECT_EQ(m.name.substr(0, 4), "zyg_");
    }
  EXPECT_EQ(smooth_count, 2);  // zyg_L and its mirrored zyg_R
  Diagnostics bad;
  EXPECT_FALSE(ParseMuscleTemplate(
      Replace(kValid, R"("strength": 0.08,)", R"("strength": 0.08, "falloff": 3,)"), &t, &bad));
  EXPECT_TRUE(bad.Contains("\"waters\" or \"smooth\"")) << bad.Format();
}

}  // namespace
}  // namespace mimetic

namespace mimetic {
namespace {

TEST(MuscleTemplate, MotionIsReadAndMirroredCopiesShareIt) {
  MuscleTemplate t;
  Diagnostics diag;
  ASSERT_TRUE(ParseMuscleTemplate(kValid, &t, &diag)) << diag.Format();
  for (const TemplateMuscle& m : t.muscles) EXPECT_EQ(m.motion, MuscleMotion::kChord);
  const std::string tangent =
      Replace(kValid, R"("mirror": true, "strength": 0.08,)",
              R"("mirror": true, "strength": 0.08, "motion": "tangent",)");
  ASSERT_TRUE(ParseMuscleTemplate(tangent, &t, &diag)) << diag.Format();
  int count = 0;
  for (const TemplateMuscle& m : t.muscles) count += m.motion == MuscleMotion::kTangent;
  EXPECT_EQ(count, 2);
  for (const TemplateMuscle& m : t.muscles) EXPECT_EQ(m.tangent_radius, 0.f);
  // The normals' radius (units of s) is read, and the mirrored copy has it too.
  ASSERT_TRUE(ParseMuscleTemplate(Replace(tangent, R"("motion": "tangent",)",
                                          R"("motion": "tangent", "tangent_radius": 0.45,)"),
                                  &t, &diag)) << diag.Format();
  count = 0;
  for (const TemplateMuscle& m : t.muscles) count += m.tangent_radius == 0.45f;
  EXPECT_EQ(count, 2);
  Diagnostics negative;
  EXPECT_FALSE(ParseMuscleTemplate(
      Replace(kValid, R"("strength": 0.08,)", R"("strength": 0.08, "tangent_radius": -1,)"), &t, &negative));
  EXPECT_NE(negative.Format().find("muscles[0].tangent_radius: expected a finite number >= 0, got -1"),
            std::string::npos) << negative.Format();
  Diagnostics bad;
  EXPECT_FALSE(ParseMuscleTemplate(
      Replace(kValid, R"("strength": 0.08,)", R"("strength": 0.08, "motion": "slide",)"), &t, &bad));
  EXPECT_TRUE(bad.Contains("\"chord\" or \"tangent\"")) << bad.Format();
}

// The writer (mimetic calibrate's output): what it writes parses back to the same template,
// every number to its 4 significant digits, mirrored pairs written once with "mirror".
TEST(MuscleTemplate, WriterRoundTripsTheDefaultTemplate) {
  for (const char* file : {"/assets/head/default.template.json", "/assets/calibration/seed.template.json"}) {
    MuscleTemplate a, b;
    Diagnostics diag;
    ASSERT_TRUE(LoadMuscleTemplate(test::SourceDir() + file, &a, &diag)) << diag.Format();
    const std::string text = MuscleTemplateToJson(a);
    ASSERT_TRUE(ParseMuscleTemplate(text, &b, &diag)) << diag.Format() << text;
    EXPECT_EQ(b.description, a.description);
    ASSERT_EQ(b.muscles.size(), a.muscles.size());
    auto near = [](float x, float y) { return std::fabs(x - y) <= 5e-4f * std::max(1.f, std::fabs(x)); };
    size_t copies = 0, gated = 0;
    for (size_t i = 0; i < a.muscles.size(); ++i) {
      const TemplateMuscle &x = a.muscles[i], &y = b.muscles[i];
      EXPECT_EQ(x.name, y.name);
      EXPECT_EQ(x.mirrored_copy, y.mirrored_copy) << x.name;
      copies += y.mirrored_copy;
      EXPECT_EQ(x.type, y.type);
      EXPECT_EQ(x.falloff, y.falloff);
      EXPECT_EQ(x.motion, y.motion);
      EXPECT_TRUE(near(x.tangent_radius, y.tangent_radius)) << x.name;
      EXPECT_TRUE(near(x.strength, y.strength)) << x.name;
      EXPECT_TRUE(near(x.falloff_start, y.falloff_start)) << x.name;
      EXPECT_TRUE(near(x.falloff_end, y.falloff_end)) << x.name;
      EXPECT_TRUE(near(x.zone_angle_deg, y.zone_angle_deg)) << x.name;
      for (int k = 0; k < 2; ++k) {
        EXPECT_EQ(x.attachment[k].landmarks, y.attachment[k].landmarks) << x.name;
        EXPECT_TRUE(near(x.attachment[k].offset.x, y.attachment[k].offset.x)) << x.name;
        EXPECT_TRUE(near(x.insertion[k].offset.y, y.insertion[k].offset.y)) << x.name;
        EXPECT_TRUE(near(x.attachment[k].depth, y.attachment[k].depth)) << x.name;
      }
      EXPECT_EQ(x.wrinkles.has_value(), y.wrinkles.has_value()) << x.name;
      if (x.wrinkles && y.wrinkles) {
        EXPECT_EQ(x.wrinkles->gate, y.wrinkles->gate) << x.name;
      }
      gated += x.wrinkles && x.wrinkles->gate > 0.f;
    }
    // Every wrinkled muscle's furrows wait for the muscle (docs/calibration.md "Furrows that
    // wait for their muscle"): the four sides' blocks, mirrored.
    EXPECT_EQ(gated, 8u) << file;
    EXPECT_EQ(copies, a.muscles.size() / 2);
    // Both ask the fitted rig to refine where the fall-offs bend (docs/model.md §11).
    EXPECT_EQ(a.falloff_error, 0.005f) << file;
    EXPECT_EQ(b.falloff_error, a.falloff_error) << file;
    EXPECT_EQ(b.curve_wrinkles.size(), a.curve_wrinkles.size());
    EXPECT_EQ(b.thickness.regions.size(), a.thickness.regions.size());
    ASSERT_EQ(b.jaw.has_value(), a.jaw.has_value());
    if (a.jaw) {
      EXPECT_TRUE(near(b.jaw->range_deg, a.jaw->range_deg));
      EXPECT_TRUE(near(b.jaw->translation.y, a.jaw->translation.y));
      EXPECT_TRUE(near(b.jaw->translation.z, a.jaw->translation.z));
      EXPECT_TRUE(near(b.jaw->offset.z, a.jaw->offset.z));
      EXPECT_TRUE(near(b.jaw->neck_deg[0], a.jaw->neck_deg[0]));
      EXPECT_TRUE(near(b.jaw->back[1], a.jaw->back[1]));
    }
    // Each mirrored pair appears once in the text.
    EXPECT_EQ(text.find("\"zygomaticus_major_R\""), std::string::npos);
  }
}

}  // namespace
}  // namespace mimetic

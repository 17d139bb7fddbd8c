// tests/io/arkit_map_test.cpp: ARKit maps (io/arkit_map.h): a hand-made map of all 52 names,
// its round trip, the bad-input table, the shipped default map against the sample head rig,
// and one solved shape recomputed on ICT-FaceKit (skipped without ../shared).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "fitting/compare.h"
#include "fitting/fit.h"
#include "io/arkit_map.h"
#include "io/landmarks_file.h"
#include "io/mesh_io.h"
#include "io/rig_loader.h"
#include "io/template_file.h"
#include "moved_region.h"
#include "rig/offline/rig_builder.h"
#include "test_support.h"

namespace mimetic {
namespace {

// Apple's ARFaceAnchor.BlendShapeLocation names, written out here (not taken from the code).
const std::vector<std::string> kApple = {
    "browDownLeft", "browDownRight", "browInnerUp", "browOuterUpLeft", "browOuterUpRight",
    "cheekPuff", "cheekSquintLeft", "cheekSquintRight", "eyeBlinkLeft", "eyeBlinkRight",
    "eyeLookDownLeft", "eyeLookDownRight", "eyeLookInLeft", "eyeLookInRight", "eyeLookOutLeft",
    "eyeLookOutRight", "eyeLookUpLeft", "eyeLookUpRight", "eyeSquintLeft", "eyeSquintRight",
    "eyeWideLeft", "eyeWideRight", "jawForward", "jawLeft", "jawOpen", "jawRight", "mouthClose",
    "mouthDimpleLeft", "mouthDimpleRight", "mouthFrownLeft", "mouthFrownRight", "mouthFunnel",
    "mouthLeft", "mouthLowerDownLeft", "mouthLowerDownRight", "mouthPressLeft",
    "mouthPressRight", "mouthPucker", "mouthRight", "mouthRollLower", "mouthRollUpper",
    "mouthShrugLower", "mouthShrugUpper", "mouthSmileLeft", "mouthSmileRight",
    "mouthStretchLeft", "mouthStretchRight", "mouthUpperUpLeft", "mouthUpperUpRight",
    "noseSneerLeft", "noseSneerRight", "tongueOut"};

// A map with every name "none" except a solved smile and an anatomy frown.
nlohmann::json GoodMap() {
  nlohmann::json shapes = nlohmann::json::object();
  for (const std::string& n : kApple)
    shapes[n] = {{"how", "none"}, {"activations", nlohmann::json::object()}, {"note", "no"}};
  shapes["mouthSmileLeft"] = {{"how", "solved"},
                              {"activations", {{"zygomaticus_major_L", 0.75}}},
                              {"target", "ict-facekit/arkit/mouthSmile_L.obj"},
                              {"mean_distance", 0.05},
                              {"neutral_mean_distance", 0.1},
                              {"ratio", 0.5}};
  shapes["mouthFrownLeft"] = {{"how", "anatomy"},
                              {"activations", {{"depressor_anguli_oris_L", 0.5}}},
                              {"note", "AU15"}};
  return {{"format", "mimetic-arkit-map"}, {"version", 1}, {"shapes", shapes}};
}

TEST(ArkitMap, AppleHas52NamesAndTheCodeKnowsExactlyThose) {
  ASSERT_EQ(kApple.size(), 52u);
  std::vector<std::string> code(ArkitShapeNames().begin(), ArkitShapeNames().end());
  std::sort(code.begin(), code.end());
  EXPECT_EQ(code, kApple);  // kApple is sorted
}

TEST(ArkitMap, ReadsAHandMadeMapAndRoundTrips) {
  std::vector<ArkitShape> shapes;
  Diagnostics diag;
  ASSERT_TRUE(ParseArkitMap(GoodMap().dump(), "m.json", &shapes, &diag)) << diag.Format();
  ASSERT_EQ(shapes.size(), 52u);
  int solved = 0, anatomy = 0;
  for (const ArkitShape& s : shapes) {
    if (s.name == "mouthSmileLeft") {
      ++solved;
      EXPECT_EQ(s.how, ArkitShape::How::kSolved);
      EXPECT_EQ(s.target, "ict-facekit/arkit/mouthSmile_L.obj");
      EXPECT_DOUBLE_EQ(s.ratio, 0.5);
      EXPECT_EQ(s.activations,
                (std::vector<std::pair<std::string, float>>{{"zygomaticus_major_L", 0.75f}}));
    } else if (s.name == "mouthFrownLeft") {
      ++anatomy;
      EXPECT_EQ(s.how, ArkitShape::How::kAnatomy);
      EXPECT_EQ(s.note, "AU15");
    } else {
      EXPECT_EQ(s.how, ArkitShape::How::kNone) << s.name;
    }
  }
  EXPECT_EQ(solved, 1);
  EXPECT_EQ(anatomy, 1);
  const std::string path = test::TempDir() + "/m.arkit.json";
  ASSERT_TRUE(SaveArkitMap(path, shapes, &diag)) << diag.Format();
  std::vector<ArkitShape> back;
  ASSERT_TRUE(LoadArkitMap(path, &back, &diag)) << diag.Format();
  ASSERT_EQ(back.size(), shapes.size());
  for (size_t i = 0; i < shapes.size(); ++i) {
    EXPECT_EQ(back[i].name, shapes[i].name);
    EXPECT_EQ(back[i].how, shapes[i].how);
    EXPECT_EQ(back[i].activations, shapes[i].activations);
    EXPECT_EQ(back[i].note, shapes[i].note);
    EXPECT_EQ(back[i].target, shapes[i].target);
    EXPECT_EQ(back[i].mean_distance, shapes[i].mean_distance);
    EXPECT_EQ(back[i].ratio, shapes[i].ratio);
  }
}

TEST(ArkitMap, BadInputsSayWhatAndWhere) {
  struct Case {
    std::string text;
    std::vector<std::string> messages;
  };
  std::vector<Case> cases;
  auto edit = [&](auto change, std::vector<std::string> messages) {
    nlohmann::json j = GoodMap();
    change(j);
    cases.push_back({j.dump(), messages});
  };
  edit([](nlohmann::json& j) { j["shapes"].erase("tongueOut"); },
       {"shapes.tongueOut: missing required key"});
  edit([](nlohmann::json& j) { j["shapes"]["browDownLeftt"] = j["shapes"]["tongueOut"]; },
       {"shapes.browDownLeftt: unknown key", "closest: browDownLeft"});
  edit([](nlohmann::json& j) { j["shapes"]["eyeBlink_L"] = j["shapes"]["tongueOut"]; },
       {"shapes.eyeBlink_L", "eyeBlinkLeft"});
  edit([](nlohmann::json& j) { j["shapes"]["jawOpen"]["how"] = "maybe"; },
       {"shapes.jawOpen.how"});
  edit([](nlohmann::json& j) { j["shapes"]["jawOpen"].erase("how"); },
       {"shapes.jawOpen.how: missing required key"});
  edit([](nlohmann::json& j) { j["shapes"]["mouthFrownLeft"]["activations"]["m"] = 2; },
       {"shapes.mouthFrownLeft.activations.m: is 2; expected an activation in [0, 1]"});
  edit([](nlohmann::json& j) { j["shapes"]["mouthFrownLeft"]["activations"] = {0.5}; },
       {"shapes.mouthFrownLeft.activations"});
  edit([](nlohmann::json& j) { j["shapes"]["jawOpen"]["activations"]["m"] = 0.3; },
       {"shapes.jawOpen.activations.m: is 0.3 in a shape the muscles cannot make"});
  edit([](nlohmann::json& j) { j["shapes"]["mouthSmileLeft"].erase("target"); },
       {"shapes.mouthSmileLeft.target: missing required key"});
  edit([](nlohmann::json& j) { j["shapes"]["mouthSmileLeft"]["ratio"] = 0.9; },
       {"shapes.mouthSmileLeft.ratio: is 0.9; expected mean_distance / neutral_mean_distance = 0.5"});
  edit([](nlohmann::json& j) { j["shapes"]["mouthSmileLeft"]["neutral_mean_distance"] = 0; },
       {"shapes.mouthSmileLeft.neutral_mean_distance"});
  edit([](nlohmann::json& j) { j["shapes"]["jawOpen"]["target"] = "x.obj"; },
       {"shapes.jawOpen.target: unknown key"});
  edit([](nlohmann::json& j) { j["version"] = 2; }, {"version"});
  edit([](nlohmann::json& j) { j["format"] = "mimetic-rig"; }, {"format"});
  edit([](nlohmann::json& j) { j.erase("shapes"); }, {"shapes: missing required key"});
  // A name twice (the JSON library keeps one, so the text is written by hand).
  std::string twice = GoodMap().dump();
  const std::string tongue = "\"tongueOut\":";
  twice.insert(twice.find(tongue), "\"tongueOut\":{\"how\":\"none\",\"activations\":{}},");
  cases.push_back({twice, {"shapes.tongueOut: duplicate key"}});
  for (const Case& c : cases) {
    std::vector<ArkitShape> shapes;
    Diagnostics diag;
    EXPECT_FALSE(ParseArkitMap(c.text, "m.json", &shapes, &diag));
    for (const std::string& m : c.messages)
      EXPECT_NE(diag.Format().find(m), std::string::npos) << m << "\n" << diag.Format();
  }
}

TEST(ArkitMap, TheWriterRefusesAnIncompleteMap) {
  std::vector<ArkitShape> shapes;
  Diagnostics diag;
  ASSERT_TRUE(ParseArkitMap(GoodMap().dump(), "m.json", &shapes, &diag)) << diag.Format();
  shapes.pop_back();  // tongueOut
  shapes[0].activations = {{"m", 0.5f}};  // eyeBlinkLeft is "none"
  const std::string path = test::TempDir() + "/bad.arkit.json";
  EXPECT_FALSE(SaveArkitMap(path, shapes, &diag));
  EXPECT_NE(diag.Format().find("shapes.tongueOut"), std::string::npos) << diag.Format();
  EXPECT_NE(diag.Format().find("shapes.eyeBlinkLeft.activations.m"), std::string::npos)
      << diag.Format();
  EXPECT_FALSE(std::filesystem::exists(path));
}

std::vector<ArkitShape> LoadDefaultMap() {
  std::vector<ArkitShape> shapes;
  Diagnostics diag;
  EXPECT_TRUE(LoadArkitMap(test::SourceDir() + "/assets/arkit/default.arkit.json", &shapes, &diag))
      << diag.Format();
  return shapes;
}

TEST(ArkitMap, TheDefaultMapFitsTheSampleHead) {
  const std::vector<ArkitShape> shapes = LoadDefaultMap();
  ASSERT_EQ(shapes.size(), 52u);
  LoadedRig loaded;
  Diagnostics diag;
  ASSERT_TRUE(LoadRig(test::SourceDir() + "/assets/head/sample_head.rig.json", &loaded, &diag))
      << diag.Format();
  EXPECT_TRUE(CheckArkitMuscles(shapes, loaded.rig.muscle_names(), "default.arkit.json", &diag))
      << diag.Format();
  for (const ArkitShape& s : shapes) {
    EXPECT_FALSE(s.note.empty()) << s.name;
    if (s.how != ArkitShape::How::kNone) {
      EXPECT_FALSE(s.activations.empty()) << s.name;
    }
    // A Left shape moves the subject's left muscles more than the right ones.
    const bool left = s.name.ends_with("Left"), right = s.name.ends_with("Right");
    if (s.how == ArkitShape::How::kNone || !(left || right) || s.name.starts_with("mouthLeft") ||
        s.name.starts_with("mouthRight"))
      continue;
    double l = 0, r = 0;
    for (const auto& [m, v] : s.activations) (m.ends_with("_L") ? l : r) += v;
    EXPECT_GT(left ? l : r, left ? r : l) << s.name;
  }
}

// The smile, recomputed: the template fitted to ICT's neutral, posed with the stored
// activations, measured against the real mouthSmile_L over the vertices it moves more than 2%
// of its largest motion: closer than the neutral, and the distances the file records.
TEST(ArkitMap, TheSolvedSmileBeatsTheNeutralOnTheRealShape) {
  const std::string shared = test::SharedDir();
  const std::string data = shared + "/data/ict-facekit/";
  if (shared.empty() || !std::ifstream(data + "arkit/mouthSmile_L.obj"))
    GTEST_SKIP() << "../shared/data/ict-facekit is absent: the solved smile is not recomputed";
  const std::vector<ArkitShape> shapes = LoadDefaultMap();
  const auto smile = std::find_if(shapes.begin(), shapes.end(),
                                  [](const ArkitShape& s) { return s.name == "mouthSmileLeft"; });
  ASSERT_NE(smile, shapes.end());
  ASSERT_EQ(smile->how, ArkitShape::How::kSolved);
  EXPECT_EQ(smile->target, "ict-facekit/arkit/mouthSmile_L.obj");

  Diagnostics diag;
  MuscleTemplate tmpl;
  MeshData neutral, target;
  Landmarks landmarks;
  ASSERT_TRUE(LoadMuscleTemplate(test::SourceDir() + "/assets/head/default.template.json", &tmpl,
                                 &diag)) << diag.Format();
  ASSERT_TRUE(ImportMesh(data + "ict_skin_neutral.obj", "", &neutral, &diag)) << diag.Format();
  ASSERT_TRUE(ImportMesh(data + "arkit/mouthSmile_L.obj", "", &target, &diag)) << diag.Format();
  ASSERT_TRUE(LoadLandmarks(test::SourceDir() + "/tests/data/landmarks/ict_facekit.landmarks.json",
                            &landmarks, &diag)) << diag.Format();
  RigSpec spec;
  ASSERT_TRUE(FitTemplate(tmpl, neutral, landmarks, "cm", &spec, &diag)) << diag.Format();
  Rig rig;
  ASSERT_TRUE(BuildRig(spec, neutral, {}, &rig, &diag)) << diag.Format();
  std::vector<float> a(rig.muscle_count(), 0.f);
  for (const auto& [m, v] : smile->activations) {
    const int i = rig.FindMuscle(m);
    ASSERT_GE(i, 0) << m;
    a[size_t(i)] = v;
  }
  MeshData full;
  ASSERT_TRUE(PosedMesh(rig, a, {}, &full));
  MeshData posed = neutral;
  for (size_t v = 0; v < neutral.vertex_count(); ++v) posed.positions[v] = full.positions[v];
  const CompareOptions o = test::MovedRegion(neutral, target);
  CompareResult r;
  ASSERT_TRUE(CompareMeshes(posed, target, o, &r, &diag)) << diag.Format();
  EXPECT_LT(r.b_to_a.mean, r.b_to_neutral.mean);
  EXPECT_NEAR(r.b_to_a.mean, smile->mean_distance, 0.01 * smile->mean_distance);
  EXPECT_NEAR(r.b_to_neutral.mean, smile->neutral_mean_distance, 0.01 * smile->neutral_mean_distance);
}

}  // namespace
}  // namespace mimetic

// The viewer's session (viewer/core/session.h): a file that fails to load keeps the last good
// state and reports every message; --set, the expression blend and the clip pose the rig; the
// displacement overlay equals |posed - rest| of an independent PosedMesh.
#include "viewer/core/session.h"

#include <cmath>
#include <cstring>
#include <fstream>
#include <set>

#include <gtest/gtest.h>

#include "io/expression_library.h"
#include "rig/offline/rig_builder.h"
#include "test_support.h"
#include "viewer/core/rig_edit.h"

namespace mimetic::viewer {
namespace {

std::string Surface() { return test::SourceDir() + "/assets/surface/surface.rig.json"; }

bool AnyMessageContains(const Session& s, const std::string& needle) {
  for (const Message& m : s.messages())
    if (m.text.find(needle) != std::string::npos) return true;
  return false;
}

TEST(ViewerSession, ABrokenRigKeepsTheLastGoodOne) {
  Session s(1);
  ASSERT_TRUE(s.LoadRigFile(Surface()));
  const uint32_t vertices = s.rig().vertex_count();
  const std::string bad = test::SourceDir() + "/tests/data/bad/rig_mesh_missing.json";
  EXPECT_FALSE(s.LoadRigFile(bad));
  ASSERT_TRUE(s.has_rig());
  EXPECT_EQ(s.rig_path(), Surface());
  EXPECT_EQ(s.rig().vertex_count(), vertices);
  EXPECT_TRUE(AnyMessageContains(s, "rig_mesh_missing.json"));
  EXPECT_TRUE(AnyMessageContains(s, "still showing"));
  EXPECT_FALSE(s.LoadRigFile(test::TempDir() + "/no_such.rig.json"));
  EXPECT_TRUE(AnyMessageContains(s, "no_such.rig.json"));
  EXPECT_TRUE(s.Evaluate(Overlay::kNone));
}

TEST(ViewerSession, ABrokenClipOrLibraryChangesNothing) {
  Session s(1);
  EXPECT_FALSE(s.LoadClipFile(test::SourceDir() + "/assets/clips/smile.clip.json"));
  EXPECT_TRUE(AnyMessageContains(s, "no rig is loaded"));
  ASSERT_TRUE(s.LoadRigFile(Surface()));
  EXPECT_FALSE(s.LoadClipFile(test::SourceDir() + "/tests/data/bad/clip_unknown_muscle.clip.json"));
  EXPECT_FALSE(s.has_clip());
  EXPECT_TRUE(AnyMessageContains(s, "zygomatc"));
  EXPECT_FALSE(s.LoadLibraryFile(test::SourceDir() + "/tests/data/bad/clip_not_json.clip.json"));
  EXPECT_TRUE(s.library().empty());
}

TEST(ViewerSession, SettingsBlendAndClipPoseTheRig) {
  Session s(2);
  ASSERT_TRUE(s.LoadRigFile(Surface()));
  const int zyg = s.rig().FindMuscle("zygomatic"), front = s.rig().FindMuscle("frontalis");
  ASSERT_GE(zyg, 0);
  ASSERT_GE(front, 0);
  ASSERT_TRUE(s.ApplySettings({"zygomatic=0.75"}));
  EXPECT_FLOAT_EQ(s.activations[size_t(zyg)], 0.75f);
  EXPECT_FALSE(s.ApplySettings({"zygomatc=1"}));  // unknown: the pose is kept
  EXPECT_FLOAT_EQ(s.activations[size_t(zyg)], 0.75f);
  EXPECT_TRUE(AnyMessageContains(s, "zygomatc"));

  // The displacement overlay is |posed - rest| of the same pose through PosedMesh.
  ASSERT_TRUE(s.Evaluate(Overlay::kDisplacement));
  MeshData posed;
  ASSERT_TRUE(PosedMesh(s.rig(), s.activations, SkinLayers{}, &posed));
  const MeshData rest = RestMesh(s.rig());
  const OverlayField& f = s.overlay_field();
  ASSERT_EQ(f.values.size(), posed.positions.size());
  float largest = 0.f;
  for (size_t v = 0; v < posed.positions.size(); ++v) {
    EXPECT_NEAR(f.values[v], Length(posed.positions[v] - rest.positions[v]), 1e-4f) << v;
    largest = std::max(largest, f.values[v]);
  }
  EXPECT_GT(largest, 0.1f);
  EXPECT_FLOAT_EQ(f.max_value, largest);

  // Blend: 0.5 A + 1.0 B with A = {zygomatic 0.8, frontalis 0.4}, B = {frontalis 0.9}:
  // zygomatic 0.4, frontalis min(1, 0.2 + 0.9) = 1.
  const std::string lib = test::TempDir() + "/two.library.json";
  std::ofstream(lib) << R"({"format": "mimetic-expression-library", "version": 1, "expressions": [
    {"name": "A", "activations": {"zygomatic": 0.8, "frontalis": 0.4}},
    {"name": "B", "activations": {"frontalis": 0.9}}]})";
  ASSERT_TRUE(s.LoadLibraryFile(lib));
  ASSERT_EQ(s.expression_weights.size(), 2u);
  s.expression_weights = {0.5f, 1.f};
  s.ApplyExpressionBlend();
  EXPECT_FLOAT_EQ(s.activations[size_t(zyg)], 0.4f);
  EXPECT_FLOAT_EQ(s.activations[size_t(front)], 1.f);

  // A clip of expression A, weight 0 at t = 0 rising linearly to 1 at t = 2: at t = 1, 0.5 A.
  const std::string clip = test::TempDir() + "/a.clip.json";
  std::ofstream(clip) << R"({"format": "mimetic-clip", "version": 1, "name": "a", "channels": [
    {"expression": "A", "keys": [{"t": 0, "v": 0}, {"t": 2, "v": 1}]}]})";
  ASSERT_TRUE(s.LoadClipFile(clip));
  ASSERT_TRUE(s.SampleClip(1.f));
  EXPECT_NEAR(s.activations[size_t(zyg)], 0.4f, 1e-6f);
  EXPECT_NEAR(s.activations[size_t(front)], 0.2f, 1e-6f);
  ASSERT_EQ(s.timeline().size(), 1u);
  EXPECT_EQ(s.timeline()[0].label, "expression A");
}

TEST(ViewerSession, ThreadedEvaluationGivesTheSameBits) {
  Session one(1), two(2);
  ASSERT_TRUE(one.LoadRigFile(Surface()));
  ASSERT_TRUE(two.LoadRigFile(Surface()));
  ASSERT_TRUE(one.ApplySettings({"zygomatic=1", "frontalis=0.6"}));
  ASSERT_TRUE(two.ApplySettings({"zygomatic=1", "frontalis=0.6"}));
  ASSERT_TRUE(one.Evaluate(Overlay::kAreaRatio));
  ASSERT_TRUE(two.Evaluate(Overlay::kAreaRatio));
  ASSERT_EQ(one.positions().size(), two.positions().size());
  EXPECT_EQ(0, std::memcmp(one.positions().data(), two.positions().data(),
                           one.positions().size() * sizeof(float3)));
  EXPECT_EQ(one.overlay_field().values, two.overlay_field().values);
}

// A library made for another rig (the sample head's on the two-muscle test surface): the first
// few unknown names each get a warning, the rest one summary line with the counts, which are
// computed here from the library file independently.
TEST(ViewerSession, ALibraryForAnotherRigWarnsInAFewLines) {
  Session s(1);
  ASSERT_TRUE(s.LoadRigFile(Surface()));
  const std::string lib = test::SourceDir() + "/assets/expressions/default.library.json";
  std::vector<Expression> library;
  Diagnostics diag;
  ASSERT_TRUE(LoadExpressionLibrary(lib, &library, &diag)) << diag.Format();
  const std::set<std::string> known = {"frontalis", "zygomatic", "jaw"};
  size_t activations = 0;
  std::set<std::string> muscles, expressions;
  for (const Expression& e : library)
    for (const auto& [m, v] : e.activations)
      if (!known.count(m)) ++activations, muscles.insert(m), expressions.insert(e.name);
  ASSERT_GT(activations, 3u);
  const size_t before = s.messages().size();
  ASSERT_TRUE(s.LoadLibraryFile(lib));
  ASSERT_EQ(s.messages().size() - before, 4u);
  const std::string summary = s.messages().back().text;
  EXPECT_FALSE(s.messages().back().error);
  const std::string counts = std::to_string(activations - 3) + " more activations name muscles the rig lacks (" +
                             std::to_string(expressions.size()) + " of " + std::to_string(library.size()) +
                             " expressions, " + std::to_string(muscles.size()) + " muscles: ";
  EXPECT_NE(summary.find(counts), std::string::npos) << summary << "\nexpected: " << counts;
  EXPECT_NE(summary.find(*muscles.begin()), std::string::npos) << summary;
}

}  // namespace
}  // namespace mimetic::viewer

namespace mimetic::viewer {
namespace {

// StartRigLoad (the Files panel's Load): the load runs on another thread, PollRigLoad adopts
// it; a broken rig keeps the one shown; two loads in a row show the newer; an edit made
// while a load runs keeps the edit and drops the load, with a message.
TEST(ViewerSession, RigLoadsRunOffTheUiThreadAndTheNewestWins) {
  const std::string surface = test::SourceDir() + "/assets/surface/surface.rig.json";
  const std::string dir = test::TempDir();
  const std::string broken = dir + "/broken.rig.json";
  std::ofstream(broken) << R"({"format": "mimetic-rig", "version": 1, "muscles": 3})";
  Session s(1);
  EXPECT_FALSE(s.PollRigLoad());  // nothing started
  s.StartRigLoad(surface);
  EXPECT_EQ(s.rig_loading_path(), surface);
  ASSERT_TRUE(s.WaitRigLoad());
  ASSERT_TRUE(s.has_rig());
  EXPECT_FALSE(s.rig_loading());
  const uint32_t vertices = s.rig().vertex_count();
  // Loaded alone, the same rig.
  LoadedRig direct;
  Diagnostics diag;
  ASSERT_TRUE(LoadRig(surface, &direct, &diag)) << diag.Format();
  EXPECT_EQ(vertices, direct.rig.vertex_count());

  const size_t before = s.messages().size();
  s.StartRigLoad(broken);
  EXPECT_FALSE(s.WaitRigLoad());
  EXPECT_TRUE(s.has_rig());  // the surface is still shown
  ASSERT_GT(s.messages().size(), before);
  EXPECT_NE(s.messages().back().text.find("the rig was not loaded (still showing"), std::string::npos)
      << s.messages().back().text;

  s.StartRigLoad(broken);
  s.StartRigLoad(surface);  // supersedes the broken one
  EXPECT_TRUE(s.WaitRigLoad());
  EXPECT_FALSE(s.PollRigLoad());  // the broken one's result was dropped, not reported later

  s.StartRigLoad(surface);
  std::string error;
  ASSERT_TRUE(s.Edit(MakeMuscleEdit(*s.rig_spec(), s.rig_spec()->muscles[0].name, "strength", {"5"}, &error), &error))
      << error;
  EXPECT_FALSE(s.WaitRigLoad());
  EXPECT_NE(s.messages().back().text.find("loaded, but not shown"), std::string::npos)
      << s.messages().back().text;
  EXPECT_EQ(s.rig_spec()->muscles[0].strength, 5.f);  // the edit stays
}

}  // namespace
}  // namespace mimetic::viewer

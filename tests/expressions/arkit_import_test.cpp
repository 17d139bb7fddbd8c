// tests/expressions/arkit_import_test.cpp: a take through an ARKit map into a clip
// (expressions/offline/arkit_import.h), against activations worked out by hand.
#include <gtest/gtest.h>

#include "expressions/offline/arkit_import.h"

namespace mimetic {
namespace {

// Two ARKit channels that both move muscle "m" (0.6 and 0.7 of it) and one that also moves "n".
std::vector<ArkitShapeActivations> Map() {
  return {{"jawOpen", false, {{"m", 0.6f}, {"n", 0.5f}}},
          {"mouthClose", false, {{"m", 0.7f}}},
          {"eyeBlinkLeft", true, {}}};
}
const std::vector<std::string> kMuscles = {"n", "m", "idle"};

TEST(ArkitImport, ChannelsOnOneMuscleAddAndClamp) {
  const auto map = Map();
  const std::vector<int> shape = {0, 1};
  const float w1[] = {0.5f, 0.25f};  // m = 0.5 * 0.6 + 0.25 * 0.7 = 0.475, n = 0.25
  auto a = ArkitFrameActivations(map, shape, kMuscles, w1);
  EXPECT_FLOAT_EQ(a[0], 0.25f);
  EXPECT_FLOAT_EQ(a[1], 0.475f);
  EXPECT_EQ(a[2], 0.f);
  const float w2[] = {1.f, 1.f};  // m = 0.6 + 0.7 = 1.3 -> 1
  a = ArkitFrameActivations(map, shape, kMuscles, w2);
  EXPECT_EQ(a[1], 1.f);
  EXPECT_FLOAT_EQ(a[0], 0.5f);
  EXPECT_EQ(FindArkitShape(map, "JawOpen"), 0);
  EXPECT_EQ(FindArkitShape(map, "jawopen"), -1);
}

TEST(ArkitImport, ClipOfATake) {
  ArkitTake take;
  take.names = {"JawOpen", "mouthClose", "EyeBlinkLeft", "HeadYaw"};
  take.times = {0.f, 0.5f, 1.f, 1.5f};
  take.weights = {0.0f, 0.0f, 0.f, 0.1f,    //
                  0.5f, 0.25f, 1.f, 0.2f,   //
                  1.0f, 0.5f, 0.f, 0.f,     //
                  1.0f, 1.0f, 0.f, 0.f};
  ArkitImport out;
  Diagnostics diag;
  ASSERT_TRUE(ImportArkitTake(take, Map(), kMuscles, "take", &out, &diag)) << diag.Format();
  EXPECT_EQ(out.clip.name, "take");
  EXPECT_EQ(out.clip.duration, 1.5f);
  ASSERT_EQ(out.clip.channels.size(), 2u);  // "idle" never moves: no channel
  // n = 0.5 jawOpen: 0, 0.25, 0.5, 0.5: the key at 0.5 s lies on the line 0 -> 0.5 (dropped).
  const auto& n = out.clip.channels[0];
  EXPECT_EQ(n.target, "n");
  ASSERT_EQ(n.keys.size(), 3u);
  EXPECT_EQ(n.keys[0].t, 0.f);
  EXPECT_EQ(n.keys[1].t, 1.f);
  EXPECT_FLOAT_EQ(n.keys[1].v, 0.5f);
  EXPECT_EQ(n.keys[2].t, 1.5f);
  // m: 0, 0.5 * 0.6 + 0.25 * 0.7 = 0.475, 0.6 + 0.5 * 0.7 = 0.95, 1.3 -> 1 (clamped). 0.475
  // is half of 0.95, on the line from 0 s to 1 s: dropped.
  const auto& m = out.clip.channels[1];
  EXPECT_EQ(m.target, "m");
  ASSERT_EQ(m.keys.size(), 3u);
  EXPECT_EQ(m.keys[1].t, 1.f);
  EXPECT_FLOAT_EQ(m.keys[1].v, 0.95f);
  EXPECT_EQ(m.keys[2].v, 1.f);
  for (const auto& k : m.keys) EXPECT_EQ(k.interp, KeyInterp::kLinear);
  // Unused: EyeBlinkLeft ("none", 1 non-zero frame), HeadYaw (not ARKit, 2 non-zero frames).
  ASSERT_EQ(out.unmapped.size(), 2u);
  EXPECT_EQ(out.unmapped[0].name, "EyeBlinkLeft");
  EXPECT_TRUE(out.unmapped[0].none);
  EXPECT_EQ(out.unmapped[0].nonzero, 1u);
  EXPECT_EQ(out.unmapped[1].name, "HeadYaw");
  EXPECT_FALSE(out.unmapped[1].none);
  EXPECT_EQ(out.unmapped[1].nonzero, 2u);
  const std::string w = ArkitUnmappedWarning(out.unmapped);
  EXPECT_EQ(w, "2 channels are not used: HeadYaw (2 non-zero frames) (not ARKit blendshape "
               "names); EyeBlinkLeft (1 non-zero frame) (the map marks them \"none\": the "
               "rig's muscles cannot make them)");
}

TEST(ArkitImport, ReductionKeepsEveryDroppedSampleWithinTolerance) {
  // Flat for 1 s, then a ramp: every key but the corner lies on its neighbours' line, and the
  // line from the first key must not swallow the corner (its error grows past 1e-4).
  std::vector<ClipKeySpec> keys;
  for (int i = 0; i <= 20; ++i) {
    const float t = float(i) * 0.1f;
    const float v = i <= 10 ? 0.f : float(i - 10) * 0.05f;  // flat, then a ramp: a corner at 1 s
    keys.push_back({t, v, KeyInterp::kLinear, KeyTangent::kAuto});
  }
  const std::vector<ClipKeySpec> original = keys;
  ReduceLinearKeys(&keys, 1e-4f);
  ASSERT_EQ(keys.size(), 3u);  // 0 s, the corner at 1 s, 2 s
  EXPECT_FLOAT_EQ(keys[1].t, 1.0f);
  EXPECT_EQ(keys[1].v, 0.f);
  // Every original sample is reproduced by the reduced keys within 1e-4.
  for (const ClipKeySpec& k : original) {
    size_t s = 0;
    while (s + 2 < keys.size() && keys[s + 1].t <= k.t) ++s;
    const double u = (double(k.t) - keys[s].t) / (double(keys[s + 1].t) - keys[s].t);
    EXPECT_NEAR(keys[s].v + u * (keys[s + 1].v - keys[s].v), k.v, 1e-4);
  }
}

TEST(ArkitImport, Errors) {
  ArkitTake take;
  ArkitImport out;
  Diagnostics diag;
  EXPECT_FALSE(ImportArkitTake(take, Map(), kMuscles, "x", &out, &diag));
  EXPECT_NE(diag.Format().find("has no frames"), std::string::npos) << diag.Format();
  take.names = {"jawOpen"};
  take.times = {0.f};
  take.weights = {0.5f};
  diag.Clear();
  EXPECT_FALSE(ImportArkitTake(take, Map(), {"m"}, "x", &out, &diag));  // no "n" in the rig
  EXPECT_NE(diag.Format().find("muscle \"n\" is not one of the rig's"), std::string::npos)
      << diag.Format();
}

}  // namespace
}  // namespace mimetic

// tests/io/clip_file_test.cpp: clip files (io/clip_file.h): the example file, defaults, a
// round trip through ClipToJson / SaveClip, and the bad-input table (every message with the
// JSON path of what is wrong).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "io/clip_file.h"
#include "test_support.h"

namespace mimetic {
namespace {

bool SameKeys(const ClipKeySpec& a, const ClipKeySpec& b) {
  return a.t == b.t && a.v == b.v && a.interp == b.interp && a.tangent == b.tangent;
}

void ExpectSameClip(const ClipSpec& a, const ClipSpec& b) {
  EXPECT_EQ(a.name, b.name);
  EXPECT_EQ(a.duration, b.duration);
  EXPECT_EQ(a.end, b.end);
  ASSERT_EQ(a.channels.size(), b.channels.size());
  for (size_t i = 0; i < a.channels.size(); ++i) {
    const ClipChannelSpec &x = a.channels[i], &y = b.channels[i];
    EXPECT_EQ(x.kind, y.kind);
    EXPECT_EQ(x.target, y.target);
    EXPECT_EQ(x.layer, y.layer);
    ASSERT_EQ(x.keys.size(), y.keys.size());
    for (size_t k = 0; k < x.keys.size(); ++k) EXPECT_TRUE(SameKeys(x.keys[k], y.keys[k])) << i << " " << k;
  }
}

TEST(ClipFile, ReadsTheExample) {
  ClipSpec clip;
  Diagnostics diag;
  ASSERT_TRUE(LoadClip(test::SourceDir() + "/tests/data/clips/smile_blink.clip.json", &clip, &diag))
      << diag.Format();
  EXPECT_EQ(clip.name, "smile_and_brows");
  EXPECT_EQ(clip.duration, 2.f);
  EXPECT_EQ(clip.end, ClipEnd::kLoop);
  ASSERT_EQ(clip.channels.size(), 2u);
  const ClipChannelSpec& smile = clip.channels[0];
  EXPECT_EQ(smile.kind, ClipChannelKind::kExpression);
  EXPECT_EQ(smile.target, "mouthSmile_L");
  EXPECT_EQ(smile.layer, ClipLayer::kAdd);
  ASSERT_EQ(smile.keys.size(), 3u);
  EXPECT_TRUE(SameKeys(smile.keys[1], {1.f, 1.f, KeyInterp::kCubic, KeyTangent::kClamped}));
  // Defaults: interp linear, tangent auto.
  EXPECT_TRUE(SameKeys(smile.keys[2], {2.f, 0.f, KeyInterp::kLinear, KeyTangent::kAuto}));
  const ClipChannelSpec& brow = clip.channels[1];
  EXPECT_EQ(brow.kind, ClipChannelKind::kMuscle);
  EXPECT_EQ(brow.target, "frontalis_inner");
  EXPECT_TRUE(SameKeys(brow.keys[0], {0.f, 0.f, KeyInterp::kStep, KeyTangent::kAuto}));
}

TEST(ClipFile, DefaultsAndTheDurationOfTheLastKey) {
  const std::string text = R"({"format": "mimetic-clip", "version": 1, "name": "c",
      "channels": [{"expression": "E", "keys": [{"t": 0.25, "v": 0.5}, {"t": 1.5, "v": 1}]},
                   {"muscle": "m", "keys": [{"t": 0, "v": 0}]}]})";
  ClipSpec clip;
  Diagnostics diag;
  ASSERT_TRUE(ParseClip(text, "c.clip.json", &clip, &diag)) << diag.Format();
  EXPECT_LT(clip.duration, 0.f);  // not given
  EXPECT_EQ(ClipDuration(clip), 1.5f);
  EXPECT_EQ(clip.end, ClipEnd::kClamp);
  EXPECT_EQ(clip.channels[0].layer, ClipLayer::kAdd);
}

TEST(ClipFile, RoundTripsThroughSaveAndLoad) {
  ClipSpec clip{"round trip", 3.5f, ClipEnd::kLoop, {}};
  clip.channels.push_back({ClipChannelKind::kMuscle, "zygomaticus_major_L", ClipLayer::kAdd,
                           {{0.f, 0.1f, KeyInterp::kCubic, KeyTangent::kClamped},
                            {0.1f, 0.3333333f, KeyInterp::kStep, KeyTangent::kAuto},
                            {3.25f, 1.f, KeyInterp::kLinear, KeyTangent::kAuto}}});
  clip.channels.push_back({ClipChannelKind::kExpression, "Smile", ClipLayer::kOverride,
                           {{1e-3f, 0.7f, KeyInterp::kCubic, KeyTangent::kAuto}}});
  clip.channels.push_back({ClipChannelKind::kExpression, "Frown", ClipLayer::kMax,
                           {{0.f, 0.f, KeyInterp::kLinear, KeyTangent::kAuto}}});
  ClipSpec back;
  Diagnostics diag;
  ASSERT_TRUE(ParseClip(ClipToJson(clip), "", &back, &diag)) << diag.Format() << ClipToJson(clip);
  ExpectSameClip(clip, back);
  const std::string path = test::TempDir() + "/r.clip.json";
  ASSERT_TRUE(SaveClip(path, clip, &diag)) << diag.Format();
  ClipSpec loaded;
  ASSERT_TRUE(LoadClip(path, &loaded, &diag)) << diag.Format();
  ExpectSameClip(clip, loaded);
  // Short numbers: 0.1f is written as 0.1, not 0.10000000149011612.
  EXPECT_NE(ClipToJson(clip).find("\"v\": 0.1,"), std::string::npos) << ClipToJson(clip);
}

TEST(ClipFile, SaveRefusesABrokenClipAndWritesNothing) {
  ClipSpec clip{"bad", -1.f, ClipEnd::kClamp, {}};
  clip.channels.push_back({ClipChannelKind::kMuscle, "m", ClipLayer::kAdd,
                           {{1.f, 0.5f}, {1.f, 0.6f}}});
  const std::string path = test::TempDir() + "/bad.clip.json";
  Diagnostics diag;
  EXPECT_FALSE(SaveClip(path, clip, &diag));
  EXPECT_NE(diag.Format().find(path + ": channels[0].keys[1].t: is 1, not after keys[0].t = 1"),
            std::string::npos) << diag.Format();
  ClipSpec back;
  Diagnostics none;
  EXPECT_FALSE(LoadClip(path, &back, &none));  // nothing was written
}

TEST(ClipFile, BadInputsSayWhatAndWhere) {
  const std::string head = R"({"format": "mimetic-clip", "version": 1, "name": "c", )";
  auto clip = [&](const std::string& rest) { return head + rest + "}"; };
  const std::string one = R"("channels": [{"muscle": "m", "keys": [{"t": 0, "v": 0.5}]}])";
  struct Case {
    std::string text;
    std::string message;  // "where: what" as Diagnostics::Format prints it
  };
  const std::vector<Case> cases = {
      {"", "bad.clip.json: invalid JSON"},
      {"[1]", "expected an object with \"format\": \"mimetic-clip\""},
      {R"({"format": "mimetic-rig", "version": 1, "name": "c", "channels": []})",
       "bad.clip.json: format: expected \"mimetic-clip\", got \"mimetic-rig\""},
      {R"({"format": "mimetic-clip", "version": 2, "name": "c", "channels": []})",
       "bad.clip.json: version: unsupported version 2"},
      {clip(R"("channels": [])"), "bad.clip.json: channels: expected a non-empty array of channels, got array of 0 elements"},
      {clip(R"("channels": [{"muscle": "m", "keys": []}])"),
       "bad.clip.json: channels[0].keys: expected a non-empty array of keys {\"t\": s, \"v\": value}, got array of 0 elements"},
      {clip(R"("channels": [{"muscle": "m"}])"),
       "bad.clip.json: channels[0].keys: missing required key; expected a non-empty array of keys"},
      {clip(R"("channels": [{"muscle": "m", "expression": "E", "keys": [{"t": 0, "v": 0}]}])"),
       "bad.clip.json: channels[0]: has both \"muscle\" and \"expression\""},
      {clip(R"("channels": [{"keys": [{"t": 0, "v": 0}]}])"),
       "bad.clip.json: channels[0]: has neither \"muscle\" nor \"expression\""},
      {clip(R"("channels": [{"muscle": "m", "layer": "add", "keys": [{"t": 0, "v": 0}]}])"),
       "bad.clip.json: channels[0].layer: is given on a muscle channel"},
      {clip(R"("channels": [{"expression": "E", "layer": "multiply", "keys": [{"t": 0, "v": 0}]}])"),
       "bad.clip.json: channels[0].layer: expected one of \"add\", \"max\", \"override\", got \"multiply\""},
      {clip(R"("channels": [{"muscle": "m", "keys": [{"t": -1, "v": 0}]}])"),
       "bad.clip.json: channels[0].keys[0].t: expected a time in seconds >= 0, got -1"},
      {clip(R"("channels": [{"muscle": "m", "keys": [{"t": 0, "v": 1.5}]}])"),
       "bad.clip.json: channels[0].keys[0].v: expected a value in [0, 1], got 1.5"},
      {clip(R"("channels": [{"muscle": "m", "keys": [{"t": 0, "v": "half"}]}])"),
       "bad.clip.json: channels[0].keys[0].v: expected a value in [0, 1], got string"},
      {clip(R"("channels": [{"muscle": "m", "keys": [{"t": 0, "v": 0, "interp": "bezier"}]}])"),
       "bad.clip.json: channels[0].keys[0].interp: expected one of \"step\", \"linear\", \"cubic\", got \"bezier\""},
      {clip(R"("channels": [{"muscle": "m", "keys": [{"t": 0, "v": 0, "tangent": "flat"}]}])"),
       "bad.clip.json: channels[0].keys[0].tangent: expected one of \"auto\", \"clamped\", got \"flat\""},
      {clip(R"("channels": [{"muscle": "m", "keys": [{"t": 0, "v": 0, "time": 1}]}])"),
       "bad.clip.json: channels[0].keys[0].time: unknown key \"time\"; allowed keys for a key: t, v, interp, tangent"},
      {clip(R"("channels": [{"muscle": "m", "keys": [{"t": 0.5, "v": 0}, {"t": 0.25, "v": 1}]}])"),
       "bad.clip.json: channels[0].keys[1].t: is 0.25, not after keys[0].t = 0.5; expected key "
       "times strictly increasing"},
      {clip(R"("channels": [{"muscle": "m", "keys": [{"t": 0.5, "v": 0}, {"t": 0.5, "v": 1}]}])"),
       "bad.clip.json: channels[0].keys[1].t: is 0.5, not after keys[0].t = 0.5"},
      {clip(R"("channels": [{"muscle": "m", "keys": [{"t": 0, "v": 0}]},
                            {"muscle": "m", "keys": [{"t": 0, "v": 1}]}])"),
       "bad.clip.json: channels[1].muscle: \"m\" is already the target of channels[0]"},
      {clip(R"("channels": [{"expression": "E", "keys": [{"t": 0, "v": 0}]},
                            {"expression": "E", "keys": [{"t": 0, "v": 1}]}])"),
       "bad.clip.json: channels[1].expression: \"E\" is already the target of channels[0]"},
      {clip(R"("duration": 0.5, "channels": [{"muscle": "m", "keys": [{"t": 0, "v": 0}, {"t": 2, "v": 1}]}])"),
       "bad.clip.json: duration: is 0.5 s, before the last key (channels[0].keys[1].t = 2)"},
      {clip(R"("duration": 0, )" + one), "bad.clip.json: duration: expected a number of seconds > 0, got 0"},
      {clip(R"("end": "loop", )" + one),
       "bad.clip.json: end: is \"loop\" but the clip lasts 0 s"},
      {clip(R"("end": "bounce", )" + one),
       "bad.clip.json: end: expected one of \"clamp\", \"loop\", got \"bounce\""},
      {clip(R"("channels": [{"muscle": "", "keys": [{"t": 0, "v": 0}]}])"),
       "bad.clip.json: channels[0].muscle: expected non-empty string, got empty string"},
      {clip(R"("channels": [{"muscle": "m", "keys": [{"t": 1e400, "v": 0}]}])"),
       "bad.clip.json: channels[0].keys[0].t: expected a time in seconds >= 0, got a number that overflows to infinity"},
      {head.substr(0, head.size() - 2) + "}", "bad.clip.json: channels: missing required key; expected a non-empty array of channels"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.text);
    ClipSpec out;
    Diagnostics diag;
    EXPECT_FALSE(ParseClip(c.text, "bad.clip.json", &out, &diag));
    EXPECT_NE(diag.Format().find(c.message), std::string::npos)
        << "expected: " << c.message << "\ngot:\n" << diag.Format();
  }
  // Every problem of a file is reported, not only the first.
  ClipSpec out;
  Diagnostics diag;
  EXPECT_FALSE(ParseClip(clip(R"("channels": [{"muscle": "m", "keys": [{"t": -1, "v": 2}]},
      {"expression": "E", "layer": "x", "keys": [{"t": 0, "v": 0}]}])"), "bad.clip.json", &out, &diag));
  EXPECT_EQ(diag.ErrorCount(), 3u) << diag.Format();
}

TEST(ClipFile, BuildClipTakesTheExpressionsOfExpressionFiles) {
  ClipSpec spec;
  Diagnostics diag;
  ASSERT_TRUE(LoadClip(test::SourceDir() + "/tests/data/clips/smile_blink.clip.json", &spec, &diag))
      << diag.Format();
  Expression smile;
  ASSERT_TRUE(LoadExpression(test::SourceDir() + "/tests/data/expressions/smile_L.expression.json",
                             &smile, &diag)) << diag.Format();
  const std::vector<std::string> muscles = {"frontalis_inner_L", "frontalis_inner_R", "risorius_L",
                                            "zygomaticus_major_L"};
  CompiledClip clip;
  ASSERT_TRUE(BuildClip(spec, muscles, std::vector<Expression>{smile}, &clip, &diag))
      << diag.Format();
  EXPECT_EQ(clip.channel_count(), 3u);  // the expression, frontalis_inner_L and _R
  EXPECT_EQ(clip.expression_count(), 1u);
  // The expression's row, dense in rig order: frontalis_inner_L 0, _R 0 (not named), risorius 0.42, zygomaticus 1.
  const auto row = clip.expression_activations();
  ASSERT_EQ(row.size(), 4u);
  EXPECT_EQ(row[2], 0.42f);
  EXPECT_EQ(row[3], 1.f);
  EXPECT_EQ(clip.expression_masks()[0], 1);  // named (0.0)
  EXPECT_EQ(clip.expression_masks()[1], 0);
}

}  // namespace
}  // namespace mimetic

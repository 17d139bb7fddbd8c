// The timeline's channel and key listing and the playhead (viewer/core/timeline.h).
#include "viewer/core/timeline.h"

#include <gtest/gtest.h>

#include "expressions/offline/clip_builder.h"

namespace mimetic::viewer {
namespace {

TEST(ViewerTimeline, ListsEveryChannelWithItsKeys) {
  ClipSpec spec;
  spec.name = "t";
  ClipChannelSpec a;
  a.kind = ClipChannelKind::kMuscle;
  a.target = "b";
  a.keys = {{0.f, 0.f}, {0.5f, 1.f}, {2.f, 0.25f}};
  ClipChannelSpec e;
  e.kind = ClipChannelKind::kExpression;
  e.target = "Smile";
  e.keys = {{1.f, 0.5f}};
  spec.channels = {a, e};
  const std::vector<std::string> muscles = {"a", "b"};
  const std::vector<ClipExpression> expressions = {{"Smile", {{"a", 1.f}}}};
  CompiledClip clip;
  Diagnostics diag;
  ASSERT_TRUE(BuildClip(spec, muscles, expressions, &clip, &diag)) << diag.Format();
  const std::vector<TimelineChannel> rows = ListTimeline(clip, muscles, &spec);
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0].label, "muscle b");
  EXPECT_EQ(rows[0].key_times, (std::vector<float>{0.f, 0.5f, 2.f}));
  EXPECT_EQ(rows[0].key_values, (std::vector<float>{0.f, 1.f, 0.25f}));
  EXPECT_EQ(rows[1].label, "expression Smile");
  EXPECT_EQ(rows[1].key_times, (std::vector<float>{1.f}));
  // Without the spec (a compiled .mclip) the expression has no name.
  EXPECT_EQ(ListTimeline(clip, muscles, nullptr)[1].label, "expression #0");
  EXPECT_TRUE(ListTimeline(CompiledClip{}, muscles, nullptr).empty());
}

TEST(ViewerTimeline, PlayheadLoopsOrStops) {
  bool stopped = true;
  EXPECT_FLOAT_EQ(AdvancePlayhead(1.f, 0.5f, 2.f, false, &stopped), 1.5f);
  EXPECT_FALSE(stopped);
  EXPECT_FLOAT_EQ(AdvancePlayhead(1.5f, 1.f, 2.f, false, &stopped), 2.f);
  EXPECT_TRUE(stopped);
  EXPECT_FLOAT_EQ(AdvancePlayhead(1.5f, 1.f, 2.f, true, &stopped), 0.5f);
  EXPECT_FALSE(stopped);
  EXPECT_FLOAT_EQ(AdvancePlayhead(0.5f, -1.f, 2.f, true, &stopped), 1.5f);
  EXPECT_FLOAT_EQ(AdvancePlayhead(0.5f, 6.f, 2.f, true, &stopped), 0.5f);
  EXPECT_FLOAT_EQ(AdvancePlayhead(1.f, 1.f, 0.f, true, &stopped), 0.f);
}

}  // namespace
}  // namespace mimetic::viewer

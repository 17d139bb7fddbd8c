// mimetic-viewer's command line (viewer/core/args.h).
#include "viewer/core/args.h"

#include <gtest/gtest.h>

namespace mimetic::viewer {
namespace {

TEST(ViewerArgs, AScreenshotWithEveryOption) {
  ViewerArgs a;
  std::string error;
  ASSERT_TRUE(ParseViewerArgs({"head.rig.json", "--clip", "c.clip.json", "--time=1.5",
                               "--screenshot", "out.PNG", "--size", "640x360", "--overlay",
                               "compression", "--view", "three-quarter", "--ui", "--select", "m"},
                              &a, &error))
      << error;
  EXPECT_EQ(a.rig, "head.rig.json");
  EXPECT_EQ(a.clip, "c.clip.json");
  EXPECT_TRUE(a.has_time);
  EXPECT_FLOAT_EQ(a.time, 1.5f);
  EXPECT_EQ(a.screenshot, "out.PNG");
  EXPECT_EQ(a.width, 640);
  EXPECT_EQ(a.height, 360);
  EXPECT_EQ(a.overlay, Overlay::kCompression);
  EXPECT_EQ(a.view, ViewPreset::kThreeQuarter);
  EXPECT_TRUE(a.ui);
  EXPECT_EQ(a.select, "m");
  EXPECT_TRUE(a.headless());
}

TEST(ViewerArgs, PanelsOpenTheRigEditors) {
  ViewerArgs a;
  std::string error;
  ASSERT_TRUE(ParseViewerArgs({"r.rig.json", "--panel", "uv-curves", "--panel=muscle-editor"}, &a, &error))
      << error;
  EXPECT_EQ(a.panels, (std::vector<std::string>{"uv-curves", "muscle-editor"}));
  EXPECT_FALSE(a.headless());  // a window may open with an editor too
  EXPECT_FALSE(ParseViewerArgs({"r.rig.json", "--panel", "timeline"}, &a, &error));
  EXPECT_EQ(error, "--panel timeline: expected muscle-editor, uv-curves or directions");
}

TEST(ViewerArgs, UiTraceIsForTheWindowOnly) {
  ViewerArgs a;
  std::string error;
  ASSERT_TRUE(ParseViewerArgs({"r.rig.json", "--ui-trace", "t.json"}, &a, &error)) << error;
  EXPECT_EQ(a.ui_trace, "t.json");
  EXPECT_FALSE(a.headless());
  ASSERT_TRUE(ParseViewerArgs({"--ui-trace=u.json"}, &a, &error)) << error;  // no rig: fine
  EXPECT_EQ(a.ui_trace, "u.json");
  ASSERT_TRUE(ParseViewerArgs({"r.rig.json"}, &a, &error)) << error;
  EXPECT_EQ(a.ui_trace, "");  // off by default
  EXPECT_FALSE(ParseViewerArgs({"r.rig.json", "--ui-trace"}, &a, &error));
  EXPECT_EQ(error, "--ui-trace: missing value");
  EXPECT_FALSE(ParseViewerArgs({"r.rig.json", "--ui-trace", "t.json", "--screenshot", "o.png"}, &a, &error));
  EXPECT_EQ(error, "--ui-trace traces the window's widgets: it excludes --screenshot, --bench-frames "
                   "and --script");
}

TEST(ViewerArgs, SetsAndDefaults) {
  ViewerArgs a;
  std::string error;
  ASSERT_TRUE(ParseViewerArgs({"r.mrig", "--set", "jaw=0.5", "--set=frontalis_inner=1"}, &a, &error));
  EXPECT_EQ(a.sets, (std::vector<std::string>{"jaw=0.5", "frontalis_inner=1"}));
  EXPECT_EQ(a.width, 1280);
  EXPECT_EQ(a.height, 720);
  EXPECT_FALSE(a.headless());
  ASSERT_TRUE(ParseViewerArgs({}, &a, &error));  // no rig: the viewer opens empty
  EXPECT_TRUE(a.rig.empty());
  ASSERT_TRUE(ParseViewerArgs({"--help"}, &a, &error));
  EXPECT_TRUE(a.help);
}

TEST(ViewerArgs, FineMapsAndTheirDepth) {
  ViewerArgs a;
  std::string error;
  ASSERT_TRUE(ParseViewerArgs({"r", "--fine", "maps"}, &a, &error)) << error;
  EXPECT_EQ(a.fine, "maps");
  EXPECT_FALSE(a.has_fine_depth);
  EXPECT_EQ(a.fine_depth, 0.15f);  // mimetic render's default
  ASSERT_TRUE(ParseViewerArgs({"r", "--fine=m2", "--fine-depth", "0.4"}, &a, &error)) << error;
  EXPECT_EQ(a.fine, "m2");
  EXPECT_EQ(a.fine_depth, 0.4f);
}

TEST(ViewerArgs, UsageErrorsNameTheOption) {
  const std::vector<std::pair<std::vector<std::string>, std::string>> cases = {
      {{"r", "--bogus"}, "unknown option --bogus"},
      {{"r", "--clip"}, "--clip: missing value"},
      {{"r", "--screenshot", "out.jpg"}, "expected a .png"},
      {{"r", "--screenshot", "o.png", "--size", "10x720"}, "--size 10x720"},
      {{"r", "--screenshot", "o.png", "--size", "1280"}, "WIDTHxHEIGHT"},
      {{"r", "--screenshot", "o.png", "--overlay", "ratio"}, "area-ratio"},
      {{"r", "--screenshot", "o.png", "--view", "top"}, "--view top"},
      {{"r", "--time", "1"}, "--time needs --clip"},
      {{"r", "--clip", "c", "--time", "-1"}, "--time -1"},
      {{"r", "--clip", "c", "--set", "a=1"}, "exclude each other"},
      {{"r", "--overlay", "wrinkle"}, "need --screenshot"},
      {{"r", "--select", "frontalis_inner_L"}, "need --screenshot"},
      {{"--screenshot", "o.png"}, "need RIG"},
      {{"a", "b"}, "at most one RIG"},
      {{"r", "--bench-frames", "2.5"}, "--bench-frames 2.5"},
      {{"r", "--threads", "0"}, "--threads 0"},
      {{"r", "--fine-depth", "0.2"}, "--fine-depth needs --fine"},
      {{"r", "--fine", "maps", "--fine-depth", "nan"}, "--fine-depth nan"},
      {{"r", "--fine", "maps", "--fine-depth", "-1"}, "--fine-depth -1"},
      {{"r", "--fine"}, "--fine: missing value"},
  };
  for (const auto& [args, needle] : cases) {
    ViewerArgs a;
    std::string error;
    EXPECT_FALSE(ParseViewerArgs(args, &a, &error)) << needle;
    EXPECT_NE(error.find(needle), std::string::npos) << "error '" << error << "' lacks '" << needle << "'";
  }
}

}  // namespace
}  // namespace mimetic::viewer

// tests/tools/calibrate_jaw_test.cpp: `mimetic calibrate-jaw`: its usage errors, and (with
// ../shared present) that a run without descent rounds writes the template back with the jaw
// block it was given (range, glide and region unchanged up to the writer's rounding), so the
// command's figures are those of the committed block.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <string>

#include "core/diagnostics.h"
#include "fitting/muscle_template.h"
#include "io/template_file.h"
#include "test_support.h"

namespace mimetic {
namespace {

TEST(CalibrateJaw, UsageAndBadInputs) {
  const test::ToolResult help = test::RunTool({"calibrate-jaw", "--help"});
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_NE(help.output.find("usage: mimetic calibrate-jaw"), std::string::npos) << help.output;
  EXPECT_EQ(test::RunTool({"calibrate-jaw", "extra"}).exit_code, 2);
  EXPECT_EQ(test::RunTool({"calibrate-jaw", "--bogus"}).exit_code, 2);
  const test::ToolResult range = test::RunTool({"calibrate-jaw", "--range", "200"});
  EXPECT_EQ(range.exit_code, 2);
  EXPECT_NE(range.output.find("--range '200': expected a number of degrees in [1, 90]"),
            std::string::npos)
      << range.output;
  const test::ToolResult rounds = test::RunTool({"calibrate-jaw", "--rounds", "2.5"});
  EXPECT_EQ(rounds.exit_code, 2);
  EXPECT_NE(rounds.output.find("--rounds '2.5': expected a whole number in [0, 20]"),
            std::string::npos)
      << rounds.output;
  const test::ToolResult out = test::RunTool({"calibrate-jaw", "--out", "jaw.txt"});
  EXPECT_EQ(out.exit_code, 2);
  EXPECT_NE(out.output.find("expected a .json file name"), std::string::npos) << out.output;
  const std::string dir = test::TempDir();
  const test::ToolResult bad = test::RunTool(
      {"calibrate-jaw", "--data", dir + "/nowhere", "--template",
       test::SourceDir() + "/assets/head/default.template.json", "--landmarks",
       test::SourceDir() + "/tests/data/landmarks/ict_facekit.landmarks.json", "--out",
       dir + "/t.json"});
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_NE(bad.output.find("ict_skin_neutral.obj"), std::string::npos) << bad.output;
  EXPECT_NE(bad.output.find("cannot read the inputs"), std::string::npos) << bad.output;
  EXPECT_FALSE(std::ifstream(dir + "/t.json").good());
}

TEST(CalibrateJaw, NoRoundsWritesTheGivenJawBack) {
  const std::string shared = test::SharedDir();
  if (shared.empty() || !std::ifstream(shared + "/data/ict-facekit/arkit/jawOpen.obj"))
    GTEST_SKIP() << "../shared/data/ict-facekit is absent: the jaw calibration is not run";
  const std::string dir = test::TempDir();
  const std::string in = test::SourceDir() + "/assets/head/default.template.json";
  const test::ToolResult r = test::RunTool(
      {"calibrate-jaw", "--data", shared + "/data", "--template", in, "--landmarks",
       test::SourceDir() + "/tests/data/landmarks/ict_facekit.landmarks.json", "--rounds", "0",
       "--out", dir + "/t.json"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("flips 0"), std::string::npos) << r.output;
  MuscleTemplate a, b;
  Diagnostics diag;
  ASSERT_TRUE(LoadMuscleTemplate(in, &a, &diag)) << diag.Format();
  ASSERT_TRUE(LoadMuscleTemplate(dir + "/t.json", &b, &diag)) << diag.Format();
  ASSERT_TRUE(a.jaw && b.jaw);
  auto near = [](float x, float y) { return std::fabs(x - y) <= 1e-4f * std::fmax(1.f, std::fabs(x)); };
  EXPECT_TRUE(near(a.jaw->range_deg, b.jaw->range_deg)) << b.jaw->range_deg;
  EXPECT_TRUE(near(a.jaw->translation.y, b.jaw->translation.y)) << b.jaw->translation.y;
  EXPECT_TRUE(near(a.jaw->translation.z, b.jaw->translation.z)) << b.jaw->translation.z;
  EXPECT_TRUE(near(a.jaw->offset.y, b.jaw->offset.y));
  EXPECT_EQ(a.jaw->lip_blend_deg, b.jaw->lip_blend_deg);
  EXPECT_EQ(a.jaw->neck_deg[0], b.jaw->neck_deg[0]);
  EXPECT_EQ(a.jaw->back[1], b.jaw->back[1]);
  EXPECT_EQ(b.muscles.size(), a.muscles.size());
}

}  // namespace
}  // namespace mimetic

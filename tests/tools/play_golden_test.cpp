// tests/tools/play_golden_test.cpp: `mimetic play --write-golden` (tools/play_golden.cpp).
#include <gtest/gtest.h>

#include <filesystem>

#include "io/golden_file.h"
#include "test_support.h"

namespace mimetic {
namespace {

std::string GoldenDir() { return test::SourceDir() + "/tests/golden"; }
std::string HeadRig() { return test::SourceDir() + "/assets/head/sample_head.rig.json"; }

// The command writes what the comparison reads, atomically (no temporary file left).
TEST(Golden, WriteGoldenCommand) {
  const std::string dir = test::TempDir();
  const auto r = test::RunTool({"play", HeadRig(), GoldenDir() + "/brows.clip.json",
                                "--write-golden", dir, "--frames", "0.5,1"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  Golden g;
  Diagnostics diag;
  ASSERT_TRUE(LoadGolden(dir + "/brows.golden", &g, &diag)) << diag.Format();
  ASSERT_EQ(g.frames.size(), 2u);
  EXPECT_EQ(g.frames[0].time, 0.5f);
  EXPECT_EQ(g.frames[1].time, 1.0f);
  size_t files = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir)) ++files, (void)e;
  EXPECT_EQ(files, 1u);
  const auto bad = test::RunTool({"play", HeadRig(), GoldenDir() + "/brows.clip.json",
                                  "--write-golden", dir, "--frames", "0.5,x"});
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.output.find("\"x\" is not a time"), std::string::npos) << bad.output;
}

}  // namespace
}  // namespace mimetic

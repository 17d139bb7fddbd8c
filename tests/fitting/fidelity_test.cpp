// tests/fitting/fidelity_test.cpp: `mimetic fidelity` on one claimed and one unclaimed shape.
// The report's numbers are recomputed here from the posed mesh it wrote (CompareMeshes over
// the documented region), so the table says what the rig does. Skips without ../shared.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

#include "fitting/compare.h"
#include "io/mesh_io.h"
#include "test_support.h"

namespace mimetic {
namespace {

std::string Fixed(double v, int digits) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

TEST(FidelityTool, TheTableMatchesThePosedMeshItWrote) {
  const std::string shared = test::SharedDir();
  if (shared.empty() || !std::ifstream(shared + "/data/ict-facekit/arkit/mouthSmile_L.obj"))
    GTEST_SKIP() << "../shared/data/ict-facekit is absent: the fidelity report is not checked";
  const std::string dir = test::TempDir();
  const test::ToolResult t = test::RunTool(
      {"fidelity", "--data", shared + "/data", "--template",
       test::SourceDir() + "/assets/head/default.template.json", "--landmarks",
       test::SourceDir() + "/tests/data/landmarks/ict_facekit.landmarks.json", "--only",
       "mouthSmile_L,jawOpen", "--report", dir + "/fidelity.md", "--images", dir + "/images",
       "--meshes", dir + "/meshes", "--size", "64"});
  ASSERT_EQ(t.exit_code, 0) << t.output;
  MeshData neutral, target, posed;
  Diagnostics diag;
  ASSERT_TRUE(ImportMesh(shared + "/data/ict-facekit/ict_skin_neutral.obj", "", &neutral, &diag));
  ASSERT_TRUE(ImportMesh(shared + "/data/ict-facekit/arkit/mouthSmile_L.obj", "", &target, &diag));
  ASSERT_TRUE(ImportMesh(dir + "/meshes/mouthSmile_L.obj", "", &posed, &diag)) << diag.Format();
  // The region: vertices the real shape moves more than 2% of its largest motion.
  double largest = 0;
  for (size_t v = 0; v < target.vertex_count(); ++v)
    largest = std::max(largest, double(Length(target.positions[v] - neutral.positions[v])));
  CompareOptions o;
  o.neutral = &neutral;
  o.region.kind = CompareRegion::Kind::kMoved;
  o.region.threshold = float(0.02 * largest);
  CompareResult r;
  ASSERT_TRUE(CompareMeshes(posed, target, o, &r, &diag)) << diag.Format();
  EXPECT_LT(r.ratio, 1.0);  // a smile solved with the smile muscles beats doing nothing
  EXPECT_GT(r.direction_cosine, 0.3);
  std::ifstream in(dir + "/fidelity.md");
  const std::string md((std::istreambuf_iterator<char>(in)), {});
  const std::string row = "| mouthSmile_L | ";
  const size_t at = md.find(row);
  ASSERT_NE(at, std::string::npos) << md;
  const std::string line = md.substr(at, md.find('\n', at) - at);
  EXPECT_NE(line.find(" | " + Fixed(r.ratio, 3) + " | "), std::string::npos) << line << " vs " << r.ratio;
  EXPECT_NE(line.find(" | " + Fixed(r.direction_cosine, 2) + " | "), std::string::npos)
      << line << " vs " << r.direction_cosine;
  EXPECT_NE(line.find(" | " + Fixed(r.magnitude_ratio, 2) + " | "), std::string::npos)
      << line << " vs " << r.magnitude_ratio;
  EXPECT_NE(md.find("| jawOpen | the jaw, not a muscle"), std::string::npos) << md;
  EXPECT_TRUE(std::ifstream(dir + "/images/mouthSmile_L.png").good());
  // Bad usage: an unknown shape names the known ones.
  const test::ToolResult bad = test::RunTool({"fidelity", "--only", "smile"});
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.output.find("unknown shape 'smile'; known: browRaise (AU1+2)"), std::string::npos)
      << bad.output;
}

}  // namespace
}  // namespace mimetic

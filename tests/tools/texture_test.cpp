// tests/tools/texture_test.cpp: `mimetic texture` on the bundled rig (its default fields from
// the template, docs/model.md §20-23): 16-bit maps, the same bytes for a seed with one or two
// threads, the merge as the minimum, bad input, and the sample head's default fields under
// the frontalis (the forehead compressed across field 1: its amplitude rises).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "core/file_util.h"
#include "io/image.h"
#include "io/rig_loader.h"
#include "rig/runtime/evaluate_job.h"
#include "test_support.h"

namespace mimetic {
namespace {

std::string HeadRig() { return test::SourceDir() + "/assets/head/sample_head.rig.json"; }

std::string Bytes(const std::string& path) {
  std::string s;
  Diagnostics d;
  EXPECT_TRUE(ReadFile(path, &s, &d, size_t(64) << 20)) << d.Format();
  return s;
}

const char* const kFiles[] = {"fine_height_1.png", "fine_height_2.png", "fine_height.png",
                              "fine_normal.png"};

TEST(Texture, SameSeedSameBytesWithOneOrTwoThreadsAndSixteenBitMaps) {
  const std::string dir = test::TempDir();
  const std::string a = dir + "/a", b = dir + "/b", c = dir + "/c";
  auto run = [&](const std::string& out, const char* seed, const char* threads) {
    return test::RunTool({"texture", HeadRig(), "--size", "256", "--out", out, "--seed", seed,
                          "--threads", threads, "--quiet"});
  };
  test::ToolResult r = run(a, "3", "1");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(r.output.empty()) << "--quiet prints nothing: " << r.output;
  ASSERT_EQ(run(b, "3", "2").exit_code, 0);
  ASSERT_EQ(run(c, "4", "1").exit_code, 0);
  for (const char* f : kFiles) {
    EXPECT_EQ(Bytes(a + "/" + f), Bytes(b + "/" + f)) << f;
    if (std::string(f) != "fine_normal.png") {
      EXPECT_NE(Bytes(a + "/" + f), Bytes(c + "/" + f)) << f;
    }
  }
  // 16-bit grey: the PNG header says bit depth 16, colour type 0 (IHDR at byte 16: width,
  // height, depth, colour type).
  const std::string h1 = Bytes(a + "/fine_height_1.png");
  ASSERT_GT(h1.size(), 26u);
  EXPECT_EQ(uint8_t(h1[24]), 16);
  EXPECT_EQ(uint8_t(h1[25]), 0);
  Gray16Image m1, m2, merged;
  Diagnostics d;
  ASSERT_TRUE(LoadGray16Png(a + "/fine_height_1.png", "h1", "height map", &m1, &d)) << d.Format();
  ASSERT_TRUE(LoadGray16Png(a + "/fine_height_2.png", "h2", "height map", &m2, &d));
  ASSERT_TRUE(LoadGray16Png(a + "/fine_height.png", "h", "height map", &merged, &d));
  ASSERT_EQ(m1.width, 256);
  ASSERT_EQ(m1.pixels.size(), 256u * 256u);
  size_t furrowed = 0, not_8bit = 0;
  for (size_t i = 0; i < m1.pixels.size(); ++i) {
    // k_noise is 0 in the bundled rig: the merge is exactly the minimum (003 step 8).
    ASSERT_EQ(merged.pixels[i], std::min(m1.pixels[i], m2.pixels[i])) << i;
    furrowed += m1.pixels[i] < 65535;
    not_8bit += m1.pixels[i] % 257 != 0;
  }
  EXPECT_GT(furrowed, 1000u) << "field 1 carves furrows";
  EXPECT_GT(not_8bit, 100u) << "the grey levels use more than 8 bits";
}

TEST(Texture, BadInputIsNamedAndNothingCrashes) {
  const std::string dir = test::TempDir();
  test::ToolResult r = test::RunTool({"texture", HeadRig(), "--size", "0", "--out", dir});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("--size 0: expected a whole number of pixels in [16, 8192]"), std::string::npos) << r.output;
  r = test::RunTool({"texture", HeadRig(), "--size", "100000", "--out", dir});
  EXPECT_EQ(r.exit_code, 2);
  r = test::RunTool({"texture", HeadRig(), "--size", "64"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("missing --out DIR"), std::string::npos) << r.output;
  r = test::RunTool({"texture", HeadRig(), "--size", "64", "--out", dir, "--threads", "3"});
  EXPECT_EQ(r.exit_code, 2);
  // An output folder that cannot be made.
  r = test::RunTool({"texture", HeadRig(), "--size", "64", "--out", "/proc/no/such/dir"});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("--out /proc/no/such/dir: cannot create the folder"), std::string::npos) << r.output;
  // A rig without fine_scale.
  r = test::RunTool({"texture", test::SourceDir() + "/assets/surface/surface.rig.json", "--size",
                     "64", "--out", dir});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("fine_scale: the rig has no fine_scale block"), std::string::npos) << r.output;
  // A compiled rig keeps no fields.
  r = test::RunTool({"texture", dir + "/x.mrig", "--size", "64", "--out", dir});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find("a compiled rig keeps no direction fields"), std::string::npos) << r.output;
}

TEST(Texture, TheFrontalisCompressesTheForeheadAcrossFieldOne) {
  LoadedRig loaded;
  Diagnostics diag;
  ASSERT_TRUE(LoadRig(HeadRig(), &loaded, &diag)) << diag.Format();
  const Rig& rig = loaded.rig;
  ASSERT_FALSE(rig.fine_scale().empty());
  ASSERT_TRUE(loaded.spec.fine_scale.has_value());
  // Field 1's forehead vector is its first (the template's order): horizontal furrows.
  const uint32_t forehead = loaded.spec.fine_scale->fields[0].anchors[0].vertex;
  std::vector<float> act(rig.muscle_count(), 0.f);
  int frontalis = 0;
  for (uint32_t m = 0; m < rig.muscle_count(); ++m)
    if (rig.muscle_names()[m].rfind("frontalis", 0) == 0) act[m] = 1.f, ++frontalis;
  ASSERT_GT(frontalis, 0);
  auto amplitudes = [&](span<const float> a, std::vector<float>* out) {
    EvaluateContext ctx(rig);
    std::vector<float> pos(3 * rig.vertex_count());
    out->assign(2 * rig.vertex_count(), 0.f);
    EvaluateJob job;
    job.rig = &rig;
    job.context = &ctx;
    job.activations = a;
    job.out_positions = pos;
    job.out_fine_amplitudes = *out;
    return job.Run();
  };
  std::vector<float> rest, raised;
  const std::vector<float> zero(rig.muscle_count(), 0.f);
  ASSERT_TRUE(amplitudes(zero, &rest));
  ASSERT_TRUE(amplitudes(act, &raised));
  const float r = loaded.spec.fine_scale->rest_amplitude;
  EXPECT_FLOAT_EQ(rest[2 * forehead], r);
  EXPECT_FLOAT_EQ(rest[2 * forehead + 1], r);
  // The brows go up, the forehead skin shortens vertically: across the horizontal furrows.
  EXPECT_GT(raised[2 * forehead], r + 0.02f) << "amplitude 1 at the forehead vector";
  // Mean over the forehead band around it (vertices within 15 mm).
  const std::vector<float3>& pts = rig.rest_points();
  const float3 c = pts[rig.vertex_points()[forehead]];
  double s1 = 0, s2 = 0;
  int n = 0;
  for (uint32_t v = 0; v < rig.vertex_count(); ++v)
    if (Length(pts[rig.vertex_points()[v]] - c) < 15.f) s1 += raised[2 * v], s2 += raised[2 * v + 1], ++n;
  ASSERT_GT(n, 10);
  EXPECT_GT(s1 / n, r);
  EXPECT_GT(s1 / n, s2 / n) << "the horizontal furrows deepen more than the vertical ones";
}

}  // namespace
}  // namespace mimetic

// tests/tools/import_arkit_test.cpp: `mimetic import-arkit` (tools/cmd_import_arkit.cpp): a
// small Live Link Face CSV (tests/data/arkit/take.csv, 30 fps) through the test map
// (tests/data/arkit/test.arkit.json) on the sample head; `mimetic play --time` of the clip it
// writes equals `mimetic eval` with the activations worked out by hand below.
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <sstream>

#include "geometry/mesh.h"
#include "io/clip_file.h"
#include "io/mesh_io.h"
#include "sample_rig.h"
#include "test_support.h"
#include "tools/mesh_expect.h"

namespace mimetic {
namespace {

using test::ExpectSameMesh;
using test::RunTool;

std::string Data(const std::string& f) { return test::SourceDir() + "/tests/data/arkit/" + f; }
std::string HeadRig() { return test::SourceDir() + "/assets/head/sample_head.rig.json"; }

size_t Count(const std::string& s, const std::string& part) {
  size_t n = 0;
  for (size_t at = s.find(part); at != std::string::npos; at = s.find(part, at + 1)) ++n;
  return n;
}

// The take (times 0, 0.5, 1 s at 30 fps) and the test map:
//   jawOpen         -> depressor_labii_inferioris_L 0.6, platysma_L 0.5
//   mouthSmileLeft  -> zygomaticus_major_L 0.8, risorius_L 0.5
//   mouthDimpleLeft -> zygomaticus_major_L 0.6
// At 0.5 s (JawOpen 0.5, MouthSmileLeft 0.5, MouthDimpleLeft 0.25):
//   zygomaticus_major_L = 0.5 * 0.8 + 0.25 * 0.6 = 0.55, risorius_L = 0.25,
//   depressor_labii_inferioris_L = 0.3, platysma_L = 0.25.
// At 1 s (0.25, 1, 1): zygomaticus_major_L = 0.8 + 0.6 -> 1 (clamped), risorius_L = 0.5,
//   depressor_labii_inferioris_L = 0.15, platysma_L = 0.125.
TEST(ImportArkit, CsvToClipPlaysAsTheHandComputedActivations) {
  const std::string dir = test::TempDir();
  const std::string clip = dir + "/take.clip.json";
  const auto r = RunTool({"import-arkit", Data("take.csv"), "--rig", HeadRig(), "--map",
                          Data("test.arkit.json"), "--fps", "30", "--out", clip});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // One warning lists both unused channels, each with its count of non-zero frames.
  EXPECT_EQ(Count(r.output, "not used"), 1u) << r.output;
  EXPECT_NE(r.output.find("HeadYaw (3 non-zero frames) (not ARKit blendshape names)"),
            std::string::npos) << r.output;
  EXPECT_NE(r.output.find("EyeBlinkLeft (2 non-zero frames) (the map marks them \"none\""),
            std::string::npos) << r.output;

  ClipSpec spec;
  Diagnostics diag;
  ASSERT_TRUE(LoadClip(clip, &spec, &diag)) << diag.Format();
  EXPECT_EQ(spec.duration, 1.f);
  ASSERT_EQ(spec.channels.size(), 4u);
  for (const auto& c : spec.channels)
    if (c.target == "risorius_L") {
      EXPECT_EQ(c.keys.size(), 2u);  // 0, 0.25, 0.5: on a line
    }

  struct At {
    const char* time;
    std::vector<std::string> set;
  } checks[] = {
      {"0.5", {"zygomaticus_major_L=0.55", "risorius_L=0.25",
               "depressor_labii_inferioris_L=0.3", "platysma_L=0.25"}},
      {"1", {"zygomaticus_major_L=1", "risorius_L=0.5", "depressor_labii_inferioris_L=0.15",
             "platysma_L=0.125"}},
  };
  for (const At& at : checks) {
    SCOPED_TRACE(at.time);
    const std::string played = dir + "/played_" + at.time + ".obj";
    const std::string evald = dir + "/eval_" + at.time + ".obj";
    const auto p = RunTool({"play", HeadRig(), clip, "--time", at.time, "--out", played});
    ASSERT_EQ(p.exit_code, 0) << p.output;
    std::vector<std::string> args = {"eval", HeadRig()};
    for (const std::string& s : at.set) args.insert(args.end(), {"--set", s});
    args.insert(args.end(), {"--out", evald});
    const auto e = RunTool(args);
    ASSERT_EQ(e.exit_code, 0) << e.output;
    ExpectSameMesh(played, evald);
  }
}

// The default map sends jawOpen to the jaw: on a rig with a jaw (the sample head fitted with
// the default template) the clip gets a "jaw" channel whose keys are the take's JawOpen
// weights (jaw 1.0 per unit weight); on the committed sample head rig (no jaw) JawOpen is
// listed as unused, with the reason.
TEST(ImportArkit, JawOpenDrivesTheJaw) {
  const std::string dir = test::TempDir();
  const std::string src = test::SourceDir();
  const std::string map = src + "/assets/arkit/default.arkit.json";
  const auto fit = RunTool({"fit", src + "/assets/head/default.template.json", "--mesh",
                            src + "/assets/head/sample_head.glb", "--landmarks",
                            src + "/assets/head/sample_head.landmarks.json", "--out",
                            dir + "/jaw.rig.json"});
  ASSERT_EQ(fit.exit_code, 0) << fit.output;
  const auto r = RunTool({"import-arkit", Data("take.csv"), "--rig", dir + "/jaw.rig.json",
                          "--map", map, "--fps", "30", "--out", dir + "/jaw.clip.json"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.output.find("JawOpen ("), std::string::npos) << r.output;
  ClipSpec spec;
  Diagnostics diag;
  ASSERT_TRUE(LoadClip(dir + "/jaw.clip.json", &spec, &diag)) << diag.Format();
  const auto jaw = std::find_if(spec.channels.begin(), spec.channels.end(),
                                [](const ClipChannelSpec& c) { return c.target == "jaw"; });
  ASSERT_NE(jaw, spec.channels.end());
  // take.csv's JawOpen: 0, 0.5, 0.25 at 0, 0.5, 1 s (jaw = 1.0 x the weight).
  ASSERT_EQ(jaw->keys.size(), 3u);
  const float t[3] = {0.f, 0.5f, 1.f}, v[3] = {0.f, 0.5f, 0.25f};
  for (int k = 0; k < 3; ++k) {
    EXPECT_EQ(jaw->keys[size_t(k)].t, t[k]) << k;
    EXPECT_EQ(jaw->keys[size_t(k)].v, v[k]) << k;
  }

  const auto n = RunTool({"import-arkit", Data("take.csv"), "--rig", test::SampleRigWithoutJaw(), "--map", map,
                          "--fps", "30", "--out", dir + "/nojaw.clip.json"});
  ASSERT_EQ(n.exit_code, 0) << n.output;
  EXPECT_NE(n.output.find("JawOpen (2 non-zero frames) (the map drives the jaw with them, and "
                          "the rig has no jaw)"),
            std::string::npos) << n.output;
}

TEST(ImportArkit, JsonTake) {
  const std::string dir = test::TempDir();
  const auto r = RunTool({"import-arkit", Data("take.json"), "--rig", HeadRig(), "--map",
                          Data("test.arkit.json"), "--out", dir + "/j.clip.json"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.output.find("not used"), std::string::npos) << r.output;
  ClipSpec spec;
  Diagnostics diag;
  ASSERT_TRUE(LoadClip(dir + "/j.clip.json", &spec, &diag)) << diag.Format();
  EXPECT_EQ(spec.name, "take");
  EXPECT_EQ(spec.channels.size(), 4u);
}

TEST(ImportArkit, HelpUsageAndInputErrors) {
  const auto help = RunTool({"import-arkit", "--help"});
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_NE(help.output.find("usage: mimetic import-arkit"), std::string::npos);
  const std::string dir = test::TempDir();
  EXPECT_EQ(RunTool({"import-arkit", Data("take.csv"), "--out", dir + "/x.json"}).exit_code, 2);
  EXPECT_EQ(RunTool({"import-arkit", Data("take.csv"), "--rig", HeadRig()}).exit_code, 2);
  EXPECT_EQ(RunTool({"import-arkit", Data("take.csv"), "--rig", HeadRig(), "--fps", "0",
                     "--out", dir + "/x.json"}).exit_code, 2);
  const std::string bad = dir + "/bad.csv";
  std::ofstream(bad) << "Timecode,JawOpen\n00:00:00:00,0.5\n00:00:00:01,2\n";
  const auto r = RunTool({"import-arkit", bad, "--rig", HeadRig(), "--out", dir + "/x.json"});
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.output.find(bad + ":3:2 (JawOpen): 2 is outside [0, 1]"), std::string::npos)
      << r.output;
  EXPECT_NE(r.output.find("nothing was written"), std::string::npos) << r.output;
  // The default map (assets/arkit/default.arkit.json) is found from the rig.
  const auto d = RunTool({"import-arkit", Data("take.csv"), "--rig", HeadRig(), "--fps", "30",
                          "--out", dir + "/d.clip.json"});
  EXPECT_EQ(d.exit_code, 0) << d.output;
}

}  // namespace
}  // namespace mimetic

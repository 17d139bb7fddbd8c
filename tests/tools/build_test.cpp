// tests/tools/build_test.cpp: `mimetic build RIG --out FILE.mrig` (tools/cmd_build.cpp) and the
// commands that accept its output: the sample head's .mrig evaluates bit-identically to the
// JSON-built rig, the bytes are the same on every build, `eval` / `play` / `info` read it, and a
// broken .mrig is exit 1 with a message naming the file and the section.
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "io/rig_loader.h"
#include "rig/runtime/evaluate_job.h"
#include "test_support.h"
#include "tools/mesh_expect.h"

namespace mimetic {
namespace {

using test::ExpectSameMesh;
using test::ReadText;
using test::RunTool;

bool Contains(const std::string& haystack, const std::string& needle) {
  return haystack.find(needle) != std::string::npos;
}

std::string SurfaceRig() { return test::SourceDir() + "/assets/surface/surface.rig.json"; }
std::string HeadRig() { return test::SourceDir() + "/assets/head/sample_head.rig.json"; }

std::vector<float> Evaluate(const Rig& rig, span<const float> act) {
  EvaluateContext ctx(rig);
  std::vector<float> pos(3 * rig.vertex_count()), nrm(3 * rig.vertex_count());
  EvaluateJob job;
  job.rig = &rig;
  job.context = &ctx;
  job.activations = act;
  job.out_positions = pos;
  job.out_normals = nrm;
  job.layers = {true, true, true};
  EXPECT_TRUE(job.Run());
  pos.insert(pos.end(), nrm.begin(), nrm.end());
  return pos;
}

TEST(Build, HelpAndUsageErrors) {
  const auto help = RunTool({"build", "--help"});
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_TRUE(Contains(help.output, "usage: mimetic build RIG --out FILE.mrig")) << help.output;
  EXPECT_TRUE(Contains(RunTool({"--help"}).output, "build"));
  const std::string dir = test::TempDir();
  EXPECT_EQ(RunTool({"build", SurfaceRig()}).exit_code, 2);
  EXPECT_EQ(RunTool({"build", "--out", dir + "/a.mrig"}).exit_code, 2);
  const auto ext = RunTool({"build", SurfaceRig(), "--out", dir + "/a.glb"});
  EXPECT_EQ(ext.exit_code, 2);
  EXPECT_TRUE(Contains(ext.output, "expected a .mrig or .mclip file name")) << ext.output;
  EXPECT_EQ(RunTool({"build", SurfaceRig(), "--out", dir + "/a.mrig", "--bogus"}).exit_code, 2);
  const auto missing = RunTool({"build", dir + "/none.rig.json", "--out", dir + "/a.mrig"});
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_TRUE(Contains(missing.output, dir + "/none.rig.json")) << missing.output;
}

TEST(Build, SampleHeadLoadsBitIdenticallyAndDeterministically) {
  const std::string dir = test::TempDir();
  const auto r = RunTool({"build", HeadRig(), "--out", dir + "/head.mrig"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(Contains(r.output, "wrote " + dir + "/head.mrig")) << r.output;
  ASSERT_EQ(RunTool({"build", HeadRig(), "--out", dir + "/again.mrig"}).exit_code, 0);
  const std::string bytes = ReadText(dir + "/head.mrig");
  EXPECT_EQ(bytes.substr(0, 4), "MRIG");
  EXPECT_EQ(bytes, ReadText(dir + "/again.mrig"));
  // Building from the .mrig itself gives the same bytes again.
  ASSERT_EQ(RunTool({"build", dir + "/head.mrig", "--out", dir + "/third.mrig"}).exit_code, 0);
  EXPECT_EQ(bytes, ReadText(dir + "/third.mrig"));

  LoadedRig json, binary;
  Diagnostics diag;
  ASSERT_TRUE(LoadRig(HeadRig(), &json, &diag)) << diag.Format();
  ASSERT_TRUE(LoadRig(dir + "/head.mrig", &binary, &diag)) << diag.Format();
  EXPECT_TRUE(binary.compiled);
  EXPECT_EQ(binary.spec.units, json.spec.units);
  EXPECT_EQ(binary.source_vertex_count, json.mesh.vertex_count());
  const Rig& a = json.rig;
  const Rig& b = binary.rig;
  ASSERT_TRUE(a.layers().thickness && a.layers().muscle_wrinkles && a.layers().curve_wrinkles);
  ASSERT_EQ(a.vertex_count(), b.vertex_count());
  ASSERT_EQ(a.muscle_names(), b.muscle_names());
  EXPECT_EQ(a.vertex_indices(), b.vertex_indices());
  for (int set = 0; set < 4; ++set) {
    std::vector<float> act(a.muscle_count(), 0.f);
    for (size_t m = 0; m < act.size(); ++m)
      act[m] = set == 0 ? 0.f : set == 3 ? 1.f : float((m * 7 + set * 3) % 10) / 10.f;
    const std::vector<float> want = Evaluate(a, act), got = Evaluate(b, act);
    ASSERT_EQ(want.size(), got.size());
    EXPECT_EQ(std::memcmp(want.data(), got.data(), want.size() * sizeof(float)), 0)
        << "activation set " << set;
  }
}

TEST(Build, EvalPlayAndInfoAcceptTheMrig) {
  const std::string dir = test::TempDir();
  const std::string mrig = dir + "/surface.mrig";
  ASSERT_EQ(RunTool({"build", SurfaceRig(), "--out", mrig}).exit_code, 0);
  for (const std::string& rig : {SurfaceRig(), mrig}) {
    const std::string tag = rig == mrig ? "b" : "a";
    const auto e = RunTool({"eval", rig, "--set", "zygomatic=0.7", "--set", "frontalis=0.4",
                            "--out", dir + "/eval_" + tag + ".obj"});
    ASSERT_EQ(e.exit_code, 0) << e.output;
  }
  ExpectSameMesh(dir + "/eval_a.obj", dir + "/eval_b.obj");
  std::ofstream(dir + "/c.clip.json") << R"({"format": "mimetic-clip", "version": 1,
    "name": "c", "channels": [{"muscle": "zygomatic", "keys": [{"t": 0, "v": 0}, {"t": 2, "v": 1}]}]})";
  for (const std::string& rig : {SurfaceRig(), mrig}) {
    const std::string tag = rig == mrig ? "b" : "a";
    const auto p = RunTool({"play", rig, dir + "/c.clip.json", "--time", "1.5", "--out",
                            dir + "/play_" + tag + ".obj"});
    ASSERT_EQ(p.exit_code, 0) << p.output;
  }
  ExpectSameMesh(dir + "/play_a.obj", dir + "/play_b.obj");
  const auto info = RunTool({"info", mrig});
  ASSERT_EQ(info.exit_code, 0) << info.output;
  EXPECT_TRUE(Contains(info.output, "(compiled")) << info.output;
  EXPECT_TRUE(Contains(info.output, "zygomatic")) << info.output;
  EXPECT_TRUE(Contains(info.output, "units:      mm")) << info.output;
  EXPECT_EQ(RunTool({"validate", mrig}).exit_code, 0);
}

TEST(Build, BrokenMrigIsAnInputError) {
  const std::string dir = test::TempDir();
  const std::string mrig = dir + "/surface.mrig";
  ASSERT_EQ(RunTool({"build", SurfaceRig(), "--out", mrig}).exit_code, 0);
  const std::string bytes = ReadText(mrig);
  std::ofstream(dir + "/cut.mrig", std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  const auto cut = RunTool({"info", dir + "/cut.mrig"});
  EXPECT_EQ(cut.exit_code, 1);
  EXPECT_TRUE(Contains(cut.output, dir + "/cut.mrig")) << cut.output;
  EXPECT_TRUE(Contains(cut.output, "section '")) << cut.output;
  std::string flipped = bytes;
  flipped[bytes.size() - 3] = char(flipped[bytes.size() - 3] ^ 0x40);
  std::ofstream(dir + "/flip.mrig", std::ios::binary) << flipped;
  const auto flip = RunTool({"eval", dir + "/flip.mrig", "--out", dir + "/x.obj"});
  EXPECT_EQ(flip.exit_code, 1);
  EXPECT_TRUE(Contains(flip.output, "checksum mismatch")) << flip.output;
  const auto play = RunTool({"play", dir + "/flip.mrig", dir + "/none.clip.json", "--time", "0",
                             "--out", dir + "/y.obj"});
  EXPECT_EQ(play.exit_code, 1);
  EXPECT_TRUE(Contains(play.output, "checksum mismatch")) << play.output;
}

}  // namespace
}  // namespace mimetic

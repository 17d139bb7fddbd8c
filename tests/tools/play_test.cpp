// tests/tools/play_test.cpp: `mimetic play` (tools/cmd_play.cpp) on the surface rig: one pose
// and an OBJ sequence equal `mimetic eval` with the activations the clip gives at those times
// (worked out here by hand), and its usage and input errors.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "geometry/mesh.h"
#include "io/mesh_io.h"
#include "sample_rig.h"
#include "test_support.h"
#include "tools/mesh_expect.h"

namespace mimetic {
namespace {

using test::ExpectSameMesh;
using test::ReadText;
using test::RunTool;

std::string SurfaceRig() { return test::SourceDir() + "/assets/surface/surface.rig.json"; }

bool Contains(const std::string& haystack, const std::string& needle) {
  return haystack.find(needle) != std::string::npos;
}

std::string Write(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

// zygomatic: linear 0 -> 1 over 2 s; the expression "Raise" (frontalis 0.5, zygomatic 0.25)
// added with a weight going linearly 0 -> 0.5 over 2 s. At t: zygomatic = t / 2 + 0.25 * t / 4,
// frontalis = 0.5 * t / 4. At t = 1: zygomatic 0.5 + 0.0625 = 0.5625, frontalis 0.125.
struct Files {
  std::string dir, clip, expression;
};

Files MakeFiles(const std::string& end = "clamp") {
  Files f;
  f.dir = test::TempDir();
  f.clip = Write(f.dir + "/c.clip.json", R"({"format": "mimetic-clip", "version": 1, "name": "c",
    "end": ")" + end + R"(", "channels": [
      {"muscle": "zygomatic", "keys": [{"t": 0, "v": 0}, {"t": 2, "v": 1}]},
      {"expression": "Raise", "layer": "add", "keys": [{"t": 0, "v": 0}, {"t": 2, "v": 0.5}]}]})");
  f.expression = Write(f.dir + "/raise.expression.json",
                       R"({"format": "mimetic-expression", "version": 1, "name": "Raise",
                           "activations": {"frontalis": 0.5, "zygomatic": 0.25}})");
  return f;
}

TEST(Play, HelpAndUsageErrors) {
  const auto help = RunTool({"play", "--help"});
  EXPECT_EQ(help.exit_code, 0);
  EXPECT_TRUE(Contains(help.output, "usage: mimetic play")) << help.output;
  EXPECT_TRUE(Contains(RunTool({"--help"}).output, "play"));
  const Files f = MakeFiles();
  struct Case {
    std::vector<std::string> args;
    const char* message;
  } cases[] = {
      {{"play", SurfaceRig()}, "missing CLIP"},
      {{"play", SurfaceRig(), f.clip, "--out", f.dir + "/x.obj"}, "missing --time T or --fps F"},
      {{"play", SurfaceRig(), f.clip, "--time", "1", "--fps", "30", "--out", f.dir + "/x.obj"},
       "--time and --fps together"},
      {{"play", SurfaceRig(), f.clip, "--time", "1"}, "missing --out"},
      {{"play", SurfaceRig(), f.clip, "--time", "soon", "--out", f.dir + "/x.obj"},
       "--time soon: expected a number of seconds"},
      {{"play", SurfaceRig(), f.clip, "--time", "1", "--out", f.dir + "/x.stl"},
       "expected a .obj or .glb file name"},
      {{"play", SurfaceRig(), f.clip, "--fps", "0", "--out", f.dir + "/f_%d.obj"},
       "--fps 0: expected a number of frames per second in (0, 1000]"},
      {{"play", SurfaceRig(), f.clip, "--fps", "30", "--out", f.dir + "/frame.obj"},
       "no frame number"},
      {{"play", SurfaceRig(), f.clip, "--fps", "30", "--out", f.dir + "/f_%d_%d.obj"},
       "more than one frame number"},
      {{"play", SurfaceRig(), f.clip, "--fps", "30", "--out", f.dir + "/f_%s.obj"},
       "is not %d, %0Nd (N at most 9) or %%"},
      {{"play", SurfaceRig(), f.clip, "--fps", "30", "--out", f.dir + "/f_%04d.glb"},
       "a .glb bake is one file, not a frame pattern"},
      {{"play", SurfaceRig(), f.clip, "--time", "1", "--out", f.clip}, "expected a .obj or .glb"},
      {{"play", SurfaceRig(), f.clip, "--bogus"}, "unknown option '--bogus'"},
  };
  for (const Case& c : cases) {
    const auto r = RunTool(c.args);
    EXPECT_EQ(r.exit_code, 2) << c.message << "\n" << r.output;
    EXPECT_TRUE(Contains(r.output, c.message)) << c.message << "\n" << r.output;
  }
}

TEST(Play, OnePoseEqualsEvalWithTheClipsActivations) {
  const Files f = MakeFiles();
  const auto r = RunTool({"play", SurfaceRig(), f.clip, "--expression", f.expression, "--time", "1",
                          "--out", f.dir + "/play.obj"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(Contains(r.output, "wrote " + f.dir + "/play.obj")) << r.output;
  const auto e = RunTool({"eval", SurfaceRig(), "--set", "zygomatic=0.5625", "--set",
                          "frontalis=0.125", "--out", f.dir + "/eval.obj"});
  ASSERT_EQ(e.exit_code, 0) << e.output;
  ExpectSameMesh(f.dir + "/play.obj", f.dir + "/eval.obj");
  // Past the end, clamp holds the last pose: zygomatic 1 + 0.25 * 0.5 -> 1 (add clamps),
  // frontalis 0.25.
  ASSERT_EQ(RunTool({"play", SurfaceRig(), f.clip, "--expression", f.expression, "--time", "7",
                     "--out", f.dir + "/late.obj"}).exit_code, 0);
  ASSERT_EQ(RunTool({"eval", SurfaceRig(), "--set", "zygomatic=1", "--set", "frontalis=0.25",
                     "--out", f.dir + "/late_eval.obj"}).exit_code, 0);
  ExpectSameMesh(f.dir + "/late.obj", f.dir + "/late_eval.obj");
}

// The jaw in a clip: the sample head fitted with the default template (which has a jaw) plays
// a "jaw" channel and an expression naming the jaw as `mimetic eval --set jaw=...` poses them;
// on the committed sample head rig (no jaw) the clip plays with a warning.
TEST(Play, JawChannelsAndExpressionsPoseTheJaw) {
  const std::string dir = test::TempDir();
  const std::string src = test::SourceDir();
  const auto fit = RunTool({"fit", src + "/assets/head/default.template.json", "--mesh",
                            src + "/assets/head/sample_head.glb", "--landmarks",
                            src + "/assets/head/sample_head.landmarks.json", "--out",
                            dir + "/jaw.rig.json"});
  ASSERT_EQ(fit.exit_code, 0) << fit.output;
  // jaw: linear 0 -> 0.8 over 2 s; the expression Open {jaw 0.5, frontalis_major_L 0.4} added
  // at weight 0.5: at t = 1, jaw = 0.4 + 0.25 = 0.65, frontalis_major_L = 0.2.
  const std::string clip = Write(dir + "/jaw.clip.json", R"({"format": "mimetic-clip",
    "version": 1, "name": "jaw", "channels": [
      {"muscle": "jaw", "keys": [{"t": 0, "v": 0}, {"t": 2, "v": 0.8}]},
      {"expression": "Open", "keys": [{"t": 0, "v": 0.5}]}]})");
  const std::string open = Write(dir + "/open.expression.json",
                                 R"({"format": "mimetic-expression", "version": 1, "name": "Open",
                                     "activations": {"jaw": 0.5, "frontalis_major_L": 0.4}})");
  const auto r = RunTool({"play", dir + "/jaw.rig.json", clip, "--expression", open, "--time", "1",
                          "--out", dir + "/play.obj"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto e = RunTool({"eval", dir + "/jaw.rig.json", "--set", "jaw=0.65", "--set",
                          "frontalis_major_L=0.2", "--out", dir + "/eval.obj"});
  ASSERT_EQ(e.exit_code, 0) << e.output;
  ExpectSameMesh(dir + "/play.obj", dir + "/eval.obj");
  // The jaw moved the chin: the pose differs from the same activations without it.
  ASSERT_EQ(RunTool({"eval", dir + "/jaw.rig.json", "--set", "frontalis_major_L=0.2", "--out",
                     dir + "/closed.obj"}).exit_code, 0);
  EXPECT_NE(ReadText(dir + "/play.obj"), ReadText(dir + "/closed.obj"));
  // No jaw in the rig: a warning, and the jaw values do nothing.
  const auto w = RunTool({"play", test::SampleRigWithoutJaw(), clip, "--expression",
                          open, "--time", "1", "--out", dir + "/nojaw.obj"});
  ASSERT_EQ(w.exit_code, 0) << w.output;
  EXPECT_TRUE(Contains(w.output, "animates the jaw, but")) << w.output;
  EXPECT_TRUE(Contains(w.output, "has none")) << w.output;
}

TEST(Play, SequenceWritesEveryFrame) {
  const Files f = MakeFiles();
  // Clamp, 2 s at 2 fps: frames at 0, 0.5, 1, 1.5, 2 s.
  auto r = RunTool({"play", SurfaceRig(), f.clip, "--expression", f.expression, "--fps", "2",
                    "--out", f.dir + "/seq/frame_%04d.obj"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(Contains(r.output, "wrote 5 frames")) << r.output;
  for (int i = 0; i < 5; ++i) {
    char name[64];
    std::snprintf(name, sizeof name, "/seq/frame_%04d.obj", i);
    EXPECT_FALSE(ReadText(f.dir + name).empty()) << name;
  }
  EXPECT_TRUE(ReadText(f.dir + "/seq/frame_0005.obj").empty());
  // Frame 2 is t = 1 s: the pose of the test above.
  ASSERT_EQ(RunTool({"eval", SurfaceRig(), "--set", "zygomatic=0.5625", "--set",
                     "frontalis=0.125", "--out", f.dir + "/eval.obj"}).exit_code, 0);
  ExpectSameMesh(f.dir + "/seq/frame_0002.obj", f.dir + "/eval.obj");
  // Frame 1 is t = 0.5 s: zygomatic 0.25 + 0.25 * 0.125 = 0.28125, frontalis 0.0625.
  ASSERT_EQ(RunTool({"eval", SurfaceRig(), "--set", "zygomatic=0.28125", "--set",
                     "frontalis=0.0625", "--out", f.dir + "/eval1.obj"}).exit_code, 0);
  ExpectSameMesh(f.dir + "/seq/frame_0001.obj", f.dir + "/eval1.obj");
  // Not a terminal: no progress bar.
  EXPECT_FALSE(Contains(r.output, "[#")) << r.output;

  // A loop stops before the duration (its last frame would be frame 0 again): 4 frames.
  const Files g = MakeFiles("loop");
  r = RunTool({"play", SurfaceRig(), g.clip, "--expression", g.expression, "--fps", "2",
               "--out", g.dir + "/f%d.obj"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(Contains(r.output, "wrote 4 frames")) << r.output;
  EXPECT_FALSE(ReadText(g.dir + "/f3.obj").empty());
  EXPECT_TRUE(ReadText(g.dir + "/f4.obj").empty());
}

TEST(Play, InputErrorsNameTheFileAndWhere) {
  const Files f = MakeFiles();
  // No --expression: the clip's expression channel names an expression nobody gave.
  auto r = RunTool({"play", SurfaceRig(), f.clip, "--time", "1", "--out", f.dir + "/x.obj"});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(Contains(r.output, f.clip + ": channels[1].expression: unknown expression \"Raise\" "
                                          "(no expressions were given)")) << r.output;
  EXPECT_TRUE(ReadText(f.dir + "/x.obj").empty());
  // A muscle the rig does not have, with the closest names.
  const std::string bad = Write(f.dir + "/bad.clip.json",
      R"({"format": "mimetic-clip", "version": 1, "name": "c",
          "channels": [{"muscle": "zygo", "keys": [{"t": 0, "v": 1}]}]})");
  r = RunTool({"play", SurfaceRig(), bad, "--time", "0", "--out", f.dir + "/x.obj"});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(Contains(r.output, bad + ": channels[0].muscle: unknown muscle \"zygo\"; closest: "
                                       "zygomatic")) << r.output;
  // A broken clip file, an expression file that does not exist.
  const std::string broken = Write(f.dir + "/broken.clip.json",
      R"({"format": "mimetic-clip", "version": 1, "name": "c",
          "channels": [{"muscle": "zygomatic", "keys": [{"t": 1, "v": 1}, {"t": 0, "v": 0}]}]})");
  r = RunTool({"play", SurfaceRig(), broken, "--expression", f.dir + "/none.expression.json",
               "--time", "0", "--out", f.dir + "/x.obj"});
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_TRUE(Contains(r.output, broken + ": channels[0].keys[1].t: is 0, not after keys[0].t = 1"))
      << r.output;
  EXPECT_TRUE(Contains(r.output, f.dir + "/none.expression.json")) << r.output;
  EXPECT_TRUE(Contains(r.output, "nothing was written")) << r.output;
}

}  // namespace
}  // namespace mimetic

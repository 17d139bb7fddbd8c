// tests/tools/build_clip_test.cpp: `mimetic build CLIP --rig RIG --out FILE.mclip`
// (tools/cmd_build.cpp) and the commands that take its output: the library clips
// (assets/clips with assets/expressions/default.library.json, on the sample head) read back
// from their .mclip sample bit-identically to the clips built from JSON; `mimetic play` on the
// .mclip writes the same bytes as on the JSON clip; a .mclip compiled for another rig's
// muscle count, or a broken one, is exit 1 with a message naming the file.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "expressions/runtime/clip_binary.h"
#include "expressions/runtime/clip_sample_job.h"
#include "io/clip_file.h"
#include "io/expression_library.h"
#include "io/rig_loader.h"
#include "test_support.h"
#include "tools/mesh_expect.h"

namespace mimetic {
namespace {

using test::ReadText;
using test::RunTool;

bool Contains(const std::string& haystack, const std::string& needle) {
  return haystack.find(needle) != std::string::npos;
}

std::string Src(const std::string& rel) { return test::SourceDir() + "/" + rel; }
std::string Library() { return Src("assets/expressions/default.library.json"); }
const char* kClips[] = {"fear", "frowning", "smile", "surprise"};

// The sample head compiled once for the suite (a .mrig loads in a fraction of the build).
class BuildClip : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new std::string(test::TempDir());
    const auto r = RunTool({"build", Src("assets/head/sample_head.rig.json"), "--out", Head()});
    ASSERT_EQ(r.exit_code, 0) << r.output;
  }
  static std::string Head() { return *dir_ + "/head.mrig"; }
  static std::string Dir() { return *dir_; }
  static std::string* dir_;
};
std::string* BuildClip::dir_ = nullptr;

TEST_F(BuildClip, LibraryClipsRoundTripAndSampleBitIdentically) {
  LoadedRig head;
  Diagnostics diag;
  ASSERT_TRUE(LoadRig(Head(), &head, &diag)) << diag.Format();
  std::vector<Expression> library;
  ASSERT_TRUE(LoadExpressionLibrary(Library(), &library, &diag)) << diag.Format();
  for (const char* name : kClips) {
    SCOPED_TRACE(name);
    const std::string json = Src(std::string("assets/clips/") + name + ".clip.json");
    ClipSpec spec;
    ASSERT_TRUE(LoadClip(json, &spec, &diag)) << diag.Format();
    CompiledClip clip;
    ASSERT_TRUE(mimetic::BuildClip(spec, head.rig.muscle_names(), library, &clip, &diag))
        << diag.Format();
    // Through the command, and through the library call: the same bytes.
    const std::string out = Dir() + "/" + name + ".mclip";
    const auto r = RunTool({"build", json, "--rig", Head(), "--library", Library(), "--out", out});
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_TRUE(Contains(r.output, "wrote " + out)) << r.output;
    const std::string bytes = ReadText(out);
    EXPECT_EQ(bytes, WriteClipBinary(clip));
    CompiledClip back;
    std::string error;
    ASSERT_TRUE(LoadClipBinaryFile(out, &back, &error)) << error;
    EXPECT_EQ(back.muscle_count(), head.rig.muscle_count());
    EXPECT_EQ(back.channel_count(), clip.channel_count());
    // 1001 times over [-0.5, duration + 0.5] and the odd ones.
    std::vector<float> times = {std::nanf(""), INFINITY, -INFINITY, clip.duration()};
    for (int i = 0; i <= 1000; ++i)
      times.push_back(-0.5f + (clip.duration() + 1.f) * float(i) / 1000.f);
    std::vector<float> a(clip.muscle_count() + 1), b(clip.muscle_count() + 1);
    for (float t : times) {
      for (auto [c, o] : {std::pair{&clip, &a}, std::pair{&back, &b}}) {
        ClipSampleJob job;
        job.clip = c;
        job.time = t;
        job.out_activations = span<float>(o->data(), c->muscle_count());
        job.out_jaw = span<float>(o->data() + c->muscle_count(), 1);
        ASSERT_TRUE(job.Run());
      }
      ASSERT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(float)), 0) << "t = " << t;
    }
    // A clip that does something: some muscle is well above 0 at half the duration.
    ClipSampleJob job{&back, 0.5f * back.duration(), a, {}};
    ASSERT_TRUE(job.Run());
    float peak = 0.f;
    for (uint32_t m = 0; m < back.muscle_count(); ++m) peak = std::max(peak, a[m]);
    EXPECT_GT(peak, 0.1f);
  }
}

TEST_F(BuildClip, PlayOnTheMclipWritesTheSameBytes) {
  const std::string json = Src("assets/clips/surprise.clip.json");
  const std::string mclip = Dir() + "/surprise_play.mclip";
  ASSERT_EQ(RunTool({"build", json, "--rig", Head(), "--library", Library(), "--out", mclip})
                .exit_code,
            0);
  for (const char* t : {"0.4", "1.1"}) {
    const auto a = RunTool({"play", Head(), json, "--library", Library(), "--time", t, "--out",
                            Dir() + "/json_" + t + ".obj"});
    ASSERT_EQ(a.exit_code, 0) << a.output;
    const auto b = RunTool({"play", Head(), mclip, "--time", t, "--out",
                            Dir() + "/mclip_" + t + ".obj"});
    ASSERT_EQ(b.exit_code, 0) << b.output;
    const std::string want = ReadText(Dir() + "/json_" + t + ".obj");
    EXPECT_GT(want.size(), 1000u);
    EXPECT_TRUE(want == ReadText(Dir() + "/mclip_" + t + ".obj")) << "t = " << t;
  }
  // A bake (every frame, the weights animation): the same .glb bytes.
  const auto a = RunTool({"play", Head(), json, "--library", Library(), "--fps", "6", "--quiet",
                          "--out", Dir() + "/json.glb"});
  ASSERT_EQ(a.exit_code, 0) << a.output;
  const auto b = RunTool({"play", Head(), mclip, "--fps", "6", "--quiet", "--out",
                          Dir() + "/mclip.glb"});
  ASSERT_EQ(b.exit_code, 0) << b.output;
  EXPECT_TRUE(ReadText(Dir() + "/json.glb") == ReadText(Dir() + "/mclip.glb"));
  // --library with a .mclip: unused, and said so.
  const auto w = RunTool({"play", Head(), mclip, "--library", Library(), "--time", "1", "--out",
                          Dir() + "/w.obj"});
  EXPECT_EQ(w.exit_code, 0) << w.output;
  EXPECT_TRUE(Contains(w.output, "--expression and --library are not used")) << w.output;
}

TEST_F(BuildClip, GoldenFromTheMclipIsTheSameFile) {
  const std::string json = Src("tests/golden/smile.clip.json");
  const std::string mclip = Dir() + "/golden/smile.mclip";
  std::filesystem::create_directories(Dir() + "/golden/a");
  std::filesystem::create_directories(Dir() + "/golden/b");
  ASSERT_EQ(RunTool({"build", json, "--rig", Head(), "--out", mclip}).exit_code, 0);
  const auto a = RunTool({"play", Head(), json, "--write-golden", Dir() + "/golden/a"});
  ASSERT_EQ(a.exit_code, 0) << a.output;
  const auto b = RunTool({"play", Head(), mclip, "--write-golden", Dir() + "/golden/b"});
  ASSERT_EQ(b.exit_code, 0) << b.output;
  // Named after the clip file without .clip.json / .mclip: the same name, the same bytes.
  const std::string want = ReadText(Dir() + "/golden/a/smile.golden");
  EXPECT_GT(want.size(), 100u);
  EXPECT_TRUE(want == ReadText(Dir() + "/golden/b/smile.golden"));
}

TEST_F(BuildClip, WrongRigAndBrokenFilesAreInputErrors) {
  const std::string surface = Src("assets/surface/surface.rig.json");
  const std::string json = Dir() + "/z.clip.json";
  std::ofstream(json) << R"({"format": "mimetic-clip", "version": 1, "name": "z",
    "channels": [{"muscle": "zygomatic", "keys": [{"t": 0, "v": 0}, {"t": 2, "v": 1}]}]})";
  const std::string mclip = Dir() + "/z.mclip";
  const auto r = RunTool({"build", json, "--rig", surface, "--out", mclip});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  CompiledClip z;
  std::string error;
  ASSERT_TRUE(LoadClipBinaryFile(mclip, &z, &error)) << error;
  LoadedRig head;
  Diagnostics diag;
  ASSERT_TRUE(LoadRig(Head(), &head, &diag));
  ASSERT_NE(z.muscle_count(), head.rig.muscle_count());
  // Played on the sample head: refused, naming both counts.
  const auto p = RunTool({"play", Head(), mclip, "--time", "1", "--out", Dir() + "/no.obj"});
  EXPECT_EQ(p.exit_code, 1) << p.output;
  EXPECT_TRUE(Contains(p.output, mclip + ": was compiled for a rig of " +
                                     std::to_string(z.muscle_count()) + " muscles; " + Head() +
                                     " has " + std::to_string(head.rig.muscle_count())))
      << p.output;
  EXPECT_FALSE(std::filesystem::exists(Dir() + "/no.obj"));
  // On its own rig it plays.
  EXPECT_EQ(RunTool({"play", surface, mclip, "--time", "1", "--out", Dir() + "/yes.obj"})
                .exit_code,
            0);
  // Truncated: the file and the section are named.
  const std::string bytes = ReadText(mclip);
  std::ofstream(Dir() + "/cut.mclip", std::ios::binary) << bytes.substr(0, bytes.size() - 5);
  const auto cut = RunTool({"play", surface, Dir() + "/cut.mclip", "--time", "1", "--out",
                            Dir() + "/no.obj"});
  EXPECT_EQ(cut.exit_code, 1);
  EXPECT_TRUE(Contains(cut.output, Dir() + "/cut.mclip: section '")) << cut.output;
  // Recognised by its tag under another name.
  std::ofstream(Dir() + "/tagged.bin", std::ios::binary) << bytes;
  EXPECT_EQ(RunTool({"play", surface, Dir() + "/tagged.bin", "--time", "1", "--out",
                     Dir() + "/tag.obj"})
                .exit_code,
            0);
  // Usage: a clip needs --rig; a rig takes no --rig.
  const auto no_rig = RunTool({"build", json, "--out", Dir() + "/x.mclip"});
  EXPECT_EQ(no_rig.exit_code, 2);
  EXPECT_TRUE(Contains(no_rig.output, "missing --rig RIG")) << no_rig.output;
  EXPECT_EQ(RunTool({"build", surface, "--rig", surface, "--out", Dir() + "/x.mrig"}).exit_code,
            2);
  // An unknown expression: exit 1, nothing written.
  std::ofstream(Dir() + "/e.clip.json") << R"({"format": "mimetic-clip", "version": 1,
    "name": "e", "channels": [{"expression": "Nope", "keys": [{"t": 0, "v": 1}]}]})";
  const auto bad = RunTool({"build", Dir() + "/e.clip.json", "--rig", surface, "--out",
                            Dir() + "/e.mclip"});
  EXPECT_EQ(bad.exit_code, 1);
  EXPECT_TRUE(Contains(bad.output, "nothing was written")) << bad.output;
  EXPECT_FALSE(std::filesystem::exists(Dir() + "/e.mclip"));
}

}  // namespace
}  // namespace mimetic

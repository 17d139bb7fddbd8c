// tests/io/golden_file_test.cpp: the playback goldens (tests/golden/README.md): the runtime's
// outputs match every committed golden; a 1% change of one muscle's strength breaks one,
// naming a vertex; sequential and random-seek playback give the same bits; the reader refuses
// truncated, foreign and newer files.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "expressions/runtime/clip_sample_job.h"
#include "io/clip_file.h"
#include "io/golden_file.h"
#include "io/mesh_io.h"
#include "io/rig_loader.h"
#include "rig/runtime/evaluate_job.h"
#include "test_support.h"

namespace mimetic {
namespace {

std::string GoldenDir() { return test::SourceDir() + "/tests/golden"; }
std::string HeadRig() { return test::SourceDir() + "/assets/head/sample_head.rig.json"; }

const LoadedRig& Head() {
  static const LoadedRig* rig = [] {
    auto* r = new LoadedRig;
    Diagnostics diag;
    if (!LoadRig(HeadRig(), r, &diag)) ADD_FAILURE() << diag.Format();
    return r;
  }();
  return *rig;
}

CompiledClip Clip(const Rig& rig, const std::string& name) {
  ClipSpec spec;
  CompiledClip clip;
  Diagnostics diag;
  EXPECT_TRUE(LoadClip(GoldenDir() + "/" + name + ".clip.json", &spec, &diag)) << diag.Format();
  EXPECT_TRUE(BuildClip(spec, rig.muscle_names(), std::vector<Expression>{}, &clip, &diag)) << diag.Format();
  return clip;
}

const char* const kClips[] = {"brows", "smile"};

TEST(Golden, RuntimeMatchesEveryGolden) {
  const Rig& rig = Head().rig;
  for (const char* name : kClips) {
    SCOPED_TRACE(name);
    Golden golden;
    Diagnostics diag;
    ASSERT_TRUE(LoadGolden(GoldenDir() + "/" + name + ".golden", &golden, &diag))
        << diag.Format();
    ASSERT_EQ(golden.vertex_count, rig.vertex_count());
    ASSERT_GE(golden.frames.size(), 3u);
    const CompiledClip clip = Clip(rig, name);
    std::vector<float> p, n;
    for (size_t f = 0; f < golden.frames.size(); ++f) {
      ASSERT_TRUE(EvaluateClipFrame(rig, clip, golden.frames[f].time, &p, &n));
      const GoldenMismatch m = CompareGoldenFrame(golden, f, p, n);
      EXPECT_TRUE(m.ok) << name << ".golden " << m.message
                        << "\n(if the change is intended: regenerate with `mimetic play "
                           "assets/head/sample_head.rig.json tests/golden/"
                        << name << ".clip.json --write-golden tests/golden --frames ...`, "
                                   "tests/golden/README.md)";
    }
  }
}

// The golden is sensitive: a muscle 1% stronger fails it, naming a vertex that moved.
TEST(Golden, FailsWhenAMuscleStrengthChangesByOnePercent) {
  RigSpec spec = Head().spec;
  const auto it = std::find_if(spec.muscles.begin(), spec.muscles.end(),
                               [](const MuscleSpec& m) { return m.name == "zygomaticus_major_L"; });
  ASSERT_NE(it, spec.muscles.end());
  it->strength *= 1.01f;
  Rig changed;
  Diagnostics diag;
  ASSERT_TRUE(BuildRig(spec, Head().mesh, {}, &changed, &diag)) << diag.Format();
  Golden golden;
  ASSERT_TRUE(LoadGolden(GoldenDir() + "/smile.golden", &golden, &diag)) << diag.Format();
  const CompiledClip clip = Clip(changed, "smile");
  std::vector<float> p, n;
  bool failed = false;
  for (size_t f = 0; f < golden.frames.size(); ++f) {
    ASSERT_TRUE(EvaluateClipFrame(changed, clip, golden.frames[f].time, &p, &n));
    const GoldenMismatch m = CompareGoldenFrame(golden, f, p, n);
    if (m.ok) continue;
    failed = true;
    EXPECT_EQ(m.what, "position");
    EXPECT_GT(m.distance, m.limit);
    // The reported numbers are the vertex's own: its distance is |expected - got| there.
    const size_t v = m.vertex;
    EXPECT_EQ(m.got.x, p[3 * v]);
    const double dx = double(m.expected.x) - p[3 * v], dy = double(m.expected.y) - p[3 * v + 1],
                 dz = double(m.expected.z) - p[3 * v + 2];
    EXPECT_NEAR(m.distance, std::sqrt(dx * dx + dy * dy + dz * dz), 1e-9);
    EXPECT_NE(m.message.find("vertex " + std::to_string(v)), std::string::npos) << m.message;
    EXPECT_NE(m.message.find("expected ("), std::string::npos) << m.message;
  }
  EXPECT_TRUE(failed) << "a 1% stronger zygomaticus_major_L passed the smile golden";
}

// Sampling is stateless: frames played in order and in a shuffled order give the same bits.
TEST(Golden, SequentialAndRandomSeekPlaybackMatchBitForBit) {
  const Rig& rig = Head().rig;
  const CompiledClip clip = Clip(rig, "smile");
  const size_t frames = 24, nv = size_t(rig.vertex_count()) * 3;
  auto play = [&](const std::vector<size_t>& order, std::vector<float>* out) {
    out->assign(frames * nv * 2, 0.f);
    std::vector<float> a(rig.muscle_count());
    EvaluateContext context(rig);
    for (size_t f : order) {
      ClipSampleJob s;
      s.clip = &clip;
      s.time = float(f) / 12.f;  // 0 .. 1.92 s of the 2 s loop
      s.out_activations = a;
      ASSERT_TRUE(s.Run());
      EvaluateJob e;
      e.rig = &rig;
      e.context = &context;
      e.activations = a;
      e.out_positions = span<float>(out->data() + f * nv * 2, nv);
      e.out_normals = span<float>(out->data() + f * nv * 2 + nv, nv);
      ASSERT_TRUE(e.Run());
    }
  };
  std::vector<size_t> order(frames);
  for (size_t i = 0; i < frames; ++i) order[i] = i;
  std::vector<float> seq, rnd;
  play(order, &seq);
  std::mt19937 rng(12);
  std::shuffle(order.begin(), order.end(), rng);
  play(order, &rnd);
  ASSERT_EQ(seq.size(), rnd.size());
  EXPECT_EQ(std::memcmp(seq.data(), rnd.data(), seq.size() * sizeof(float)), 0);
  // and the frames differ from each other (the clip moves), so the check has teeth
  EXPECT_NE(std::memcmp(seq.data(), seq.data() + 12 * nv * 2, nv * sizeof(float)), 0);
}

TEST(Golden, ReaderRefusesTruncatedForeignAndNewerFiles) {
  const std::string bytes = test::ReadFileBytes(GoldenDir() + "/brows.golden");
  ASSERT_GT(bytes.size(), 100u);
  const std::string dir = test::TempDir();
  struct Case {
    std::string bytes;
    const char* message;
  } cases[] = {
      {bytes.substr(0, bytes.size() - 7), "is truncated: "},
      {bytes.substr(0, 20), "shorter than the 28-byte golden header"},
      {"GLTF" + bytes.substr(4), "is not a mimetic golden file"},
      {bytes + "x", "is too long"},
  };
  for (const Case& c : cases) {
    const std::string path = dir + "/copy.golden";
    std::ofstream(path, std::ios::binary) << c.bytes;
    Golden g;
    Diagnostics diag;
    EXPECT_FALSE(LoadGolden(path, &g, &diag));
    EXPECT_NE(diag.Format().find(c.message), std::string::npos) << diag.Format();
    EXPECT_NE(diag.Format().find(path), std::string::npos) << diag.Format();
  }
  // The truncated message says how many bytes it has and expected.
  Golden g;
  Diagnostics diag;
  EXPECT_FALSE(ParseGolden(bytes.substr(0, bytes.size() - 7), "t", &g, &diag));
  EXPECT_NE(diag.Format().find(std::to_string(bytes.size() - 7) + " bytes; expected " +
                               std::to_string(bytes.size())),
            std::string::npos)
      << diag.Format();
  std::string newer = bytes;
  newer[8] = 2;
  diag.Clear();
  EXPECT_FALSE(ParseGolden(newer, "n", &g, &diag));
  EXPECT_NE(diag.Format().find("golden version 2: this build reads version 1"),
            std::string::npos)
      << diag.Format();
  // A round trip of the committed file is byte-exact.
  diag.Clear();
  ASSERT_TRUE(ParseGolden(bytes, "b", &g, &diag)) << diag.Format();
  EXPECT_EQ(GoldenToBytes(g), bytes);
}

}  // namespace
}  // namespace mimetic

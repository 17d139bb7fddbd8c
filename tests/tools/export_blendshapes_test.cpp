// tests/tools/export_blendshapes_test.cpp: `mimetic export-blendshapes RIG --map arkit --out
// FILE.glb` (tools/cmd_export_blendshapes.cpp) on the sample head: 52 morph targets named in
// Apple's order, each the map's pose evaluated here (LoadRig, EvaluateJob) minus the neutral,
// all-zero for the shapes the map marks "none"; bad input refused with a message.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include "gltf_decode.h"
#include "io/arkit_map.h"
#include "io/rig_loader.h"
#include "rig/runtime/evaluate_job.h"
#include "test_support.h"

namespace mimetic {
namespace {

using test::RunTool;

std::string Head() { return test::SourceDir() + "/assets/head/sample_head.rig.json"; }
std::string Map() { return test::SourceDir() + "/assets/arkit/default.arkit.json"; }

std::string ReadBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// The rig's positions at `shape`'s activations (the jaw too, where the rig has one).
std::vector<float> Pose(const Rig& rig, const ArkitShape* shape) {
  std::vector<float> activations(rig.muscle_count(), 0.f), out(3 * size_t(rig.vertex_count()));
  float jaw = 0.f;
  if (shape)
    for (const auto& [name, value] : shape->activations) {
      if (name == "jaw") {
        jaw = value;
        continue;
      }
      const int m = rig.FindMuscle(name);
      EXPECT_GE(m, 0) << name;
      if (m >= 0) activations[size_t(m)] = value;
    }
  EvaluateContext context(rig);
  EvaluateJob job;
  job.rig = &rig;
  job.context = &context;
  job.activations = activations;
  job.jaw = jaw;
  job.out_positions = out;
  EXPECT_TRUE(job.Run());
  return out;
}

TEST(ExportBlendshapes, SampleHeadHas52NamedTargetsEqualToTheMapsPoses) {
  const std::string glb = test::TempDir() + "/out/head_arkit52.glb";
  const auto run = RunTool({"export-blendshapes", Head(), "--map", "arkit", "--out", glb,
                            "--no-normals"});
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("exported 52 ARKit blendshapes"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("all-zero targets: eyeBlinkLeft"), std::string::npos) << run.output;

  tinygltf::Model m;
  std::string err;
  ASSERT_TRUE(test::LoadGlb(ReadBytes(glb), &m, &err)) << err;
  ASSERT_EQ(m.meshes.size(), 1u);
  const tinygltf::Mesh& mesh = m.meshes[0];
  const tinygltf::Primitive& prim = mesh.primitives[0];
  ASSERT_EQ(prim.targets.size(), 52u);
  EXPECT_EQ(prim.attributes.count("NORMAL"), 0u);  // --no-normals
  const tinygltf::Value& names = mesh.extras.Get("targetNames");
  ASSERT_EQ(names.ArrayLen(), 52u);
  const span<const char* const> apple = ArkitShapeNames();
  ASSERT_EQ(apple.size(), 52u);
  for (size_t k = 0; k < 52; ++k) EXPECT_EQ(names.Get(int(k)).Get<std::string>(), apple[k]) << k;

  LoadedRig loaded;
  Diagnostics diag;
  ASSERT_TRUE(LoadRig(Head(), &loaded, &diag)) << diag.Format();
  std::vector<ArkitShape> map;
  ASSERT_TRUE(LoadArkitMap(Map(), &map, &diag)) << diag.Format();
  const Rig& rig = loaded.rig;
  const size_t nv = rig.vertex_count();
  const std::vector<float> base = test::ReadFloats(m, prim.attributes.at("POSITION"));
  ASSERT_EQ(base.size(), 3 * nv);
  const std::vector<float> neutral = Pose(rig, nullptr);
  for (size_t i = 0; i < base.size(); ++i) ASSERT_EQ(base[i], neutral[i]) << i;
  // The exporter drops moves under 1e-6 of the head's diagonal (~0.25 um): the tolerance.
  const float tolerance = 1e-3f;  // mm
  size_t checked = 0;
  for (size_t k = 0; k < 52; ++k) {
    const ArkitShape& shape = map[k];
    ASSERT_EQ(shape.name, apple[k]);
    const std::vector<float> d = test::ReadFloats(m, prim.targets[k].at("POSITION"));
    ASSERT_EQ(d.size(), 3 * nv) << shape.name;
    if (shape.how == ArkitShape::How::kNone) {
      for (float x : d) ASSERT_EQ(x, 0.f) << shape.name;
      continue;
    }
    // Every fourth made shape against its own evaluation (the whole set is slow under sanitizers).
    if (checked++ % 4 != 0) continue;
    const std::vector<float> pose = Pose(rig, &shape);
    float moved = 0.f, worst = 0.f;
    for (size_t i = 0; i < d.size(); ++i) {
      moved = std::max(moved, std::fabs(pose[i] - neutral[i]));
      worst = std::max(worst, std::fabs(base[i] + d[i] - pose[i]));
    }
    EXPECT_LT(worst, tolerance) << shape.name;
    bool drives = false;  // a muscle above 0, or the jaw on a rig that has one
    for (const auto& [name, value] : shape.activations)
      drives |= value > 0.f && (name != "jaw" || !rig.jaw().empty());
    if (drives) {
      EXPECT_GT(moved, 0.1f) << shape.name << " moves the face by a tenth of a millimetre or more";
    }
  }
  EXPECT_GE(checked, 20u);  // 24 of the 52 are made by the default map
}

TEST(ExportBlendshapes, RefusesBadInput) {
  const std::string dir = test::TempDir();
  auto missing = RunTool({"export-blendshapes", Head()});
  EXPECT_EQ(missing.exit_code, 2) << missing.output;
  EXPECT_NE(missing.output.find("missing --out"), std::string::npos) << missing.output;
  auto ext = RunTool({"export-blendshapes", Head(), "--out", dir + "/x.obj"});
  EXPECT_EQ(ext.exit_code, 2) << ext.output;
  EXPECT_NE(ext.output.find(".glb"), std::string::npos) << ext.output;
  // A map that names a muscle the rig does not have.
  std::string text = ReadBytes(Map());
  const size_t at = text.find("\"zygomaticus_major_L\"");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, std::string("\"zygomaticus_major_L\"").size(), "\"zygomaticus_majr_L\"");
  const std::string bad_map = dir + "/bad.arkit.json";
  std::ofstream(bad_map) << text;
  const std::string out = dir + "/never.glb";
  auto unknown = RunTool({"export-blendshapes", Head(), "--map", bad_map, "--out", out});
  EXPECT_EQ(unknown.exit_code, 1) << unknown.output;
  EXPECT_NE(unknown.output.find("zygomaticus_majr_L"), std::string::npos) << unknown.output;
  EXPECT_NE(unknown.output.find("nothing was written"), std::string::npos) << unknown.output;
  EXPECT_FALSE(std::ifstream(out).good());
  auto absent = RunTool({"export-blendshapes", dir + "/no_such.rig.json", "--out", out});
  EXPECT_EQ(absent.exit_code, 1) << absent.output;
  EXPECT_NE(absent.output.find("no_such.rig.json"), std::string::npos) << absent.output;
}

}  // namespace
}  // namespace mimetic

// tests/tools/bake_test.cpp: `mimetic play RIG CLIP --fps F --out FILE.glb` (tools/play_bake.cpp)
// on the sample head: the glb read back with tinygltf (tests/gltf_decode.h) has one morph
// target per frame whose sparse-expanded deltas plus the base equal an independent evaluation
// (LoadRig, BuildClip, ClipSampleJob, EvaluateJob here) at k / fps, input times k / fps,
// sparse targets where few vertices move; --library feeds expression channels; the four
// shipped clips (assets/clips) play and move the face by millimetres at mid-clip.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "expressions/offline/clip_builder.h"
#include "expressions/runtime/clip_sample_job.h"
#include "gltf_decode.h"
#include "io/clip_file.h"
#include "io/expression_library.h"
#include "io/mesh_io.h"
#include "io/rig_loader.h"
#include "rig/offline/rig_builder.h"
#include "rig/runtime/evaluate_job.h"
#include "test_support.h"

namespace mimetic {
namespace {

using test::RunTool;

std::string Head() { return test::SourceDir() + "/assets/head/sample_head.rig.json"; }
std::string Library() { return test::SourceDir() + "/assets/expressions/default.library.json"; }

std::string ReadBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

bool Contains(const std::string& haystack, const std::string& needle) {
  return haystack.find(needle) != std::string::npos;
}

// Frames of `clip_path` at `times`, evaluated here: positions (#F * #V * 3 floats) and, when
// `tension`, out_tension (#F * #V * 2) and out_region_weights (#F * #regions). The clip's
// expressions come from the default library.
struct Frames {
  std::vector<float> positions, tension, regions;
};
Frames Evaluate(const LoadedRig& loaded, const std::string& clip_path,
                const std::vector<double>& times, bool tension = false) {
  Diagnostics diag;
  ClipSpec spec;
  EXPECT_TRUE(LoadClip(clip_path, &spec, &diag)) << diag.Format();
  std::vector<Expression> library;
  EXPECT_TRUE(LoadExpressionLibrary(Library(), &library, &diag)) << diag.Format();
  CompiledClip clip;
  EXPECT_TRUE(BuildClip(spec, loaded.rig.muscle_names(), library, &clip, &diag)) << diag.Format();
  const size_t nv = loaded.rig.vertex_count(), nr = loaded.rig.tension_region_count();
  Frames out;
  out.positions.resize(times.size() * nv * 3);
  if (tension) {
    out.tension.resize(times.size() * nv * 2);
    out.regions.resize(times.size() * nr);
  }
  std::vector<float> activations(loaded.rig.muscle_count());
  EvaluateContext context(loaded.rig);
  for (size_t k = 0; k < times.size(); ++k) {
    ClipSampleJob sample;
    sample.clip = &clip;
    sample.time = float(times[k]);
    sample.out_activations = activations;
    EXPECT_TRUE(sample.Run());
    EvaluateJob job;
    job.rig = &loaded.rig;
    job.context = &context;
    job.activations = activations;
    job.out_positions = span<float>(&out.positions[k * nv * 3], nv * 3);
    if (tension) {
      job.out_tension = span<float>(&out.tension[k * nv * 2], nv * 2);
      job.out_region_weights = span<float>(out.regions.data() + k * nr, nr);
    }
    EXPECT_TRUE(job.Run());
  }
  return out;
}

TEST(Bake, SampleHeadFramesEqualTheRuntime) {
  const std::string dir = test::TempDir();
  // 0.4 s at 10 fps: frames at 0, 0.1, .. 0.4. Corrugators only (Frowning): few vertices move.
  const std::string clip = dir + "/frown.clip.json";
  std::ofstream(clip) << R"({"format": "mimetic-clip", "version": 1, "name": "f", "channels": [
    {"expression": "Frowning", "keys": [{"t": 0, "v": 0, "interp": "cubic"}, {"t": 0.4, "v": 1}]}]})";
  const std::string glb = dir + "/out/frown.glb";
  const auto run = RunTool({"play", Head(), clip, "--library", Library(), "--fps", "10", "--out",
                            glb, "--threads", "2"});
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_TRUE(Contains(run.output, "baked 5 frames")) << run.output;
  EXPECT_TRUE(Contains(run.output, "vertices moved:")) << run.output;

  LoadedRig loaded;
  Diagnostics diag;
  ASSERT_TRUE(LoadRig(Head(), &loaded, &diag)) << diag.Format();
  const size_t nv = loaded.rig.vertex_count();
  const std::vector<double> times = {0.0, 0.1, 0.2, 0.3, 0.4};
  const std::vector<float> want = Evaluate(loaded, clip, times).positions;

  tinygltf::Model m;
  std::string err;
  ASSERT_TRUE(test::LoadGlb(ReadBytes(glb), &m, &err)) << err;
  ASSERT_EQ(m.meshes.size(), 1u);
  const tinygltf::Primitive& prim = m.meshes[0].primitives[0];
  // Frame 0 is the neutral (no target); frames 1-4 differ: one target each.
  ASSERT_EQ(prim.targets.size(), times.size() - 1);
  EXPECT_EQ(m.nodes[0].scale, (std::vector<double>{0.001, 0.001, 0.001}));  // the head is in mm
  const std::vector<float> base = test::ReadFloats(m, prim.attributes.at("POSITION"));
  ASSERT_EQ(base.size(), nv * 3);
  // The base is the neutral: the rig evaluated at zero activations.
  const MeshData rest = RestMesh(loaded.rig);
  ASSERT_EQ(rest.vertex_count(), nv);
  EXPECT_EQ(m.accessors[size_t(prim.indices)].count, rest.indices.size());
  // The bake drops moves below 1e-6 of the head's diagonal (tools/play_bake.cpp).
  double lo[3] = {1e30, 1e30, 1e30}, hi[3] = {-1e30, -1e30, -1e30};
  for (size_t i = 0; i < base.size(); ++i)
    lo[i % 3] = std::min(lo[i % 3], double(base[i])), hi[i % 3] = std::max(hi[i % 3], double(base[i]));
  const double epsilon = 1e-6 * std::hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
  EXPECT_GT(epsilon, 1e-4);  // a head of more than 100 mm
  EXPECT_LT(epsilon, 1e-3);
  size_t sparse = 0;
  std::vector<std::vector<float>> deltas;
  for (const auto& target : prim.targets) {
    const tinygltf::Accessor& a = m.accessors[size_t(target.at("POSITION"))];
    sparse += a.sparse.isSparse;
    ASSERT_EQ(a.minValues.size(), 3u);
    deltas.push_back(test::ReadFloats(m, target.at("POSITION")));
    ASSERT_EQ(deltas.back().size(), nv * 3);
    for (size_t i = 0; i < nv * 3; ++i) {
      EXPECT_GE(deltas.back()[i], a.minValues[i % 3]);
      EXPECT_LE(deltas.back()[i], a.maxValues[i % 3]);
    }
  }
  const tinygltf::AnimationSampler& ws = m.animations.at(0).samplers.at(0);
  const std::vector<float> weights = test::ReadFloats(m, ws.output);
  ASSERT_EQ(weights.size(), times.size() * deltas.size());
  for (size_t k = 0; k < times.size(); ++k) {
    // The frame as a viewer shows it at its time: base + sum of weight x target.
    double worst = 0;
    size_t moved = 0;
    for (size_t v = 0; v < nv; ++v) {
      bool mv = false;
      for (int c = 0; c < 3; ++c) {
        const size_t i = 3 * v + size_t(c);
        float p = base[i];
        for (size_t t = 0; t < deltas.size(); ++t)
          if (weights[k * deltas.size() + t] != 0.f) p += weights[k * deltas.size() + t] * deltas[t][i];
        worst = std::max(worst, std::abs(double(p) - want[k * nv * 3 + i]));
        mv |= p != base[i];
      }
      moved += mv;
    }
    EXPECT_LT(worst, epsilon + 1e-4) << "frame " << k << " (mm)";  // the epsilon, float rounding
    if (k == 0) {
      EXPECT_EQ(moved, 0u);  // frame 0 is the neutral
    }
    if (k == 4) {
      EXPECT_GT(moved, 0u);
      EXPECT_LT(moved, nv / 2) << "the corrugators move a small part of the head";
    }
  }
  EXPECT_EQ(sparse, 4u) << "frames 1-4 move few vertices: sparse";
  const tinygltf::AnimationSampler& s = m.animations.at(0).samplers.at(0);
  const std::vector<float> in = test::ReadFloats(m, s.input);
  ASSERT_EQ(in.size(), times.size());
  for (size_t k = 0; k < times.size(); ++k) EXPECT_EQ(in[k], float(double(k) / 10.0)) << k;
  EXPECT_EQ(s.interpolation, "LINEAR");
}

// --tension (docs/tension.md "Baking") on the procedural surface's rig with two tension regions
// added here (every vertex at weight 1, and the left half at 0.5): base + each target's
// _TENSION deltas is (r - 1, eps) of an independent EvaluateJob with out_tension at k / fps
// (within the bake's 1e-5), and FILE.regions.json holds the job's out_region_weights per frame.
TEST(Bake, TensionAttributeAndRegionWeights) {
  const std::string dir = test::TempDir();
  nlohmann::json rig = nlohmann::json::parse(
      ReadBytes(test::SourceDir() + "/assets/surface/surface.rig.json"));
  rig["mesh"]["path"] = test::SourceDir() + "/assets/surface/surface.obj";
  MeshData mesh;
  Diagnostics diag;
  ASSERT_TRUE(ImportMesh(rig["mesh"]["path"], "", &mesh, &diag)) << diag.Format();
  std::vector<double> all(mesh.vertex_count(), 1.0), half(mesh.vertex_count(), 0.0);
  for (size_t v = 0; v < mesh.vertex_count(); ++v) half[v] = mesh.positions[v].x < 0 ? 0.5 : 0.0;
  rig["tension_regions"] = {{{"name", "all"}, {"weights", all}},
                            {{"name", "left"}, {"reference", 0.05}, {"weights", half}}};
  const std::string rig_path = dir + "/tension.rig.json";
  std::ofstream(rig_path) << rig.dump();
  const std::string clip = dir + "/z.clip.json";
  std::ofstream(clip) << R"({"format": "mimetic-clip", "version": 1, "name": "z", "channels": [
    {"muscle": "zygomatic", "keys": [{"t": 0, "v": 0}, {"t": 0.3, "v": 1}]},
    {"muscle": "frontalis", "keys": [{"t": 0, "v": 0}, {"t": 0.3, "v": 0.5}]}]})";
  const std::string glb = dir + "/z.glb";
  const auto run = RunTool({"play", rig_path, clip, "--fps", "10", "--out", glb, "--tension"});
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_TRUE(Contains(run.output, "2 regions per frame in " + dir + "/z.regions.json"))
      << run.output;

  LoadedRig loaded;
  ASSERT_TRUE(LoadRig(rig_path, &loaded, &diag)) << diag.Format();
  ASSERT_EQ(loaded.rig.tension_region_count(), 2u);
  const size_t nv = loaded.rig.vertex_count();
  const std::vector<double> times = {0.0, 0.1, 0.2, 0.3};
  const Frames frames = Evaluate(loaded, clip, times, true);
  const std::vector<float>& want = frames.tension;
  const std::vector<float>& want_regions = frames.regions;
  tinygltf::Model m;
  std::string err;
  ASSERT_TRUE(test::LoadGlb(ReadBytes(glb), &m, &err)) << err;
  const tinygltf::Primitive& prim = m.meshes[0].primitives[0];
  ASSERT_TRUE(prim.attributes.count("_TENSION"));
  const std::vector<float> base = test::ReadFloats(m, prim.attributes.at("_TENSION"));
  ASSERT_EQ(base.size(), nv * 2);
  std::vector<std::vector<float>> deltas;
  for (const auto& target : prim.targets) {
    ASSERT_TRUE(target.count("_TENSION"));
    deltas.push_back(test::ReadFloats(m, target.at("_TENSION")));
  }
  const std::vector<float> weights = test::ReadFloats(m, m.animations[0].samplers[0].output);
  ASSERT_EQ(weights.size(), times.size() * deltas.size());
  double most = 0;
  for (size_t k = 0; k < times.size(); ++k) {
    double worst = 0;
    for (size_t i = 0; i < nv * 2; ++i) {
      float t = base[i];
      for (size_t j = 0; j < deltas.size(); ++j) t += weights[k * deltas.size() + j] * deltas[j][i];
      const double expected = want[k * nv * 2 + i] - (i % 2 == 0 ? 1.0 : 0.0);  // r - 1, eps
      worst = std::max(worst, std::abs(double(t) - expected));
      most = std::max(most, std::abs(expected));
    }
    EXPECT_LT(worst, 1e-5 + 1e-6) << "frame " << k;
  }
  EXPECT_GT(most, 0.01) << "the muscles compress or stretch the surface by more than 1%";

  const nlohmann::json regions = nlohmann::json::parse(ReadBytes(dir + "/z.regions.json"));
  EXPECT_EQ(regions["format"], "mimetic-tension-regions");
  ASSERT_EQ(regions["times"].size(), times.size());
  ASSERT_EQ(regions["regions"].size(), 2u);
  EXPECT_EQ(regions["regions"][0]["name"], "all");
  EXPECT_EQ(regions["regions"][1]["name"], "left");
  for (size_t k = 0; k < times.size(); ++k)
    for (size_t i = 0; i < 2; ++i)
      EXPECT_EQ(regions["regions"][i]["weights"][k].get<float>(), want_regions[k * 2 + i])
          << "frame " << k << " region " << i;
  EXPECT_EQ(want_regions[0], 0.f);          // the neutral compresses nothing
  EXPECT_GT(want_regions[3 * 2 + 0], 0.f);  // the full pull compresses some of the surface
}

TEST(Bake, UsageAndInputErrors) {
  const std::string dir = test::TempDir();
  const std::string clip = test::SourceDir() + "/assets/clips/surprise.clip.json";
  struct Case {
    std::vector<std::string> args;
    int exit_code;
    const char* message;
  } cases[] = {
      {{"play", Head(), clip, "--fps", "30", "--out", dir + "/a.glb"}, 1,
       "unknown expression \"Surprise\""},
      {{"play", Head(), clip, "--library", dir + "/missing.json", "--fps", "30", "--out",
        dir + "/a.glb"}, 1, "missing.json"},
      {{"play", Head(), clip, "--library", Library(), "--fps", "30", "--out", dir + "/a_%d.glb"}, 2,
       "a .glb bake is one file"},
      {{"play", Head(), clip, "--library", Library(), "--time", "1", "--out", dir + "/a.obj",
        "--no-normals"}, 2, "is for a bake only"},
      {{"play", Head(), clip, "--library", Library(), "--fps", "30", "--out", dir + "/a.glb",
        "--threads", "0"}, 2, "--threads 0"},
      {{"play", Head(), clip, "--library", Library(), "--time", "1", "--out", dir + "/a.obj",
        "--tension"}, 2, "--tension is for a bake only"},
      {{"play", Head(), clip, "--library", Library(), "--fps", "1000", "--out", dir + "/a.glb"}, 1,
       "in a bake"},
  };
  for (const Case& c : cases) {
    const auto r = RunTool(c.args);
    EXPECT_EQ(r.exit_code, c.exit_code) << r.output;
    EXPECT_TRUE(Contains(r.output, c.message)) << c.message << "\n" << r.output;
  }
  EXPECT_FALSE(std::ifstream(dir + "/a.glb").good());
}

// The four shipped clips play from the CLI: at mid-clip (1.2 s, in the hold) the face differs
// from the neutral by more than 0.5 mm somewhere, and every coordinate is finite.
TEST(Bake, ShippedClipsPlay) {
  const std::string dir = test::TempDir();
  const auto neutral = RunTool({"play", Head(), test::SourceDir() + "/assets/clips/smile.clip.json",
                                "--library", Library(), "--time", "0", "--out", dir + "/n.obj"});
  ASSERT_EQ(neutral.exit_code, 0) << neutral.output;
  MeshData n;
  Diagnostics diag;
  ASSERT_TRUE(ImportMesh(dir + "/n.obj", "", &n, &diag)) << diag.Format();
  for (const char* name : {"surprise", "frowning", "fear", "smile"}) {
    const std::string out = dir + "/" + name + ".obj";
    const auto r = RunTool({"play", Head(), test::SourceDir() + "/assets/clips/" + name +
                            ".clip.json", "--library", Library(), "--time", "1.2", "--out", out});
    ASSERT_EQ(r.exit_code, 0) << name << ": " << r.output;
    MeshData p;
    ASSERT_TRUE(ImportMesh(out, "", &p, &diag)) << diag.Format();
    ASSERT_EQ(p.vertex_count(), n.vertex_count());
    double worst = 0;
    bool finite = true;
    for (size_t v = 0; v < p.vertex_count(); ++v) {
      const float3 a = p.positions[v], b = n.positions[v];
      finite &= std::isfinite(a.x) && std::isfinite(a.y) && std::isfinite(a.z);
      worst = std::max(worst, double(std::hypot(a.x - b.x, a.y - b.y, a.z - b.z)));
    }
    EXPECT_TRUE(finite) << name;
    EXPECT_GT(worst, 0.5) << name << ": the largest displacement from the neutral, mm";
  }
}

}  // namespace
}  // namespace mimetic

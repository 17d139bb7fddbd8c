// tests/io/gltf_bake_test.cpp: io/gltf_bake.h on a hand-made quad whose frames are written out
// here: the glb read back with tinygltf (tests/gltf_decode.h) has one morph target per distinct
// frame that is not the base, and the weights animation's rows times the sparse-expanded
// deltas plus the base are the frames, sparse accessors exactly where
// they are smaller, min/max, the LINEAR weights animation at k / fps, the unit node; bad input
// is refused with a message; the file write is atomic.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "gltf_decode.h"
#include "io/gltf_bake.h"
#include "io/mesh_io.h"
#include "test_support.h"

namespace mimetic {
namespace {

// A unit quad (4 vertices, 2 triangles) in mm; 3 frames at 10 fps: frame 0 = the base,
// frame 1 moves vertex 2 by (0, 0, 0.5) (1 vertex: sparse 1 * (2 + 12) = 14 bytes < 48 dense),
// frame 2 moves every vertex by (0.25, 0, 0) (sparse 64 bytes > 48: dense).
BakedFrames Quad() {
  BakedFrames f;
  f.base.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  f.base.normals = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
  f.base.indices = {0, 1, 2, 0, 2, 3};
  f.times = {0.0, 0.1, 0.2};
  f.metres_per_unit = 0.001;
  for (int k = 0; k < 3; ++k)
    for (int v = 0; v < 4; ++v) {
      float3 p = f.base.positions[size_t(v)];
      if (k == 1 && v == 2) p.z += 0.5f;
      if (k == 2) p.x += 0.25f;
      f.positions.insert(f.positions.end(), {p.x, p.y, p.z});
      f.normals.insert(f.normals.end(), {0.f, 0.f, 1.f});
    }
  return f;
}

TEST(GltfBake, QuadReadsBackFrameByFrame) {
  const BakedFrames f = Quad();
  std::string bytes;
  BakeStats stats;
  Diagnostics diag;
  ASSERT_TRUE(BakeGlbBytes(f, &bytes, &stats, &diag)) << diag.Format();
  EXPECT_EQ(stats.frames, 3u);
  EXPECT_EQ(stats.sparse_targets, 1u);
  EXPECT_EQ(stats.moved_vertices, 4u);
  EXPECT_EQ(stats.max_moved_in_frame, 4u);
  EXPECT_EQ(stats.bytes, bytes.size());
  ASSERT_EQ(bytes.substr(0, 4), "glTF");

  tinygltf::Model m;
  std::string err;
  ASSERT_TRUE(test::LoadGlb(bytes, &m, &err)) << err;
  ASSERT_EQ(m.nodes.size(), 1u);
  EXPECT_EQ(m.nodes[0].name, "mimetic_units");
  EXPECT_EQ(m.nodes[0].scale, (std::vector<double>{0.001, 0.001, 0.001}));
  ASSERT_EQ(m.meshes.size(), 1u);
  ASSERT_EQ(m.meshes[0].primitives.size(), 1u);
  const tinygltf::Primitive& prim = m.meshes[0].primitives[0];
  // Frame 0 is the base: no target; frames 1 and 2 have one each.
  ASSERT_EQ(prim.targets.size(), 2u);
  EXPECT_EQ(stats.targets, 2u);
  const std::vector<float> base = test::ReadFloats(m, prim.attributes.at("POSITION"));
  ASSERT_EQ(base.size(), 12u);
  const tinygltf::Accessor& pa = m.accessors[size_t(prim.attributes.at("POSITION"))];
  EXPECT_EQ(pa.minValues, (std::vector<double>{0, 0, 0}));
  EXPECT_EQ(pa.maxValues, (std::vector<double>{1, 1, 0}));
  for (size_t k = 1; k < 3; ++k) {
    const int acc = prim.targets[k - 1].at("POSITION");
    const std::vector<float> d = test::ReadFloats(m, acc);
    ASSERT_EQ(d.size(), 12u);
    for (size_t i = 0; i < 12; ++i)
      EXPECT_EQ(base[i] + d[i], f.positions[k * 12 + i]) << "frame " << k << " float " << i;
    ASSERT_TRUE(prim.targets[k - 1].count("NORMAL"));
    for (float n : test::ReadFloats(m, prim.targets[k - 1].at("NORMAL"))) EXPECT_EQ(n, 0.f);
  }
  // Frame 1: sparse, index 2 only; frame 2 dense.
  const tinygltf::Accessor& a1 = m.accessors[size_t(prim.targets[0].at("POSITION"))];
  EXPECT_TRUE(a1.sparse.isSparse);
  EXPECT_EQ(a1.sparse.count, 1);
  EXPECT_EQ(a1.sparse.indices.componentType, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT);
  EXPECT_EQ(a1.minValues, (std::vector<double>{0, 0, 0}));
  EXPECT_EQ(a1.maxValues, (std::vector<double>{0, 0, 0.5}));
  const tinygltf::Accessor& a2 = m.accessors[size_t(prim.targets[1].at("POSITION"))];
  EXPECT_FALSE(a2.sparse.isSparse);
  EXPECT_GE(a2.bufferView, 0);
  EXPECT_EQ(a2.minValues, (std::vector<double>{0.25, 0, 0}));
  EXPECT_EQ(a2.maxValues, (std::vector<double>{0.25, 0, 0}));

  // The animation: weights of node 0, LINEAR, input k / 10; row 0 all 0 (the base), row 1 =
  // e_0, row 2 = e_1.
  ASSERT_EQ(m.animations.size(), 1u);
  ASSERT_EQ(m.animations[0].channels.size(), 1u);
  EXPECT_EQ(m.animations[0].channels[0].target_path, "weights");
  EXPECT_EQ(m.animations[0].channels[0].target_node, 0);
  const tinygltf::AnimationSampler& s = m.animations[0].samplers[0];
  EXPECT_EQ(s.interpolation, "LINEAR");
  const std::vector<float> in = test::ReadFloats(m, s.input);
  ASSERT_EQ(in.size(), 3u);
  for (size_t k = 0; k < 3; ++k) EXPECT_EQ(in[k], float(k / 10.0)) << k;
  EXPECT_EQ(m.accessors[size_t(s.input)].minValues, (std::vector<double>{0.0}));
  EXPECT_EQ(m.accessors[size_t(s.input)].maxValues, (std::vector<double>{double(0.2f)}));
  const std::vector<float> out = test::ReadFloats(m, s.output);
  ASSERT_EQ(out.size(), 6u);
  const float rows[3][2] = {{0, 0}, {1, 0}, {0, 1}};
  for (size_t r = 0; r < 3; ++r)
    for (size_t c = 0; c < 2; ++c) EXPECT_EQ(out[r * 2 + c], rows[r][c]) << r << " " << c;

  // The base mesh also reads back through ImportMesh (morph targets ignored, units kept).
  const std::string dir = test::TempDir();
  ASSERT_TRUE(WriteBakedGlb(dir + "/q.glb", f, nullptr, &diag)) << diag.Format();
  MeshData back;
  Diagnostics import;
  ASSERT_TRUE(ImportMesh(dir + "/q.glb", "", &back, &import)) << import.Format();
  EXPECT_EQ(back.positions, f.base.positions);
  EXPECT_EQ(back.indices, f.base.indices);
}

// A held pose shares one target; frames at the base have none; weights x targets + base
// reproduce every frame. Frames: base, A, A, B, A, base (A moves vertex 1, B vertex 3; B's
// normal also turns).
TEST(GltfBake, HeldAndNeutralFramesShareTargets) {
  BakedFrames f = Quad();
  f.times = {0.0, 0.1, 0.2, 0.3, 0.4, 0.5};
  f.positions.clear();
  f.normals.clear();
  const int pose[6] = {0, 1, 1, 2, 1, 0};
  for (int k = 0; k < 6; ++k)
    for (int v = 0; v < 4; ++v) {
      float3 p = f.base.positions[size_t(v)];
      float3 n{0, 0, 1};
      if (pose[k] == 1 && v == 1) p.y += 0.125f;
      if (pose[k] == 2 && v == 3) {
        p.z -= 0.5f;
        n = {0.6f, 0, 0.8f};
      }
      f.positions.insert(f.positions.end(), {p.x, p.y, p.z});
      f.normals.insert(f.normals.end(), {n.x, n.y, n.z});
    }
  std::string bytes;
  BakeStats stats;
  Diagnostics diag;
  ASSERT_TRUE(BakeGlbBytes(f, &bytes, &stats, &diag)) << diag.Format();
  EXPECT_EQ(stats.frames, 6u);
  EXPECT_EQ(stats.targets, 2u);
  tinygltf::Model m;
  std::string err;
  ASSERT_TRUE(test::LoadGlb(bytes, &m, &err)) << err;
  const tinygltf::Primitive& prim = m.meshes[0].primitives[0];
  ASSERT_EQ(prim.targets.size(), 2u);
  EXPECT_EQ(m.meshes[0].weights.size(), 2u);
  const std::vector<float> base = test::ReadFloats(m, prim.attributes.at("POSITION"));
  const std::vector<float> base_n = test::ReadFloats(m, prim.attributes.at("NORMAL"));
  std::vector<std::vector<float>> dp, dn;
  for (const auto& t : prim.targets) {
    dp.push_back(test::ReadFloats(m, t.at("POSITION")));
    dn.push_back(test::ReadFloats(m, t.at("NORMAL")));
  }
  const std::vector<float> out = test::ReadFloats(m, m.animations[0].samplers[0].output);
  ASSERT_EQ(out.size(), 6u * 2u);
  for (size_t k = 0; k < 6; ++k) {
    const float* w = &out[k * 2];
    EXPECT_EQ(w[0] + w[1], pose[k] == 0 ? 0.f : 1.f) << k;
    for (size_t i = 0; i < 12; ++i) {
      EXPECT_EQ(base[i] + w[0] * dp[0][i] + w[1] * dp[1][i], f.positions[k * 12 + i]) << k << " " << i;
      EXPECT_EQ(base_n[i] + w[0] * dn[0][i] + w[1] * dn[1][i], f.normals[k * 12 + i]) << k << " " << i;
    }
  }
  EXPECT_EQ(std::vector<float>(out.begin() + 2, out.begin() + 4),
            std::vector<float>(out.begin() + 4, out.begin() + 6));  // frames 1 and 2: one target

  // Every frame the base: one all-zero target, weights all 0.
  BakedFrames still = Quad();
  still.positions.clear();
  still.normals.clear();
  for (int k = 0; k < 2; ++k)
    for (const float3& p : still.base.positions) {
      still.positions.insert(still.positions.end(), {p.x, p.y, p.z});
      still.normals.insert(still.normals.end(), {0.f, 0.f, 1.f});
    }
  still.times = {0.0, 0.1};
  ASSERT_TRUE(BakeGlbBytes(still, &bytes, &stats, &diag)) << diag.Format();
  EXPECT_EQ(stats.targets, 1u);
  tinygltf::Model m2;
  ASSERT_TRUE(test::LoadGlb(bytes, &m2, &err)) << err;
  ASSERT_EQ(m2.meshes[0].primitives[0].targets.size(), 1u);
  for (float x : test::ReadFloats(m2, m2.animations[0].samplers[0].output)) EXPECT_EQ(x, 0.f);
  for (float x : test::ReadFloats(m2, m2.meshes[0].primitives[0].targets[0].at("POSITION")))
    EXPECT_EQ(x, 0.f);
}

// Named targets (blendshape export): frames 0 (the base) and 3 (the same as 1) still get their
// own targets, in frame order, and the names land in the mesh's extras.targetNames.
TEST(GltfBake, NamedTargetsOnePerFrameInOrder) {
  BakedFrames f = Quad();
  f.times = {0.0, 1.0, 2.0, 3.0};
  for (int v = 0; v < 12; ++v) f.positions.push_back(f.positions[size_t(12 + v)]);  // 3 = 1
  for (int v = 0; v < 12; ++v) f.normals.push_back(f.normals[size_t(12 + v)]);
  f.target_names = {"neutralish", "up", "across", "up_again"};
  std::string bytes;
  BakeStats stats;
  Diagnostics diag;
  ASSERT_TRUE(BakeGlbBytes(f, &bytes, &stats, &diag)) << diag.Format();
  EXPECT_EQ(stats.targets, 4u);
  tinygltf::Model m;
  std::string err;
  ASSERT_TRUE(test::LoadGlb(bytes, &m, &err)) << err;
  const tinygltf::Mesh& mesh = m.meshes[0];
  ASSERT_EQ(mesh.primitives[0].targets.size(), 4u);
  ASSERT_TRUE(mesh.extras.Has("targetNames"));
  const tinygltf::Value& names = mesh.extras.Get("targetNames");
  ASSERT_EQ(names.ArrayLen(), 4u);
  for (size_t k = 0; k < 4; ++k) EXPECT_EQ(names.Get(int(k)).Get<std::string>(), f.target_names[k]);
  // Target k is frame k minus the base: 0 everywhere for frame 0, +0.5 z at vertex 2 for 1 and 3.
  const std::vector<float> base = test::ReadFloats(m, mesh.primitives[0].attributes.at("POSITION"));
  for (size_t k = 0; k < 4; ++k) {
    const std::vector<float> d = test::ReadFloats(m, mesh.primitives[0].targets[k].at("POSITION"));
    ASSERT_EQ(d.size(), 12u);
    for (size_t i = 0; i < 12; ++i) EXPECT_EQ(base[i] + d[i], f.positions[k * 12 + i]) << k << " " << i;
  }
  EXPECT_EQ(test::ReadFloats(m, mesh.primitives[0].targets[1].at("POSITION")),
            test::ReadFloats(m, mesh.primitives[0].targets[3].at("POSITION")));
  // One name short: refused, naming the counts.
  f.target_names.pop_back();
  Diagnostics bad;
  EXPECT_FALSE(BakeGlbBytes(f, &bytes, &stats, &bad));
  EXPECT_NE(bad.Format().find("3 target names for 4 frames"), std::string::npos) << bad.Format();
}

TEST(GltfBake, U32SparseIndicesPastU16AndNoNormals) {
  // 70000 vertices (a strip of triangles), one frame moving vertex 69999 only.
  BakedFrames f;
  const size_t nv = 70000;
  for (size_t v = 0; v < nv; ++v) f.base.positions.push_back({float(v % 100), float(v / 100), 0});
  for (uint32_t t = 0; t + 2 < nv; t += 3) f.base.indices.insert(f.base.indices.end(), {t, t + 1, t + 2});
  f.times = {0.5};
  f.positions.resize(nv * 3);
  for (size_t v = 0; v < nv; ++v) {
    f.positions[3 * v] = f.base.positions[v].x;
    f.positions[3 * v + 1] = f.base.positions[v].y;
    f.positions[3 * v + 2] = v == nv - 1 ? -2.f : 0.f;
  }
  std::string bytes;
  BakeStats stats;
  Diagnostics diag;
  ASSERT_TRUE(BakeGlbBytes(f, &bytes, &stats, &diag)) << diag.Format();
  EXPECT_EQ(stats.moved_vertices, 1u);
  tinygltf::Model m;
  std::string err;
  ASSERT_TRUE(test::LoadGlb(bytes, &m, &err)) << err;
  const tinygltf::Primitive& prim = m.meshes[0].primitives[0];
  EXPECT_FALSE(prim.attributes.count("NORMAL"));
  ASSERT_EQ(prim.targets.size(), 1u);
  EXPECT_FALSE(prim.targets[0].count("NORMAL"));
  const tinygltf::Accessor& a = m.accessors[size_t(prim.targets[0].at("POSITION"))];
  ASSERT_TRUE(a.sparse.isSparse);
  EXPECT_EQ(a.sparse.indices.componentType, TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT);
  const std::vector<float> d = test::ReadFloats(m, prim.targets[0].at("POSITION"));
  EXPECT_EQ(d[3 * (nv - 1) + 2], -2.f);
  EXPECT_EQ(d[3 * (nv - 2) + 2], 0.f);
  EXPECT_EQ(a.minValues, (std::vector<double>{0, 0, -2}));
  // 70000 * 12 bytes dense would be 840 kB; the file is the base (840 kB + indices) and little.
  EXPECT_LT(bytes.size(), nv * 12 + f.base.indices.size() * 4 + 4096);
}

// Tension (docs/tension.md "Baking"): the quad's frames with pairs (r - 1, eps) written out here:
// frame 0 the base's pairs, frame 1 vertex 2 at (0.5, 0.25), frame 2 every vertex at
// (-0.125, 0), and a frame 3 with the positions of frame 2 but vertex 0's pair changed, which
// must get its own target (a held-pose match compares tension too). The primitive's _TENSION
// is the base's pairs; base + each target's _TENSION delta is the frame's pairs.
TEST(GltfBake, TensionAttributeAndDeltasPerTarget) {
  BakedFrames f = Quad();
  f.times.push_back(0.3);
  f.positions.insert(f.positions.end(), f.positions.begin() + 24, f.positions.begin() + 36);
  f.normals.insert(f.normals.end(), f.normals.begin() + 24, f.normals.begin() + 36);
  f.base_tension = {0.f, 0.f, 0.f, 0.f, 0.f, 0.f, 0.f, 0.f};
  f.tension.assign(4 * 4 * 2, 0.f);
  f.tension[(1 * 4 + 2) * 2 + 0] = 0.5f;
  f.tension[(1 * 4 + 2) * 2 + 1] = 0.25f;
  for (size_t k = 2; k < 4; ++k)
    for (size_t v = 0; v < 4; ++v) f.tension[(k * 4 + v) * 2] = -0.125f;
  f.tension[(3 * 4 + 0) * 2 + 1] = 0.0625f;
  std::string bytes;
  BakeStats stats;
  Diagnostics diag;
  ASSERT_TRUE(BakeGlbBytes(f, &bytes, &stats, &diag)) << diag.Format();
  tinygltf::Model m;
  std::string err;
  ASSERT_TRUE(test::LoadGlb(bytes, &m, &err)) << err;
  const tinygltf::Primitive& prim = m.meshes[0].primitives[0];
  ASSERT_TRUE(prim.attributes.count("_TENSION"));
  const tinygltf::Accessor& ta = m.accessors[size_t(prim.attributes.at("_TENSION"))];
  EXPECT_EQ(ta.type, TINYGLTF_TYPE_VEC2);
  EXPECT_EQ(ta.count, 4u);
  const std::vector<float> base = test::ReadFloats(m, prim.attributes.at("_TENSION"));
  EXPECT_EQ(base, f.base_tension);
  // Frames 1, 2, 3 each their own target (frame 3 differs from 2 in tension only).
  ASSERT_EQ(prim.targets.size(), 3u);
  for (size_t k = 1; k < 4; ++k) {
    ASSERT_TRUE(prim.targets[k - 1].count("_TENSION")) << k;
    const std::vector<float> d = test::ReadFloats(m, prim.targets[k - 1].at("_TENSION"));
    ASSERT_EQ(d.size(), 8u);
    for (size_t i = 0; i < 8; ++i)
      EXPECT_EQ(base[i] + d[i], f.tension[k * 8 + i]) << "frame " << k << " float " << i;
  }
  // The animation shows frame k's target at its time: row 3 is 1 at target 2.
  const std::vector<float> rows = test::ReadFloats(m, m.animations[0].samplers[0].output);
  ASSERT_EQ(rows.size(), 4u * 3u);
  EXPECT_EQ(rows[3 * 3 + 2], 1.f);
  EXPECT_EQ(rows[3 * 3 + 1], 0.f);

  // A held pose whose tension is held too shares the target; tension within the epsilon of
  // the base is the base.
  f.tension.resize(3 * 8);
  f.times.pop_back();
  f.positions.resize(3 * 12);
  f.normals.resize(3 * 12);
  f.tension_epsilon = 0.5f;  // frame 1's pair (0.5, 0.25) and frame 2's -0.125 are within it
  f.positions[1 * 12 + 2 * 3 + 2] = f.base.positions[2].z;  // frame 1 = the base's positions
  ASSERT_TRUE(BakeGlbBytes(f, &bytes, &stats, &diag)) << diag.Format();
  ASSERT_TRUE(test::LoadGlb(bytes, &m, &err)) << err;
  EXPECT_EQ(m.meshes[0].primitives[0].targets.size(), 1u);  // frame 2 only (it moves)
}

TEST(GltfBake, TensionRegionsJson) {
  const std::string json =
      TensionRegionsToJson({"forehead", "glabella"}, {0.0, 0.5}, {0.f, 0.25f, 0.5f, 1.f});
  const nlohmann::json j = nlohmann::json::parse(json);
  EXPECT_EQ(j["format"], "mimetic-tension-regions");
  EXPECT_EQ(j["version"], 1);
  EXPECT_EQ(j["times"], (std::vector<double>{0.0, 0.5}));
  ASSERT_EQ(j["regions"].size(), 2u);
  EXPECT_EQ(j["regions"][0]["name"], "forehead");
  EXPECT_EQ(j["regions"][0]["weights"], (std::vector<double>{0.0, 0.5}));
  EXPECT_EQ(j["regions"][1]["name"], "glabella");
  EXPECT_EQ(j["regions"][1]["weights"], (std::vector<double>{0.25, 1.0}));
}

TEST(GltfBake, RefusesBadInput) {
  struct Case {
    const char* what;
    void (*edit)(BakedFrames*);
    const char* message;
  } cases[] = {
      {"no frames", [](BakedFrames* f) { f->times.clear(); f->positions.clear(); f->normals.clear(); }, "no frames"},
      {"short positions", [](BakedFrames* f) { f->positions.pop_back(); }, "sizes do not match"},
      {"times not increasing", [](BakedFrames* f) { f->times[2] = 0.1; }, "not after the previous"},
      {"negative time", [](BakedFrames* f) { f->times[0] = -1; }, "negative"},
      {"NaN", [](BakedFrames* f) { f->positions[5] = std::nanf(""); }, "non-finite"},
      {"index", [](BakedFrames* f) { f->base.indices[4] = 9; }, "out of range"},
      {"unit", [](BakedFrames* f) { f->metres_per_unit = 0; }, "metres_per_unit"},
      {"tension without its base", [](BakedFrames* f) { f->tension.assign(3 * 4 * 2, 0.f); }, "sizes do not match"},
      {"short tension", [](BakedFrames* f) { f->tension.assign(3 * 4 * 2 - 1, 0.f); f->base_tension.assign(8, 0.f); }, "sizes do not match"},
      {"NaN tension", [](BakedFrames* f) { f->tension.assign(24, 0.f); f->base_tension.assign(8, 0.f); f->tension[3] = std::nanf(""); }, "non-finite"},
      {"tension epsilon", [](BakedFrames* f) { f->tension_epsilon = -1; }, "epsilons"},
  };
  for (const Case& c : cases) {
    BakedFrames f = Quad();
    c.edit(&f);
    std::string bytes = "untouched";
    Diagnostics diag;
    EXPECT_FALSE(BakeGlbBytes(f, &bytes, nullptr, &diag)) << c.what;
    EXPECT_EQ(bytes, "untouched") << c.what;
    EXPECT_NE(diag.Format().find(c.message), std::string::npos) << c.what << ": " << diag.Format();
    const std::string dir = test::TempDir();
    Diagnostics write;
    EXPECT_FALSE(WriteBakedGlb(dir + "/x.glb", f, nullptr, &write)) << c.what;
    EXPECT_FALSE(std::filesystem::exists(dir + "/x.glb")) << c.what;
  }
}

}  // namespace
}  // namespace mimetic

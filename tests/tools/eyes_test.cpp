// tests/tools/eyes_test.cpp: the sample head's eyeballs, a second, rigid mesh in its .glb
// (content/sample_head.h MakeSampleHeadEyes), carried along by `mimetic eval` and drawn by
// `mimetic render`; the rig and every reader of the file take the skin (the first mesh).
//
// Expectations: the eyes in every output are the input file's eyes bit for bit; the skin is
// what the same command writes from a skin-only copy of the file; the render differs from the
// skin-only one only where an in-process label render (eyes white, skin black) shows the eyes.
#include <gtest/gtest.h>
#include <stb/stb_image.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "content/sample_head.h"
#include "geometry/mesh.h"
#include "io/mesh_io.h"
#include "sample_rig.h"
#include "test_support.h"
#include "tools/render/render.h"

namespace mimetic {
namespace {

std::string Asset() { return test::SourceDir() + "/assets/head/sample_head.glb"; }

bool SameBits(const MeshData& a, const MeshData& b) {
  auto same = [](const auto& x, const auto& y) {
    return x.size() == y.size() && (x.empty() || std::memcmp(x.data(), y.data(), x.size() * sizeof(x[0])) == 0);
  };
  return same(a.positions, b.positions) && same(a.normals, b.normals) && same(a.uvs, b.uvs) &&
         same(a.indices, b.indices);
}

// The asset with its skin alone (ExportMesh: one mesh), and a copy of the sample rig on it.
struct SkinOnly {
  std::string glb, rig;
};
const SkinOnly& SkinOnlyCopy() {
  static const SkinOnly s = [] {
    SkinOnly out;
    MeshData skin;
    Diagnostics d;
    EXPECT_TRUE(ImportMesh(Asset(), "", &skin, &d)) << d.Format();
    out.glb = test::TempDir() + "/skin_only.glb";
    EXPECT_TRUE(ExportMesh(out.glb, skin, &d)) << d.Format();
    out.rig = test::EditedSampleRig("skin_only", [&](nlohmann::json& j) { j["mesh"]["path"] = out.glb; });
    return out;
  }();
  return s;
}

TEST(SampleHeadEyes, TheAssetHoldsTheSkinFirstAndTheEyesSecond) {
  MeshData first, head, eyes;
  Diagnostics d;
  ASSERT_TRUE(ImportMesh(Asset(), "", &first, &d)) << d.Format();
  ASSERT_TRUE(ImportMesh(Asset(), "head", &head, &d)) << d.Format();
  ASSERT_TRUE(ImportMesh(Asset(), "eyes", &eyes, &d)) << d.Format();
  EXPECT_TRUE(SameBits(first, head));
  // The generator's meshes, as written.
  EXPECT_TRUE(SameBits(head, MakeSampleHead().mesh));
  EXPECT_TRUE(SameBits(eyes, MakeSampleHeadEyes()));
  // The rig is built on the skin: its fingerprint counts the skin's vertices.
  std::ifstream in(test::SourceDir() + "/assets/head/sample_head.rig.json");
  const nlohmann::json rig = nlohmann::json::parse(in);
  EXPECT_EQ(rig["mesh"]["fingerprint"]["vertices"].get<size_t>(), head.vertex_count());
  EXPECT_FALSE(rig["mesh"].contains("name"));
}

TEST(SampleHeadEyes, TwoSpheresOfAnAdultEyeballBehindTheOpenLids) {
  const MeshData eyes = MakeSampleHeadEyes();
  const size_t per = eyes.vertex_count() / 2;
  ASSERT_EQ(eyes.vertex_count(), 2 * per);
  for (size_t v = 0; v < eyes.vertex_count(); ++v) {
    const float sx = v < per ? -1.f : 1.f;  // the subject's right eye first
    const float3 c{sx * kSampleHeadEyeCentre.x, kSampleHeadEyeCentre.y, kSampleHeadEyeCentre.z};
    EXPECT_NEAR(Length(eyes.positions[v] - c), kSampleHeadEyeballRadius, 1e-4f) << v;
    // The right eye mirrors the left exactly.
    if (v < per) {
      const float3 l = eyes.positions[v + per];
      EXPECT_EQ(eyes.positions[v].x, -l.x);
      EXPECT_EQ(eyes.positions[v].y, l.y);
      EXPECT_EQ(eyes.positions[v].z, l.z);
    }
  }
  // Closed and outward: each sphere's signed volume is close to 4/3 pi r^3 (a polyhedron
  // inscribed in the sphere: a little less).
  for (int e = 0; e < 2; ++e) {
    const float3 c{(e ? 1.f : -1.f) * kSampleHeadEyeCentre.x, kSampleHeadEyeCentre.y, kSampleHeadEyeCentre.z};
    double vol = 0;
    for (size_t t = 0; t < eyes.indices.size(); t += 3) {
      if ((eyes.indices[t] >= per) != (e == 1)) continue;
      const float3 a = eyes.positions[eyes.indices[t]] - c, b = eyes.positions[eyes.indices[t + 1]] - c,
                   d = eyes.positions[eyes.indices[t + 2]] - c;
      vol += Dot(a, Cross(b, d)) / 6.0;
    }
    const double r = kSampleHeadEyeballRadius, sphere = 4.0 / 3.0 * 3.14159265358979 * r * r * r;
    EXPECT_LT(vol, sphere) << e;
    EXPECT_GT(vol, 0.97 * sphere) << e;
  }
  // The cornea's front (the front pole) lies behind the lids' surface: behind every skin point
  // of the upper and lower lid landmarks, and the lid rolls end outside the eyeball.
  const SampleHead head = MakeSampleHead();
  for (int l : {37, 38, 40, 41, 43, 44, 46, 47}) {
    const float3 c{head.landmarks[l].x < 0 ? -kSampleHeadEyeCentre.x : kSampleHeadEyeCentre.x,
                   kSampleHeadEyeCentre.y, kSampleHeadEyeCentre.z};
    EXPECT_GT(Length(head.landmarks[l] - c), kSampleHeadEyeballRadius) << l;
  }
}

// The v lines of OBJ object `name` (from its `o` line to the next one).
std::vector<float3> ObjObjectVertices(const std::string& path, const std::string& name) {
  std::istringstream in(test::ReadFileBytes(path));
  std::string line;
  bool inside = false;
  std::vector<float3> out;
  while (std::getline(in, line)) {
    if (line.rfind("o ", 0) == 0) inside = line == "o " + name;
    if (inside && line.rfind("v ", 0) == 0) {
      float3 p;
      if (std::sscanf(line.c_str(), "v %f %f %f", &p.x, &p.y, &p.z) == 3) out.push_back(p);
    }
  }
  return out;
}

TEST(SampleHeadEyes, EvalWritesThePosedSkinAndTheEyesUnchanged) {
  const std::string rig = test::SourceDir() + "/assets/head/sample_head.rig.json";
  const std::string dir = test::TempDir();
  MeshData eyes_in;
  Diagnostics d;
  ASSERT_TRUE(ImportMesh(Asset(), "eyes", &eyes_in, &d)) << d.Format();
  for (const std::vector<std::string>& pose :
       {std::vector<std::string>{}, {"--set", "frontalis_major_L=0.8", "--set", "jaw=0.6"}}) {
    std::vector<std::string> with{"eval", rig, "--out", dir + "/with.glb"}, alone{"eval", SkinOnlyCopy().rig, "--out", dir + "/alone.glb"};
    with.insert(with.end(), pose.begin(), pose.end());
    alone.insert(alone.end(), pose.begin(), pose.end());
    auto r = test::RunTool(with);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    r = test::RunTool(alone);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    MeshData skin_with, skin_alone, eyes_out;
    ASSERT_TRUE(ImportMesh(dir + "/with.glb", "", &skin_with, &d)) << d.Format();
    ASSERT_TRUE(ImportMesh(dir + "/alone.glb", "", &skin_alone, &d)) << d.Format();
    ASSERT_TRUE(ImportMesh(dir + "/with.glb", "eyes", &eyes_out, &d)) << d.Format();
    EXPECT_TRUE(SameBits(skin_with, skin_alone)) << "the skin output changed with the eyes";
    EXPECT_TRUE(SameBits(eyes_out, eyes_in)) << "the eyes moved";
    // The skin-only rig's output has no second mesh.
    MeshData none;
    Diagnostics missing;
    EXPECT_FALSE(ImportMesh(dir + "/alone.glb", "eyes", &none, &missing));
    // OBJ: the eyes are the second object, their `v` lines the input's floats.
    with[3] = dir + "/with.obj";
    r = test::RunTool(with);
    ASSERT_EQ(r.exit_code, 0) << r.output;
    EXPECT_EQ(ObjObjectVertices(dir + "/with.obj", "eyes"), eyes_in.positions);
    EXPECT_EQ(ObjObjectVertices(dir + "/with.obj", "head"), skin_with.positions);
  }
}

TEST(SampleHeadEyes, PlayWritesThePosedSkinAndTheEyesUnchanged) {
  const std::string rig = test::SourceDir() + "/assets/head/sample_head.rig.json";
  const std::string clip = test::SourceDir() + "/tests/golden/brows.clip.json";
  const std::string dir = test::TempDir();
  auto r = test::RunTool({"play", rig, clip, "--time", "0.6", "--out", dir + "/with.glb", "--quiet"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  r = test::RunTool({"play", SkinOnlyCopy().rig, clip, "--time", "0.6", "--out", dir + "/alone.glb", "--quiet"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  MeshData skin_with, skin_alone, eyes_out, eyes_in, rest;
  Diagnostics d;
  ASSERT_TRUE(ImportMesh(Asset(), "eyes", &eyes_in, &d)) << d.Format();
  ASSERT_TRUE(ImportMesh(Asset(), "", &rest, &d)) << d.Format();
  ASSERT_TRUE(ImportMesh(dir + "/with.glb", "", &skin_with, &d)) << d.Format();
  ASSERT_TRUE(ImportMesh(dir + "/alone.glb", "", &skin_alone, &d)) << d.Format();
  ASSERT_TRUE(ImportMesh(dir + "/with.glb", "eyes", &eyes_out, &d)) << d.Format();
  EXPECT_TRUE(SameBits(skin_with, skin_alone));
  EXPECT_TRUE(SameBits(eyes_out, eyes_in));
  // The brows moved the skin (the rig's first vertices are the file's), not the eyes.
  ASSERT_GE(skin_with.vertex_count(), rest.vertex_count());
  size_t moved = 0;
  for (size_t v = 0; v < rest.vertex_count(); ++v) moved += Length(skin_with.positions[v] - rest.positions[v]) > 1e-3f;
  EXPECT_GT(moved, 100u);
}

Image LoadPngImage(const std::string& path) {
  const std::string bytes = test::ReadFileBytes(path);
  int w = 0, h = 0, n = 0;
  unsigned char* px = stbi_load_from_memory(reinterpret_cast<const unsigned char*>(bytes.data()),
                                            int(bytes.size()), &w, &h, &n, 3);
  Image img;
  if (!px) return img;
  img.width = w;
  img.height = h;
  img.rgb.assign(px, px + size_t(w) * h * 3);
  stbi_image_free(px);
  return img;
}

TEST(SampleHeadEyes, RenderDrawsTheEyesInsideTheOpenings) {
  const std::string dir = test::TempDir();
  const int n = 240;
  for (const char* yaw : {"0", "35"}) {
    auto r = test::RunTool({"render", Asset(), "--size", std::to_string(n), "--yaw", yaw, "--out", dir + "/with.png"});
    ASSERT_EQ(r.exit_code, 0) << r.output;
    r = test::RunTool({"render", SkinOnlyCopy().glb, "--size", std::to_string(n), "--yaw", yaw, "--out", dir + "/alone.png"});
    ASSERT_EQ(r.exit_code, 0) << r.output;
    const Image with = LoadPngImage(dir + "/with.png"), alone = LoadPngImage(dir + "/alone.png");
    ASSERT_EQ(with.width, n);
    ASSERT_EQ(alone.width, n);
    // Where the eyes show: the skin and eyes drawn flat, black and white, from the same camera
    // (the eyes lie inside the head's bounding box, so the camera fit is the same).
    MeshData skin, eyes;
    Diagnostics d;
    ASSERT_TRUE(ImportMesh(Asset(), "", &skin, &d)) << d.Format();
    ASSERT_TRUE(ImportMesh(Asset(), "eyes", &eyes, &d)) << d.Format();
    MeshData both = skin;
    const uint32_t base = uint32_t(both.vertex_count());
    both.positions.insert(both.positions.end(), eyes.positions.begin(), eyes.positions.end());
    both.normals.insert(both.normals.end(), eyes.normals.begin(), eyes.normals.end());
    for (uint32_t i : eyes.indices) both.indices.push_back(base + i);
    both.uvs.clear();
    std::vector<float3> colors(both.vertex_count(), float3{0, 0, 0});
    for (size_t v = base; v < colors.size(); ++v) colors[v] = {1, 1, 1};
    RenderOptions o;
    o.width = o.height = n;
    o.yaw_deg = float(std::atof(yaw));
    o.vertex_colors = &colors;
    o.ambient = 1.f;
    o.diffuse = 0.f;
    o.specular = 0.f;
    const Image label = RenderMesh(both, o);
    size_t shown[2] = {0, 0};
    // Pixels where two renders differ, and those of them away from the eyes.
    auto compare = [&](const Image& a, const Image& b, size_t* differ, size_t* outside) {
      *differ = *outside = 0;
      for (int y = 0; y < n; ++y)
        for (int x = 0; x < n; ++x) {
          const size_t i = (size_t(y) * n + x) * 3;
          // An eye pixel, or beside one (the box filter spreads an edge by a pixel).
          bool eye = false;
          for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
              const int xx = std::clamp(x + dx, 0, n - 1), yy = std::clamp(y + dy, 0, n - 1);
              eye = eye || label.rgb[(size_t(yy) * n + xx) * 3] > 0;
            }
          if (std::memcmp(&a.rgb[i], &b.rgb[i], 3) != 0) {
            ++*differ;
            if (!eye) ++*outside;
          }
        }
    };
    for (int y = 0; y < n; ++y)
      for (int x = 0; x < n; ++x)
        if (label.rgb[(size_t(y) * n + x) * 3] > 0) ++shown[x < n / 2 ? 0 : 1];
    size_t differ = 0, outside = 0;
    compare(with, alone, &differ, &outside);
    EXPECT_GT(differ, 20u) << "yaw " << yaw;
    EXPECT_EQ(outside, 0u) << "yaw " << yaw;
    // The same from OBJ files (mimetic eval --out x.obj writes the eyes as a second object):
    // render reads the other objects too.
    ASSERT_TRUE(ExportMeshes(dir + "/with.obj", {{"head", &skin}, {"eyes", &eyes}}, &d)) << d.Format();
    ASSERT_TRUE(ExportMesh(dir + "/alone.obj", skin, &d)) << d.Format();
    r = test::RunTool({"render", dir + "/with.obj", "--size", std::to_string(n), "--yaw", yaw, "--out", dir + "/with_obj.png"});
    ASSERT_EQ(r.exit_code, 0) << r.output;
    r = test::RunTool({"render", dir + "/alone.obj", "--size", std::to_string(n), "--yaw", yaw, "--out", dir + "/alone_obj.png"});
    ASSERT_EQ(r.exit_code, 0) << r.output;
    compare(LoadPngImage(dir + "/with_obj.png"), LoadPngImage(dir + "/alone_obj.png"), &differ, &outside);
    EXPECT_GT(differ, 20u) << "OBJ, yaw " << yaw;
    EXPECT_EQ(outside, 0u) << "OBJ, yaw " << yaw;
    // Both eyes show through their openings seen from the front (at 35 degrees both may fall
    // on one side of the image's middle).
    if (std::string(yaw) == "0") {
      EXPECT_GT(shown[0], 10u);
      EXPECT_GT(shown[1], 10u);
    } else {
      EXPECT_GT(shown[0] + shown[1], 10u);
    }
  }
}

}  // namespace
}  // namespace mimetic

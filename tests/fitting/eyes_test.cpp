// fitting/eyes.h: the spheres the lids slide on, fitted to the eyes mesh a head file carries.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "content/sample_head.h"
#include "fitting/eyes.h"
#include "io/rig_loader.h"
#include "jaw_checks.h"
#include "rig/offline/rig_builder.h"
#include "sample_rig.h"
#include "test_support.h"

namespace mimetic {
namespace {

// A sphere of radius r about c sampled on a latitude-longitude grid (poles included), from
// latitude lat0 to 90 degrees, triangulated; a cap when lat0 > -90.
MeshData Sphere(float3 c, float r, double lat0 = -90.0, int rings = 12, int segments = 16) {
  MeshData m;
  const double pi = std::acos(-1.0);
  for (int i = 0; i <= rings; ++i) {
    const double lat = (lat0 + (90.0 - lat0) * i / rings) * pi / 180.0;
    for (int j = 0; j < segments; ++j) {
      const double lon = 2 * pi * j / segments;
      m.positions.push_back({float(c.x + r * std::cos(lat) * std::cos(lon)),
                             float(c.y + r * std::sin(lat)),
                             float(c.z + r * std::cos(lat) * std::sin(lon))});
    }
  }
  for (int i = 0; i < rings; ++i)
    for (int j = 0; j < segments; ++j) {
      const uint32_t a = uint32_t(i * segments + j), b = uint32_t(i * segments + (j + 1) % segments);
      const uint32_t d = a + uint32_t(segments), e = b + uint32_t(segments);
      m.indices.insert(m.indices.end(), {a, d, b, b, d, e});
    }
  return m;
}

void Append(MeshData* to, const MeshData& part) {
  const uint32_t base = uint32_t(to->positions.size());
  to->positions.insert(to->positions.end(), part.positions.begin(), part.positions.end());
  for (uint32_t i : part.indices) to->indices.push_back(base + i);
}

TEST(FitEyeballs, TheSampleHeadsEyeballsAreItsTwoTwelveMillimetreSpheres) {
  const MeshData eyes = MakeSampleHeadEyes();
  std::vector<EyeSphere> spheres;
  std::string error;
  ASSERT_TRUE(FitEyeballs(eyes, &spheres, &error)) << error;
  ASSERT_EQ(spheres.size(), 2u);
  // content/sample_head.h: radius 12 mm about (+-31, -0.5, 66), the subject's right (-x) first.
  for (int i = 0; i < 2; ++i) {
    EXPECT_NEAR(std::fabs(spheres[i].center.x), 31.f, 1e-3f);
    EXPECT_NEAR(spheres[i].center.y, -0.5f, 1e-3f);
    EXPECT_NEAR(spheres[i].center.z, 66.f, 1e-3f);
    EXPECT_NEAR(spheres[i].radius, 12.f, 1e-3f);
  }
  EXPECT_LT(spheres[0].center.x * spheres[1].center.x, 0.f);
  const EyesSpec spec = MakeEyesSpec(spheres);
  EXPECT_NEAR(spec.band[0], 12.f / 6.f, 1e-4f);
  EXPECT_NEAR(spec.band[1], 12.f * 2.f / 3.f, 1e-4f);
}

TEST(FitEyeballs, ACapOfASphereGivesItsCentreAndRadius) {
  // Only the part above latitude 30 degrees: the centre lies outside the vertices' hull.
  MeshData mesh = Sphere({10.f, -4.f, 3.f}, 7.5f, 30.0);
  Append(&mesh, Sphere({-20.f, 0.f, 1.f}, 2.f));
  std::vector<EyeSphere> spheres;
  std::string error;
  ASSERT_TRUE(FitEyeballs(mesh, &spheres, &error)) << error;
  ASSERT_EQ(spheres.size(), 2u);
  EXPECT_NEAR(spheres[0].center.x, 10.f, 1e-3f);
  EXPECT_NEAR(spheres[0].center.y, -4.f, 1e-3f);
  EXPECT_NEAR(spheres[0].center.z, 3.f, 1e-3f);
  EXPECT_NEAR(spheres[0].radius, 7.5f, 1e-3f);
  EXPECT_NEAR(spheres[1].center.x, -20.f, 1e-3f);
  EXPECT_NEAR(spheres[1].radius, 2.f, 1e-3f);
  EXPECT_NEAR(MakeEyesSpec(spheres).band[1], (7.5f + 2.f) / 2.f * 2.f / 3.f, 1e-4f);
}

TEST(FitEyeballs, WhatIsNotASphereIsRefusedNamingThePart) {
  std::vector<EyeSphere> spheres;
  std::string error;
  MeshData empty;
  EXPECT_FALSE(FitEyeballs(empty, &spheres, &error));
  EXPECT_EQ(error, "the eyes mesh has no triangles");
  // A flat grid after a good sphere: part 2, coplanar.
  MeshData mesh = Sphere({0.f, 0.f, 0.f}, 5.f);
  MeshData flat;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) flat.positions.push_back({float(i), float(j), 0.f});
  for (uint32_t i = 0; i < 2; ++i)
    for (uint32_t j = 0; j < 2; ++j) {
      const uint32_t a = i * 3 + j;
      flat.indices.insert(flat.indices.end(), {a, a + 3, a + 1, a + 1, a + 3, a + 4});
    }
  Append(&mesh, flat);
  EXPECT_FALSE(FitEyeballs(mesh, &spheres, &error));
  EXPECT_NE(error.find("part 2 of the eyes mesh"), std::string::npos) << error;
  EXPECT_NE(error.find("do not span a sphere"), std::string::npos) << error;
  // A lone triangle: too few vertices.
  MeshData tri;
  tri.positions = {{0.f, 0.f, 0.f}, {1.f, 0.f, 0.f}, {0.f, 1.f, 0.f}};
  tri.indices = {0, 1, 2};
  EXPECT_FALSE(FitEyeballs(tri, &spheres, &error));
  EXPECT_NE(error.find("part 1 of the eyes mesh (from vertex 0) has 3 vertices"),
            std::string::npos)
      << error;
  // A non-finite vertex.
  MeshData nan = Sphere({0.f, 0.f, 0.f}, 5.f);
  nan.positions[7].x = std::nanf("");
  EXPECT_FALSE(FitEyeballs(nan, &spheres, &error));
  EXPECT_NE(error.find("part 1 of the eyes mesh (from vertex 0): vertex 7 is not finite"),
            std::string::npos)
      << error;
}

// The committed sample head rig (assets/head/sample_head.rig.json, made by `mimetic fit` from a
// head file that carries its eyeballs) with the library's Surprise (the three frontalis pairs at
// 0.9): the lid points that slide fully (weight 1) keep their rest distance from the eyeball's
// centre to float rounding with the skin layers off, and within 0.5 mm with every layer and the
// fold limiter on (the furrows' offsets along the normal); without the eyes block the frontalis
// lifts the upper lids off the eyeballs by millimetres (the dark gap of the renders before
// docs/model.md §24). No triangle turns over.
struct LidMotion {
  float largest = 0.f;  // the largest change of distance from the eyeball's centre
  size_t points = 0;    // weight-1 vertices measured
  size_t turned_over = 0;
};

LidMotion MeasureLids(const Rig& rig, const RigEyes& eyes, SkinLayers layers = {}) {
  std::vector<float> act(rig.muscle_count(), 0.f);
  for (size_t m = 0; m < act.size(); ++m)
    if (rig.muscle_names()[m].rfind("frontalis_", 0) == 0) act[m] = 0.9f;
  MeshData posed;
  EXPECT_TRUE(PosedMesh(rig, act, layers, &posed));
  const MeshData rest = RestMesh(rig);
  LidMotion out;
  for (size_t v = 0; v < rest.positions.size(); ++v) {
    const uint32_t p = rig.vertex_points()[v];
    const auto it = std::lower_bound(eyes.points.begin(), eyes.points.end(), p);
    if (it == eyes.points.end() || *it != p) continue;
    const size_t i = size_t(it - eyes.points.begin());
    if (eyes.weights[i] < 1.f) continue;
    const float3 c = eyes.centers[eyes.eyes[i]];
    out.largest = std::max(out.largest, std::fabs(Length(posed.positions[v] - c) -
                                                  Length(rest.positions[v] - c)));
    ++out.points;
  }
  out.turned_over = test::CountTurnedOver(rest, posed.positions).count;
  return out;
}

TEST(EyesOnSampleHead, SurpriseSlidesTheLidsOverTheEyeballsInsteadOfLiftingThem) {
  LoadedRig head;
  Diagnostics diag;
  ASSERT_TRUE(LoadRig(test::SourceDir() + "/assets/head/sample_head.rig.json", &head, &diag))
      << diag.Format();
  const RigEyes& eyes = head.rig.eyes();
  ASSERT_FALSE(eyes.empty()) << "assets/head/sample_head.rig.json has no eyes block: rerun "
                                "mimetic fit (assets/head/README.md)";
  ASSERT_EQ(eyes.centers.size(), 2u);
  for (const float3& c : eyes.centers) {
    EXPECT_NEAR(std::fabs(c.x), 31.f, 1e-3f);
    EXPECT_NEAR(c.z, 66.f, 1e-3f);
  }
  const LidMotion bare = MeasureLids(head.rig, eyes, {false, false, false});
  const LidMotion with = MeasureLids(head.rig, eyes);
  std::printf("sample head, Surprise: %zu lid vertices slide on the eyeballs, largest change of "
              "their distance from the centre %.2g mm with the skin layers off, %.3f mm with "
              "them on",
              with.points, double(bare.largest), double(with.largest));
  EXPECT_GT(with.points, 100u);
  EXPECT_LT(bare.largest, 1e-3f);
  EXPECT_LT(with.largest, 0.5f);
  EXPECT_EQ(with.turned_over, 0u);
  LoadedRig no_eyes;
  ASSERT_TRUE(LoadRig(test::EditedSampleRig("no_eyes", [](nlohmann::json& j) { j.erase("eyes"); }),
                      &no_eyes, &diag))
      << diag.Format();
  ASSERT_TRUE(no_eyes.rig.eyes().empty());
  const LidMotion without = MeasureLids(no_eyes.rig, eyes, {false, false, false});
  const LidMotion without_all = MeasureLids(no_eyes.rig, eyes);
  std::printf("; without the eyes block %.3f and %.3f mm\n", double(without.largest),
              double(without_all.largest));
  EXPECT_EQ(without.points, with.points);
  EXPECT_GT(without.largest, 2.f);
  EXPECT_GT(without_all.largest, 2.f);
  EXPECT_EQ(without_all.turned_over, 0u);
}

}  // namespace
}  // namespace mimetic

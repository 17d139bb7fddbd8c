// Hover and the muscles panel (viewer/core/scene_query.h): the ray pick, the muscles that reach a
// point (a point inside one muscle's zone names that muscle and no other), the grouping and the
// left/right mirror.
#include "viewer/core/scene_query.h"

#include <cmath>

#include <gtest/gtest.h>

#include "content/procedural.h"
#include "rig/offline/rig_builder.h"

namespace mimetic::viewer {
namespace {

TEST(ViewerSceneQuery, PickFindsTheNearestTriangleAndItsBarycentrics) {
  // Two unit right triangles in the planes z = 0 and z = -1, the ray down -Z through (0.25, 0.5).
  const std::vector<float3> p = {{0, 0, -1}, {1, 0, -1}, {0, 1, -1}, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const std::vector<uint32_t> tris = {0, 1, 2, 3, 4, 5};
  PickHit hit;
  ASSERT_TRUE(PickTriangle(p, tris, {0.25f, 0.5f, 5.f}, {0, 0, -1}, &hit));
  EXPECT_EQ(hit.triangle, 1u);  // z = 0 is nearer
  EXPECT_NEAR(hit.distance, 5.f, 1e-5f);
  EXPECT_NEAR(hit.u, 0.25f, 1e-6f);  // weight of corner (1, 0)
  EXPECT_NEAR(hit.w, 0.5f, 1e-6f);   // weight of corner (0, 1)
  EXPECT_EQ(hit.nearest, 5u);        // (0, 1) has the largest weight
  EXPECT_FALSE(PickTriangle(p, tris, {2.f, 2.f, 5.f}, {0, 0, -1}, &hit));    // misses both
  EXPECT_FALSE(PickTriangle(p, tris, {0.2f, 0.2f, -5.f}, {0, 0, -1}, &hit)); // both behind
}

TEST(ViewerSceneQuery, APointInOneMusclesZoneNamesThatMuscleAndNoOther) {
  // Four muscles on a 100 x 100 sheet, each zone about 5% of it: no two overlap.
  const RigSpec spec = MakeSurfaceRigSpec(4, 100.f, 100.f, 10.f, 0.05f, 2.f);
  const MeshData mesh = MakeSurfaceMesh(41, 41, 100.f, 100.f, 10.f);
  Rig rig;
  Diagnostics diag;
  ASSERT_TRUE(BuildRig(spec, mesh, {}, &rig, &diag)) << diag.Format();
  // Muscle 0 is linear: the point 3/4 of the way along its axis, within Rf and inside the cone
  // (angle 0), lies in its zone (docs/model.md §2) and nowhere near the other three.
  const LinearMuscleSpec& l = spec.muscles[0].linear;
  ASSERT_EQ(spec.muscles[0].type, MuscleType::kLinear);
  const float3 target = l.attachment + 0.75f * (l.insertion - l.attachment);
  uint32_t best = 0;
  float best_d = INFINITY;
  for (uint32_t p = 0; p < rig.point_count(); ++p) {
    const float dx = rig.rest_points()[p].x - target.x, dy = rig.rest_points()[p].y - target.y;
    if (dx * dx + dy * dy < best_d) best_d = dx * dx + dy * dy, best = p;
  }
  const float3 q = rig.rest_points()[best];
  const float3 axis = NormalizeOr(l.insertion - l.attachment, float3{});
  const float3 to_q = q - l.attachment;
  ASSERT_LT(Length(to_q), l.falloff_end);  // the nearest point is inside the zone too
  ASSERT_LT(std::acos(Dot(NormalizeOr(to_q, float3{}), axis)), l.zone_angle);
  EXPECT_EQ(MusclesReachingPoint(rig, best), (std::vector<uint32_t>{0}));
  // The sheet's corner, about 35 from every zone's centre (zones reach about 15), reaches none;
  // a point out of range none either.
  uint32_t corner = 0;
  float corner_d = INFINITY;
  for (uint32_t p = 0; p < rig.point_count(); ++p) {
    const float dx = rig.rest_points()[p].x + 50.f, dy = rig.rest_points()[p].y + 50.f;
    if (dx * dx + dy * dy < corner_d) corner_d = dx * dx + dy * dy, corner = p;
  }
  EXPECT_TRUE(MusclesReachingPoint(rig, corner).empty());
  EXPECT_TRUE(MusclesReachingPoint(rig, rig.point_count()).empty());
}

TEST(ViewerSceneQuery, RegionsAndMirrors) {
  const std::vector<std::string> names = {"frontalis_inner_L", "zygomaticus_major_R", "mentalis_L",
                                          "frontalis_inner_R", "crows_feet_L", "nasalis_L",
                                          "mystery"};
  EXPECT_STREQ(MuscleRegion("corrugator_supercilii_L"), "brow and forehead");
  EXPECT_STREQ(MuscleRegion("levator_labii_alaeque_nasi_L"), "nose");
  EXPECT_STREQ(MuscleRegion("levator_labii_superioris_L"), "cheeks");
  const std::vector<MuscleGroup> groups = GroupMuscles(names);
  ASSERT_EQ(groups.size(), 6u);
  EXPECT_EQ(groups[0].region, "brow and forehead");
  EXPECT_EQ(groups[0].muscles, (std::vector<uint32_t>{0, 3}));
  EXPECT_EQ(groups[1].region, "eyes");
  EXPECT_EQ(groups[2].region, "nose");
  EXPECT_EQ(groups[3].region, "cheeks");
  EXPECT_EQ(groups[4].region, "mouth and chin");
  EXPECT_EQ(groups[5].region, "other");
  EXPECT_EQ(groups[5].muscles, (std::vector<uint32_t>{6}));
  EXPECT_EQ(MirrorMuscle(names, 0), 3);
  EXPECT_EQ(MirrorMuscle(names, 3), 0);
  EXPECT_EQ(MirrorMuscle(names, 2), -1);  // no mentalis_R
  EXPECT_EQ(MirrorMuscle(names, 6), -1);
}

}  // namespace
}  // namespace mimetic::viewer

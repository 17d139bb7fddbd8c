// Tests for geometry/surface_query.h on the unit square z = 0 split along its diagonal:
// T0 = (0,0,0) (1,0,0) (1,1,0), T1 = (0,0,0) (1,1,0) (0,1,0). Answers worked out by hand.
#include <gtest/gtest.h>

#include <cmath>

#include "geometry/surface_query.h"

namespace mimetic {
namespace {

MeshData Square() {
  MeshData m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  m.indices = {0, 1, 2, 0, 2, 3};
  return m;
}

TEST(SurfaceQuery, RayHitsTheKnownFaceFromEitherSide) {
  const MeshData m = Square();
  const SurfaceQuery q(m);
  // From above, straight down (dir not unit): (0.25, 0.75) lies in T1 (y > x), t = 5.
  SurfaceQuery::Hit h = q.Raycast({0.25f, 0.75f, 5}, {0, 0, -2});
  ASSERT_TRUE(h.found);
  EXPECT_EQ(h.triangle, 1u);
  EXPECT_FLOAT_EQ(h.t, 5.f);
  EXPECT_EQ(h.point, (float3{0.25f, 0.75f, 0}));
  EXPECT_EQ(h.normal, (float3{0, 0, 1}));  // facing the ray origin
  // (0.25, 0.75) = T1's a + 0.25 (b - a) + 0.5 (c - a): weights (0.25, 0.25, 0.5).
  EXPECT_EQ(h.bary, (float3{0.25f, 0.25f, 0.5f}));
  // From below: (0.75, 0.25) lies in T0; the normal turns toward the origin.
  h = q.Raycast({0.75f, 0.25f, -3}, {0, 0, 1});
  ASSERT_TRUE(h.found);
  EXPECT_EQ(h.triangle, 0u);
  EXPECT_FLOAT_EQ(h.t, 3.f);
  EXPECT_EQ(h.normal, (float3{0, 0, -1}));
  // Misses: beside the square, pointing away, no direction.
  EXPECT_FALSE(q.Raycast({2, 2, 5}, {0, 0, -1}).found);
  EXPECT_FALSE(q.Raycast({0.5f, 0.25f, 5}, {0, 0, 1}).found);
  EXPECT_FALSE(q.Raycast({0.5f, 0.25f, 5}, {0, 0, 0}).found);
}

TEST(SurfaceQuery, NearestPointOnAnEdgeAndOnTheFace) {
  const MeshData m = Square();
  const SurfaceQuery q(m);
  // (0.5, -1, 2): nearest is (0.5, 0, 0) on T0's edge, distance sqrt(1 + 4) = sqrt(5).
  SurfaceQuery::Hit h = q.Nearest({0.5f, -1, 2});
  ASSERT_TRUE(h.found);
  EXPECT_EQ(h.triangle, 0u);
  EXPECT_EQ(h.point, (float3{0.5f, 0, 0}));
  EXPECT_FLOAT_EQ(h.t, std::sqrt(5.f));
  EXPECT_EQ(h.normal, (float3{0, 0, 1}));
  // Over the face: straight down.
  h = q.Nearest({0.2f, 0.6f, -0.5f});
  ASSERT_TRUE(h.found);
  EXPECT_EQ(h.triangle, 1u);
  EXPECT_EQ(h.point, (float3{0.2f, 0.6f, 0}));
  EXPECT_FLOAT_EQ(h.t, 0.5f);
  // An empty mesh finds nothing.
  const MeshData empty;
  EXPECT_FALSE(SurfaceQuery(empty).Nearest({0, 0, 0}).found);
  EXPECT_FALSE(SurfaceQuery(empty).Raycast({0, 0, 1}, {0, 0, -1}).found);
}

TEST(SurfaceQuery, NormalAtInterpolatesVertexNormalsAcrossARidge) {
  // A roof, two slopes meeting at the ridge x = 1: the left one (0,0,0) (1,0,1) (1,1,1)
  // (0,1,0) rises along +x (face cross products (-1, 0, 1)), the right one (1,0,1) (2,0,0)
  // (2,1,0) (1,1,1) falls ((1, 0, 1)). Ridge vertex 1 sums (1, 0, 3), vertex 2 (-1, 0, 3):
  // halfway between them the interpolated normal is (0, 0, 1). At the left eave, halfway
  // between vertices 0 and 3 (left slope only), it is the slope's (-1, 0, 1) / sqrt 2.
  MeshData m;
  m.positions = {{0, 0, 0}, {1, 0, 1}, {1, 1, 1}, {0, 1, 0}, {2, 0, 0}, {2, 1, 0}};
  m.indices = {0, 1, 2, 0, 2, 3, 1, 4, 5, 1, 5, 2};
  const SurfaceQuery q(m);
  const float3 ridge = q.NormalAt(0, {1, 0.5f, 1});
  EXPECT_NEAR(ridge.x, 0.f, 1e-6f);
  EXPECT_NEAR(ridge.z, 1.f, 1e-6f);
  const float3 eave = q.NormalAt(1, {0, 0.5f, 0});  // on the left slope's outer edge
  EXPECT_NEAR(eave.x, -std::sqrt(0.5f), 1e-6f);
  EXPECT_NEAR(eave.z, std::sqrt(0.5f), 1e-6f);
}

}  // namespace
}  // namespace mimetic

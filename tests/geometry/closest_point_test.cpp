// Tests for geometry/closest_point.h: one query in each of the seven Voronoi regions of the
// triangle a = (0,0,0), b = (2,0,0), c = (0,2,0), answers worked out by hand.
#include <gtest/gtest.h>

#include "geometry/closest_point.h"

namespace mimetic {
namespace {

struct Case {
  const char* region;
  float3 p;
  float3 expected;
  float3 bary;
};

TEST(ClosestPoint, EveryVoronoiRegion) {
  const float3 a{0, 0, 0}, b{2, 0, 0}, c{0, 2, 0};
  const Case cases[] = {
      {"vertex a", {-1, -1, 0}, {0, 0, 0}, {1, 0, 0}},
      {"vertex b", {3, -1, 0}, {2, 0, 0}, {0, 1, 0}},
      {"vertex c", {-1, 3, 5}, {0, 2, 0}, {0, 0, 1}},
      // Below ab: the foot of the perpendicular, halfway along it.
      {"edge ab", {1, -1, 3}, {1, 0, 0}, {0.5f, 0.5f, 0}},
      {"edge ac", {-1, 1, 0}, {0, 1, 0}, {0.5f, 0, 0.5f}},
      // Beyond the hypotenuse: (2,2) projects to its midpoint (1,1).
      {"edge bc", {2, 2, 0}, {1, 1, 0}, {0, 0.5f, 0.5f}},
      // Above the face: straight down; (0.5, 0.5) = a + 0.25 (b - a) + 0.25 (c - a).
      {"face", {0.5f, 0.5f, 7}, {0.5f, 0.5f, 0}, {0.5f, 0.25f, 0.25f}},
  };
  for (const Case& k : cases) {
    float3 bary;
    EXPECT_EQ(ClosestPointOnTriangle(k.p, a, b, c, &bary), k.expected) << k.region;
    EXPECT_EQ(bary, k.bary) << k.region;
    // The double version agrees.
    const double p[3] = {k.p.x, k.p.y, k.p.z}, da[3] = {0, 0, 0}, db[3] = {2, 0, 0},
                 dc[3] = {0, 2, 0};
    const TrianglePoint r = ClosestPointOnTriangle(p, da, db, dc);
    EXPECT_EQ(r.point[0], k.expected.x) << k.region;
    EXPECT_EQ(r.point[1], k.expected.y) << k.region;
    EXPECT_EQ(r.point[2], k.expected.z) << k.region;
    EXPECT_EQ(r.bary[0] + r.bary[1] + r.bary[2], 1.0) << k.region;
  }
  // A point on the triangle is its own closest point.
  EXPECT_EQ(ClosestPointOnTriangle(float3{0.5f, 1, 0}, a, b, c), (float3{0.5f, 1, 0}));
}

}  // namespace
}  // namespace mimetic

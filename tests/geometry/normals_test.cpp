// Tests for geometry/normals.h: a right triangle's cross product, area and normal, and
// area-weighted vertex normals on a fold, with and without a seam shared by position. Every
// expected number is worked out by hand in the comments.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "geometry/normals.h"

namespace mimetic {
namespace {

TEST(Normals, RightTriangleCrossAreaAndNormal) {
  // Legs 3 (along x) and 4 (along y): (3,0,0) x (0,4,0) = (0, 0, 12), area 3 * 4 / 2 = 6.
  const float3 a{0, 0, 0}, b{3, 0, 0}, c{0, 4, 0};
  double n[3];
  TriangleCross(a, b, c, n);
  EXPECT_EQ(n[0], 0.0);
  EXPECT_EQ(n[1], 0.0);
  EXPECT_EQ(n[2], 12.0);
  EXPECT_EQ(TriangleArea(a, b, c), 6.0);
  EXPECT_EQ(TriangleNormal(a, b, c, {}), (float3{0, 0, 1}));
  // Clockwise seen from +z: the normal flips, the area does not.
  EXPECT_EQ(TriangleNormal(a, c, b, {}), (float3{0, 0, -1}));
  EXPECT_EQ(TriangleArea(a, c, b), 6.0);
  // Collinear corners: area 0, the fallback.
  EXPECT_EQ(TriangleArea(a, b, {6, 0, 0}), 0.0);
  EXPECT_EQ(TriangleNormal(a, b, {6, 0, 0}, {1, 2, 3}), (float3{1, 2, 3}));
}

// T0 = (p0, p1, p2) in z = 0: cross (1,0,0) x (0,1,0) = (0, 0, 1) (area 1/2).
// T1 = (p0', p3, p1) in y = 0: cross (0,0,2) x (1,0,0) = (0, 2, 0) (area 1), where p0' is
// vertex 4, a copy of p0 (a seam) or p0 itself.
MeshData Fold(bool seam) {
  MeshData m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 2}, {0, 0, 0}, {5, 5, 5}};
  m.indices = {0, 1, 2, seam ? 4u : 0u, 3, 1};
  return m;
}

TEST(Normals, AreaWeightedOnAFold) {
  const std::vector<float3> n = ComputeVertexNormals(Fold(false));
  ASSERT_EQ(n.size(), 6u);
  // p0 and p1 are in both: (0, 2, 1) / sqrt(5), the larger triangle weighing twice as much.
  const float s = 1.f / std::sqrt(5.f);
  for (int v : {0, 1}) {
    EXPECT_EQ(n[v].x, 0.f) << v;
    EXPECT_NEAR(n[v].y, 2 * s, 1e-7f) << v;
    EXPECT_NEAR(n[v].z, s, 1e-7f) << v;
  }
  EXPECT_EQ(n[2], (float3{0, 0, 1}));  // T0 only
  EXPECT_EQ(n[3], (float3{0, 1, 0}));  // T1 only
  EXPECT_EQ(n[4], (float3{0, 0, 1}));  // unused: the fallback (+z by default)
  EXPECT_EQ(n[5], (float3{0, 0, 1}));
}

TEST(Normals, SeamSharedByPositionOrNot) {
  const MeshData m = Fold(true);
  // Split: p0 sees T0 only, its copy (vertex 4) T1 only.
  const std::vector<float3> split = ComputeVertexNormals(m);
  EXPECT_EQ(split[0], (float3{0, 0, 1}));
  EXPECT_EQ(split[4], (float3{0, 1, 0}));
  // Shared: both get (0, 2, 1) / sqrt(5), as without the seam; bit for bit the same.
  VertexNormalOptions o;
  o.share_by_position = true;
  o.fallback = {0, -1, 0};
  const std::vector<float3> shared = ComputeVertexNormals(m, o);
  const std::vector<float3> welded = ComputeVertexNormals(Fold(false), o);
  EXPECT_EQ(shared[0], welded[0]);
  EXPECT_EQ(shared[4], welded[0]);
  EXPECT_EQ(shared[1], welded[1]);
  EXPECT_EQ(shared[5], (float3{0, -1, 0}));  // unused: the given fallback
}

TEST(Normals, OutOfRangeTrianglesAndPartialTrianglesAreSkipped) {
  const std::vector<float3> p = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  const std::vector<uint32_t> idx = {0, 1, 2, 0, 9, 1, 2, 1};  // valid, out of range, partial
  const std::vector<float3> n = ComputeVertexNormals(p, idx, {});
  for (const float3& v : n) EXPECT_EQ(v, (float3{0, 0, 1}));
  EXPECT_TRUE(ComputeVertexNormals(MeshData{}).empty());
}

}  // namespace
}  // namespace mimetic

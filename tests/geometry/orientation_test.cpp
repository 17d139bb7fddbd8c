// Tests for geometry/orientation.h: consistent winding on grids, a closed box, two separate
// pieces and a Moebius strip, with the flips worked out by hand.
#include <gtest/gtest.h>

#include <cmath>
#include <utility>
#include <vector>

#include "core/math.h"
#include "geometry/mesh.h"
#include "geometry/orientation.h"
#include "geometry/topology.h"

namespace mimetic {
namespace {

// n x n quads in the plane z = 0, point j * (n + 1) + i at (i, j); quad (a, b, c, d) split
// into (a, b, c) and (a, c, d), both counter-clockwise seen from +z.
MeshData Grid(uint32_t n) {
  MeshData m;
  m.source = "grid.obj";
  for (uint32_t j = 0; j <= n; ++j)
    for (uint32_t i = 0; i <= n; ++i) m.positions.push_back({float(i), float(j), 0.f});
  for (uint32_t j = 0; j < n; ++j)
    for (uint32_t i = 0; i < n; ++i) {
      const uint32_t a = j * (n + 1) + i, b = a + 1, c = a + n + 2, d = a + n + 1;
      m.indices.insert(m.indices.end(), {a, b, c, a, c, d});
    }
  return m;
}

void Reverse(std::vector<uint32_t>* indices, size_t t) {
  std::swap((*indices)[3 * t + 1], (*indices)[3 * t + 2]);
}

OrientationResult Orient(const std::vector<uint32_t>& tris) {
  EdgeTable edges;
  BuildEdgeTable(tris, &edges);
  return OrientTriangles(tris, edges);
}

// z of each triangle's normal (the grid lies in z = 0).
std::vector<float> NormalZ(const MeshData& m, const std::vector<uint32_t>& indices) {
  std::vector<float> z;
  for (size_t t = 0; t < indices.size() / 3; ++t) {
    const float3 a = m.positions[indices[3 * t]], b = m.positions[indices[3 * t + 1]],
                 c = m.positions[indices[3 * t + 2]];
    z.push_back(Cross(b - a, c - a).z);
  }
  return z;
}

TEST(Orientation, ConsistentGridNeedsNoFlip) {
  const OrientationResult r = Orient(Grid(4).indices);
  EXPECT_TRUE(r.orientable);
  EXPECT_EQ(r.components, 1u);
  EXPECT_EQ(r.flipped, 0u);
  EXPECT_EQ(r.flip, std::vector<uint8_t>(32, 0));
}

TEST(Orientation, AFewReversedTrianglesAreTheOnesToFlip) {
  std::vector<uint32_t> tris = Grid(4).indices;  // 32 triangles
  for (size_t t : {3u, 10u, 31u}) Reverse(&tris, t);
  const OrientationResult r = Orient(tris);
  EXPECT_TRUE(r.orientable);
  EXPECT_EQ(r.flipped, 3u);
  for (size_t t = 0; t < 32; ++t) EXPECT_EQ(r.flip[t], t == 3 || t == 10 || t == 31) << t;
}

TEST(Orientation, MajorityWinsEvenWhenTriangleZeroIsTheOddOne) {
  std::vector<uint32_t> tris = Grid(4).indices;
  Reverse(&tris, 0);
  const OrientationResult r = Orient(tris);
  EXPECT_EQ(r.flipped, 1u);
  EXPECT_EQ(r.flip[0], 1);
}

TEST(Orientation, EveryOtherTriangleReversed) {
  // The mesh: 16 of 32 reversed, a tie: triangle 0's winding (the unreversed) is kept.
  std::vector<uint32_t> tris = Grid(4).indices;
  for (size_t t = 1; t < 32; t += 2) Reverse(&tris, t);
  const OrientationResult r = Orient(tris);
  EXPECT_TRUE(r.orientable);
  EXPECT_EQ(r.flipped, 16u);
  for (size_t t = 0; t < 32; ++t) EXPECT_EQ(r.flip[t], t % 2) << t;
}

TEST(Orientation, SeparatePiecesKeepTheirOwnMajority) {
  // Two grids sharing no point; the second wholly reversed except its triangle 5: that one is
  // the only flip there (a piece is never compared with another).
  std::vector<uint32_t> tris = Grid(2).indices;  // 8 triangles on points 0..8
  std::vector<uint32_t> second = Grid(2).indices;
  for (uint32_t& i : second) i += 9;
  for (size_t t = 0; t < 8; ++t)
    if (t != 5) Reverse(&second, t);
  tris.insert(tris.end(), second.begin(), second.end());
  const OrientationResult r = Orient(tris);
  EXPECT_EQ(r.components, 2u);
  EXPECT_EQ(r.flipped, 1u);
  EXPECT_EQ(r.flip[8 + 5], 1);
}

TEST(Orientation, ClosedBoxIsConsistent) {
  // The 12 triangles of a cube, all counter-clockwise seen from outside; then 5 reversed.
  const std::vector<uint32_t> box = {0, 2, 1, 0, 3, 2, 4, 5, 6, 4, 6, 7, 0, 1, 5, 0, 5, 4,
                                     1, 2, 6, 1, 6, 5, 2, 3, 7, 2, 7, 6, 3, 0, 4, 3, 4, 7};
  EXPECT_EQ(Orient(box).flipped, 0u);
  std::vector<uint32_t> bad = box;
  for (size_t t : {1u, 4u, 6u, 9u, 11u}) Reverse(&bad, t);
  const OrientationResult r = Orient(bad);
  EXPECT_TRUE(r.orientable);
  EXPECT_EQ(r.flipped, 5u);
  for (size_t t : {1u, 4u, 6u, 9u, 11u}) EXPECT_EQ(r.flip[t], 1) << t;
}

// A strip of 6 quads whose ends are joined with a half twist: top point a_i = i, bottom b_i =
// 6 + i; quad i is (a_i, b_i, b_i+1, a_i+1), and the last joins (a_5, b_5) to (b_0, a_0).
std::vector<uint32_t> Moebius() {
  std::vector<uint32_t> t;
  for (uint32_t i = 0; i < 6; ++i) {
    const uint32_t p = i, q = 6 + i;
    const uint32_t r = i < 5 ? 6 + i + 1 : 0, s = i < 5 ? i + 1 : 6;  // the twist
    t.insert(t.end(), {p, q, r, p, r, s});
  }
  return t;
}

TEST(Orientation, MoebiusStripIsNotOrientable) {
  const OrientationResult r = Orient(Moebius());
  EXPECT_FALSE(r.orientable);
  EXPECT_EQ(r.components, 1u);
  // Without the twist (the last quad back to a_0, b_0) the same strip is an orientable ring.
  const std::vector<uint32_t> fixed_ring = {0, 6, 7, 0, 7, 1, 1, 7, 8, 1, 8, 2, 2, 8, 9,
                                            2, 9, 3, 3, 9, 10, 3, 10, 4, 4, 10, 11, 4, 11, 5,
                                            5, 11, 6, 5, 6, 0};
  const OrientationResult ok = Orient(fixed_ring);
  EXPECT_TRUE(ok.orientable);
  EXPECT_EQ(ok.flipped, 0u);
}

TEST(Orientation, MakeWindingConsistentReversesTheMinorityAndWarns) {
  MeshData m = Grid(4);
  for (size_t t : {3u, 10u, 31u}) Reverse(&m.indices, t);
  Diagnostics diag;
  std::vector<uint32_t> fixed;
  ASSERT_TRUE(MakeWindingConsistent(m, 0.f, m.source, &fixed, &diag));
  EXPECT_FALSE(diag.HasErrors());
  ASSERT_EQ(diag.items().size(), 1u);
  EXPECT_EQ(diag.items()[0].severity, Severity::kWarning);
  EXPECT_EQ(diag.items()[0].where, "grid.obj");
  EXPECT_EQ(diag.items()[0].what.rfind("3 of 32 triangles (9.4%) were wound against their "
                                       "neighbours (first: triangle 3); reversed them",
                                       0),
            0u)
      << diag.Format();
  ASSERT_EQ(fixed.size(), m.indices.size());
  for (float z : NormalZ(m, fixed)) EXPECT_GT(z, 0.f);
  // A consistent mesh: nothing to change, nothing said.
  Diagnostics quiet;
  ASSERT_TRUE(MakeWindingConsistent(Grid(4), 0.f, "grid.obj", &fixed, &quiet));
  EXPECT_TRUE(fixed.empty());
  EXPECT_TRUE(quiet.empty());
}

TEST(Orientation, MakeWindingConsistentRefusesAMoebiusStrip) {
  MeshData m;
  m.source = "strip.obj";
  for (int i = 0; i < 6; ++i) {
    const float a = float(i) * kPi / 3.f;  // around a circle; the twist turns the strip over
    m.positions.push_back({3.f * std::cos(a), 3.f * std::sin(a), 1.f});
  }
  for (int i = 0; i < 6; ++i) {
    const float a = float(i) * kPi / 3.f;
    m.positions.push_back({4.f * std::cos(a), 4.f * std::sin(a), -1.f});
  }
  m.indices = Moebius();
  Diagnostics diag;
  std::vector<uint32_t> fixed;
  EXPECT_FALSE(MakeWindingConsistent(m, 0.f, m.source, &fixed, &diag));
  ASSERT_TRUE(diag.HasErrors());
  EXPECT_TRUE(diag.Contains("strip.obj")) << diag.Format();
  EXPECT_TRUE(diag.Contains("the surface is not orientable")) << diag.Format();
  EXPECT_TRUE(diag.Contains("Moebius strip")) << diag.Format();
}

}  // namespace
}  // namespace mimetic

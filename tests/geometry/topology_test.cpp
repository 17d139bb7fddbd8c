// Tests for geometry/topology.h on a 2 x 2 grid of quads (3 x 3 points, point j * 3 + i at
// (i, j)), each quad (a, b, c, d) = ((i,j), (i+1,j), (i+1,j+1), (i,j+1)) split into
// (a, b, c) and (a, c, d):
//   6 7 8
//   3 4 5      triangles 0-1 in the lower left quad, 2-3 lower right, 4-5 upper left,
//   0 1 2      6-7 upper right.
// Every table below is worked out by hand.
#include <gtest/gtest.h>

#include <vector>

#include "geometry/topology.h"

namespace mimetic {
namespace {

std::vector<uint32_t> Grid2x2() {
  std::vector<uint32_t> t;
  for (uint32_t j = 0; j < 2; ++j) {
    for (uint32_t i = 0; i < 2; ++i) {
      const uint32_t a = j * 3 + i, b = a + 1, c = a + 4, d = a + 3;
      t.insert(t.end(), {a, b, c, a, c, d});
    }
  }
  return t;
}

std::vector<uint32_t> Row(const CsrTable& t, uint32_t r) {
  return {t.items.begin() + t.offsets[r], t.items.begin() + t.offsets[r + 1]};
}

TEST(Topology, PointNeighborsOfA2x2Grid) {
  const CsrTable n = BuildPointNeighbors(Grid2x2(), 9);
  ASSERT_EQ(n.offsets.size(), 10u);
  const std::vector<std::vector<uint32_t>> expected = {
      {1, 3, 4}, {0, 2, 4, 5}, {1, 5}, {0, 4, 6, 7}, {0, 1, 3, 5, 7, 8},
      {1, 2, 4, 8}, {3, 7}, {3, 4, 6, 8}, {4, 5, 7}};
  for (uint32_t p = 0; p < 9; ++p) EXPECT_EQ(Row(n, p), expected[p]) << p;
  EXPECT_EQ(n.items.size(), 32u);  // 16 edges (12 grid edges, 4 diagonals), both ways
}

TEST(Topology, PointTrianglesOfA2x2Grid) {
  const CsrTable t = BuildPointTriangles(Grid2x2(), 9);
  EXPECT_EQ(Row(t, 0), (std::vector<uint32_t>{0, 1}));
  EXPECT_EQ(Row(t, 2), (std::vector<uint32_t>{2}));
  EXPECT_EQ(Row(t, 4), (std::vector<uint32_t>{0, 1, 3, 4, 6, 7}));
  EXPECT_EQ(Row(t, 8), (std::vector<uint32_t>{6, 7}));
  EXPECT_EQ(t.items.size(), 24u);
  // Out-of-range indices are skipped.
  EXPECT_EQ(BuildPointTriangles(std::vector<uint32_t>{0, 1, 7}, 2).items.size(), 2u);
}

TEST(Topology, EdgesBoundaryAndNonManifold) {
  std::vector<uint32_t> tris = Grid2x2();
  EdgeTable et;
  BuildEdgeTable(tris, &et);
  ASSERT_EQ(et.edge_count(), 16u);
  // Keys ascending: point 0's edges (0,1), (0,3), (0,4) come first.
  EXPECT_EQ(et.keys[0], EdgeKey(1, 0));
  EXPECT_EQ(EdgeKeyLow(et.keys[1]), 0u);
  EXPECT_EQ(EdgeKeyHigh(et.keys[1]), 3u);
  EXPECT_EQ(et.tri_edge[0], 0u);  // triangle 0's corner 0: edge (0, 1)
  // The diagonal (0, 4) is shared by triangles 0 and 1.
  const uint32_t diag = et.tri_edge[2];  // triangle 0, corner 2: (4, 0)
  EXPECT_EQ(et.keys[diag], EdgeKey(0, 4));
  ASSERT_EQ(et.use_count(diag), 2u);
  EXPECT_EQ(et.corners[et.start[diag]] / 3, 0u);
  EXPECT_EQ(et.corners[et.start[diag] + 1] / 3, 1u);
  // The outline: 8 boundary edges; nothing non-manifold.
  EXPECT_EQ(BoundaryEdges(et).size(), 8u);
  EXPECT_TRUE(NonManifoldEdges(et).empty());
  // Two fins on the edge (0, 1) make it non-manifold (3 uses); a triangle using a point
  // twice adds no edge.
  tris.insert(tris.end(), {0, 1, 9, 1, 0, 10, 2, 2, 5});
  BuildEdgeTable(tris, &et);
  const std::vector<uint32_t> bad = NonManifoldEdges(et);
  ASSERT_EQ(bad.size(), 1u);
  EXPECT_EQ(et.keys[bad[0]], EdgeKey(0, 1));
  EXPECT_EQ(et.use_count(bad[0]), 3u);
  EXPECT_EQ(et.tri_edge[3 * 10], EdgeTable::kNoEdge);
  EXPECT_EQ(et.edge_count(), 16u + 4u);  // (0,9) (1,9) (0,10) (1,10)
}

}  // namespace
}  // namespace mimetic

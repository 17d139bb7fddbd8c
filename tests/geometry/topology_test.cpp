// Tests for geometry/topology.h on a 2 x 2 grid of quads (3 x 3 points, point j * 3 + i at
// (i, j)), each quad (a, b, c, d) = ((i,j), (i+1,j), (i+1,j+1), (i,j+1)) split into
// (a, b, c) and (a, c, d):
//   6 7 8
//   3 4 5      triangles 0-1 in the lower left quad, 2-3 lower right, 4-5 upper left,
//   0 1 2      6-7 upper right.
// Every table below is worked out by hand.
#include <gtest/gtest.h>

#include <utility>

#include <algorithm>

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

// Against the plain definition (every (key, corner) pair sorted at once) on random soups with
// degenerate, repeated and non-manifold triangles, dense and sparse indices.
TEST(Topology, EdgeTableEqualsOneSortOfEveryCorner) {
  uint64_t state = 12345;
  auto next = [&](uint32_t n) {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return uint32_t((state >> 33) % n);
  };
  for (uint32_t points : {5u, 60u, 4000u, 4000000000u}) {
    std::vector<uint32_t> tris;
    for (int t = 0; t < 900; ++t)
      for (int k = 0; k < 3; ++k) tris.push_back(points > 1e6 ? next(7) * 500000000u : next(points));
    EdgeTable et;
    BuildEdgeTable(tris, &et);
    std::vector<std::pair<uint64_t, uint32_t>> uses;
    for (uint32_t t = 0; t < tris.size(); t += 3) {
      const uint32_t* v = &tris[t];
      if (v[0] == v[1] || v[1] == v[2] || v[0] == v[2]) continue;
      for (uint32_t k = 0; k < 3; ++k) uses.push_back({EdgeKey(v[k], v[(k + 1) % 3]), t + k});
    }
    std::sort(uses.begin(), uses.end());
    ASSERT_EQ(et.corners.size(), uses.size()) << points;
    size_t edges = 0;
    for (size_t i = 0; i < uses.size(); ++i) {
      if (i == 0 || uses[i].first != uses[i - 1].first) {
        ASSERT_EQ(et.keys[edges], uses[i].first);
        ASSERT_EQ(et.start[edges], i);
        ++edges;
      }
      EXPECT_EQ(et.corners[i], uses[i].second);
      EXPECT_EQ(et.tri_edge[uses[i].second], edges - 1);
    }
    EXPECT_EQ(et.keys.size(), edges);
    EXPECT_EQ(et.start.back(), uses.size());
  }
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

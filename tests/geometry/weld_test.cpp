// Tests for WeldMesh (geometry/weld.h): point counts computed by hand, determinism,
// tolerance, the grid search across cell borders, topology errors and their caps, speed, and
// the shared face datasets when ../shared is present.
#include <gtest/gtest.h>

#include <cmath>
#include <algorithm>
#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "core/diagnostics.h"
#include "geometry/mesh.h"
#include "geometry/weld.h"

namespace mimetic {
namespace {

// An n x n grid of points (spacing 1, z = 0) whose column `seam` is duplicated: quads right of
// the seam use the duplicates. File vertices: n*n + n; welded points: n*n;
// triangles: 2 (n-1)^2.
MeshData SeamGrid(int n, int seam) {
  MeshData m;
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      m.positions.push_back({static_cast<float>(i), static_cast<float>(j), 0.f});
    }
  }
  const uint32_t dup0 = static_cast<uint32_t>(n * n);
  for (int j = 0; j < n; ++j) m.positions.push_back({static_cast<float>(seam), static_cast<float>(j), 0.f});
  auto vid = [&](int i, int j, bool right_of_seam) {
    if (i == seam && right_of_seam) return dup0 + static_cast<uint32_t>(j);
    return static_cast<uint32_t>(j * n + i);
  };
  for (int j = 0; j + 1 < n; ++j) {
    for (int i = 0; i + 1 < n; ++i) {
      const bool right = i >= seam;
      const uint32_t a = vid(i, j, right), b = vid(i + 1, j, right),
                     c = vid(i + 1, j + 1, right), d = vid(i, j + 1, right);
      m.indices.insert(m.indices.end(), {a, b, c, a, c, d});
    }
  }
  return m;
}

TEST(Weld, SmallSeamGridByHand) {
  const MeshData m = SeamGrid(3, 1);
  ASSERT_EQ(m.vertex_count(), 12u);
  WeldedMesh w;
  Diagnostics diag;
  ASSERT_TRUE(WeldMesh(m, 0.f, &w, &diag)) << diag.Format();
  EXPECT_TRUE(diag.empty());
  EXPECT_EQ(w.points.size(), 9u);
  const std::vector<uint32_t> pov = {0, 1, 2, 3, 4, 5, 6, 7, 8, 1, 4, 7};
  EXPECT_EQ(w.point_of_vertex, pov);
  const std::vector<uint32_t> tris = {0, 1, 4, 0, 4, 3, 1, 2, 5, 1, 5, 4,
                                      3, 4, 7, 3, 7, 6, 4, 5, 8, 4, 8, 7};
  EXPECT_EQ(w.triangles, tris);
  // A point keeps its first vertex's position.
  EXPECT_EQ(w.points[4], (float3{1.f, 1.f, 0.f}));
}

TEST(Weld, PointsInFirstOccurrenceOrderAndDeterministic) {
  // Vertices A, B, A', C, B' (primes are within tolerance): points A, B, C.
  MeshData m;
  m.positions = {{0, 0, 0}, {1, 0, 0}, {1e-7f, 0, 0}, {0, 1, 0}, {1, 0, 5e-8f}};
  m.indices = {0, 1, 3, 2, 3, 4};  // the same triangle A B C twice, once via A' and B'
  WeldedMesh w1, w2;
  Diagnostics diag;
  ASSERT_TRUE(WeldMesh(m, 1e-6f, &w1, &diag)) << diag.Format();
  ASSERT_TRUE(WeldMesh(m, 1e-6f, &w2, &diag)) << diag.Format();
  const std::vector<uint32_t> pov = {0, 1, 0, 2, 1};
  EXPECT_EQ(w1.point_of_vertex, pov);
  ASSERT_EQ(w1.points.size(), 3u);
  EXPECT_EQ(w1.points[0], (float3{0, 0, 0}));
  EXPECT_EQ(w1.points[1], (float3{1, 0, 0}));
  EXPECT_EQ(w1.points[2], (float3{0, 1, 0}));
  EXPECT_EQ(w1.point_of_vertex, w2.point_of_vertex);
  EXPECT_EQ(w1.triangles, w2.triangles);
  // Reversed vertex order: points follow the new first occurrences (B', C, A', B, A).
  MeshData r;
  r.positions.assign(m.positions.rbegin(), m.positions.rend());
  r.indices = {4, 3, 1, 2, 1, 0};
  WeldedMesh wr;
  ASSERT_TRUE(WeldMesh(r, 1e-6f, &wr, &diag)) << diag.Format();
  const std::vector<uint32_t> pov_r = {0, 1, 2, 0, 2};
  EXPECT_EQ(wr.point_of_vertex, pov_r);
  EXPECT_EQ(wr.points[0], (float3{1, 0, 5e-8f}));
}

TEST(Weld, DefaultToleranceIsOneMillionthOfTheDiagonal) {
  // Bounding box (0,0,0)-(3,4,0): diagonal 5, default tolerance 5e-6.
  MeshData m;
  m.positions = {{0, 0, 0}, {3, 0, 0}, {3, 4, 0}, {1, 1, 0}, {1 + 4e-6f, 1, 0},
                 {2, 2, 0}, {2 + 6e-6f, 2, 0}};
  m.indices = {0, 1, 2};
  WeldedMesh w;
  Diagnostics diag;
  ASSERT_TRUE(WeldMesh(m, 0.f, &w, &diag)) << diag.Format();
  EXPECT_EQ(w.points.size(), 6u);  // 4e-6 apart welds, 6e-6 apart does not
  EXPECT_EQ(w.point_of_vertex[4], 3u);
  EXPECT_EQ(w.point_of_vertex[6], 5u);
  // An explicit tolerance of 1e-5 welds both pairs; negative means default again.
  ASSERT_TRUE(WeldMesh(m, 1e-5f, &w, &diag));
  EXPECT_EQ(w.points.size(), 5u);
  ASSERT_TRUE(WeldMesh(m, -1.f, &w, &diag));
  EXPECT_EQ(w.points.size(), 6u);
}

TEST(Weld, WeldsClosePairsAnywhere) {
  // Pairs 0.002 apart straddling x = 0.1 and (y, z) = (0.3, 0.2), tolerance 0.1.
  MeshData m;
  m.positions = {{0, 0, 0}, {0.099f, 0.5f, 0.5f}, {0.101f, 0.5f, 0.5f},
                 {0.5f, 0.299f, 0.199f}, {0.5f, 0.301f, 0.201f}, {1, 1, 1}};
  m.indices = {0, 1, 5};
  WeldedMesh w;
  Diagnostics diag;
  ASSERT_TRUE(WeldMesh(m, 0.1f, &w, &diag)) << diag.Format();
  const std::vector<uint32_t> pov = {0, 1, 1, 2, 2, 3};
  EXPECT_EQ(w.point_of_vertex, pov);
}

// Second method: a brute-force O(n^2) weld with the documented rule (a vertex joins the
// lowest-numbered point whose position is within tolerance, else starts a new point) on a
// random cloud dense enough that many vertices sit near grid-cell faces.
TEST(Weld, MatchesBruteForceOnRandomCloud) {
  std::mt19937 rng(12345);
  std::uniform_real_distribution<float> unit(0.f, 1.f), jitter(-0.02f, 0.02f);
  const float tol = 0.05f;
  MeshData m;
  for (int b = 0; b < 1500; ++b) {
    const float3 p{unit(rng), unit(rng), unit(rng)};
    const int copies = 1 + static_cast<int>(rng() % 3);
    for (int k = 0; k < copies; ++k) {
      m.positions.push_back(k == 0 ? p : float3{p.x + jitter(rng), p.y + jitter(rng), p.z + jitter(rng)});
    }
  }
  std::shuffle(m.positions.begin(), m.positions.end(), rng);
  m.indices = {0, 1, 2};
  std::vector<float3> ref_points;
  std::vector<uint32_t> ref_pov;
  for (const float3& p : m.positions) {
    uint32_t best = UINT32_MAX;
    for (uint32_t q = 0; q < ref_points.size() && best == UINT32_MAX; ++q) {
      const double dx = double(ref_points[q].x) - p.x, dy = double(ref_points[q].y) - p.y,
                   dz = double(ref_points[q].z) - p.z;
      if (dx * dx + dy * dy + dz * dz <= double(tol) * double(tol)) best = q;
    }
    if (best == UINT32_MAX) {
      best = static_cast<uint32_t>(ref_points.size());
      ref_points.push_back(p);
    }
    ref_pov.push_back(best);
  }
  WeldedMesh w;
  Diagnostics diag;
  WeldMesh(m, tol, &w, &diag);  // triangle 0 may be degenerate; only the mapping matters
  EXPECT_EQ(w.points.size(), ref_points.size());
  EXPECT_EQ(w.point_of_vertex, ref_pov);
  EXPECT_LT(ref_points.size(), m.positions.size());  // the test really welds something
}

TEST(Weld, LargeSeamGridCountAndSpeed) {
  // 200 x 200 points, seam column 100 duplicated: 40,200 vertices weld to 40,000 points.
  const MeshData m = SeamGrid(200, 100);
  ASSERT_EQ(m.vertex_count(), 40200u);
  WeldedMesh w;
  Diagnostics diag;
  ASSERT_TRUE(WeldMesh(m, 0.f, &w, &diag)) << diag.Format();
  EXPECT_EQ(w.points.size(), 40000u);
  for (int j = 0; j < 200; ++j) {
    EXPECT_EQ(w.point_of_vertex[40000 + j], static_cast<uint32_t>(j * 200 + 100)) << j;
  }
  EXPECT_EQ(w.triangles.size(), 6u * 199 * 199);

  // ~100k vertices: 316 x 316 + 316 = 100,172 welds to the grid's points (a hang or an
  // O(n^2) search shows as the ctest timeout; its speed is not a unit test's business).
  const MeshData big = SeamGrid(316, 158);
  ASSERT_TRUE(WeldMesh(big, 0.f, &w, &diag)) << diag.Format();
  EXPECT_EQ(w.points.size(), 316u * 316u);
}

TEST(Weld, ErrorsAreCappedPerKind) {
  // 45 degenerate triangles (repeated index) and 25 non-manifold edges.
  MeshData m = SeamGrid(3, 1);
  for (int k = 0; k < 45; ++k) m.indices.insert(m.indices.end(), {0, 4, 4});
  for (int k = 0; k < 25; ++k) {
    // Fan of 3 triangles on the edge (k, k + 1000) of fresh points.
    const float x = static_cast<float>(k) * 10.f + 100.f;
    const uint32_t v = static_cast<uint32_t>(m.positions.size());
    m.positions.push_back({x, 0, 0});
    m.positions.push_back({x + 1, 0, 0});
    m.positions.push_back({x, 1, 0});
    m.positions.push_back({x, -1, 0});
    m.positions.push_back({x, 0, 1});
    m.indices.insert(m.indices.end(), {v, v + 1, v + 2, v + 1, v, v + 3, v, v + 1, v + 4});
  }
  WeldedMesh w;
  Diagnostics diag;
  EXPECT_FALSE(WeldMesh(m, 0.f, &w, &diag));
  // 20 + 1 lines for each kind.
  EXPECT_EQ(diag.ErrorCount(), 42u) << diag.Format();
  EXPECT_TRUE(diag.Contains("... and 25 more triangles with repeated points"));
  EXPECT_TRUE(diag.Contains("... and 5 more non-manifold edges"));
  // Triangle 8 is the first degenerate one; the first fan's edge is points (9, 10).
  EXPECT_TRUE(diag.Contains("triangle 8 (vertices 0, 4, 4)"));
  EXPECT_TRUE(diag.Contains("edge (points 9, 10)"));
}

TEST(Weld, BadInputDoesNotCrash) {
  Diagnostics diag;
  WeldedMesh w;
  MeshData m;
  m.source = "bad.glb";
  m.positions = {{0, 0, 0}, {1, 0, 0}, {0, std::numeric_limits<float>::quiet_NaN(), 0}};
  m.indices = {0, 1, 2, 0, 1, 7};
  EXPECT_FALSE(WeldMesh(m, 0.f, &w, &diag));
  EXPECT_NE(diag.Format().find("error: vertex 2: position is not finite"), std::string::npos)
      << diag.Format();
  EXPECT_TRUE(diag.Contains("index 7 out of range (mesh has 3 vertices)")) << diag.Format();

  // All vertices at one spot: a zero diagonal still welds (to one point) and reports.
  diag.Clear();
  m.positions = {{2, 2, 2}, {2, 2, 2}, {2, 2, 2}};
  m.indices = {0, 1, 2};
  EXPECT_FALSE(WeldMesh(m, 0.f, &w, &diag));
  EXPECT_EQ(w.points.size(), 1u);
  EXPECT_TRUE(diag.Contains("uses a point twice")) << diag.Format();

  diag.Clear();
  EXPECT_FALSE(WeldMesh(m, std::numeric_limits<float>::infinity(), &w, &diag));
  EXPECT_TRUE(diag.Contains("not finite"));
}

}  // namespace
}  // namespace mimetic

// tests/fitting/compare_test.cpp: CompareMeshes (fitting/compare.h) and `mimetic compare` on
// hand-built cases whose answers follow from elementary geometry: planes moved by known
// amounts, a plane slid within itself, concentric spheres.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "core/diagnostics.h"
#include "fitting/compare.h"
#include "io/mesh_io.h"
#include "test_support.h"

namespace mimetic {
namespace {

// An n x n grid of vertices over [0, size]^2 in the plane z, displaced by (dx, dy).
MeshData Plane(int n, float size, float z, float dx = 0.f, float dy = 0.f) {
  MeshData m;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      m.positions.push_back({size * float(i) / float(n - 1) + dx, size * float(j) / float(n - 1) + dy, z});
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      const uint32_t a = uint32_t(j * n + i), b = a + 1, c = a + uint32_t(n), d = c + 1;
      m.indices.insert(m.indices.end(), {a, b, d, a, d, c});
    }
  m.source = "plane";
  return m;
}

// An icosphere of radius r: the icosahedron split `levels` times, vertices pushed onto the
// sphere (a convex polyhedron inscribed in it).
MeshData Sphere(int levels, float r) {
  const float t = (1.f + std::sqrt(5.f)) / 2.f;
  std::vector<float3> p = {{-1, t, 0}, {1, t, 0}, {-1, -t, 0}, {1, -t, 0}, {0, -1, t}, {0, 1, t},
                           {0, -1, -t}, {0, 1, -t}, {t, 0, -1}, {t, 0, 1}, {-t, 0, -1}, {-t, 0, 1}};
  std::vector<uint32_t> f = {0, 11, 5, 0, 5, 1, 0, 1, 7, 0, 7, 10, 0, 10, 11, 1, 5, 9, 5, 11, 4,
                             11, 10, 2, 10, 7, 6, 7, 1, 8, 3, 9, 4, 3, 4, 2, 3, 2, 6, 3, 6, 8,
                             3, 8, 9, 4, 9, 5, 2, 4, 11, 6, 2, 10, 8, 6, 7, 9, 8, 1};
  for (float3& v : p) v = v / Length(v);
  for (int l = 0; l < levels; ++l) {
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> mid;
    auto midpoint = [&](uint32_t a, uint32_t b) {
      const auto key = std::make_pair(std::min(a, b), std::max(a, b));
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      const float3 m = (p[a] + p[b]) * 0.5f;
      p.push_back(m / Length(m));
      return mid[key] = uint32_t(p.size() - 1);
    };
    std::vector<uint32_t> g;
    for (size_t i = 0; i < f.size(); i += 3) {
      const uint32_t a = f[i], b = f[i + 1], c = f[i + 2];
      const uint32_t ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
      g.insert(g.end(), {a, ab, ca, b, bc, ab, c, ca, bc, ab, bc, ca});
    }
    f = g;
  }
  MeshData m;
  for (const float3& v : p) m.positions.push_back(v * r);
  m.indices = f;
  m.source = "sphere";
  return m;
}

TEST(Compare, PlanesMovedByKnownAmounts) {
  // Neutral at z = 0, the real shape B at z = 0.3, the rig A at z = 0.1.
  const MeshData n = Plane(11, 10.f, 0.f), b = Plane(11, 10.f, 0.3f), a = Plane(11, 10.f, 0.1f);
  CompareOptions o;
  o.neutral = &n;
  CompareResult r;
  Diagnostics diag;
  ASSERT_TRUE(CompareMeshes(a, b, o, &r, &diag)) << diag.Format();
  EXPECT_TRUE(r.same_topology);
  EXPECT_EQ(r.region_count, 121u);
  EXPECT_NEAR(r.b_to_a.mean, 0.2, 1e-6);
  EXPECT_NEAR(r.b_to_a.max, 0.2, 1e-6);
  EXPECT_NEAR(r.a_to_b.mean, 0.2, 1e-6);
  EXPECT_NEAR(r.b_to_neutral.mean, 0.3, 1e-6);
  EXPECT_NEAR(r.ratio, 0.2 / 0.3, 1e-5);
  EXPECT_NEAR(r.vertex_error.mean, 0.2, 1e-6);
  EXPECT_NEAR(r.direction_cosine, 1.0, 1e-9);       // both move along +z
  EXPECT_NEAR(r.magnitude_ratio, 0.1 / 0.3, 1e-5);  // the rig moves a third as far
  EXPECT_NEAR(r.mean_b_displacement, 0.3, 1e-6);
  // The rig moving the other way: cosine -1, still a third of the magnitude.
  const MeshData down = Plane(11, 10.f, -0.1f);
  ASSERT_TRUE(CompareMeshes(down, b, o, &r, &diag));
  EXPECT_NEAR(r.direction_cosine, -1.0, 1e-9);
  EXPECT_NEAR(r.b_to_a.mean, 0.4, 1e-6);
}

// The residual's split: on the flat neutral (normal +z) B stays at rest; A is off by
// (0.3, 0, 0.4) on the columns x < 5 (part 0, 55 vertices) and by (0, 0, 0.1) on the rest
// (part 1); the last vertex is left out of the region. By hand: |r|^2 = 0.25 and 0.01,
// (r . n)^2 = 0.16 and 0.01, so over 55 + 65 vertices the error is 13.75 + 0.65 = 14.40,
// of which 8.8 + 0.65 = 9.45 along the normal. Distances (given): 0.4 in part 0, 0.1 in
// part 1 and 7 on the left-out vertex, so part 0 holds 22 of 22 + 6.5.
TEST(Compare, TheResidualSplitsAlongTheNormalAndByPart) {
  const MeshData n = Plane(11, 10.f, 0.f), b = n;
  MeshData a = n;
  std::vector<uint8_t> parts(n.vertex_count()), region(n.vertex_count(), 1);
  std::vector<float> distance(n.vertex_count());
  for (size_t v = 0; v < a.vertex_count(); ++v) {
    parts[v] = a.positions[v].x < 4.5f ? 0 : 1;
    a.positions[v] += parts[v] == 0 ? float3{0.3f, 0.f, 0.4f} : float3{0.f, 0.f, 0.1f};
    distance[v] = parts[v] == 0 ? 0.4f : 0.1f;
  }
  region.back() = 0;
  distance.back() = 7.f;
  ResidualSplit split;
  Diagnostics diag;
  ASSERT_TRUE(SplitResidual(a, b, n, region, distance, parts, 2, &split, &diag)) << diag.Format();
  EXPECT_NEAR(split.normal_share, 9.45 / 14.40, 1e-6);
  ASSERT_EQ(split.part_share.size(), 2u);
  EXPECT_NEAR(split.part_share[0], 22.0 / 28.5, 1e-6);
  EXPECT_NEAR(split.part_share[1], 6.5 / 28.5, 1e-6);
  // No residual: every share 0.
  ASSERT_TRUE(SplitResidual(b, b, n, region, std::vector<float>(n.vertex_count(), 0.f), parts, 2,
                            &split, &diag));
  EXPECT_EQ(split.normal_share, 0.0);
  EXPECT_EQ(split.part_share[0], 0.0);
  // Bad inputs say what is wrong.
  const MeshData small = Plane(5, 10.f, 0.f);
  EXPECT_FALSE(SplitResidual(small, b, n, region, distance, parts, 2, &split, &diag));
  EXPECT_NE(diag.Format().find("25, 121 and 121 vertices"), std::string::npos) << diag.Format();
  diag.Clear();
  EXPECT_FALSE(SplitResidual(a, b, n, region, std::vector<float>(3), parts, 2, &split, &diag));
  EXPECT_NE(diag.Format().find("the distances 3"), std::string::npos) << diag.Format();
  diag.Clear();
  EXPECT_FALSE(SplitResidual(a, b, n, region, distance, parts, 1, &split, &diag));
  EXPECT_NE(diag.Format().find("has part 1, of 1"), std::string::npos) << diag.Format();
}

TEST(Compare, SlidingWithinThePlaneIsNoSurfaceDistanceButAVertexError) {
  // A slides 0.25 along x inside its own plane: B's interior vertices still lie on A's
  // surface (distance 0), but each vertex is 0.25 from where B has it.
  const MeshData b = Plane(11, 10.f, 0.f), a = Plane(11, 10.f, 0.f, 0.25f);
  CompareOptions o;
  o.neutral = &b;
  o.region.kind = CompareRegion::Kind::kVertices;
  for (int j = 1; j < 10; ++j)
    for (int i = 1; i < 10; ++i) o.region.vertices.push_back(uint32_t(j * 11 + i));
  CompareResult r;
  Diagnostics diag;
  ASSERT_TRUE(CompareMeshes(a, b, o, &r, &diag)) << diag.Format();
  EXPECT_EQ(r.region_count, 81u);
  EXPECT_NEAR(r.b_to_a.max, 0.0, 1e-6);
  EXPECT_NEAR(r.vertex_error.mean, 0.25, 1e-6);
  EXPECT_NEAR(r.vertex_error.max, 0.25, 1e-6);
  // B does not move from its neutral: the motion measures are 0 by definition.
  EXPECT_EQ(r.direction_cosine, 0.0);
  EXPECT_EQ(r.magnitude_ratio, 0.0);
  // The first column of B (x = 0) is 0.25 outside A's edge: with every vertex it shows up.
  o.region = {};
  ASSERT_TRUE(CompareMeshes(a, b, o, &r, &diag));
  EXPECT_NEAR(r.b_to_a.max, 0.25, 1e-6);
  EXPECT_NEAR(r.b_to_a.mean, 0.25 * 11.0 / 121.0, 1e-6);
}

TEST(Compare, ConcentricSpheres) {
  // B's vertices lie on radius 1.1, A is the polyhedron inscribed in the unit sphere. Each
  // vertex of B is radially outside a vertex of A, and for a convex polyhedron inscribed in a
  // sphere that vertex is the nearest point (every other vertex w has v . w <= 1), so B -> A
  // is exactly 0.1. A -> B: the unit vertex to B's faces lies between 1.1 c - 1 and 0.1,
  // c = the smallest distance from the centre to a face plane of the unit polyhedron.
  const MeshData a = Sphere(3, 1.f), b = Sphere(3, 1.1f);
  double c = 1.0;
  for (size_t i = 0; i < a.indices.size(); i += 3) {
    const float3 p = a.positions[a.indices[i]], q = a.positions[a.indices[i + 1]],
                 s = a.positions[a.indices[i + 2]];
    const float3 nrm = Cross(q - p, s - p);
    c = std::min(c, std::fabs(double(Dot(nrm, p))) / double(Length(nrm)));
  }
  CompareResult r;
  Diagnostics diag;
  ASSERT_TRUE(CompareMeshes(a, b, {}, &r, &diag)) << diag.Format();
  EXPECT_NEAR(r.b_to_a.mean, 0.1, 1e-5);
  EXPECT_NEAR(r.b_to_a.max, 0.1, 1e-5);
  EXPECT_GE(r.a_to_b.mean, 1.1 * c - 1.0 - 1e-6);
  EXPECT_LE(r.a_to_b.max, 0.1 + 1e-6);
  EXPECT_LT(r.a_to_b.mean, 0.1);  // strictly inside: the faces are nearer than the vertices
}

TEST(Compare, DifferentTopologyMeasuresSurfacesOnly) {
  // A coarse plane against a finer one 0.3 above: every distance is 0.3; no per-vertex measures.
  const MeshData a = Plane(5, 10.f, 0.f), b = Plane(17, 10.f, 0.3f), n = Plane(17, 10.f, 0.f);
  CompareOptions o;
  o.neutral = &n;
  CompareResult r;
  Diagnostics diag;
  ASSERT_TRUE(CompareMeshes(a, b, o, &r, &diag)) << diag.Format();
  EXPECT_FALSE(r.same_topology);
  EXPECT_FALSE(r.has_vertex_measures);
  EXPECT_NEAR(r.b_to_a.mean, 0.3, 1e-6);
  EXPECT_NEAR(r.a_to_b.mean, 0.3, 1e-6);
  EXPECT_EQ(r.a_to_b.count, 25u);
  EXPECT_NEAR(r.ratio, 1.0, 1e-5);  // A sits where the neutral is
}

TEST(Compare, MovedRegionPicksTheVerticesThatMove) {
  // B lifts the vertices with x > 5 by 1: moved:0.5 is exactly those (5 columns of 11).
  const MeshData n = Plane(11, 10.f, 0.f);
  MeshData b = n;
  for (float3& p : b.positions)
    if (p.x > 5.5f) p.z = 1.f;
  CompareOptions o;
  o.neutral = &n;
  o.region.kind = CompareRegion::Kind::kMoved;
  o.region.threshold = 0.5f;
  CompareResult r;
  Diagnostics diag;
  ASSERT_TRUE(CompareMeshes(b, b, o, &r, &diag)) << diag.Format();
  EXPECT_EQ(r.region_count, 55u);
  EXPECT_EQ(r.b_to_a.max, 0.0);
  EXPECT_NEAR(r.direction_cosine, 1.0, 1e-12);
  EXPECT_NEAR(r.magnitude_ratio, 1.0, 1e-12);
}

TEST(Compare, BadInputsSayWhatIsWrong) {
  const MeshData p = Plane(5, 1.f, 0.f), q = Plane(6, 1.f, 0.f);
  struct Case {
    const char* what;
    const MeshData* a;
    const MeshData* b;
    CompareOptions options;
    const char* message;
  };
  CompareOptions moved_without_neutral;
  moved_without_neutral.region.kind = CompareRegion::Kind::kMoved;
  CompareOptions wrong_neutral;
  wrong_neutral.neutral = &q;
  CompareOptions out_of_range;
  out_of_range.region.kind = CompareRegion::Kind::kVertices;
  out_of_range.region.vertices = {3, 25};
  CompareOptions empty_list;
  empty_list.region.kind = CompareRegion::Kind::kVertices;
  CompareOptions nothing_moves;
  nothing_moves.neutral = &p;
  nothing_moves.region.kind = CompareRegion::Kind::kMoved;
  nothing_moves.region.threshold = 0.1f;
  const MeshData empty;
  const std::vector<Case> cases = {
      {"moved without neutral", &p, &p, moved_without_neutral, "needs the neutral"},
      {"neutral of another mesh", &p, &p, wrong_neutral, "neutral: has 36 vertices, B has 25"},
      {"vertex out of range", &p, &p, out_of_range, "region[1]: vertex 25 is out of range; B has 25"},
      {"empty list", &p, &p, empty_list, "region: is empty"},
      {"nothing moves", &p, &p, nothing_moves, "no vertex of B moves more than 0.1"},
      {"empty A", &empty, &p, {}, "A: mesh '' has no vertices"},
  };
  for (const Case& c : cases) {
    CompareResult r;
    Diagnostics diag;
    EXPECT_FALSE(CompareMeshes(*c.a, *c.b, c.options, &r, &diag)) << c.what;
    EXPECT_NE(diag.Format().find(c.message), std::string::npos) << c.what << ": " << diag.Format();
  }
}

TEST(CompareTool, PrintsTheNumbersWritesJsonAndAHeatMap) {
  const std::string dir = test::TempDir();
  Diagnostics diag;
  ASSERT_TRUE(ExportMesh(dir + "/n.obj", Plane(11, 10.f, 0.f), &diag)) << diag.Format();
  ASSERT_TRUE(ExportMesh(dir + "/b.obj", Plane(11, 10.f, 0.3f), &diag));
  ASSERT_TRUE(ExportMesh(dir + "/a.obj", Plane(11, 10.f, 0.1f), &diag));
  test::ToolResult t = test::RunTool({"compare", dir + "/a.obj", dir + "/b.obj", "--neutral",
                                      dir + "/n.obj", "--json", dir + "/c.json", "--heatmap",
                                      dir + "/c.png", "--size", "64"});
  ASSERT_EQ(t.exit_code, 0) << t.output;
  EXPECT_NE(t.output.find("B -> A surface: mean 0.2, max 0.2"), std::string::npos) << t.output;
  EXPECT_NE(t.output.find("cosine 1.0000; magnitude 0.3333"), std::string::npos) << t.output;
  std::ifstream json(dir + "/c.json");
  const std::string text((std::istreambuf_iterator<char>(json)), {});
  EXPECT_NE(text.find("\"direction_cosine\": 1"), std::string::npos) << text;
  EXPECT_NE(text.find("\"region_count\": 121"), std::string::npos) << text;
  std::ifstream png(dir + "/c.png", std::ios::binary);
  std::string head(8, '\0');
  png.read(head.data(), 8);
  EXPECT_EQ(head, "\x89PNG\r\n\x1a\n");

  // A region file, then mistakes: exit 1 with the reason, 2 for usage.
  std::ofstream(dir + "/region.txt") << "# two vertices\n[12, 13]\n";
  t = test::RunTool({"compare", dir + "/a.obj", dir + "/b.obj", "--region", dir + "/region.txt"});
  EXPECT_EQ(t.exit_code, 0) << t.output;
  EXPECT_NE(t.output.find("region: 2 of B's vertices"), std::string::npos) << t.output;
  std::ofstream(dir + "/bad_region.txt") << "1 2\n3 x7\n";
  t = test::RunTool({"compare", dir + "/a.obj", dir + "/b.obj", "--region", dir + "/bad_region.txt"});
  EXPECT_EQ(t.exit_code, 1);
  EXPECT_NE(t.output.find("bad_region.txt:2: 'x7' is not a vertex index"), std::string::npos)
      << t.output;
  ASSERT_TRUE(ExportMesh(dir + "/small.obj", Plane(4, 1.f, 0.f), &diag));
  t = test::RunTool({"compare", dir + "/a.obj", dir + "/b.obj", "--neutral", dir + "/small.obj"});
  EXPECT_EQ(t.exit_code, 1);
  EXPECT_NE(t.output.find("neutral: has 16 vertices, B has 121"), std::string::npos) << t.output;
  t = test::RunTool({"compare", dir + "/a.obj", dir + "/missing.obj"});
  EXPECT_EQ(t.exit_code, 1);
  EXPECT_NE(t.output.find("missing.obj"), std::string::npos) << t.output;
  t = test::RunTool({"compare", dir + "/a.obj"});
  EXPECT_EQ(t.exit_code, 2);
  t = test::RunTool({"compare", dir + "/a.obj", dir + "/b.obj", "--region", "moved:-1"});
  EXPECT_EQ(t.exit_code, 2);
  t = test::RunTool({"compare", dir + "/a.obj", dir + "/b.obj", "--yaw", "30"});
  EXPECT_EQ(t.exit_code, 2);
  EXPECT_NE(t.output.find("--yaw goes with --heatmap"), std::string::npos) << t.output;
  t = test::RunTool({"compare", "--help"});
  EXPECT_EQ(t.exit_code, 0);
  EXPECT_NE(t.output.find("usage: mimetic compare A B"), std::string::npos);
}

}  // namespace
}  // namespace mimetic

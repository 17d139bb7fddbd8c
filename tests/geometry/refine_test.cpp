// Tests for RefineMesh (geometry/refine.h, docs/model.md §11). Expected values come from the
// construction of the inputs: a flat 20 x 20 grid (unit spacing, area 400, 80 boundary edges),
// the same grid with a UV seam, and an octahedron (closed: Euler characteristic 2). Bounds
// checked: edge length inside the support, untouched triangles far from it, exact welding at
// seams, area and orientation, the Rosenberg-Stenger angle bound of longest-edge bisection,
// attributes carried linearly, limits that stop with a warning, and bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "core/diagnostics.h"
#include "geometry/mesh.h"
#include "geometry/refine.h"
#include "geometry/weld.h"

namespace mimetic {
namespace {

constexpr float kInf = std::numeric_limits<float>::infinity();

// An n x n cell grid (vertices (i * s + ox, j * s + oy, 0), i, j in 0..n), normals +z, uv =
// (x / 20, y / 20). With seam >= 0 the vertices of column `seam` are duplicated and used by the
// quads right of it, whose vertices get u + 1 (a seam: same position, u jumps by 1).
// Vertices: (n+1)^2 (+ n+1 duplicates); triangles 2 n^2; boundary edges 4 n.
MeshData Grid(int n, int seam = -1, float s = 1.f, float ox = 0.f, float oy = 0.f) {
  MeshData m;
  auto pos = [&](int i, int j) { return float3{i * s + ox, j * s + oy, 0.f}; };
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) {
      const float3 p = pos(i, j);
      m.positions.push_back(p);
      m.normals.push_back({0, 0, 1});
      m.uvs.push_back({p.x / 20.f + (seam >= 0 && i > seam ? 1.f : 0.f), p.y / 20.f});
    }
  }
  const uint32_t dup0 = static_cast<uint32_t>(m.positions.size());
  if (seam >= 0) {
    for (int j = 0; j <= n; ++j) {
      const float3 p = pos(seam, j);
      m.positions.push_back(p);
      m.normals.push_back({0, 0, 1});
      m.uvs.push_back({p.x / 20.f + 1.f, p.y / 20.f});
    }
  }
  auto vid = [&](int i, int j, bool right) {
    if (i == seam && right) return dup0 + static_cast<uint32_t>(j);
    return static_cast<uint32_t>(j * (n + 1) + i);
  };
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      const bool right = seam >= 0 && i >= seam;
      const uint32_t a = vid(i, j, right), b = vid(i + 1, j, right),
                     c = vid(i + 1, j + 1, right), d = vid(i, j + 1, right);
      m.indices.insert(m.indices.end(), {a, b, c, a, c, d});
    }
  }
  return m;
}

double Dist2D(float3 p, double cx, double cy) { return std::hypot(p.x - cx, p.y - cy); }

double Edge(const MeshData& m, uint32_t a, uint32_t b) {
  const float3 p = m.positions[a], q = m.positions[b];
  return std::sqrt(double(p.x - q.x) * (p.x - q.x) + double(p.y - q.y) * (p.y - q.y) +
                   double(p.z - q.z) * (p.z - q.z));
}

// Signed area for flat (z = 0) meshes; unsigned for 3D ones.
double SignedAreaXY(const MeshData& m, size_t t) {
  const float3 a = m.positions[m.indices[3 * t]], b = m.positions[m.indices[3 * t + 1]],
               c = m.positions[m.indices[3 * t + 2]];
  return 0.5 * ((double(b.x) - a.x) * (double(c.y) - a.y) - (double(b.y) - a.y) * (double(c.x) - a.x));
}
double Area3D(const MeshData& m, size_t t) {
  const float3 a = m.positions[m.indices[3 * t]], b = m.positions[m.indices[3 * t + 1]],
               c = m.positions[m.indices[3 * t + 2]];
  const double u[3] = {double(b.x) - a.x, double(b.y) - a.y, double(b.z) - a.z};
  const double w[3] = {double(c.x) - a.x, double(c.y) - a.y, double(c.z) - a.z};
  const double n[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
  return 0.5 * std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
}

// Smallest interior angle of triangle t, in degrees.
double MinAngleDeg(const MeshData& m, size_t t) {
  const uint32_t* v = &m.indices[3 * t];
  const double a = Edge(m, v[1], v[2]), b = Edge(m, v[2], v[0]), c = Edge(m, v[0], v[1]);
  auto angle = [](double opp, double s1, double s2) {
    return std::acos(std::clamp((s1 * s1 + s2 * s2 - opp * opp) / (2 * s1 * s2), -1.0, 1.0));
  };
  return std::min({angle(a, b, c), angle(b, c, a), angle(c, a, b)}) * 180.0 / M_PI;
}

struct Topology {
  size_t points = 0, edges = 0, boundary_edges = 0, max_edge_use = 0;
};
Topology WeldedTopology(const WeldedMesh& w) {
  std::map<std::pair<uint32_t, uint32_t>, int> use;
  for (size_t t = 0; t < w.triangles.size() / 3; ++t) {
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = w.triangles[3 * t + k], b = w.triangles[3 * t + (k + 1) % 3];
      ++use[{std::min(a, b), std::max(a, b)}];
    }
  }
  Topology topo;
  topo.points = w.points.size();
  topo.edges = use.size();
  for (const auto& [edge, n] : use) {
    topo.boundary_edges += n == 1;
    topo.max_edge_use = std::max(topo.max_edge_use, size_t(n));
  }
  return topo;
}

// 0.3 inside the disc of radius 5 around (10, 10), no constraint outside.
float DiscField(float3 p, float2) { return Dist2D(p, 10, 10) < 5 ? 0.3f : kInf; }

TEST(Refine, DiscOnGridBoundsEdgesAndLeavesTheRestAlone) {
  const MeshData in = Grid(20);
  RefineResult r;
  Diagnostics diag;
  ASSERT_TRUE(RefineMesh(in, DiscField, {}, &r, &diag)) << diag.Format();
  EXPECT_TRUE(diag.empty()) << diag.Format();
  EXPECT_TRUE(r.bound_met);
  EXPECT_GE(r.passes, 1u);
  const MeshData& m = r.mesh;
  ASSERT_EQ(m.triangle_count(), r.triangle_origin.size());
  ASSERT_EQ(m.vertex_count(), r.parents.size());
  ASSERT_EQ(m.normals.size(), m.vertex_count());
  ASSERT_EQ(m.uvs.size(), m.vertex_count());
  EXPECT_EQ(r.input_vertex_count, in.vertex_count());

  // Input vertices keep their index and position.
  for (size_t v = 0; v < in.vertex_count(); ++v) {
    ASSERT_EQ(m.positions[v], in.positions[v]) << v;
    ASSERT_EQ(r.parents[v], std::make_pair(uint32_t(v), uint32_t(v)));
  }
  // Every output triangle touching the disc of radius 4 lies in the support: its centroid is
  // within 4 + (2/3) sqrt(2) < 5 because children are no larger than their parents.
  size_t inside = 0;
  double worst = 0;
  for (size_t t = 0; t < m.triangle_count(); ++t) {
    const uint32_t* v = &m.indices[3 * t];
    double centre = 1e9;
    for (int k = 0; k < 3; ++k) centre = std::min(centre, Dist2D(m.positions[v[k]], 10, 10));
    if (centre >= 4) continue;
    ++inside;
    for (int k = 0; k < 3; ++k) worst = std::max(worst, Edge(m, v[k], v[(k + 1) % 3]));
  }
  EXPECT_LE(worst, 0.3);
  // The disc of radius 4 (area 16 pi) is tiled by triangles of area <= 0.3^2 / 2 at most
  // (hypotenuse <= 0.3 of right isosceles triangles, the only shape bisection makes here).
  EXPECT_GE(inside, size_t(16 * M_PI / (0.3 * 0.3 / 2)));

  // Input triangles with all vertices more than 3 units outside the disc are kept as they were.
  std::vector<std::vector<size_t>> children(in.triangle_count());
  for (size_t t = 0; t < m.triangle_count(); ++t) children[r.triangle_origin[t]].push_back(t);
  size_t far = 0;
  for (size_t t = 0; t < in.triangle_count(); ++t) {
    const uint32_t* v = &in.indices[3 * t];
    bool is_far = true;
    for (int k = 0; k < 3; ++k) is_far = is_far && Dist2D(in.positions[v[k]], 10, 10) > 8;
    if (!is_far) continue;
    ++far;
    ASSERT_EQ(children[t].size(), 1u) << "input triangle " << t;
    const size_t c = children[t][0];
    EXPECT_EQ(m.indices[3 * c], v[0]);
    EXPECT_EQ(m.indices[3 * c + 1], v[1]);
    EXPECT_EQ(m.indices[3 * c + 2], v[2]);
  }
  EXPECT_GT(far, 100u);  // the four corners beyond radius 8: about 400 - 64 pi ~ 199 cells

  // Children tile their parent: area per input triangle preserved, orientation kept (+z).
  std::vector<double> area(in.triangle_count(), 0.0);
  double total = 0, min_angle = 180;
  for (size_t t = 0; t < m.triangle_count(); ++t) {
    const double a = SignedAreaXY(m, t);
    ASSERT_GT(a, 0) << "triangle " << t << " flipped or degenerate";
    area[r.triangle_origin[t]] += a;
    total += a;
    min_angle = std::min(min_angle, MinAngleDeg(m, t));
  }
  EXPECT_NEAR(total, 400.0, 400.0 * 1e-9);
  for (size_t t = 0; t < in.triangle_count(); ++t) EXPECT_NEAR(area[t], 0.5, 1e-9) << t;
  // Longest-edge bisection keeps every angle >= half the smallest input angle (45 degrees).
  EXPECT_GE(min_angle, 22.5 - 1e-6);

  // Conforming: welds cleanly, and the welded mesh's only boundary is the grid's (4 * 20).
  WeldedMesh w;
  Diagnostics weld_diag;
  ASSERT_TRUE(WeldMesh(m, 0.f, &w, &weld_diag)) << weld_diag.Format();
  EXPECT_TRUE(weld_diag.empty()) << weld_diag.Format();
  const Topology topo = WeldedTopology(w);
  EXPECT_EQ(topo.boundary_edges, 80u);
  EXPECT_EQ(topo.max_edge_use, 2u);
  // A disc-like surface: V - E + F = 1.
  EXPECT_EQ(int64_t(topo.points) - int64_t(topo.edges) + int64_t(m.triangle_count()), 1);
  // Normals carried: all +z.
  for (const float3& n : m.normals) ASSERT_EQ(n, (float3{0, 0, 1}));
}

TEST(Refine, SeamSplitsOnBothSidesAndWelds) {
  const int seam = 10;  // the column x = 10 runs through the disc's centre
  const MeshData in = Grid(20, seam);
  ASSERT_EQ(in.vertex_count(), 21u * 21u + 21u);
  RefineResult r;
  Diagnostics diag;
  ASSERT_TRUE(RefineMesh(in, DiscField, {}, &r, &diag)) << diag.Format();
  EXPECT_TRUE(diag.empty()) << diag.Format();
  const MeshData& m = r.mesh;

  WeldedMesh w;
  Diagnostics weld_diag;
  ASSERT_TRUE(WeldMesh(m, 1e-7f, &w, &weld_diag)) << weld_diag.Format();
  EXPECT_TRUE(weld_diag.empty()) << weld_diag.Format();
  const Topology topo = WeldedTopology(w);
  EXPECT_EQ(topo.boundary_edges, 80u);  // no crack along the seam
  EXPECT_EQ(topo.max_edge_use, 2u);

  std::vector<std::vector<uint32_t>> vertices_of(w.points.size());
  for (size_t v = 0; v < m.vertex_count(); ++v) vertices_of[w.point_of_vertex[v]].push_back(v);
  size_t seam_points = 0;
  for (size_t p = 0; p < w.points.size(); ++p) {
    const std::vector<uint32_t>& vs = vertices_of[p];
    if (w.points[p].x == 10.f) {
      ++seam_points;
      ASSERT_EQ(vs.size(), 2u) << "seam point " << p;
      EXPECT_EQ(m.positions[vs[0]], m.positions[vs[1]]);  // the same bits on both sides
      EXPECT_NEAR(std::fabs(m.uvs[vs[0]].x - m.uvs[vs[1]].x), 1.0, 1e-6);
    } else {
      ASSERT_EQ(vs.size(), 1u) << "point " << p;
    }
  }
  // Within radius 4 of the centre (y in [6, 14]) seam edges are <= 0.3 (see the disc test):
  // at least 8 / 0.3 segments there instead of 8.
  EXPECT_GE(seam_points, 21u - 8u + size_t(8 / 0.3));

  // uvs carried: u = x / 20 on the left, x / 20 + 1 on the right; v = y / 20. A triangle uses
  // vertices of one side only.
  for (size_t v = 0; v < m.vertex_count(); ++v) {
    const float3 p = m.positions[v];
    const bool right = m.uvs[v].x >= 1.f;
    if (p.x != 10.f) {
      EXPECT_EQ(right, p.x > 10.f) << v;
    }
    EXPECT_NEAR(m.uvs[v].x, p.x / 20.0 + (right ? 1.0 : 0.0), 1e-6) << v;
    EXPECT_NEAR(m.uvs[v].y, p.y / 20.0, 1e-6) << v;
  }
  for (size_t t = 0; t < m.triangle_count(); ++t) {
    const uint32_t* v = &m.indices[3 * t];
    const bool right = m.uvs[v[0]].x >= 1.f;
    EXPECT_EQ(m.uvs[v[1]].x >= 1.f, right) << t;
    EXPECT_EQ(m.uvs[v[2]].x >= 1.f, right) << t;
  }
}

TEST(Refine, CarriesLinearAttributeExactly) {
  // Non-dyadic spacing and offset, so positions round; the attribute 2x + 3y is linear, so the
  // average of the parents' values is the value at the midpoint.
  const MeshData in = Grid(20, 10, 0.1f, 0.3f, 0.7f);
  auto field = [](float3 p, float2) { return Dist2D(p, 1.3, 1.7) < 0.5 ? 0.03f : kInf; };
  RefineResult r;
  Diagnostics diag;
  ASSERT_TRUE(RefineMesh(in, field, {}, &r, &diag)) << diag.Format();
  ASSERT_GT(r.mesh.vertex_count(), in.vertex_count() + 100);
  std::vector<float> attr(in.vertex_count());
  for (size_t v = 0; v < in.vertex_count(); ++v) {
    attr[v] = 2 * in.positions[v].x + 3 * in.positions[v].y;
  }
  const std::vector<float> carried = CarryAttribute(r, attr);
  ASSERT_EQ(carried.size(), r.mesh.vertex_count());
  for (size_t v = 0; v < carried.size(); ++v) {
    const float3 p = r.mesh.positions[v];
    ASSERT_NEAR(carried[v], 2.0 * p.x + 3.0 * p.y, 1e-5) << v;
  }
  // Too few input values: empty.
  attr.pop_back();
  EXPECT_TRUE(CarryAttribute(r, attr).empty());
}

TEST(Refine, ClosedSurfaceStaysClosed) {
  // Octahedron: 6 vertices, 8 faces, edges sqrt(2), area 8 * (sqrt(3)/4) * 2 = 4 sqrt(3).
  MeshData m;
  m.positions = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  m.indices = {0, 2, 4, 2, 1, 4, 1, 3, 4, 3, 0, 4, 2, 0, 5, 1, 2, 5, 3, 1, 5, 0, 3, 5};
  RefineResult r;
  Diagnostics diag;
  ASSERT_TRUE(RefineMesh(m, [](float3, float2) { return 0.2f; }, {}, &r, &diag)) << diag.Format();
  EXPECT_TRUE(diag.empty()) << diag.Format();
  EXPECT_TRUE(r.bound_met);
  double area = 0, longest = 0, min_angle = 180;
  for (size_t t = 0; t < r.mesh.triangle_count(); ++t) {
    area += Area3D(r.mesh, t);
    min_angle = std::min(min_angle, MinAngleDeg(r.mesh, t));
    const uint32_t* v = &r.mesh.indices[3 * t];
    for (int k = 0; k < 3; ++k) longest = std::max(longest, Edge(r.mesh, v[k], v[(k + 1) % 3]));
  }
  EXPECT_LE(longest, 0.2);
  EXPECT_NEAR(area, 4 * std::sqrt(3.0), 4 * std::sqrt(3.0) * 1e-6);
  EXPECT_GE(min_angle, 30.0 - 1e-4);  // half of 60 degrees
  WeldedMesh w;
  Diagnostics weld_diag;
  ASSERT_TRUE(WeldMesh(r.mesh, 0.f, &w, &weld_diag)) << weld_diag.Format();
  const Topology topo = WeldedTopology(w);
  EXPECT_EQ(topo.boundary_edges, 0u);
  EXPECT_EQ(topo.max_edge_use, 2u);
  EXPECT_EQ(int64_t(topo.points) - int64_t(topo.edges) + int64_t(r.mesh.triangle_count()), 2);
}

TEST(Refine, Deterministic) {
  const MeshData in = Grid(20, 10);
  RefineResult a, b;
  ASSERT_TRUE(RefineMesh(in, DiscField, {}, &a, nullptr));
  ASSERT_TRUE(RefineMesh(in, DiscField, {}, &b, nullptr));
  ASSERT_EQ(a.mesh.vertex_count(), b.mesh.vertex_count());
  EXPECT_EQ(0, std::memcmp(a.mesh.positions.data(), b.mesh.positions.data(),
                           a.mesh.positions.size() * sizeof(float3)));
  EXPECT_EQ(0, std::memcmp(a.mesh.uvs.data(), b.mesh.uvs.data(), a.mesh.uvs.size() * sizeof(float2)));
  EXPECT_EQ(a.mesh.indices, b.mesh.indices);
  EXPECT_EQ(a.parents, b.parents);
  EXPECT_EQ(a.triangle_origin, b.triangle_origin);
}

TEST(Refine, NoConstraintLeavesMeshAsItWas) {
  const MeshData in = Grid(6, 3);
  for (float value : {kInf, 0.f, -1.f}) {
    RefineResult r;
    Diagnostics diag;
    ASSERT_TRUE(RefineMesh(in, [value](float3, float2) { return value; }, {}, &r, &diag));
    EXPECT_TRUE(diag.empty()) << diag.Format();
    EXPECT_EQ(r.passes, 0u);
    EXPECT_EQ(r.mesh.indices, in.indices);
    EXPECT_EQ(r.mesh.vertex_count(), in.vertex_count());
  }
}

TEST(Refine, NaNFieldIsNoConstraintWithWarning) {
  const MeshData in = Grid(6, 3);
  RefineResult r;
  Diagnostics diag;
  ASSERT_TRUE(RefineMesh(in, [](float3, float2) { return std::nanf(""); }, {}, &r, &diag));
  EXPECT_FALSE(diag.HasErrors());
  EXPECT_TRUE(diag.Contains("NaN")) << diag.Format();
  EXPECT_EQ(r.mesh.indices, in.indices);
  EXPECT_EQ(r.passes, 0u);
}

TEST(Refine, ImpossibleTargetStopsAtPassLimit) {
  const MeshData in = Grid(20);
  auto tiny = [](float3 p, float2) { return Dist2D(p, 10, 10) < 5 ? 1e-9f : kInf; };
  RefineOptions options;
  options.max_passes = 2;
  RefineResult r;
  Diagnostics diag;
  ASSERT_TRUE(RefineMesh(in, tiny, options, &r, &diag)) << diag.Format();
  EXPECT_FALSE(diag.HasErrors());
  EXPECT_TRUE(diag.Contains("pass limit")) << diag.Format();
  EXPECT_FALSE(r.bound_met);
  EXPECT_EQ(r.passes, 2u);
  WeldedMesh w;
  Diagnostics weld_diag;
  EXPECT_TRUE(WeldMesh(r.mesh, 0.f, &w, &weld_diag)) << weld_diag.Format();
  EXPECT_EQ(WeldedTopology(w).boundary_edges, 80u);
}

TEST(Refine, ImpossibleTargetStopsAtTriangleLimit) {
  const MeshData in = Grid(20);
  auto tiny = [](float3 p, float2) { return Dist2D(p, 10, 10) < 5 ? 1e-9f : kInf; };
  RefineOptions options;
  options.max_passes = 1000;
  options.max_triangles = 5000;
  RefineResult r;
  Diagnostics diag;
  const auto start = std::chrono::steady_clock::now();
  ASSERT_TRUE(RefineMesh(in, tiny, options, &r, &diag)) << diag.Format();
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 10.0);
  EXPECT_TRUE(diag.Contains("triangle limit")) << diag.Format();
  EXPECT_FALSE(r.bound_met);
  EXPECT_LE(r.mesh.triangle_count(), 5000u);
  EXPECT_GT(r.mesh.triangle_count(), 800u);
}

TEST(Refine, ImpossibleTargetStopsAtShortestSplittableEdge) {
  // A small support, so that refining down to 2e-4 of the diagonal (20 sqrt 2 * 2e-4 ~ 0.0057)
  // stays affordable; the result must still weld at the default tolerance without errors. The
  // support holds the midpoint (10.5, 10.5) of a diagonal, where the field is sampled.
  const MeshData in = Grid(20);
  auto tiny = [](float3 p, float2) { return Dist2D(p, 10.5, 10.5) < 0.3 ? 1e-9f : kInf; };
  RefineOptions options;
  options.max_passes = 1000;
  RefineResult r;
  Diagnostics diag;
  ASSERT_TRUE(RefineMesh(in, tiny, options, &r, &diag)) << diag.Format();
  EXPECT_TRUE(diag.Contains("shortest edge")) << diag.Format();
  EXPECT_FALSE(r.bound_met);
  EXPECT_LT(r.passes, 1000u);
  double shortest = 1e9;
  for (size_t t = 0; t < r.mesh.triangle_count(); ++t) {
    const uint32_t* v = &r.mesh.indices[3 * t];
    for (int k = 0; k < 3; ++k) shortest = std::min(shortest, Edge(r.mesh, v[k], v[(k + 1) % 3]));
  }
  const double split_floor = 2e-4 * 20 * std::sqrt(2.0);
  EXPECT_LT(shortest, split_floor);        // refined down to the floor...
  EXPECT_GE(shortest, split_floor / 2.5);  // ...and no further (halves of an edge >= floor)
  WeldedMesh w;
  Diagnostics weld_diag;
  EXPECT_TRUE(WeldMesh(r.mesh, 0.f, &w, &weld_diag)) << weld_diag.Format();
  EXPECT_EQ(WeldedTopology(w).boundary_edges, 80u);
}

TEST(Refine, EmptyAndInvalidInput) {
  {
    RefineResult r;
    Diagnostics diag;
    EXPECT_TRUE(RefineMesh(MeshData{}, DiscField, {}, &r, &diag)) << diag.Format();
    EXPECT_FALSE(diag.HasErrors());
    EXPECT_EQ(r.mesh.vertex_count(), 0u);
    EXPECT_EQ(r.mesh.triangle_count(), 0u);
    EXPECT_TRUE(CarryAttribute(r, {}).empty());
  }
  {  // Vertices without triangles: returned as they are.
    MeshData m;
    m.positions = {{0, 0, 0}, {1, 0, 0}};
    RefineResult r;
    EXPECT_TRUE(RefineMesh(m, DiscField, {}, &r, nullptr));
    EXPECT_EQ(r.mesh.vertex_count(), 2u);
    EXPECT_EQ(r.parents.size(), 2u);
  }
  {  // Out-of-range index: weld error, false.
    MeshData m = Grid(2);
    m.indices[4] = 1000;
    RefineResult r;
    Diagnostics diag;
    EXPECT_FALSE(RefineMesh(m, DiscField, {}, &r, &diag));
    EXPECT_TRUE(diag.Contains("out of range")) << diag.Format();
  }
  {  // uv count neither 0 nor #V.
    MeshData m = Grid(2);
    m.uvs.pop_back();
    RefineResult r;
    Diagnostics diag;
    EXPECT_FALSE(RefineMesh(m, DiscField, {}, &r, &diag));
    EXPECT_TRUE(diag.Contains("uvs")) << diag.Format();
  }
  {  // No field, no output.
    Diagnostics diag;
    RefineResult r;
    EXPECT_FALSE(RefineMesh(Grid(2), EdgeLengthField{}, {}, &r, &diag));
    EXPECT_TRUE(diag.Contains("field")) << diag.Format();
    EXPECT_FALSE(RefineMesh(Grid(2), DiscField, {}, nullptr, &diag));
  }
  {  // A throwing field is an error, not an escaping exception.
    Diagnostics diag;
    RefineResult r;
    auto thrower = [](float3, float2) -> float { throw std::runtime_error("boom"); };
    EXPECT_FALSE(RefineMesh(Grid(2), thrower, {}, &r, &diag));
    EXPECT_TRUE(diag.Contains("boom")) << diag.Format();
  }
}

TEST(Refine, LargeMeshIsFast) {
  // 200 x 200 cells (80,000 triangles), a support of radius 20 refined to 0.25: far from any
  // quadratic cost.
  const MeshData in = Grid(200);
  auto field = [](float3 p, float2) { return Dist2D(p, 100, 100) < 20 ? 0.25f : kInf; };
  RefineResult r;
  Diagnostics diag;
  const auto start = std::chrono::steady_clock::now();
  ASSERT_TRUE(RefineMesh(in, field, {}, &r, &diag)) << diag.Format();
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_TRUE(diag.empty()) << diag.Format();
  EXPECT_GT(r.mesh.triangle_count(), 80000u + 20000u);
  EXPECT_LT(seconds, 20.0);
}

}  // namespace
}  // namespace mimetic

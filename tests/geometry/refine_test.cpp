// Tests for RefineMesh (geometry/refine.h, docs/model.md §11). Expected values come from the
// construction of the inputs: a flat 20 x 20 grid (unit spacing, area 400, 80 boundary edges),
// the same grid with a UV seam, and an octahedron (closed: Euler characteristic 2). Bounds
// checked: edge length inside the support, untouched triangles far from it, exact welding at
// seams, area and orientation, the Rosenberg-Stenger angle bound of longest-edge bisection,
// attributes carried linearly, limits that stop with a warning, and bad input.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "core/diagnostics.h"
#include "geometry/mesh.h"
#include "geometry/normals.h"
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

// The unit icosahedron subdivided `levels` times 1-to-4, every vertex on the unit sphere
// (counter-clockwise seen from outside). levels 2: 162 vertices, 320 triangles.
MeshData IcoSphere(int levels) {
  const double g = (1 + std::sqrt(5.0)) / 2;
  std::vector<std::array<double, 3>> p = {{-1, g, 0}, {1, g, 0},  {-1, -g, 0}, {1, -g, 0},
                                          {0, -1, g}, {0, 1, g},  {0, -1, -g}, {0, 1, -g},
                                          {g, 0, -1}, {g, 0, 1},  {-g, 0, -1}, {-g, 0, 1}};
  std::vector<uint32_t> f = {0, 11, 5,  0, 5,  1,  0, 1, 7,  0, 7,  10, 0, 10, 11,
                             1, 5,  9,  5, 11, 4,  11, 10, 2, 10, 7, 6,  7, 1,  8,
                             3, 9,  4,  3, 4,  2,  3, 2, 6,  3, 6,  8,  3, 8,  9,
                             4, 9,  5,  2, 4,  11, 6, 2, 10, 8, 6,  7,  9, 8,  1};
  auto unit = [](std::array<double, 3> a) {
    const double l = std::sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2]);
    return std::array<double, 3>{a[0] / l, a[1] / l, a[2] / l};
  };
  for (auto& q : p) q = unit(q);
  for (int level = 0; level < levels; ++level) {
    std::map<std::pair<uint32_t, uint32_t>, uint32_t> mid;
    auto m = [&](uint32_t a, uint32_t b) {
      const auto key = std::make_pair(std::min(a, b), std::max(a, b));
      auto it = mid.find(key);
      if (it != mid.end()) return it->second;
      p.push_back(unit({p[a][0] + p[b][0], p[a][1] + p[b][1], p[a][2] + p[b][2]}));
      return mid[key] = uint32_t(p.size() - 1);
    };
    std::vector<uint32_t> next;
    for (size_t t = 0; t < f.size(); t += 3) {
      const uint32_t a = f[t], b = f[t + 1], c = f[t + 2];
      const uint32_t ab = m(a, b), bc = m(b, c), ca = m(c, a);
      next.insert(next.end(), {a, ab, ca, ab, b, bc, ca, bc, c, ab, bc, ca});
    }
    f = std::move(next);
  }
  MeshData mesh;
  for (const auto& q : p) mesh.positions.push_back({float(q[0]), float(q[1]), float(q[2])});
  mesh.indices = f;
  return mesh;
}

double Norm(float3 p) { return std::sqrt(double(p.x) * p.x + double(p.y) * p.y + double(p.z) * p.z); }

double AngleDeg(float3 a, float3 b) {
  const double c = (double(a.x) * b.x + double(a.y) * b.y + double(a.z) * b.z) / (Norm(a) * Norm(b));
  return std::acos(std::clamp(c, -1.0, 1.0)) * 180.0 / M_PI;
}

// The flat positions of a refinement (every new vertex the midpoint of its parents' flat
// positions, i.e. on the input's flat triangles), computed from the parents alone.
std::vector<float3> FlatPositions(const RefineResult& r, const MeshData& in) {
  std::vector<float> x(in.vertex_count()), y(x.size()), z(x.size());
  for (size_t v = 0; v < in.vertex_count(); ++v)
    x[v] = in.positions[v].x, y[v] = in.positions[v].y, z[v] = in.positions[v].z;
  const std::vector<float> cx = CarryAttribute(r, x), cy = CarryAttribute(r, y), cz = CarryAttribute(r, z);
  std::vector<float3> out(cx.size());
  for (size_t v = 0; v < out.size(); ++v) out[v] = {cx[v], cy[v], cz[v]};
  return out;
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
  // Flat placement: the children tile the octahedron's faces (the smooth placement rounds it;
  // see the sphere tests below), so area and the bisection angle bound hold exactly.
  RefineOptions flat;
  flat.placement = RefinePlacement::kFlat;
  ASSERT_TRUE(RefineMesh(m, [](float3, float2) { return 0.2f; }, flat, &r, &diag)) << diag.Format();
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

// docs/model.md §14. One pass with every edge marked: each new vertex splits an input edge (a,
// b) of the icosphere, half angle phi. The flat midpoint lies 1 - cos(phi) inside the sphere.
// The PN edge cubic's midpoint is (a + b)/2 + ((a - b).na na + (b - a).nb nb)/8; with radial
// normals that is (a + b)/2 (1 + sin^2(phi)/2), radius cos(phi) (1 + sin^2(phi)/2) = 1 -
// (3/8) phi^4 + O(phi^6). A normal off by delta changes each of the two offset terms by at
// most 2 |a - b| delta / 8, so |r - 1| <= |1 - cos(phi)(1 + sin^2(phi)/2)| + |a - b| delta / 2.
TEST(Refine, SmoothEdgeMidpointsLieOnTheSphereWithinThePnBound) {
  const MeshData in = IcoSphere(2);
  ASSERT_EQ(in.vertex_count(), 162u);
  // The input's own area-weighted normals against the true (radial) ones.
  const std::vector<float3> n = ComputeVertexNormals(in);
  double delta = 0;
  for (size_t v = 0; v < in.vertex_count(); ++v)
    delta = std::max(delta, AngleDeg(n[v], in.positions[v]) * M_PI / 180.0);
  RefineOptions one;
  one.max_passes = 1;
  RefineResult r;
  Diagnostics diag;
  ASSERT_TRUE(RefineMesh(in, [](float3, float2) { return 0.01f; }, one, &r, &diag)) << diag.Format();
  ASSERT_EQ(r.passes, 1u);
  ASSERT_EQ(r.mesh.vertex_count(), 162u + 480u);  // one new vertex per input edge (E = 480)
  for (size_t v = 0; v < in.vertex_count(); ++v) ASSERT_EQ(r.mesh.positions[v], in.positions[v]);
  double worst_smooth = 0, worst_flat = 0, worst_excess = -1;
  for (size_t v = in.vertex_count(); v < r.mesh.vertex_count(); ++v) {
    const auto [a, b] = r.parents[v];
    ASSERT_LT(a, in.vertex_count());
    ASSERT_LT(b, in.vertex_count());
    const float3 pa = in.positions[a], pb = in.positions[b];
    const double chord = Edge(in, a, b), phi = std::asin(std::min(1.0, chord / 2));
    const double flat_error = 1 - std::cos(phi);
    const double bound = std::fabs(1 - std::cos(phi) * (1 + std::sin(phi) * std::sin(phi) / 2)) +
                         chord * delta / 2 + 1e-6;
    const double error = std::fabs(Norm(r.mesh.positions[v]) - 1);
    worst_excess = std::max(worst_excess, error - bound);
    worst_smooth = std::max(worst_smooth, error);
    worst_flat = std::max(worst_flat, flat_error);
    ASSERT_LE(error, bound) << "vertex " << v << " between " << a << " and " << b;
    ASSERT_LT(error, 0.2 * flat_error) << "vertex " << v;
    // And it is the point the flat placement puts at the midpoint, moved outward only.
    const float3 mid{0.5f * (pa.x + pb.x), 0.5f * (pa.y + pb.y), 0.5f * (pa.z + pb.z)};
    EXPECT_GT(Norm(r.mesh.positions[v]), Norm(mid)) << v;
  }
  std::printf("icosphere(2) edge midpoints: normal error %.3g deg, worst |r - 1| smooth %.3g, "
              "flat %.3g\n", delta * 180 / M_PI, worst_smooth, worst_flat);
}

// docs/model.md §14. Several passes (points inside input triangles too): the refined rest
// pose's normals at the new vertices against the input's interpolated vertex normals (the
// normalised linear interpolation of its area-weighted normals, carried by the parents) and
// against the sphere's true normal; flat placement for comparison. On flat placement a new
// vertex inside a triangle has that face's normal, off by up to half the angle between
// neighbouring faces (about 6 degrees here); on the PN patch it follows the surface.
TEST(Refine, SmoothRestNormalsFollowTheInputsInterpolatedNormals) {
  const MeshData in = IcoSphere(2);
  RefineResult smooth, flat;
  RefineOptions flat_options;
  flat_options.placement = RefinePlacement::kFlat;
  Diagnostics diag;
  auto field = [](float3, float2) { return 0.06f; };
  ASSERT_TRUE(RefineMesh(in, field, {}, &smooth, &diag)) << diag.Format();
  ASSERT_TRUE(RefineMesh(in, field, flat_options, &flat, &diag)) << diag.Format();
  ASSERT_GE(smooth.passes, 3u);
  // The same topology either way; flat = the midpoints computed from the parents.
  ASSERT_EQ(smooth.mesh.indices, flat.mesh.indices);
  ASSERT_EQ(smooth.parents, flat.parents);
  const std::vector<float3> expected_flat = FlatPositions(smooth, in);
  for (size_t v = 0; v < in.vertex_count(); ++v) ASSERT_EQ(smooth.mesh.positions[v], in.positions[v]);
  for (size_t v = 0; v < flat.mesh.vertex_count(); ++v)
    ASSERT_LT(Length(flat.mesh.positions[v] - expected_flat[v]), 1e-6f) << v;

  const std::vector<float3> n_in = ComputeVertexNormals(in);
  std::vector<float> nx(in.vertex_count()), ny(nx.size()), nz(nx.size());
  for (size_t v = 0; v < in.vertex_count(); ++v) nx[v] = n_in[v].x, ny[v] = n_in[v].y, nz[v] = n_in[v].z;
  const std::vector<float> cx = CarryAttribute(smooth, nx), cy = CarryAttribute(smooth, ny),
                           cz = CarryAttribute(smooth, nz);
  const std::vector<float3> n_smooth = ComputeVertexNormals(smooth.mesh),
                            n_flat = ComputeVertexNormals(flat.mesh);
  double sum_smooth = 0, sum_flat = 0, sum_true_smooth = 0, sum_true_flat = 0, max_smooth = 0;
  double r_smooth = 0, r_flat = 0;
  size_t count = 0, closer = 0;
  for (size_t v = in.vertex_count(); v < smooth.mesh.vertex_count(); ++v) {
    const float3 phong{cx[v], cy[v], cz[v]};
    const float3 p = smooth.mesh.positions[v], q = flat.mesh.positions[v];
    sum_smooth += AngleDeg(n_smooth[v], phong);
    sum_flat += AngleDeg(n_flat[v], phong);
    max_smooth = std::max(max_smooth, AngleDeg(n_smooth[v], phong));
    sum_true_smooth += AngleDeg(n_smooth[v], p);  // the sphere's normal at p is p
    sum_true_flat += AngleDeg(n_flat[v], q);
    r_smooth = std::max(r_smooth, std::fabs(Norm(p) - 1));
    r_flat = std::max(r_flat, std::fabs(Norm(q) - 1));
    closer += std::fabs(Norm(p) - 1) < std::fabs(Norm(q) - 1);
    ++count;
  }
  ASSERT_GT(count, 1000u);
  const double mean_smooth = sum_smooth / count, mean_flat = sum_flat / count;
  std::printf("icosphere(2), %zu new vertices: mean angle to the interpolated normal %.3f deg "
              "smooth (max %.3f), %.3f flat; to the sphere's %.3f smooth, %.3f flat; worst "
              "|r - 1| %.3g smooth, %.3g flat; %zu closer to the sphere\n",
              count, mean_smooth, max_smooth, mean_flat, sum_true_smooth / count,
              sum_true_flat / count, r_smooth, r_flat, closer);
  EXPECT_LT(mean_smooth, 2.0);
  EXPECT_LT(mean_smooth, 0.25 * mean_flat);
  EXPECT_LT(sum_true_smooth, 0.25 * sum_true_flat);
  EXPECT_LT(r_smooth, 0.25 * r_flat);
  EXPECT_EQ(closer, count);  // every new vertex nearer the sphere than its flat position
}

// The smooth placement on a curved sheet with a uv seam: the two file vertices of a seam
// point get the same bits (the point is placed once, on the welded edge), so it welds
// without a crack; and on the flat grid the placement is the flat one, bit for bit.
TEST(Refine, SmoothPlacementKeepsSeamsClosedAndPlanesFlat) {
  MeshData in = Grid(20, 10);
  for (float3& p : in.positions) p.z = 0.02f * ((p.x - 10) * (p.x - 10) + (p.y - 10) * (p.y - 10));
  RefineResult r;
  Diagnostics diag;
  ASSERT_TRUE(RefineMesh(in, DiscField, {}, &r, &diag)) << diag.Format();
  WeldedMesh w;
  Diagnostics weld_diag;
  ASSERT_TRUE(WeldMesh(r.mesh, 1e-7f, &w, &weld_diag)) << weld_diag.Format();
  const Topology topo = WeldedTopology(w);
  EXPECT_EQ(topo.boundary_edges, 80u);
  EXPECT_EQ(topo.max_edge_use, 2u);
  const std::vector<float3> flat = FlatPositions(r, in);
  size_t moved = 0;
  for (size_t v = in.vertex_count(); v < r.mesh.vertex_count(); ++v)
    moved += Length(r.mesh.positions[v] - flat[v]) > 1e-5f;
  EXPECT_GT(moved, (r.mesh.vertex_count() - in.vertex_count()) / 2);  // curved: most move

  const MeshData plane = Grid(20, 10);
  RefineResult a, b;
  RefineOptions flat_options;
  flat_options.placement = RefinePlacement::kFlat;
  ASSERT_TRUE(RefineMesh(plane, DiscField, {}, &a, nullptr));
  ASSERT_TRUE(RefineMesh(plane, DiscField, flat_options, &b, nullptr));
  ASSERT_EQ(a.mesh.vertex_count(), b.mesh.vertex_count());
  EXPECT_EQ(0, std::memcmp(a.mesh.positions.data(), b.mesh.positions.data(),
                           a.mesh.positions.size() * sizeof(float3)));
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
  ASSERT_TRUE(RefineMesh(in, tiny, options, &r, &diag)) << diag.Format();
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

TEST(Refine, LargeMeshRefinesOnlyInsideTheSupport) {
  // 200 x 200 cells (80,000 triangles), a support of radius 20 refined to 0.25: far from any
  // quadratic cost.
  const MeshData in = Grid(200);
  auto field = [](float3 p, float2) { return Dist2D(p, 100, 100) < 20 ? 0.25f : kInf; };
  RefineResult r;
  Diagnostics diag;
  ASSERT_TRUE(RefineMesh(in, field, {}, &r, &diag)) << diag.Format();
  EXPECT_TRUE(diag.empty()) << diag.Format();
  EXPECT_GT(r.mesh.triangle_count(), 80000u + 20000u);
  // Far from the support the cells keep their two half-unit triangles; the area is kept.
  double area = 0;
  size_t far_split = 0;
  for (size_t t = 0; t < r.mesh.triangle_count(); ++t) {
    const double a = SignedAreaXY(r.mesh, t);
    area += a;
    const float3 c = (r.mesh.positions[r.mesh.indices[3 * t]] +
                      r.mesh.positions[r.mesh.indices[3 * t + 1]] +
                      r.mesh.positions[r.mesh.indices[3 * t + 2]]) * (1.f / 3.f);
    if (Dist2D(c, 100, 100) > 30 && std::abs(a - 0.5) > 1e-9) ++far_split;
  }
  EXPECT_NEAR(area, 200.0 * 200.0, 1e-6 * 40000);
  EXPECT_EQ(far_split, 0u);
}

}  // namespace
}  // namespace mimetic

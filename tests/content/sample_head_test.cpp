// tests/content/sample_head_test.cpp: the procedural sample head (content/sample_head.h).
//
// Expectations come from the issue (20k-40k vertices, ~230 mm chin to crown, +Y up, facing
// +Z, cylindrical UVs with a duplicated seam, 68 iBUG landmarks on the surface) and from
// anthropometric proportions, not from the generator's own output.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <map>
#include <set>
#include <string>
#include <tuple>

#include "content/sample_head.h"
#include "fitting/landmarks.h"
#include "geometry/weld.h"
#include "io/image.h"
#include "io/landmarks_file.h"
#include "io/mesh_io.h"
#include "test_support.h"
#include "tools/render/render.h"

namespace mimetic {
namespace {

const SampleHead& Head() {
  static const SampleHead head = MakeSampleHead();
  return head;
}

struct Box {
  float3 lo, hi;
};
Box Bounds(const std::vector<float3>& pts) {
  Box b{pts[0], pts[0]};
  for (const float3& p : pts) {
    b.lo = {std::min(b.lo.x, p.x), std::min(b.lo.y, p.y), std::min(b.lo.z, p.z)};
    b.hi = {std::max(b.hi.x, p.x), std::max(b.hi.y, p.y), std::max(b.hi.z, p.z)};
  }
  return b;
}

// The columns strictly between the mouth corners: those whose vertex on the mouth row lies in
// front within the mouth's half width (the construction's definition of the slit).
size_t SlitColumns(const SampleHead& h, const SampleHeadOptions& o = {}) {
  size_t n = 0;
  for (int j = 0; j <= o.columns; ++j) {
    const float3 p = h.mesh.positions[1 + size_t(h.mouth_row - 1) * (o.columns + 1) + j];
    if (p.z > 0 && std::fabs(p.x) < kSampleHeadMouthHalfWidth) ++n;
  }
  return n;
}

// The columns cut by the two lid fissures (both eyes together): those whose vertex on the lid
// row lies in front, strictly between the canthi, moved up off the closed lid line onto the
// upper lid's margin (the construction's definition of the fissure).
size_t FissureColumns(const SampleHead& h, const SampleHeadOptions& o = {}) {
  size_t n = 0;
  for (int j = 0; j <= o.columns; ++j) {
    const float3 p = h.mesh.positions[1 + size_t(h.lid_row - 1) * (o.columns + 1) + j];
    const float ax = std::fabs(p.x);
    if (p.z > 0 && ax > kSampleHeadInnerCanthusX && ax < kSampleHeadOuterCanthusX &&
        p.y > SampleHeadLidLineY(ax) + 1e-3f)
      ++n;
  }
  return n;
}

// The mesh's boundary edges (in one triangle only) that lie at an eye (|x| 8-55, |y| < 15,
// in front), per eye (0: x < 0, 1: x > 0), as directed edges of their triangles.
std::array<std::vector<std::pair<uint32_t, uint32_t>>, 2> EyeBoundary(const MeshData& m) {
  std::map<std::pair<uint32_t, uint32_t>, int> uses;
  for (size_t t = 0; t < m.indices.size(); t += 3)
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = m.indices[t + k], b = m.indices[t + (k + 1) % 3];
      uses[{std::min(a, b), std::max(a, b)}]++;
    }
  std::array<std::vector<std::pair<uint32_t, uint32_t>>, 2> out;
  for (size_t t = 0; t < m.indices.size(); t += 3)
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = m.indices[t + k], b = m.indices[t + (k + 1) % 3];
      if (uses[{std::min(a, b), std::max(a, b)}] != 1) continue;
      const float3 p = m.positions[a];
      if (p.z > 40 && std::fabs(p.y) < 15 && std::fabs(p.x) > 8 && std::fabs(p.x) < 55)
        out[p.x > 0 ? 1 : 0].push_back({a, b});
    }
  return out;
}

TEST(SampleHead, VertexCountAndLayout) {
  const MeshData& m = Head().mesh;
  EXPECT_GE(m.vertex_count(), 20000u);
  EXPECT_LE(m.vertex_count(), 40000u);
  // Defaults: a pole plus 140 rings of 240 + 1 (seam) vertices, then per column between the
  // mouth corners the lower lip's slit twin and the two lip rolls' vertices.
  const SampleHeadOptions o;
  const size_t slit = SlitColumns(Head());
  const size_t R = kSampleHeadLipRollRows;
  // The mouth is 52 mm wide; the face's columns there are about 1.1 mm apart.
  EXPECT_GT(slit, 35u);
  EXPECT_LT(slit, 60u);
  // And per column between the canthi the lower lid's margin twin and the two lid rolls'.
  const size_t lid = FissureColumns(Head());
  const size_t RL = kSampleHeadLidRollRows;
  // Each fissure is 29 mm wide; the columns there are about 1 mm apart.
  EXPECT_GT(lid, 2u * 20);
  EXPECT_LT(lid, 2u * 40);
  EXPECT_EQ(m.vertex_count(), 1u + size_t(o.rows) * (o.columns + 1) + slit * (2 * R + 1) +
                                  lid * (2 * RL + 1));
  // A fan of `columns` triangles at the pole, two per quad below; each roll row has `slit + 1`
  // quads (a lid roll row `lid / 2 + 1`), the two at the corners collapsed to one triangle.
  EXPECT_EQ(m.triangle_count(),
            size_t(o.columns) * (2 * o.rows - 1) + 2 * R * (2 * slit) + 2 * RL * (2 * lid));
  EXPECT_EQ(m.uvs.size(), m.vertex_count());
  EXPECT_EQ(m.normals.size(), m.vertex_count());
  for (uint32_t i : m.indices) ASSERT_LT(i, m.vertex_count());
}

TEST(SampleHead, ChinToCrownHeightIsAbout230mm) {
  const Box b = Bounds(Head().mesh.positions);
  EXPECT_NEAR(b.hi.y - b.lo.y, 230.f, 10.f);
  // Adult head breadth ~140-160 mm, length (glabella to back) ~185-210 mm.
  EXPECT_GT(b.hi.x - b.lo.x, 135.f);
  EXPECT_LT(b.hi.x - b.lo.x, 175.f);  // ears included
  EXPECT_GT(b.hi.z - b.lo.z, 190.f);
  EXPECT_LT(b.hi.z - b.lo.z, 245.f);  // nose included
  // The lowest point is the chin (landmark 8), not a neck hanging below it.
  EXPECT_NEAR(Head().landmarks[8].y, b.lo.y, 3.f);
}

TEST(SampleHead, FacesPlusZ) {
  const MeshData& m = Head().mesh;
  size_t front = 0;
  for (size_t i = 1; i < m.vertex_count(); ++i)
    if (m.positions[i].z > m.positions[front].z) front = i;
  const float3 tip = m.positions[front];
  EXPECT_NEAR(tip.x, 0.f, 1.0f) << "the most forward point (nose tip) is on the midline";
  // Nose tip between the eyes (y = 0) and the mouth.
  EXPECT_LT(tip.y, -15.f);
  EXPECT_GT(tip.y, -55.f);
  // The back of the head is the other way.
  const Box b = Bounds(m.positions);
  EXPECT_LT(b.lo.z, -80.f);
}

TEST(SampleHead, MirrorSymmetric) {
  const MeshData& m = Head().mesh;
  // Every vertex has a mirror image (x -> -x) within 1e-3 mm.
  std::map<std::tuple<long, long, long>, std::vector<uint32_t>> grid;
  auto key = [](float3 p) {
    return std::make_tuple(std::lround(std::floor(p.x / 0.01f)), std::lround(std::floor(p.y / 0.01f)),
                           std::lround(std::floor(p.z / 0.01f)));
  };
  for (uint32_t i = 0; i < m.vertex_count(); ++i) grid[key(m.positions[i])].push_back(i);
  size_t missing = 0;
  for (uint32_t i = 0; i < m.vertex_count(); ++i) {
    const float3 q{-m.positions[i].x, m.positions[i].y, m.positions[i].z};
    const auto k = key(q);
    bool found = false;
    for (long dx = -1; dx <= 1 && !found; ++dx)
      for (long dy = -1; dy <= 1 && !found; ++dy)
        for (long dz = -1; dz <= 1 && !found; ++dz) {
          auto it = grid.find({std::get<0>(k) + dx, std::get<1>(k) + dy, std::get<2>(k) + dz});
          if (it == grid.end()) continue;
          for (uint32_t j : it->second)
            if (Length(m.positions[j] - q) <= 1e-3f) found = true;
        }
    if (!found) ++missing;
  }
  EXPECT_EQ(missing, 0u);
}

TEST(SampleHead, WeldsWithoutErrorsIntoAClosedTopWithTheNeckAndMouthOpen) {
  const MeshData& m = Head().mesh;
  WeldedMesh w;
  Diagnostics diag;
  const bool ok = WeldMesh(m, 0.f, &w, &diag);
  ASSERT_TRUE(ok) << diag.Format();
  EXPECT_FALSE(diag.HasErrors()) << diag.Format();
  const SampleHeadOptions o;
  // Only the seam column is split: one duplicate per ring.
  EXPECT_EQ(w.points.size(), m.vertex_count() - size_t(o.rows));
  // Edge use on the welded surface: every edge in 1 or 2 triangles, and consistently
  // oriented (a directed edge in at most one triangle, so a shared edge is walked both ways);
  // the boundary is the ring at the neck (`columns` edges) and the mouth: the ends of the two
  // lip rolls, `slit + 1` edges each from corner to corner. The crown and the seam are closed.
  std::map<std::pair<uint32_t, uint32_t>, int> uses, directed;
  for (size_t t = 0; t < w.triangles.size(); t += 3)
    for (int k = 0; k < 3; ++k) {
      uint32_t a = w.triangles[t + k], b = w.triangles[t + (k + 1) % 3];
      uses[{std::min(a, b), std::max(a, b)}]++;
      directed[{a, b}]++;
    }
  for (const auto& [e, n] : directed) ASSERT_EQ(n, 1) << "edge " << e.first << "-" << e.second;
  size_t neck = 0, mouth = 0, eyes = 0, other = 0;
  std::map<uint32_t, int> mouth_degree, eye_degree;
  for (const auto& [e, n] : uses) {
    ASSERT_LE(n, 2);
    if (n != 1) continue;
    const float3 a = w.points[e.first], b = w.points[e.second];
    if (a.y < -100 && b.y < -100) {
      ++neck;
    } else if (std::fabs(a.x) <= kSampleHeadMouthHalfWidth + 2 && std::fabs(a.y + 66) < 10 &&
               a.z > 60) {
      ++mouth;
      mouth_degree[e.first]++;
      mouth_degree[e.second]++;
    } else if (std::fabs(a.x) > 8 && std::fabs(a.x) < 55 && std::fabs(a.y) < 15 && a.z > 40) {
      ++eyes;
      eye_degree[e.first]++;
      eye_degree[e.second]++;
    } else {
      ++other;
    }
  }
  EXPECT_EQ(neck, size_t(o.columns));
  EXPECT_EQ(mouth, 2 * (SlitColumns(Head()) + 1));
  // Each eye: the ends of the two lid rolls, `columns between the canthi + 1` edges each.
  EXPECT_EQ(eyes, 2 * (FissureColumns(Head()) + 2));
  EXPECT_EQ(other, 0u);
  // The mouth's and eyes' boundaries are simple: every point on them has two boundary edges.
  for (const auto& [p, d] : mouth_degree) EXPECT_EQ(d, 2) << "point " << p;
  for (const auto& [p, d] : eye_degree) EXPECT_EQ(d, 2) << "point " << p;
}

// The lips are cut apart between the corners (docs: assets/head/README.md): on the mouth row
// every vertex strictly between the corners has a twin kSampleHeadSlitWidth below it that
// shares no triangle with the upper lip's rows, and the corners are shared.
TEST(SampleHead, TheLipsAreSeparateSurfacesMeetingAtTheCorners) {
  const SampleHead& h = Head();
  const MeshData& m = h.mesh;
  const SampleHeadOptions o;
  const size_t ring = o.columns + 1;
  auto row_of = [&](uint32_t v) { return v == 0 ? 0 : int((v - 1) / ring) + 1; };
  std::vector<std::set<int>> rows_touched(m.vertex_count());  // grid rows in a vertex's triangles
  for (size_t t = 0; t < m.indices.size(); t += 3)
    for (int k = 0; k < 3; ++k)
      for (int l = 0; l < 3; ++l)
        if (m.indices[t + l] <= size_t(o.rows) * ring)
          rows_touched[m.indices[t + k]].insert(row_of(m.indices[t + l]));
  size_t twins = 0;
  for (int j = 0; j <= o.columns; ++j) {
    const uint32_t v = uint32_t(1 + size_t(h.mouth_row - 1) * ring + j);
    const float3 p = m.positions[v];
    if (!(p.z > 0 && std::fabs(p.x) < kSampleHeadMouthHalfWidth)) continue;
    // The upper side touches the row above, never the row below.
    EXPECT_TRUE(rows_touched[v].count(h.mouth_row - 1)) << j;
    EXPECT_FALSE(rows_touched[v].count(h.mouth_row + 1)) << j;
    // Its twin: the vertex beyond the grid at (x, y - width, z), touching the row below only.
    for (uint32_t u = uint32_t(1 + o.rows * ring); u < m.vertex_count(); ++u) {
      if (Length(m.positions[u] - float3{p.x, p.y - kSampleHeadSlitWidth, p.z}) > 1e-4f) continue;
      ++twins;
      EXPECT_TRUE(rows_touched[u].count(h.mouth_row + 1)) << j;
      EXPECT_FALSE(rows_touched[u].count(h.mouth_row - 1)) << j;
      EXPECT_NEAR(m.uvs[u].x, m.uvs[v].x, 1e-7f);
    }
    // On the mouth line (through the stomion of the proportions, y = -66 on the midline) half
    // the slit's width up, kSampleHeadSlitInset behind the surface (inward along the arch's
    // normal, within 30 degrees of -z across the mouth: 0.1 mm of the line's height).
    EXPECT_NEAR(p.y, SampleHeadMouthLineY(p.z + kSampleHeadSlitInset) + 0.5f * kSampleHeadSlitWidth,
                0.1f) << j;
  }
  EXPECT_EQ(twins, SlitColumns(h));
  // The inner-lip landmarks sit on their own lips: 61-63 above the slit, 65-67 below it.
  for (int l : {61, 62, 63})
    EXPECT_GT(h.landmarks[l].y, SampleHeadMouthLineY(h.landmarks[l].z) + 0.5f * kSampleHeadSlitWidth) << l;
  for (int l : {65, 66, 67})
    EXPECT_LT(h.landmarks[l].y, SampleHeadMouthLineY(h.landmarks[l].z) - 0.5f * kSampleHeadSlitWidth) << l;
  // The twins and rolls lie behind the lips' front (z ~ 99 mm): the rolls turn inward.
  size_t behind = 0;
  for (uint32_t u = uint32_t(1 + o.rows * ring); u < m.vertex_count(); ++u)
    if (m.positions[u].z < 99.f) ++behind;  // the lips' front is at z ~ 99
  EXPECT_EQ(behind, m.vertex_count() - (1 + o.rows * ring));
}

// The eyes are open (docs: assets/head/README.md): each fissure is one boundary loop, walked
// one way by its triangles, round the eyeball's centre and outside the eyeball, as wide as the
// canthi are apart; the eye landmarks lie on the lid margins, which lie on the lid surface
// about the eyeball.
TEST(SampleHead, EachEyeIsOneLoopBetweenTheLidMargins) {
  const SampleHead& h = Head();
  const MeshData& m = h.mesh;
  const auto loops = EyeBoundary(m);
  for (int e = 0; e < 2; ++e) {
    const float sx = e == 0 ? -1.f : 1.f;
    const auto& edges = loops[size_t(e)];
    ASSERT_GE(edges.size(), 10u) << e;
    // Consistent orientation: each point has one outgoing and one incoming boundary edge, and
    // following them from any point visits every edge once (one loop, not several).
    std::map<uint32_t, uint32_t> next;
    std::map<uint32_t, int> in;
    for (const auto& [a, b] : edges) {
      ASSERT_FALSE(next.count(a)) << "two boundary edges leave point " << a;
      next[a] = b;
      in[b]++;
    }
    for (const auto& [a, b] : edges) ASSERT_EQ(in[a], 1) << a;
    std::vector<uint32_t> loop{edges[0].first};
    while (true) {
      const uint32_t n = next.at(loop.back());
      if (n == loop[0]) break;
      loop.push_back(n);
      ASSERT_LE(loop.size(), edges.size());
    }
    EXPECT_EQ(loop.size(), edges.size()) << "eye " << e << " has more than one boundary loop";
    // Its width is the canthi's distance (within a column's spacing, ~1.2 mm), and it winds
    // once round the eyeball's centre seen from the front.
    float lo = 1e9f, hi = -1e9f;
    double winding = 0;
    const float3 c{sx * kSampleHeadEyeCentre.x, kSampleHeadEyeCentre.y, kSampleHeadEyeCentre.z};
    for (size_t k = 0; k < loop.size(); ++k) {
      const float3 p = m.positions[loop[k]], q = m.positions[loop[(k + 1) % loop.size()]];
      lo = std::min(lo, std::fabs(p.x));
      hi = std::max(hi, std::fabs(p.x));
      winding += std::atan2((p.x - c.x) * (q.y - c.y) - (p.y - c.y) * (q.x - c.x),
                            (p.x - c.x) * (q.x - c.x) + (p.y - c.y) * (q.y - c.y));
      // The loop (the rolls' ends) stays outside the eyeball.
      EXPECT_GE(Length(p - c), kSampleHeadEyeballRadius + kSampleHeadLidRollGap - 1e-3f) << k;
    }
    EXPECT_NEAR(lo, kSampleHeadInnerCanthusX, 1.2f) << e;
    EXPECT_NEAR(hi, kSampleHeadOuterCanthusX, 1.2f) << e;
    EXPECT_NEAR(std::fabs(winding), 2 * 3.14159265, 1e-3) << e;
  }
  // Landmarks: the corners (36/39 right, 45/42 left) 0.5 mm inside the canthi on the upper
  // margin, the upper lid's points (37-38, 43-44) on the upper margin, the lower's (40-41,
  // 46-47) on the lower one (within 0.05 mm: the margin is a polyline through points on the
  // curve, about 1 mm apart); the lid margin on the lid surface, 0-2 mm outside the eyeball.
  const std::vector<float3>& L = h.landmarks;
  for (int l : {36, 39, 42, 45}) {
    const float ax = std::fabs(L[l].x);
    EXPECT_TRUE(std::fabs(ax - kSampleHeadInnerCanthusX - 0.5f) < 1e-3f ||
                std::fabs(ax - kSampleHeadOuterCanthusX + 0.5f) < 1e-3f) << l;
    EXPECT_NEAR(L[l].y, SampleHeadUpperLidY(ax), 0.05f) << l;
  }
  for (int l : {37, 38, 43, 44}) EXPECT_NEAR(L[l].y, SampleHeadUpperLidY(std::fabs(L[l].x)), 0.05f) << l;
  for (int l : {40, 41, 46, 47}) EXPECT_NEAR(L[l].y, SampleHeadLowerLidY(std::fabs(L[l].x)), 0.05f) << l;
  for (int l : {37, 38, 40, 41, 43, 44, 46, 47}) {
    const float3 c{L[l].x < 0 ? -kSampleHeadEyeCentre.x : kSampleHeadEyeCentre.x,
                   kSampleHeadEyeCentre.y, kSampleHeadEyeCentre.z};
    EXPECT_GT(Length(L[l] - c), kSampleHeadEyeballRadius) << l;
    EXPECT_LT(Length(L[l] - c), kSampleHeadEyeballRadius + 2.f) << l;
  }
  // The opening is open: upper above lower by the almond's height at x = 26 (10 mm across at
  // mid-fissure times sin(pi * 10 / 29)).
  const float t26 = (26.f - kSampleHeadInnerCanthusX) / (kSampleHeadOuterCanthusX - kSampleHeadInnerCanthusX);
  EXPECT_NEAR(L[43].y - L[47].y,
              (kSampleHeadLidOpenUp + kSampleHeadLidOpenDown) * std::sin(3.14159265f * t26), 0.1f);
  // Each landmark lies on a mesh edge (the margin's polyline), not inside the opening.
  for (int l = 36; l <= 47; ++l) {
    float best = 1e9f;
    for (size_t t = 0; t < m.indices.size(); t += 3)
      for (int k = 0; k < 3; ++k) {
        const float3 a = m.positions[m.indices[t + k]], b = m.positions[m.indices[t + (k + 1) % 3]];
        const float u = std::clamp(Dot(L[l] - a, b - a) / std::max(LengthSquared(b - a), 1e-12f), 0.f, 1.f);
        best = std::min(best, Length(a + (b - a) * u - L[l]));
      }
    EXPECT_LT(best, 1e-4f) << l;
  }
}

// Every triangle has area in texture space (the curve wrinkles and thickness maps need it):
// the lip and lid rolls get slivers.
TEST(SampleHead, NoTriangleIsDegenerateInTextureSpace) {
  const MeshData& m = Head().mesh;
  size_t flat = 0;
  for (size_t t = 0; t < m.indices.size(); t += 3) {
    const float2 a = m.uvs[m.indices[t]], b = m.uvs[m.indices[t + 1]], c = m.uvs[m.indices[t + 2]];
    const double area = 0.5 * std::fabs(double(b.x - a.x) * (c.y - a.y) - double(b.y - a.y) * (c.x - a.x));
    if (!(area > 1e-12)) ++flat;
  }
  EXPECT_EQ(flat, 0u);
}

TEST(SampleHead, NoDegenerateTrianglesAndOutwardOrientation) {
  const MeshData& m = Head().mesh;
  const Box b = Bounds(m.positions);
  const float diag2 = LengthSquared(b.hi - b.lo);
  double volume = 0;
  const float3 c{0, 0, 10};  // a point inside the head
  for (size_t t = 0; t < m.indices.size(); t += 3) {
    const float3 p0 = m.positions[m.indices[t]], p1 = m.positions[m.indices[t + 1]],
                 p2 = m.positions[m.indices[t + 2]];
    const float area = 0.5f * Length(Cross(p1 - p0, p2 - p0));
    ASSERT_GT(area, 1e-10f * diag2) << "triangle " << t / 3;
    volume += Dot(p0 - c, Cross(p1 - c, p2 - c)) / 6.0;
  }
  // Outward-facing triangles enclose a positive volume about a point inside; an adult head
  // (with this short neck) is roughly 3.5-5.5 litres.
  EXPECT_GT(volume, 3.0e6);
  EXPECT_LT(volume, 6.5e6);
}

TEST(SampleHead, DenserOnTheForeheadThanAtTheBack) {
  const MeshData& m = Head().mesh;
  auto mean_edge = [&](auto in_region) {
    double sum = 0;
    size_t n = 0;
    for (size_t t = 0; t < m.indices.size(); t += 3)
      for (int k = 0; k < 3; ++k) {
        const float3 a = m.positions[m.indices[t + k]], b = m.positions[m.indices[t + (k + 1) % 3]];
        if (in_region(a) && in_region(b)) {
          sum += Length(a - b);
          ++n;
        }
      }
    return n ? sum / n : 0.0;
  };
  const double forehead = mean_edge([](float3 p) {
    return p.z > 50 && p.y > 30 && p.y < 70 && std::fabs(p.x) < 30;
  });
  const double back = mean_edge([](float3 p) {
    return p.z < -60 && p.y > 0 && p.y < 60 && std::fabs(p.x) < 30;
  });
  ASSERT_GT(forehead, 0);
  ASSERT_GT(back, 0);
  EXPECT_LT(forehead, 0.6 * back) << "forehead " << forehead << " mm, back " << back << " mm";
  EXPECT_LT(forehead, 2.5);  // fine enough for forehead wrinkles (docs/model.md §13: 2-12 mm wide)
}

TEST(SampleHead, UvsInUnitSquareWithDuplicatedSeam) {
  const MeshData& m = Head().mesh;
  std::multimap<std::tuple<float, float, float>, float> at_u0, at_u1;
  for (size_t i = 0; i < m.vertex_count(); ++i) {
    const float2 uv = m.uvs[i];
    ASSERT_GE(uv.x, 0.f);
    ASSERT_LE(uv.x, 1.f);
    ASSERT_GE(uv.y, 0.f);
    ASSERT_LE(uv.y, 1.f);
    const float3 p = m.positions[i];
    if (uv.x == 0.f) at_u0.insert({{p.x, p.y, p.z}, uv.y});
    if (uv.x == 1.f) at_u1.insert({{p.x, p.y, p.z}, uv.y});
  }
  const SampleHeadOptions o;
  EXPECT_EQ(at_u0.size(), size_t(o.rows));
  EXPECT_EQ(at_u1.size(), size_t(o.rows));
  size_t seam_in_front = 0;  // only next to the crown pole may the back seam reach z >= 0
  for (const auto& [pos, v] : at_u0) {
    auto it = at_u1.find(pos);
    ASSERT_NE(it, at_u1.end()) << "seam vertex without its u = 1 twin";
    EXPECT_EQ(it->second, v);
    EXPECT_NEAR(std::get<0>(pos), 0.f, 1e-6f) << "the seam is at the back midline";
    if (std::get<2>(pos) >= 0.f) ++seam_in_front;
  }
  EXPECT_LE(seam_in_front, 3u);
  // u follows the azimuth: the front midline (nose) is at u = 0.5.
  size_t front = 0;
  for (size_t i = 1; i < m.vertex_count(); ++i)
    if (m.positions[i].z > m.positions[front].z) front = i;
  EXPECT_NEAR(m.uvs[front].x, 0.5f, 0.01f);
}

TEST(SampleHead, NormalsAreUnitAndPointOutward) {
  const MeshData& m = Head().mesh;
  size_t outward = 0;
  for (size_t i = 0; i < m.vertex_count(); ++i) {
    ASSERT_NEAR(Length(m.normals[i]), 1.f, 1e-4f);
    if (Dot(m.normals[i], m.positions[i] - float3{0, -20, 0}) > 0) ++outward;
  }
  EXPECT_GT(outward, m.vertex_count() * 95 / 100);
}

TEST(SampleHead, Has68LandmarksOnTheSurface) {
  const SampleHead& h = Head();
  ASSERT_EQ(h.landmarks.size(), 68u);
  const MeshData& m = h.mesh;
  // Longest edge at each vertex.
  std::vector<float> local(m.vertex_count(), 0.f);
  for (size_t t = 0; t < m.indices.size(); t += 3)
    for (int k = 0; k < 3; ++k) {
      const uint32_t a = m.indices[t + k], b = m.indices[t + (k + 1) % 3];
      const float l = Length(m.positions[a] - m.positions[b]);
      local[a] = std::max(local[a], l);
      local[b] = std::max(local[b], l);
    }
  for (int l = 0; l < 68; ++l) {
    const float3 p = h.landmarks[l];
    size_t best = 0;
    for (size_t i = 1; i < m.vertex_count(); ++i)
      if (LengthSquared(m.positions[i] - p) < LengthSquared(m.positions[best] - p)) best = i;
    EXPECT_LE(Length(m.positions[best] - p), local[best]) << "landmark " << l;
    // Within 0.5 mm of the plane of some triangle at that vertex.
    float plane = 1e9f;
    for (size_t t = 0; t < m.indices.size(); t += 3) {
      if (m.indices[t] != best && m.indices[t + 1] != best && m.indices[t + 2] != best) continue;
      const float3 a = m.positions[m.indices[t]];
      const float3 n = NormalizeOr(Cross(m.positions[m.indices[t + 1]] - a,
                                         m.positions[m.indices[t + 2]] - a), {0, 0, 1});
      plane = std::min(plane, std::fabs(Dot(p - a, n)));
    }
    EXPECT_LT(plane, 0.5f) << "landmark " << l;
  }
}

TEST(SampleHead, LandmarksFollowTheIbugLayoutAndFacialProportions) {
  const std::vector<float3>& L = Head().landmarks;
  const Box b = Bounds(Head().mesh.positions);
  // 30 (nose tip) is the most forward landmark, on the midline.
  for (int l = 0; l < 68; ++l)
    if (l != 30) {
      EXPECT_LT(L[l].z, L[30].z) << l;
    }
  EXPECT_NEAR(L[30].x, 0.f, 1e-4f);
  // Eye corners: 36 is the subject's right outer corner (-X), 45 the left (+X); symmetric.
  EXPECT_LT(L[36].x, -30.f);
  EXPECT_GT(L[45].x, 30.f);
  EXPECT_NEAR(L[36].x, -L[45].x, 1e-3f);
  EXPECT_NEAR(L[36].y, L[45].y, 1e-3f);
  EXPECT_NEAR(L[36].z, L[45].z, 1e-3f);
  EXPECT_NEAR(L[39].x, -L[42].x, 1e-3f);
  // Biocular width ~ 85-100 mm, intercanthal ~ 28-36 mm (adult anthropometry).
  EXPECT_NEAR(L[45].x - L[36].x, 90.f, 8.f);
  EXPECT_NEAR(L[42].x - L[39].x, 32.f, 5.f);
  // Eyes about halfway down the head.
  const float eye_y = 0.5f * (L[36].y + L[39].y);
  EXPECT_NEAR((b.hi.y - eye_y) / (b.hi.y - b.lo.y), 0.5f, 0.05f);
  // Facial thirds: brow to nose base ~ nose base to chin.
  const float brow = 0.5f * (L[19].y + L[24].y), nose_base = L[33].y, chin = L[8].y;
  EXPECT_NEAR((brow - nose_base) / (brow - chin), 0.5f, 0.08f);
  // Mouth line about a third of the way from the nose base to the chin.
  EXPECT_NEAR((nose_base - L[62].y) / (nose_base - chin), 0.33f, 0.08f);
  // Jaw contour runs from the subject's right (x < 0) through the chin to the left.
  for (int l = 0; l < 8; ++l) EXPECT_LT(L[l].x, 0.f) << l;
  for (int l = 9; l <= 16; ++l) EXPECT_GT(L[l].x, 0.f) << l;
  EXPECT_NEAR(L[8].x, 0.f, 1e-4f);
  // Mouth width ~ 45-60 mm; mouth corners below the nose.
  EXPECT_NEAR(L[54].x - L[48].x, 52.f, 8.f);
  EXPECT_LT(L[48].y, L[33].y);
  // Brows above the eyes, nose bridge descending toward the tip.
  EXPECT_GT(L[19].y, L[37].y);
  for (int l = 27; l < 30; ++l) EXPECT_GT(L[l].y, L[l + 1].y) << l;
}

TEST(SampleHead, Deterministic) {
  const SampleHead a = MakeSampleHead(), b = MakeSampleHead();
  auto same = [](const auto& x, const auto& y) {
    return x.size() == y.size() &&
           std::memcmp(x.data(), y.data(), x.size() * sizeof(x[0])) == 0;
  };
  EXPECT_TRUE(same(a.mesh.positions, b.mesh.positions));
  EXPECT_TRUE(same(a.mesh.normals, b.mesh.normals));
  EXPECT_TRUE(same(a.mesh.uvs, b.mesh.uvs));
  EXPECT_TRUE(same(a.mesh.indices, b.mesh.indices));
  EXPECT_TRUE(same(a.landmarks, b.landmarks));
}

TEST(SampleHead, SmallerOptionsStillGiveAValidMesh) {
  SampleHeadOptions o;
  o.columns = 40;
  o.rows = 30;
  o.ears = false;
  const SampleHead h = MakeSampleHead(o);
  EXPECT_EQ(h.mesh.vertex_count(),
            1u + 30u * 41u + SlitColumns(h, o) * (2 * kSampleHeadLipRollRows + 1) +
                FissureColumns(h, o) * (2 * kSampleHeadLidRollRows + 1));
  WeldedMesh w;
  Diagnostics diag;
  const bool ok = WeldMesh(h.mesh, 0.f, &w, &diag);
  EXPECT_TRUE(ok) << diag.Format();
}

TEST(SampleHeadTool, MakeHeadWritesMeshAndLandmarks) {
  const std::string dir = test::TempDir();
  const test::ToolResult r = test::RunTool(
      {"make-head", "--out", dir + "/head.glb", "--landmarks", dir + "/head.landmarks.json"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find(std::to_string(Head().mesh.vertex_count()) + " vertices"),
            std::string::npos)
      << r.output;
  MeshData m;
  Diagnostics diag;
  ASSERT_TRUE(ImportMesh(dir + "/head.glb", "", &m, &diag)) << diag.Format();
  EXPECT_EQ(m.vertex_count(), Head().mesh.vertex_count());
  EXPECT_EQ(m.indices, Head().mesh.indices);
  Landmarks lm;
  ASSERT_TRUE(LoadLandmarks(dir + "/head.landmarks.json", &lm, &diag)) << diag.Format();
  ASSERT_EQ(lm.points.size(), 68u);
  for (int l = 0; l < 68; ++l) EXPECT_EQ(lm.points[l], Head().landmarks[l]) << l;
  // Bad usage.
  EXPECT_EQ(test::RunTool({"make-head"}).exit_code, 2);
  EXPECT_EQ(test::RunTool({"make-head", "--out", dir + "/x.glb", "--bogus"}).exit_code, 2);
  EXPECT_EQ(test::RunTool({"make-head", "--help"}).exit_code, 0);
  // Unwritable output.
  EXPECT_EQ(test::RunTool({"make-head", "--out", "/nonexistent-dir/x.glb"}).exit_code, 1);
}

// Writes assets/head (what `mimetic make-head` writes) when MIMETIC_HEAD_ASSET_DIR is set;
// for use before the command is registered in tools/main.cpp.
TEST(SampleHead, WritesAssetsOnRequest) {
  const char* dir = std::getenv("MIMETIC_HEAD_ASSET_DIR");
  if (!dir) GTEST_SKIP() << "set MIMETIC_HEAD_ASSET_DIR to write sample_head.glb there";
  Diagnostics d;
  const MeshData eyes = MakeSampleHeadEyes();
  ASSERT_TRUE(ExportMeshes(std::string(dir) + "/sample_head.glb", {{"head", &Head().mesh}, {"eyes", &eyes}}, &d))
      << d.Format();
  Landmarks lm;
  lm.points = Head().landmarks;
  ASSERT_TRUE(SaveLandmarks(std::string(dir) + "/sample_head.landmarks.json", lm, &d))
      << d.Format();
}

// Writes the documentation renders when MIMETIC_RENDER_DIR is set (the test-only path used
// to make docs/images/sample_head_*.png; `mimetic render` makes the same images).
TEST(SampleHead, WritesRendersOnRequest) {
  const char* dir = std::getenv("MIMETIC_RENDER_DIR");
  if (!dir) GTEST_SKIP() << "set MIMETIC_RENDER_DIR to write sample_head_*.png there";
  const struct {
    const char* name;
    float yaw;
    bool wire;
  } views[] = {{"sample_head_front", 0, false},
               {"sample_head_three_quarter", 35, false},
               {"sample_head_side", 90, false},
               {"sample_head_wire", 35, true}};
  for (const auto& v : views) {
    RenderOptions o;
    o.yaw_deg = v.yaw;
    o.wireframe = v.wire;
    Diagnostics d;
    ASSERT_TRUE(SavePng(std::string(dir) + "/" + v.name + ".png", RenderMesh(Head().mesh, o), &d))
        << d.Format();
  }
}

}  // namespace
}  // namespace mimetic

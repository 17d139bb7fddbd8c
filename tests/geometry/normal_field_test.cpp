// Tests for geometry/normal_field.h: normals averaged over a ball. On a roof (two planes meeting
// along a ridge) the answers follow from symmetry and from the definition by hand; on a bumpy
// sheet the grid search is checked against the definition summed over every pair of points.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <map>
#include <vector>

#include "geometry/normal_field.h"
#include "geometry/normals.h"

namespace mimetic {
namespace {

// A regular grid of (n+1) x (n+1) points over [-h, h]^2 in x, y, lifted by z(x, y), two
// counter-clockwise triangles per cell (normals toward +z).
template <class Height>
void Sheet(int n, double h, Height z, std::vector<float3>* points, std::vector<uint32_t>* tris) {
  const uint32_t base = uint32_t(points->size());
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const double x = -h + 2 * h * i / n, y = -h + 2 * h * j / n;
      points->push_back({float(x), float(y), float(z(x, y))});
    }
  auto id = [&](int i, int j) { return base + uint32_t(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      tris->insert(tris->end(), {id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      tris->insert(tris->end(), {id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
}

uint32_t Nearest(const std::vector<float3>& p, float3 q) {
  uint32_t best = 0;
  for (uint32_t k = 1; k < p.size(); ++k)
    if (Length(p[k] - q) < Length(p[best] - q)) best = k;
  return best;
}

TEST(NormalField, RadiusZeroGivesTheOwnNormals) {
  std::vector<float3> p;
  std::vector<uint32_t> t;
  Sheet(8, 1.0, [](double x, double y) { return 0.3 * x * x - 0.2 * x * y; }, &p, &t);
  NormalField field(p, t);
  const std::vector<float3> own = ComputeVertexNormals(p, t, {.share_by_position = true});
  EXPECT_EQ(field.At(0.f), own);
  EXPECT_EQ(field.At(-1.f), own);
  EXPECT_EQ(field.At(std::nanf("")), own);
}

// A roof: z = -0.5 |x| (slopes 1/2 each way, normals (±1, 0, 2)/sqrt5 facing up). By the mirror
// symmetry x -> -x of the grid, a ridge point's average is the bisector (0, 0, 1) for any radius.
// A point farther than r from the ridge sees one plane only: its own normal. A point closer than
// r leans toward the bisector, more the closer it is.
TEST(NormalField, RoofRidgeAveragesToTheBisector) {
  std::vector<float3> p;
  std::vector<uint32_t> t;
  Sheet(40, 2.0, [](double x, double) { return -0.5 * std::fabs(x); }, &p, &t);
  NormalField field(p, t);
  const float r = 0.5f;
  const std::vector<float3>& n = field.At(r);
  const float s5 = std::sqrt(5.f);
  const float3 left{-1 / s5, 0, 2 / s5}, right{1 / s5, 0, 2 / s5};
  const uint32_t ridge = Nearest(p, {0, 0, 0});
  EXPECT_NEAR(n[ridge].x, 0.f, 1e-6f);
  EXPECT_NEAR(n[ridge].y, 0.f, 1e-6f);
  EXPECT_NEAR(n[ridge].z, 1.f, 1e-6f);
  // x = 1.0 (grid step 0.1): every point within 0.5 lies at x >= 0.5 > 0.1, on the right
  // plane with its own normal exactly (the points at x = 0.1 mix both planes' triangles).
  const uint32_t far_right = Nearest(p, {1.0f, 0, -0.5f});
  EXPECT_NEAR(n[far_right].x, right.x, 1e-6f);
  EXPECT_NEAR(n[far_right].z, right.z, 1e-6f);
  EXPECT_NEAR(n[Nearest(p, {-1.0f, 0.3f, -0.5f})].x, left.x, 1e-6f);
  // Leaning: 0 < n.x < right.x, growing with the distance from the ridge.
  float last = 0.f;
  for (float x : {0.1f, 0.2f, 0.3f, 0.4f}) {
    const float nx = n[Nearest(p, {x, 0, -0.5f * x})].x;
    EXPECT_GT(nx, last) << "x " << x;
    EXPECT_LT(nx, right.x) << "x " << x;
    last = nx;
  }
  // And the result is kept: a second call returns the same vector.
  EXPECT_EQ(&field.At(r), &n);
}

// A two-sided sheet (top toward +z, a copy 0.05 below toward -z): both sides lie inside the
// ball and their normals nearly cancel (the mean is far shorter than 0.05), so every point keeps
// its own normal instead of a direction made of rounding.
TEST(NormalField, KeepsItsOwnNormalWhereBothSidesCancel) {
  std::vector<float3> p;
  std::vector<uint32_t> t;
  Sheet(10, 1.0, [](double, double) { return 0.0; }, &p, &t);
  const size_t top = p.size(), top_tris = t.size();
  Sheet(10, 1.0, [](double, double) { return -0.05; }, &p, &t);
  for (size_t k = top_tris; k < t.size(); k += 3) std::swap(t[k + 1], t[k + 2]);  // faces -z
  NormalField field(p, t);
  const std::vector<float3>& n = field.At(0.4f);
  for (size_t k = 0; k < top; ++k) EXPECT_NEAR(n[k].z, 1.f, 1e-6f) << k;
  for (size_t k = top; k < p.size(); ++k) EXPECT_NEAR(n[k].z, -1.f, 1e-6f) << k;
}

// A sheet with a Gaussian bump and uneven cells (areas differ from point to point). The field
// against its definition computed here the slow way: the sources aggregated cell by cell
// (side r / 8, cells anchored at the origin) and summed over every source; and against the
// unaggregated definition (every point its own source), which the aggregation approximates.
TEST(NormalField, MatchesItsDefinitionSummedOverEverySource) {
  std::vector<float3> p;
  std::vector<uint32_t> t;
  Sheet(24, 1.0, [](double x, double y) { return 0.4 * std::exp(-(x * x + 2 * y * y) / 0.15) + 0.1 * x * x * x; },
        &p, &t);
  for (float3& q : p) q.y *= 0.7f + 0.2f * q.x;  // uneven cells
  NormalField field(p, t);
  const std::vector<float3> own = ComputeVertexNormals(p, t, {.share_by_position = true});
  std::vector<double> area(p.size(), 0.0);
  for (size_t k = 0; k < t.size(); k += 3)
    for (int c = 0; c < 3; ++c) area[t[k + size_t(c)]] += TriangleArea(p[t[k]], p[t[k + 1]], p[t[k + 2]]) / 3;
  EXPECT_EQ(field.Areas(), area);
  auto unit = [](const double s[3]) {
    const double len = std::sqrt(s[0] * s[0] + s[1] * s[1] + s[2] * s[2]);
    return std::array<double, 3>{s[0] / len, s[1] / len, s[2] / len};
  };
  for (float r : {0.15f, 0.6f}) {
    const std::vector<float3>& n = field.At(r);
    // Sources: per cell, summed area, summed A n, area-weighted centroid.
    const double h = double(r) / 8;
    std::map<std::array<int64_t, 3>, std::array<double, 7>> cells;
    for (size_t b = 0; b < p.size(); ++b) {
      std::array<double, 7>& c = cells[{int64_t(std::floor(p[b].x / h)), int64_t(std::floor(p[b].y / h)),
                                       int64_t(std::floor(p[b].z / h))}];
      c[0] += area[b];
      c[1] += area[b] * own[b].x, c[2] += area[b] * own[b].y, c[3] += area[b] * own[b].z;
      c[4] += area[b] * p[b].x, c[5] += area[b] * p[b].y, c[6] += area[b] * p[b].z;
    }
    double worst = 0, worst_exact = 0;
    for (size_t a = 0; a < p.size(); ++a) {
      double s[3] = {0, 0, 0}, e[3] = {0, 0, 0};
      for (const auto& [key, c] : cells) {
        const float3 x{float(c[4] / c[0]), float(c[5] / c[0]), float(c[6] / c[0])};
        const double d = std::sqrt(std::pow(c[4] / c[0] - p[a].x, 2) + std::pow(c[5] / c[0] - p[a].y, 2) +
                                   std::pow(c[6] / c[0] - p[a].z, 2)) / r;
        (void)x;
        if (d >= 1) continue;
        const double w = (1 - d * d) * (1 - d * d);
        s[0] += w * c[1], s[1] += w * c[2], s[2] += w * c[3];
      }
      for (size_t b = 0; b < p.size(); ++b) {
        const double d = Length(p[b] - p[a]) / r;
        if (d >= 1) continue;
        const double w = (1 - d * d) * (1 - d * d) * area[b];
        e[0] += w * own[b].x, e[1] += w * own[b].y, e[2] += w * own[b].z;
      }
      const auto u = unit(s), v = unit(e);
      worst = std::max({worst, std::fabs(n[a].x - u[0]), std::fabs(n[a].y - u[1]), std::fabs(n[a].z - u[2])});
      worst_exact = std::max({worst_exact, std::fabs(n[a].x - v[0]), std::fabs(n[a].y - v[1]),
                              std::fabs(n[a].z - v[2])});
    }
    EXPECT_LT(worst, 2e-6) << "radius " << r;
    // The aggregation moves a normal by less than 1% (a cell is an eighth of the radius).
    EXPECT_LT(worst_exact, 0.01) << "radius " << r;
  }
  // And the bump is smoothed: the largest tilt from +z falls as r grows.
  auto tilt = [&](const std::vector<float3>& n) {
    float most = 0;
    for (const float3& m : n) most = std::max(most, std::sqrt(m.x * m.x + m.y * m.y));
    return most;
  };
  EXPECT_GT(tilt(field.At(0.f)), tilt(field.At(0.15f)));
  EXPECT_GT(tilt(field.At(0.15f)), tilt(field.At(0.6f)));
}

// One point at a time (the muscle table asks for the points a muscle reaches) gives At(r)'s
// floats, asked in any order, before or after the whole field; radius <= 0 the own normals; a
// point out of range (0, 0, 0).
TEST(NormalField, OnePointAtATimeIsTheWholeFieldsValue) {
  std::vector<float3> p;
  std::vector<uint32_t> t;
  Sheet(24, 1.0, [](double x, double y) { return 0.4 * std::exp(-(x * x + 2 * y * y) / 0.15) + 0.1 * x * x * x; },
        &p, &t);
  NormalField whole(p, t), single(p, t);
  for (float r : {0.15f, 0.6f}) {
    const std::vector<float3> n = whole.At(r);
    size_t differ = 0;
    // A stride coprime to the count visits every point, out of order.
    for (size_t k = 0, v = 0; k < p.size(); ++k, v = (v + 97) % p.size()) {
      const float3 got = single.At(r, uint32_t(v));
      EXPECT_EQ(got, n[v]) << r << " " << v;
      differ += got != whole.At(0.f)[v];
    }
    EXPECT_GT(differ, p.size() / 2) << "the radius changed too few normals to tell";
    EXPECT_EQ(single.At(r), n);  // the whole field after the points
  }
  EXPECT_EQ(single.At(0.f, 5), whole.At(0.f)[5]);
  EXPECT_EQ(single.At(0.3f, uint32_t(p.size())), (float3{0.f, 0.f, 0.f}));
}

}  // namespace
}  // namespace mimetic

// Per-frame wrinkle jobs (docs/model.md §4-8): known answers, volume checks (accept b, c), finite
// outputs on degenerate frames (accept g), validity tables and range-split determinism.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "wrinkles/offline/wrinkle_builder.h"
#include "wrinkles/runtime/profiles.h"
#include "wrinkles/runtime/strain_jobs.h"
#include "wrinkles/runtime/thickness_job.h"
#include "wrinkles/runtime/wrinkle_jobs.h"

namespace mimetic {
namespace {

constexpr double kPiD = 3.14159265358979323846;

struct Grid {
  std::vector<float3> points;
  std::vector<uint32_t> triangles;
  std::vector<float2> corner_uvs;  // uv = xy
};

// n x n points on [0, size]^2 (z = 0), two triangles per cell, counter-clockwise.
Grid MakeGrid(int n, float size) {
  Grid g;
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) g.points.push_back({size * i / (n - 1), size * j / (n - 1), 0.f});
  }
  for (int j = 0; j + 1 < n; ++j) {
    for (int i = 0; i + 1 < n; ++i) {
      const uint32_t a = j * n + i, b = a + 1, c = a + n, d = c + 1;
      g.triangles.insert(g.triangles.end(), {a, b, d, a, d, c});
    }
  }
  for (uint32_t v : g.triangles) g.corner_uvs.push_back({g.points[v].x, g.points[v].y});
  return g;
}

// Lumped area per point: a third of each incident triangle, in double.
std::vector<double> PointAreas(const std::vector<float3>& p, const std::vector<uint32_t>& t) {
  std::vector<double> a(p.size(), 0.0);
  for (size_t k = 0; k < t.size(); k += 3) {
    const float3 e1 = p[t[k + 1]] - p[t[k]], e2 = p[t[k + 2]] - p[t[k]];
    const double area = 0.5 * Length(Cross(e1, e2));
    for (int c = 0; c < 3; ++c) a[t[k + c]] += area / 3.0;
  }
  return a;
}

// --- docs/model.md §4: area ratio and thickness ----------------------------------------------------

TEST(AreaRatio, TriangleScaledByKnownFactors) {
  const std::vector<float3> rest = {{0, 0, 0}, {2, 0, 0}, {0, 1, 0}};
  const std::vector<float3> cur = {{0, 0, 0}, {2 * 0.7f, 0, 0}, {0, 1.3f, 0.f}};
  const std::vector<uint32_t> tri = {0, 1, 2};
  const std::vector<float> rest_area = ComputeTriangleAreas(rest, tri);
  EXPECT_NEAR(rest_area[0], 1.0, 1e-7);
  std::vector<float> ratio(1);
  TriangleAreaRatioJob job;
  job.positions = cur;
  job.triangles = tri;
  job.rest_areas = rest_area;
  job.end = 1;
  job.out_ratios = ratio;
  ASSERT_TRUE(job.Run());
  EXPECT_NEAR(ratio[0], 0.7 * 1.3, 1e-6);
}

TEST(Thickness, UniformCompressionKeepsVolume) {  // accept b, 002 eq. 3
  const Grid g = MakeGrid(21, 1.f);
  const size_t n = g.points.size();
  std::vector<float3> cur = g.points;
  for (float3& p : cur) p.x *= 0.8f;  // uniform compression: every triangle has r = 0.8
  const std::vector<float> rest_area = ComputeTriangleAreas(g.points, g.triangles);
  const CsrTable pt = BuildPointTriangles(g.triangles, n);
  std::vector<float> tri_ratio(rest_area.size()), r(n);
  TriangleAreaRatioJob tj{.positions = cur,
                          .triangles = g.triangles,
                          .rest_areas = rest_area,
                          .begin = 0,
                          .end = rest_area.size(),
                          .out_ratios = tri_ratio};
  ASSERT_TRUE(tj.Run());
  PointAreaRatioJob pj{.triangle_ratios = tri_ratio,
                       .offsets = pt.offsets,
                       .point_triangles = pt.items,
                       .begin = 0,
                       .end = n,
                       .out_ratios = r};
  ASSERT_TRUE(pj.Run());
  for (float v : r) EXPECT_NEAR(v, 0.8, 1e-5);
  std::vector<float> h(n);
  for (size_t p = 0; p < n; ++p) h[p] = 0.05f + 0.1f * g.points[p].x;  // per-point thickness
  const std::vector<float3> normals(n, float3{0, 0, 1});
  std::vector<float3> out(n);
  ThicknessJob th;
  th.positions = cur;
  th.normals = normals;
  th.area_ratios = r;
  th.thickness = h;
  th.end = n;
  th.out_positions = out;
  ASSERT_TRUE(th.Run());
  const std::vector<double> rest_s = PointAreas(g.points, g.triangles);
  const std::vector<double> cur_s = PointAreas(cur, g.triangles);
  double before = 0.0, after = 0.0;
  for (size_t p = 0; p < n; ++p) {
    const double moved = Dot(out[p] - cur[p], normals[p]);
    EXPECT_NEAR(moved, (1.0 / 0.8 - 1.0) * h[p], 1e-6);  // (1/r - 1) h
    const double h_new = h[p] + moved;                    // the layer's new thickness
    before += h[p] * rest_s[p];
    after += h_new * cur_s[p];
  }
  EXPECT_NEAR(after / before, 1.0, 1e-5);
}

TEST(Thickness, ClampsTheAreaRatio) {
  const std::vector<float3> x = {{0, 0, 0}, {1, 0, 0}, {2, 0, 0}};
  const std::vector<float3> nrm = {{0, 0, 1}, {0, 0, 1}, {0, 0, 1}};
  const std::vector<float> r = {0.01f, 0.f, NAN};
  std::vector<float3> out(3);
  ThicknessJob th;
  th.positions = x;
  th.normals = nrm;
  th.area_ratios = r;
  th.constant_thickness = 2.f;
  th.end = 3;
  th.out_positions = out;
  ASSERT_TRUE(th.Run());
  for (const float3& p : out) EXPECT_NEAR(p.z, (1.0 / 0.05 - 1.0) * 2.0, 1e-4);  // r_min = 0.05
  th.min_area_ratio = 0.f;
  EXPECT_FALSE(th.Validate());
}

// --- docs/model.md §5: shrinkage and compression ---------------------------------------------------

TEST(DirectionalShrinkage, TriangleScaledByKnownFactors) {  // 000 eq. 4
  const std::vector<float3> rest = {{0, 0, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}, {-1, -1, 0}};
  const std::vector<uint32_t> tris = {0, 1, 2, 0, 2, 3, 0, 3, 4, 0, 4, 1};
  std::vector<float2> uvs;
  for (uint32_t v : tris) uvs.push_back({rest[v].x, rest[v].y});
  const CsrTable pt = BuildPointTriangles(tris, rest.size());
  const float nn = 1.f / std::sqrt(1.25f);
  const std::vector<ShrinkageProbe> probes = {
      BuildShrinkageProbe(0, {nn, 0.5f * nn}, rest, tris, uvs, pt)};
  // Point 2 moves halfway to the centre (t3 = 1/2 on the +dp side); the -dp side is unchanged.
  std::vector<float3> cur = rest;
  cur[2] = {0.5f, 0.5f, 0.f};
  // By hand: the ray (1, 0.5) k meets the edge (1,-1)-(0.5,0.5) where 1 - 0.5 g = k and
  // -1 + 1.5 g = 0.5 k: g = 6/7, k = 4/7, so L'/L = 4/7 and s = 3/7; the other side s = 0.
  std::vector<float> s(1);
  DirectionalShrinkageJob job{.positions = cur,
                              .probes = probes,
                              .begin = 0,
                              .end = 1,
                              .out_shrinkage = s};
  ASSERT_TRUE(job.Run());
  EXPECT_NEAR(s[0], (3.0 / 7.0 + 0.0) / 2.0, 1e-6);
  // Uniform scaling by 0.6 about the centre: s = 1 - 0.6 on both sides.
  for (float3& p : cur) p = p * 0.6f;
  cur[2] = rest[2] * 0.6f;
  ASSERT_TRUE(job.Run());
  EXPECT_NEAR(s[0], 0.4, 1e-6);
  // Stretch by 1.5: s = -0.5 (negative when stretched).
  for (size_t i = 0; i < cur.size(); ++i) cur[i] = rest[i] * 1.5f;
  ASSERT_TRUE(job.Run());
  EXPECT_NEAR(s[0], -0.5, 1e-6);
  EXPECT_NEAR(SideShrinkage(0.f, 0.f, 0.5f), 1.f, 0.f);  // both edges collapsed
}

TEST(DirectionalShrinkage, OneDivisionFormMatchesTheRatioForm) {  // 000 eq. 4, two ways
  // SideShrinkageFromLengths (what the jobs run) against SideShrinkage on t = l / L.
  const float lengths[] = {0.f, 1e-6f, 0.3f, 1.f, 2.5f, 40.f};
  const float rests[] = {0.f, -1.f, 0.5f, 1.f, 3.f};
  const float betas[] = {0.f, 0.2f, 0.5f, 0.95f, 1.f};
  for (float l2 : lengths)
    for (float l3 : lengths)
      for (float r2 : rests)
        for (float r3 : rests)
          for (float beta : betas) {
            const float t2 = r2 > 0.f ? l2 / r2 : 1.f, t3 = r3 > 0.f ? l3 / r3 : 1.f;
            const double expected = SideShrinkage(t2, t3, beta);
            EXPECT_NEAR(SideShrinkageFromLengths(l2, l3, r2, r3, beta), expected,
                        1e-6 * std::max(1.0, std::fabs(expected)))
                << l2 << " " << l3 << " " << r2 << " " << r3 << " " << beta;
          }
  // At rest (l = L) s is exactly 0 for any beta, as SideShrinkage(1, 1, beta) is.
  for (float beta : {0.f, 0.1f, 0.3f, 0.7f, 1.f}) {
    EXPECT_EQ(SideShrinkage(1.f, 1.f, beta), 0.f) << beta;
    EXPECT_EQ(SideShrinkageFromLengths(0.7f, 3.1f, 0.7f, 3.1f, beta), 0.f) << beta;
  }
}

TEST(EdgeCompression, HandBuiltStar) {  // 001 eq. 9-10 with |cos|
  // Centre 0; neighbours 1 (1,0,0), 2 (0,1,0), 3 (-1,0,0), 4 (1,1,0); direction +x.
  const std::vector<float3> rest = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0}, {1, 1, 0}};
  const std::vector<uint32_t> rows = {0}, offsets = {0, 4}, nbr = {1, 2, 3, 4};
  const std::vector<float3> dir = {{1, 0, 0}};
  std::vector<float> L, w;
  ComputeCompressionWeights(rest, rows, dir, offsets, nbr, &L, &w);
  EXPECT_NEAR(w[0], 1.0, 1e-7);
  EXPECT_NEAR(w[1], 0.0, 1e-7);
  EXPECT_NEAR(w[2], 1.0, 1e-7);
  EXPECT_NEAR(w[3], std::sqrt(0.5), 1e-7);
  EXPECT_NEAR(L[3], std::sqrt(2.0), 1e-6);
  std::vector<float3> cur = rest;
  cur[1] = {0.7f, 0, 0};       // tau = 0.3
  cur[2] = {0, 0.1f, 0};       // tau = 0.9, weight 0
  cur[3] = {-1.2f, 0, 0};      // tau = -0.2
  cur[4] = {0.5f, 0.5f, 0};    // tau = 0.5
  std::vector<float> eps(1);
  EdgeCompressionJob job{.positions = cur,
                         .points = rows,
                         .offsets = offsets,
                         .neighbors = nbr,
                         .rest_lengths = L,
                         .weights = w,
                         .begin = 0,
                         .end = 1,
                         .out_compression = eps};
  ASSERT_TRUE(job.Run());
  const double c = std::sqrt(0.5);
  EXPECT_NEAR(eps[0], (0.3 - 0.2 + c * 0.5) / (1.0 + 1.0 + c), 1e-6);
}

// --- docs/model.md §6: muscle wrinkles -------------------------------------------------------------

TEST(MuscleWrinkle, KnownAnswerAlongTheNormal) {  // 001 eq. 4
  const std::vector<float3> nrm = {{0, 0, 1}, {0, 1, 0}};
  std::vector<float3> pos = {{0, 0, 0}, {5, 5, 5}};
  const std::vector<uint32_t> pts = {1};
  const std::vector<float> phase = {0.5f}, at = {0.6f}, eps = {0.5f};
  std::vector<float> amp(1);
  MuscleWrinkleJob job{.normals = nrm,
                       .points = pts,
                       .phase = phase,
                       .attenuation = at,
                       .compression = eps,
                       .half_cycle = 1.f,
                       .furrow_depth = 2.f,
                       .shape = 1.f,
                       .begin = 0,
                       .end = 1,
                       .positions = pos,
                       .out_amplitudes = amp,
                       .profile = {}};
  ASSERT_TRUE(job.Run());
  // H(0.5) with u = 1, k0 = 2, alpha = 1: t = -0.5, d = 2 (4 - 1)/4 = 1.5; H = 2(1.25)(-0.5) + 1.5.
  const double H = 2.0 * 1.25 * -0.5 + 1.5;
  const double W = H * std::cos(kPiD / 4) * 0.6;
  EXPECT_NEAR(amp[0], W, 1e-6);
  EXPECT_NEAR(pos[1].y, 5 + W, 1e-6);
  EXPECT_EQ(pos[1].x, 5.f);
  EXPECT_EQ(pos[0].z, 0.f);
  // Stretched (eps < 0): no wrinkle.
  const std::vector<float> stretched = {-0.2f};
  job.compression = stretched;
  ASSERT_TRUE(job.Run());
  EXPECT_EQ(amp[0], 0.f);
}

TEST(MuscleWrinkle, TheGateScalesEveryRowAndRefusesAFactorOutsideZeroOne) {  // docs/model.md §6
  const std::vector<float3> nrm = {{0, 0, 1}, {0, 1, 0}, {1, 0, 0}};
  const std::vector<uint32_t> pts = {1, 2};
  const std::vector<float> phase = {0.5f, 1.5f}, at = {0.6f, 1.f}, eps = {0.5f, 0.25f};
  // H by hand as above (u = 1, k0 = 2, alpha = 1, d = 1.5): t = -0.5 and t = 0.5, |t| = 0.5
  // both, so H = 1.5 - 2 * 1.25 * 0.5 = 0.25 on both rows.
  const double H = 1.5 - 2.0 * 1.25 * 0.5;
  const double W[2] = {H * std::cos(kPiD / 4) * 0.6, H * std::cos(kPiD / 2 * 0.75) * 1.0};
  const double G = 0.25 * 0.25 * (3 - 2 * 0.25);  // WrinkleGate(0.25, 1), by hand
  for (const bool fast : {false, true}) {
    std::vector<float3> pos(3, float3{1, 1, 1});
    std::vector<float> amp(2);
    std::vector<float> profile = {float(H * 0.6), float(H)};
    MuscleWrinkleJob job{.normals = nrm,
                         .points = pts,
                         .phase = phase,
                         .attenuation = at,
                         .compression = eps,
                         .half_cycle = 1.f,
                         .furrow_depth = 2.f,
                         .shape = 1.f,
                         .begin = 0,
                         .end = 2,
                         .positions = pos,
                         .out_amplitudes = amp,
                         .profile = fast ? span<const float>(profile) : span<const float>()};
    job.gate = WrinkleGate(0.25f, 1.f);
    ASSERT_TRUE(job.Run());
    EXPECT_NEAR(amp[0], G * W[0], 1e-6);
    EXPECT_NEAR(amp[1], G * W[1], 1e-6);
    EXPECT_NEAR(pos[1].y, 1 + G * W[0], 1e-6);
    EXPECT_NEAR(pos[2].x, 1 + G * W[1], 1e-6);
    EXPECT_EQ(pos[0].z, 1.f);
    for (const float bad : {-0.01f, 1.01f, std::nanf("")}) {
      job.gate = bad;
      EXPECT_FALSE(job.Validate()) << bad;
      EXPECT_FALSE(job.Run()) << bad;
    }
    job.gate = 0.f;  // shut: nothing moves
    const std::vector<float3> before = pos;
    ASSERT_TRUE(job.Run());
    EXPECT_EQ(amp[0], 0.f);
    EXPECT_EQ(pos[1].y, before[1].y);
  }
}

// --- docs/model.md §7-8: curve wrinkles ------------------------------------------------------------

TEST(CurveWrinkle, ValueKnownAnswers) {
  CurveWrinkleParams p;
  p.depth = 0.4f;
  p.width = 0.1f;
  p.rest_amplitude = 0.2f;
  // Bando, directional: S(0) = -d, M(0.5) = 0.8 * 0.5 + 0.2.
  EXPECT_NEAR(CurveWrinkleValue(p, 0.f, 0.5f, 1.f), -0.4 * 0.6, 1e-6);
  // l = 2w: d e^-2, M(-1) = 0.2 exp(-4).
  EXPECT_NEAR(CurveWrinkleValue(p, 0.2f, -1.f, 1.f), 0.4 * std::exp(-2.0) * 0.2 * std::exp(-4.0), 1e-7);
  // Area: C(0.5) = (0.2 - 1) 0.5 + 1 = 0.6.
  p.modulation = CurveWrinkleModulation::kArea;
  EXPECT_NEAR(CurveWrinkleValue(p, 0.f, 0.f, 0.5f), -0.4 * 0.6, 1e-6);
  // Yang-Zhang (area): S = r = 0.8, a = 0.08, h = sqrt(h0^2 + (1 - 0.64) a0^2); f(0) = -h.
  p.profile = CurveWrinkleProfile::kYangZhang;
  const double h = std::sqrt(0.16 + 0.36 * 0.01);
  EXPECT_NEAR(CurveWrinkleValue(p, 0.f, 0.f, 0.8f), -h, 1e-6);
  EXPECT_NEAR(CurveWrinkleValue(p, 0.08f, 0.f, 0.8f), 0.0, 1e-6);       // f(a) = 0
  EXPECT_NEAR(CurveWrinkleValue(p, 0.16f, 0.f, 0.8f), h / 8, 1e-6);     // f(2a) = h/8
  EXPECT_EQ(CurveWrinkleValue(p, 0.6f, 0.f, 0.8f), 0.f);               // beyond A
  // Exact variant at rest gives h0.
  p.profile = CurveWrinkleProfile::kYangZhangExact;
  p.rest_length = float(YangZhangSpanLength(0.1, 0.4, YangZhangSpan::kFlank));
  EXPECT_NEAR(CurveWrinkleValue(p, 0.f, 0.f, 1.f), -0.4, 1e-5);
}

TEST(CurveWrinkle, StraightFurrowKeepsVolume) {  // accept c, 000 eq. 3
  const Grid g = MakeGrid(401, 1.f);
  const size_t n = g.points.size();
  CurveWrinkleSpec spec;
  spec.control[0] = {0.5f, -0.5f};
  spec.control[1] = {0.5f, 0.1667f};
  spec.control[2] = {0.5f, 0.8333f};
  spec.control[3] = {0.5f, 1.5f};
  spec.depth = 0.01f;
  spec.width = 0.02f;
  spec.rest_amplitude = 1.f;  // M = 1 at rest
  CurveWrinkleTable table;
  Diagnostics diag;
  ASSERT_TRUE(BuildCurveWrinkleTable({&spec, 1}, g.points, g.triangles, g.corner_uvs, "w", &table, &diag));
  std::vector<float> s(table.probes.size());
  DirectionalShrinkageJob sj{.positions = g.points,
                             .probes = table.probes,
                             .begin = 0,
                             .end = table.probes.size(),
                             .out_shrinkage = s};
  ASSERT_TRUE(sj.Run());
  for (float v : s) ASSERT_NEAR(v, 0.f, 1e-6f);
  const std::vector<float3> nrm(n, float3{0, 0, 1});
  std::vector<float3> pos = g.points;
  CurveWrinkleJob job;
  job.normals = nrm;
  job.wrinkles = table.wrinkles;
  job.points = table.points;
  job.offsets = table.offsets;
  job.entries = table.entries;
  job.entry_shrinkage = s;
  job.end = table.points.size();
  job.positions = pos;
  ASSERT_TRUE(job.Run());
  // Volume under the piecewise-linear surface: sum of triangle area times mean height.
  double net = 0.0, furrow = 0.0;
  for (size_t k = 0; k < g.triangles.size(); k += 3) {
    const float3 a = g.points[g.triangles[k]], b = g.points[g.triangles[k + 1]],
                 c = g.points[g.triangles[k + 2]];
    const double area = 0.5 * Length(Cross(b - a, c - a));
    double z = 0.0, zabs = 0.0;
    for (int q = 0; q < 3; ++q) {
      z += pos[g.triangles[k + q]].z;
      zabs += std::fabs(pos[g.triangles[k + q]].z);
    }
    net += area * z / 3.0;
    furrow += area * zabs / 3.0;
  }
  // Integral of |S| across the furrow is 2 * (2 d w / e) per unit length (furrow = bulge).
  const double expected_abs = 4.0 * 0.01 * 0.02 / std::exp(1.0);
  EXPECT_NEAR(furrow / expected_abs, 1.0, 0.02);
  EXPECT_LT(std::fabs(net), 0.01 * expected_abs) << "net " << net;
  // The furrow line itself sinks by d.
  EXPECT_NEAR(pos[200 * 401 + 200].z, -0.01, 1e-6);
}

// --- accept g: finite outputs on degenerate frames --------------------------------------------

TEST(Degenerate, AllOutputsFinite) {
  const Grid g = MakeGrid(9, 1.f);
  const size_t n = g.points.size();
  const CsrTable pt = BuildPointTriangles(g.triangles, n);
  const CsrTable nb = BuildPointNeighbors(g.triangles, n);
  const std::vector<float> rest_area = ComputeTriangleAreas(g.points, g.triangles);
  // Curve wrinkles of every kind across the grid.
  std::vector<CurveWrinkleSpec> specs(6);
  for (int k = 0; k < 6; ++k) {
    CurveWrinkleSpec& c = specs[k];
    c.control[0] = {0.1f + 0.15f * k, -0.2f};
    c.control[1] = {0.3f, 0.4f};
    c.control[2] = {0.6f, 0.6f};
    c.control[3] = {0.9f - 0.1f * k, 1.2f};
    c.depth = 0.05f;
    c.width = 0.1f;
    c.rest_amplitude = 0.5f * (k % 3) / 2.f;
    c.modulation = k % 2 ? CurveWrinkleModulation::kArea : CurveWrinkleModulation::kDirectional;
    c.profile = static_cast<CurveWrinkleProfile>(k % 3);
  }
  CurveWrinkleTable ct;
  Diagnostics diag;
  ASSERT_TRUE(BuildCurveWrinkleTable(specs, g.points, g.triangles, g.corner_uvs, "w", &ct, &diag));
  WrinkleMuscleGeometry m;
  m.attachment = {-0.5f, 0.5f, 0.f};
  m.insertion = {0.5f, 0.5f, 0.f};
  m.zone_angle = 1.2f;
  m.radius = 2.f;
  MuscleWrinkleSpec ms;
  ms.lambda_w = 0.1f;
  ms.depth = 0.05f;
  ms.shape = 0.8f;
  ms.phi_c = 0.3f;
  MuscleWrinkleTable mt;
  ASSERT_TRUE(BuildMuscleWrinkleTable(ms, m, g.points, nb, "m", &mt, &diag));
  ASSERT_FALSE(mt.points.empty());

  std::mt19937 rng(7);
  std::uniform_real_distribution<float> unit(0.f, 1.f);
  for (int frame = 0; frame < 50; ++frame) {
    std::vector<float3> x = g.points;
    const float act = unit(rng);  // an activation in [0, 1] scales the random deformation
    for (float3& p : x) p += float3{unit(rng) - 0.5f, unit(rng) - 0.5f, unit(rng) - 0.5f} * act;
    // Triangle 5 collapses to a point; point 40 lands on its neighbour 41.
    x[g.triangles[16]] = x[g.triangles[15]];
    x[g.triangles[17]] = x[g.triangles[15]];
    x[40] = x[41];
    if (frame == 0) x.assign(n, float3{0.3f, 0.3f, 0.3f});  // everything collapsed
    std::vector<float> tr(rest_area.size()), r(n), eps(mt.points.size()), s(ct.probes.size());
    ASSERT_TRUE((TriangleAreaRatioJob{.positions = x,
                                      .triangles = g.triangles,
                                      .rest_areas = rest_area,
                                      .begin = 0,
                                      .end = rest_area.size(),
                                      .out_ratios = tr}.Run()));
    ASSERT_TRUE((PointAreaRatioJob{.triangle_ratios = tr,
                                   .offsets = pt.offsets,
                                   .point_triangles = pt.items,
                                   .begin = 0,
                                   .end = n,
                                   .out_ratios = r}.Run()));
    ASSERT_TRUE((EdgeCompressionJob{.positions = x,
                                    .points = mt.points,
                                    .offsets = mt.edge_offsets,
                                    .neighbors = mt.edge_neighbors,
                                    .rest_lengths = mt.edge_rest_lengths,
                                    .weights = mt.edge_weights,
                                    .begin = 0,
                                    .end = mt.points.size(),
                                    .out_compression = eps}
                     .Run()));
    ASSERT_TRUE((DirectionalShrinkageJob{.positions = x,
                                         .probes = ct.probes,
                                         .begin = 0,
                                         .end = ct.probes.size(),
                                         .out_shrinkage = s}.Run()));
    std::vector<float3> nrm(n);
    for (size_t p = 0; p < n; ++p) {  // random normals, some zero
      nrm[p] = NormalizeOr(float3{unit(rng) - 0.5f, unit(rng) - 0.5f, unit(rng) - 0.5f}, {});
    }
    nrm[40] = {0, 0, 0};
    std::vector<float3> out(n);
    ThicknessJob th;
    th.positions = x;
    th.normals = nrm;
    th.area_ratios = r;
    th.constant_thickness = 0.1f;
    th.end = n;
    th.out_positions = out;
    ASSERT_TRUE(th.Run());
    MuscleWrinkleJob mj{.normals = nrm,
                        .points = mt.points,
                        .phase = mt.phase,
                        .attenuation = mt.attenuation,
                        .compression = eps,
                        .half_cycle = mt.half_cycle,
                        .furrow_depth = mt.furrow_depth,
                        .shape = mt.shape,
                        .begin = 0,
                        .end = mt.points.size(),
                        .positions = out,
                        .out_amplitudes = {},
                        .profile = {}};
    ASSERT_TRUE(mj.Run());
    CurveWrinkleJob cj;
    cj.normals = nrm;
    cj.wrinkles = ct.wrinkles;
    cj.points = ct.points;
    cj.offsets = ct.offsets;
    cj.entries = ct.entries;
    cj.entry_shrinkage = s;
    cj.area_ratios = r;
    cj.end = ct.points.size();
    cj.positions = out;
    ASSERT_TRUE(cj.Run());
    for (float v : tr) ASSERT_TRUE(std::isfinite(v));
    for (float v : r) ASSERT_TRUE(std::isfinite(v));
    for (float v : eps) ASSERT_TRUE(std::isfinite(v) && v <= 1.f);
    for (float v : s) ASSERT_TRUE(std::isfinite(v) && v <= 1.f);
    for (const float3& p : out) ASSERT_TRUE(IsFinite(p)) << "frame " << frame;
  }
}

// --- validity tables and range splitting -----------------------------------------------------

// Runs `check` on a copy of `full` shortened by one element.
template <class T>
span<T> Short(span<T> s) {
  return s.first(s.size() - 1);
}

TEST(Validity, EverySpanOneShortIsRefused) {
  const Grid g = MakeGrid(4, 1.f);
  const size_t n = g.points.size();  // 16
  const CsrTable pt = BuildPointTriangles(g.triangles, n);
  const CsrTable nb = BuildPointNeighbors(g.triangles, n);
  const std::vector<float> ra = ComputeTriangleAreas(g.points, g.triangles);
  const size_t nt = ra.size();
  std::vector<float> tr(nt), r(n);
  std::vector<float3> out(n);
  const std::vector<float3> nrm(n, float3{0, 0, 1});

  TriangleAreaRatioJob tj{.positions = g.points,
                          .triangles = g.triangles,
                          .rest_areas = ra,
                          .begin = 0,
                          .end = nt,
                          .out_ratios = tr};
  EXPECT_TRUE(tj.Validate());
  { auto j = tj; j.positions = Short(j.positions); EXPECT_FALSE(j.Validate()); }
  { auto j = tj; j.triangles = Short(j.triangles); EXPECT_FALSE(j.Validate()); }
  { auto j = tj; j.rest_areas = Short(j.rest_areas); EXPECT_FALSE(j.Validate()); }
  { auto j = tj; j.out_ratios = Short(j.out_ratios); EXPECT_FALSE(j.Validate()); }
  { auto j = tj; j.begin = 3; j.end = 2; EXPECT_FALSE(j.Validate()); }

  PointAreaRatioJob pj{.triangle_ratios = tr,
                       .offsets = pt.offsets,
                       .point_triangles = pt.items,
                       .begin = 0,
                       .end = n,
                       .out_ratios = r};
  EXPECT_TRUE(pj.Validate());
  { auto j = pj; j.triangle_ratios = Short(j.triangle_ratios); EXPECT_FALSE(j.Validate()); }
  { auto j = pj; j.offsets = Short(j.offsets); EXPECT_FALSE(j.Validate()); }
  { auto j = pj; j.point_triangles = Short(j.point_triangles); EXPECT_FALSE(j.Validate()); }
  { auto j = pj; j.out_ratios = Short(j.out_ratios); EXPECT_FALSE(j.Validate()); }

  std::vector<uint32_t> rows(n);
  for (size_t p = 0; p < n; ++p) rows[p] = uint32_t(p);
  std::vector<float3> dirs(n, float3{1, 0, 0});
  std::vector<float> L, w, eps(n);
  ComputeCompressionWeights(g.points, rows, dirs, nb.offsets, nb.items, &L, &w);
  EdgeCompressionJob ej{.positions = g.points,
                        .points = rows,
                        .offsets = nb.offsets,
                        .neighbors = nb.items,
                        .rest_lengths = L,
                        .weights = w,
                        .begin = 0,
                        .end = n,
                        .out_compression = eps};
  EXPECT_TRUE(ej.Validate());
  { auto j = ej; j.positions = Short(j.positions); EXPECT_FALSE(j.Validate()); }
  { auto j = ej; j.points = Short(j.points); EXPECT_FALSE(j.Validate()); }
  { auto j = ej; j.offsets = Short(j.offsets); EXPECT_FALSE(j.Validate()); }
  { auto j = ej; j.neighbors = Short(j.neighbors); EXPECT_FALSE(j.Validate()); }
  { auto j = ej; j.rest_lengths = Short(j.rest_lengths); EXPECT_FALSE(j.Validate()); }
  { auto j = ej; j.weights = Short(j.weights); EXPECT_FALSE(j.Validate()); }
  { auto j = ej; j.out_compression = Short(j.out_compression); EXPECT_FALSE(j.Validate()); }
  std::vector<uint32_t> bad_offsets = nb.offsets;
  std::swap(bad_offsets[3], bad_offsets[4]);
  { auto j = ej; j.offsets = bad_offsets; EXPECT_FALSE(j.Validate()); }

  std::vector<ShrinkageProbe> probes;
  for (uint32_t p = 0; p < n; ++p) {
    probes.push_back(BuildShrinkageProbe(p, {0, 1}, g.points, g.triangles, g.corner_uvs, pt));
  }
  std::vector<float> s(n);
  DirectionalShrinkageJob sj{.positions = g.points,
                             .probes = probes,
                             .begin = 0,
                             .end = n,
                             .out_shrinkage = s};
  EXPECT_TRUE(sj.Validate());
  { auto j = sj; j.positions = Short(j.positions); EXPECT_FALSE(j.Validate()); }
  { auto j = sj; j.probes = Short(j.probes); EXPECT_FALSE(j.Validate()); }
  { auto j = sj; j.out_shrinkage = Short(j.out_shrinkage); EXPECT_FALSE(j.Validate()); }

  ThicknessJob th;
  th.positions = g.points;
  th.normals = nrm;
  th.area_ratios = r;
  th.thickness = ra;  // any n+ floats
  th.end = n;
  th.out_positions = out;
  std::vector<float> hh(n, 0.1f);
  th.thickness = hh;
  EXPECT_TRUE(th.Validate());
  { auto j = th; j.positions = Short(j.positions); EXPECT_FALSE(j.Validate()); }
  { auto j = th; j.normals = Short(j.normals); EXPECT_FALSE(j.Validate()); }
  { auto j = th; j.area_ratios = Short(j.area_ratios); EXPECT_FALSE(j.Validate()); }
  { auto j = th; j.thickness = Short(j.thickness); EXPECT_FALSE(j.Validate()); }
  { auto j = th; j.out_positions = Short(j.out_positions); EXPECT_FALSE(j.Validate()); }

  // Muscle wrinkles over every point (row i = point i; the last row uses the last point).
  std::vector<float> ph(n, 0.1f), at(n, 1.f), amp(n);
  MuscleWrinkleJob mj{.normals = nrm,
                      .points = rows,
                      .phase = ph,
                      .attenuation = at,
                      .compression = eps,
                      .half_cycle = 1.f,
                      .furrow_depth = 0.1f,
                      .shape = 1.f,
                      .begin = 0,
                      .end = n,
                      .positions = out,
                      .out_amplitudes = amp,
                      .profile = {}};
  EXPECT_TRUE(mj.Validate());
  { auto j = mj; j.normals = Short(j.normals); EXPECT_FALSE(j.Validate()); }
  { auto j = mj; j.points = Short(j.points); EXPECT_FALSE(j.Validate()); }
  { auto j = mj; j.phase = Short(j.phase); EXPECT_FALSE(j.Validate()); }
  { auto j = mj; j.attenuation = Short(j.attenuation); EXPECT_FALSE(j.Validate()); }
  { auto j = mj; j.compression = Short(j.compression); EXPECT_FALSE(j.Validate()); }
  { auto j = mj; j.positions = Short(j.positions); EXPECT_FALSE(j.Validate()); }
  { auto j = mj; j.out_amplitudes = Short(j.out_amplitudes); EXPECT_FALSE(j.Validate()); }
  { auto j = mj; j.half_cycle = 0.f; EXPECT_FALSE(j.Validate()); }

  // Curve wrinkles: one entry per point, wrinkle 0 directional, wrinkle 1 area.
  const std::vector<CurveWrinkleParams> wr = {
      {CurveWrinkleProfile::kBando, CurveWrinkleModulation::kDirectional, 0.1f, 0.1f, 0.5f, 0.f},
      {CurveWrinkleProfile::kYangZhang, CurveWrinkleModulation::kArea, 0.1f, 0.1f, 0.5f, 0.f}};
  std::vector<uint32_t> off(n + 1);
  std::vector<CurveWrinkleEntry> ent(n);
  for (size_t p = 0; p < n; ++p) {
    off[p + 1] = uint32_t(p + 1);
    ent[p] = {uint32_t(p % 2), 0.01f * p};
  }
  CurveWrinkleJob cj{.normals = nrm,
                     .wrinkles = wr,
                     .points = rows,
                     .offsets = off,
                     .entries = ent,
                     .entry_shrinkage = s,
                     .area_ratios = r,
                     .begin = 0,
                     .end = n,
                     .positions = out,
                     .out_amplitudes = amp};
  EXPECT_TRUE(cj.Validate());
  { auto j = cj; j.normals = Short(j.normals); EXPECT_FALSE(j.Validate()); }
  { auto j = cj; j.wrinkles = Short(j.wrinkles); EXPECT_FALSE(j.Validate()); }
  { auto j = cj; j.points = Short(j.points); EXPECT_FALSE(j.Validate()); }
  { auto j = cj; j.offsets = Short(j.offsets); EXPECT_FALSE(j.Validate()); }
  { auto j = cj; j.entries = Short(j.entries); EXPECT_FALSE(j.Validate()); }
  { auto j = cj; j.entry_shrinkage = Short(j.entry_shrinkage); EXPECT_FALSE(j.Validate()); }
  { auto j = cj; j.area_ratios = Short(j.area_ratios); EXPECT_FALSE(j.Validate()); }
  { auto j = cj; j.positions = Short(j.positions); EXPECT_FALSE(j.Validate()); }
  { auto j = cj; j.out_amplitudes = Short(j.out_amplitudes); EXPECT_FALSE(j.Validate()); }

  // Run() leaves outputs untouched when invalid.
  std::vector<float> sentinel(n, 42.f);
  auto bad = pj;
  bad.out_ratios = sentinel;
  bad.offsets = Short(bad.offsets);
  EXPECT_FALSE(bad.Run());
  for (float v : sentinel) EXPECT_EQ(v, 42.f);
}

TEST(RangeSplit, BitIdentical) {
  const Grid g = MakeGrid(12, 1.f);
  const size_t n = g.points.size();
  const CsrTable pt = BuildPointTriangles(g.triangles, n);
  const CsrTable nb = BuildPointNeighbors(g.triangles, n);
  const std::vector<float> ra = ComputeTriangleAreas(g.points, g.triangles);
  std::vector<float3> x = g.points;
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> d(-0.03f, 0.03f);
  for (float3& p : x) p += float3{d(rng), d(rng), d(rng)};
  const std::vector<float3> nrm(n, float3{0, 0.6f, 0.8f});
  std::vector<uint32_t> rows(n);
  for (size_t p = 0; p < n; ++p) rows[p] = uint32_t(p);
  std::vector<float3> dirs(n, float3{0.6f, 0.8f, 0});
  std::vector<float> L, w;
  ComputeCompressionWeights(g.points, rows, dirs, nb.offsets, nb.items, &L, &w);
  std::vector<ShrinkageProbe> probes;
  for (uint32_t p = 0; p < n; ++p) {
    probes.push_back(BuildShrinkageProbe(p, {0.6f, 0.8f}, g.points, g.triangles, g.corner_uvs, pt));
  }
  CurveWrinkleSpec spec;
  spec.control[0] = {0.f, 0.2f};
  spec.control[1] = {0.4f, 0.6f};
  spec.control[2] = {0.6f, 0.3f};
  spec.control[3] = {1.f, 0.8f};
  spec.depth = 0.02f;
  spec.width = 0.05f;
  spec.rest_amplitude = 0.3f;
  CurveWrinkleTable ct;
  Diagnostics diag;
  ASSERT_TRUE(BuildCurveWrinkleTable({&spec, 1}, g.points, g.triangles, g.corner_uvs, "w", &ct, &diag));

  // Runs every job over [0, total) either at once or split at `k` (in its own row units).
  auto run_all = [&](bool split, std::vector<float3>* result) {
    const size_t nt = ra.size();
    std::vector<float> tr(nt), r(n), eps(n), s(n), cs(ct.probes.size());
    auto ranges = [&](size_t total, auto&& f) {
      if (!split) return f(size_t(0), total);
      const size_t k = total / 3 + 1;
      return f(size_t(0), k) && f(k, total);
    };
    EXPECT_TRUE(ranges(nt, [&](size_t b, size_t e) {
      return TriangleAreaRatioJob{.positions = x,
                                  .triangles = g.triangles,
                                  .rest_areas = ra,
                                  .begin = b,
                                  .end = e,
                                  .out_ratios = tr}.Run(); }));
    EXPECT_TRUE(ranges(n, [&](size_t b, size_t e) {
      return PointAreaRatioJob{.triangle_ratios = tr,
                               .offsets = pt.offsets,
                               .point_triangles = pt.items,
                               .begin = b,
                               .end = e,
                               .out_ratios = r}.Run(); }));
    EXPECT_TRUE(ranges(n, [&](size_t b, size_t e) {
      return EdgeCompressionJob{.positions = x,
                                .points = rows,
                                .offsets = nb.offsets,
                                .neighbors = nb.items,
                                .rest_lengths = L,
                                .weights = w,
                                .begin = b,
                                .end = e,
                                .out_compression = eps}.Run(); }));
    EXPECT_TRUE(ranges(n, [&](size_t b, size_t e) {
      return DirectionalShrinkageJob{.positions = x,
                                     .probes = probes,
                                     .begin = b,
                                     .end = e,
                                     .out_shrinkage = s}.Run(); }));
    EXPECT_TRUE(ranges(ct.probes.size(), [&](size_t b, size_t e) {
      return DirectionalShrinkageJob{.positions = x,
                                     .probes = ct.probes,
                                     .begin = b,
                                     .end = e,
                                     .out_shrinkage = cs}.Run(); }));
    result->assign(n, float3{});
    EXPECT_TRUE(ranges(n, [&](size_t b, size_t e) {
      ThicknessJob th;
      th.positions = x; th.normals = nrm; th.area_ratios = r; th.constant_thickness = 0.05f;
      th.begin = b; th.end = e; th.out_positions = *result;
      return th.Run(); }));
    std::vector<float> ph(n), at(n, 0.7f);
    for (size_t p = 0; p < n; ++p) ph[p] = 0.017f * p;
    EXPECT_TRUE(ranges(n, [&](size_t b, size_t e) {
      return MuscleWrinkleJob{.normals = nrm,
                              .points = rows,
                              .phase = ph,
                              .attenuation = at,
                              .compression = eps,
                              .half_cycle = 0.5f,
                              .furrow_depth = 0.02f,
                              .shape = 0.7f,
                              .begin = b,
                              .end = e,
                              .positions = *result,
                              .out_amplitudes = {},
                              .profile = {}}.Run(); }));
    EXPECT_TRUE(ranges(ct.points.size(), [&](size_t b, size_t e) {
      CurveWrinkleJob cj{.normals = nrm,
                         .wrinkles = ct.wrinkles,
                         .points = ct.points,
                         .offsets = ct.offsets,
                         .entries = ct.entries,
                         .entry_shrinkage = cs,
                         .area_ratios = r,
                         .begin = b,
                         .end = e,
                         .positions = *result,
                         .out_amplitudes = {}};
      return cj.Run(); }));
    // Strain outputs are part of the comparison too.
    for (size_t p = 0; p < n; ++p) result->push_back({r[p], eps[p], s[p]});
  };
  std::vector<float3> whole, parts;
  run_all(false, &whole);
  run_all(true, &parts);
  ASSERT_EQ(whole.size(), parts.size());
  EXPECT_EQ(std::memcmp(whole.data(), parts.data(), whole.size() * sizeof(float3)), 0);
  // And the result moved (the test is not vacuous).
  double moved = 0.0;
  for (size_t p = 0; p < n; ++p) moved += Length(whole[p] - x[p]);
  EXPECT_GT(moved, 0.0);
}

}  // namespace
}  // namespace mimetic

namespace mimetic {
namespace {

// The precomputed-profile path (what EvaluateJob runs) equals the general path.
TEST(MuscleWrinkle, PrecomputedProfileMatchesTheGeneralPath) {
  const size_t n = 40;
  std::vector<float3> nrm(n, float3{0, 0, 1}), a(n), b(n);
  std::vector<uint32_t> rows(n);
  std::vector<float> ph(n), at(n), eps(n), profile(n);
  for (size_t i = 0; i < n; ++i) {
    rows[i] = uint32_t(i);
    ph[i] = 0.05f * float(i);               // w in [0, 2u) with u = 1
    at[i] = 1.f - float(i) / float(n);
    eps[i] = -0.2f + 0.03f * float(i);
    profile[i] = MuscleWrinkleProfile(ph[i], 1.f, 0.3f, 0.7f, at[i]);
  }
  MuscleWrinkleJob general{.normals = nrm,
                           .points = rows,
                           .phase = ph,
                           .attenuation = at,
                           .compression = eps,
                           .half_cycle = 1.f,
                           .furrow_depth = 0.3f,
                           .shape = 0.7f,
                           .begin = 0,
                           .end = n,
                           .positions = a,
                           .out_amplitudes = {},
                           .profile = {}};
  MuscleWrinkleJob fast{.normals = nrm,
                        .points = rows,
                        .phase = {},
                        .attenuation = {},
                        .compression = eps,
                        .half_cycle = 0.f,
                        .furrow_depth = 0.f,
                        .shape = 0.f,
                        .begin = 0,
                        .end = n,
                        .positions = b,
                        .out_amplitudes = {},
                        .profile = profile};
  ASSERT_TRUE(general.Run());
  ASSERT_TRUE(fast.Run());
  for (size_t i = 0; i < n; ++i) EXPECT_EQ(a[i].z, b[i].z) << i;
  fast.profile = span<const float>(profile).first(n - 1);
  EXPECT_FALSE(fast.Validate());
}

}  // namespace
}  // namespace mimetic

namespace mimetic {
namespace {

// Entries with S(l) precomputed (what the builder stores for Bando) give the same bits as
// entries evaluated through CurveWrinkleValue.
TEST(CurveWrinkle, PrecomputedBandoProfileMatchesTheGeneralPath) {
  const size_t n = 30;
  const std::vector<CurveWrinkleParams> wr = {
      {CurveWrinkleProfile::kBando, CurveWrinkleModulation::kDirectional, 0.3f, 0.2f, 0.4f, 0.f},
      {CurveWrinkleProfile::kBando, CurveWrinkleModulation::kArea, 0.5f, 0.1f, 0.2f, 0.f}};
  std::vector<float3> nrm(n, float3{0, 0, 1}), a(n), b(n);
  std::vector<uint32_t> rows(n), off(n + 1);
  std::vector<CurveWrinkleEntry> plain(n), pre(n);
  std::vector<float> s(n), r(n);
  for (size_t i = 0; i < n; ++i) {
    rows[i] = uint32_t(i);
    off[i + 1] = uint32_t(i + 1);
    s[i] = -0.3f + 0.04f * float(i);
    r[i] = 0.5f + 0.04f * float(i);
    plain[i] = {uint32_t(i % 2), 0.02f * float(i)};
    pre[i] = plain[i];
    pre[i].profile = CurveProfile(pre[i].distance, wr[i % 2].depth, wr[i % 2].width);
    pre[i].has_profile = 1;
  }
  CurveWrinkleJob ja{.normals = nrm,
                     .wrinkles = wr,
                     .points = rows,
                     .offsets = off,
                     .entries = plain,
                     .entry_shrinkage = s,
                     .area_ratios = r,
                     .begin = 0,
                     .end = n,
                     .positions = a,
                     .out_amplitudes = {}};
  CurveWrinkleJob jb{.normals = nrm,
                     .wrinkles = wr,
                     .points = rows,
                     .offsets = off,
                     .entries = pre,
                     .entry_shrinkage = s,
                     .area_ratios = r,
                     .begin = 0,
                     .end = n,
                     .positions = b,
                     .out_amplitudes = {}};
  ASSERT_TRUE(ja.Run());
  ASSERT_TRUE(jb.Run());
  for (size_t i = 0; i < n; ++i) EXPECT_EQ(a[i].z, b[i].z) << i;
  EXPECT_NE(a[3].z, 0.f);
}

}  // namespace
}  // namespace mimetic

// Compile-time wrinkle tables (docs/model.md §5-7): Bezier distance against closed forms, muscle
// wrinkling regions on hand-built fans (001 eq. 1-3, 7, 12-15), shrinkage probes (000 eq. 4).
#include "wrinkles/offline/wrinkle_builder.h"

#include <gtest/gtest.h>

#include <cmath>

#include "wrinkles/offline/bezier.h"
#include "wrinkles/runtime/profiles.h"

namespace mimetic {
namespace {

constexpr double kDeg = 3.14159265358979323846 / 180.0;

TEST(Bezier, StraightLineDistanceIsClosedForm) {
  // Two parametrisations of the segment (0,0)-(3,0): uniform and strongly non-uniform.
  const float2 uniform[4] = {{0, 0}, {1, 0}, {2, 0}, {3, 0}};
  const float2 skewed[4] = {{0, 0}, {0.2f, 0}, {2.9f, 0}, {3, 0}};
  for (const float2* c : {uniform, skewed}) {
    EXPECT_NEAR(ClosestPointOnBezier(c, {1.5f, 0.7f}).distance, 0.7, 1e-6);
    EXPECT_NEAR(ClosestPointOnBezier(c, {2.25f, -0.4f}).distance, 0.4, 1e-6);
    EXPECT_NEAR(ClosestPointOnBezier(c, {-1.f, 1.f}).distance, std::sqrt(2.0), 1e-6);  // end
    EXPECT_NEAR(ClosestPointOnBezier(c, {4.f, -2.f}).distance, std::sqrt(5.0), 1e-6);
    const BezierClosest hit = ClosestPointOnBezier(c, {1.5f, 0.7f});
    EXPECT_NEAR(hit.point.x, 1.5, 1e-5);
    EXPECT_NEAR(std::fabs(hit.tangent.x), 1.0, 1e-6);
    EXPECT_NEAR(hit.tangent.y, 0.0, 1e-6);
  }
}

TEST(Bezier, QuarterCircleArc) {
  // The standard cubic quarter circle of radius 1 (k = 4/3 (sqrt 2 - 1)); its radius deviates
  // from 1 by at most 2.8e-4, so the distance from a point at radius rho is |rho - 1| to that.
  const float k = 0.5522847498f;
  const float2 c[4] = {{1, 0}, {1, k}, {k, 1}, {0, 1}};
  for (double rho : {0.3, 0.8, 1.0, 1.4}) {
    for (double deg : {3.0, 20.0, 45.0, 71.0, 88.0}) {
      const float2 p{float(rho * std::cos(deg * kDeg)), float(rho * std::sin(deg * kDeg))};
      const BezierClosest hit = ClosestPointOnBezier(c, p);
      EXPECT_NEAR(hit.distance, std::fabs(rho - 1.0), 3e-4) << rho << " " << deg;
      // Second method: brute-force sampling of the curve (2e5 samples).
      double best = 1e30;
      for (int i = 0; i <= 200000; ++i) {
        const double t = i / 200000.0, s = 1 - t;
        const double x = s * s * s * c[0].x + 3 * s * s * t * c[1].x + 3 * s * t * t * c[2].x + t * t * t * c[3].x;
        const double y = s * s * s * c[0].y + 3 * s * s * t * c[1].y + 3 * s * t * t * c[2].y + t * t * t * c[3].y;
        best = std::fmin(best, std::hypot(x - p.x, y - p.y));
      }
      EXPECT_NEAR(hit.distance, best, 2e-6) << rho << " " << deg;
      // At an interior closest point the tangent is perpendicular to the offset to the query,
      // and (near) perpendicular to the circle's radius.
      if (rho != 1.0) {
        const double ox = p.x - hit.point.x, oy = p.y - hit.point.y;
        EXPECT_NEAR((hit.tangent.x * ox + hit.tangent.y * oy) / std::hypot(ox, oy), 0.0, 1e-4);
        const double dot = hit.tangent.x * std::cos(deg * kDeg) + hit.tangent.y * std::sin(deg * kDeg);
        EXPECT_NEAR(dot, 0.0, 5e-3);
      }
    }
  }
  const float2 bad[4] = {{NAN, 0}, {1, 0}, {2, 0}, {3, 0}};
  EXPECT_TRUE(std::isinf(ClosestPointOnBezier(bad, {0, 0}).distance));
  const float2 point[4] = {{1, 1}, {1, 1}, {1, 1}, {1, 1}};  // degenerate curve
  EXPECT_NEAR(ClosestPointOnBezier(point, {4, 5}).distance, 5.0, 1e-6);
}

// The shortcut is never wrong (a second method: brute-force sampling of the curve, 2e4
// samples) and is conclusive well away from the curve and close to it: on an S curve, a loop
// and a straight segment, over a grid of queries and reaches.
TEST(Bezier, ReachClassificationIsNeverWrong) {
  const float2 s_curve[4] = {{0, 0}, {2, 3}, {1, -3}, {3, 0}};
  const float2 loop[4] = {{0, 0}, {4, 3}, {-1, 3}, {3, 0}};
  const float2 line[4] = {{0, 0}, {1, 0}, {2, 0}, {3, 0}};
  size_t rejected = 0, far = 0, within = 0;
  for (const float2* c : {s_curve, loop, line}) {
    for (int i = -6; i <= 14; ++i) {
      for (int j = -8; j <= 8; ++j) {
        const float2 p{0.3f * i, 0.45f * j};
        double best = 1e30;
        for (int k = 0; k <= 20000; ++k) {
          const double t = k / 20000.0, u = 1 - t;
          const double x = u * u * u * c[0].x + 3 * u * u * t * c[1].x + 3 * u * t * t * c[2].x + t * t * t * c[3].x;
          const double y = u * u * u * c[0].y + 3 * u * u * t * c[1].y + 3 * u * t * t * c[2].y + t * t * t * c[3].y;
          best = std::fmin(best, std::hypot(x - p.x, y - p.y));
        }
        for (double reach : {0.05, 0.2, 0.5, 1.0}) {
          const BezierReach near = ClassifyBezierReach(c, p, reach);
          const bool out = near == BezierReach::kBeyond;
          if (out) {
            ++rejected;
            EXPECT_GT(best, reach) << i << " " << j << " " << reach;
          }
          if (near == BezierReach::kWithin) {
            ++within;
            EXPECT_LE(best, reach + 1e-6) << i << " " << j << " " << reach;
          }
          // Within reach of a curve point 1/32 of the way along: the chord ends catch it.
          if (best < reach - 0.5) {
            EXPECT_EQ(near, BezierReach::kWithin) << i << " " << j;
          }
          if (best > 2 * reach + 0.2) {
            ++far;
            EXPECT_TRUE(out) << "not conclusive far from the curve: " << i << " " << j << " "
                             << reach << " at distance " << best;
          }
        }
      }
    }
  }
  EXPECT_GT(far, 1000u);
  EXPECT_GE(rejected, far);
  EXPECT_GT(within, 100u);
  const float2 bad[4] = {{NAN, 0}, {1, 0}, {2, 0}, {3, 0}};
  EXPECT_EQ(ClassifyBezierReach(bad, {100, 100}, 1.0), BezierReach::kUnsure);
  EXPECT_EQ(ClassifyBezierReach(line, {NAN, 0}, 1.0), BezierReach::kUnsure);
  EXPECT_EQ(ClassifyBezierReach(line, {100, 0}, NAN), BezierReach::kUnsure);
}

// A fan of points in the xy plane at distance D and angle theta (degrees) from the origin.
float3 Polar(double D, double deg) {
  return {float(D * std::cos(deg * kDeg)), float(D * std::sin(deg * kDeg)), 0.f};
}

TEST(MuscleRegion, LinearFanMatchesEq3) {  // 001 eq. 1-3, 6-7, 12
  WrinkleMuscleGeometry m;
  m.kind = WrinkleMuscleKind::kLinear;
  m.attachment = {0, 0, 0};
  m.insertion = {1, 0, 0};
  m.zone_angle = float(40 * kDeg);
  m.radius = 10.f;
  MuscleWrinkleSpec spec;
  spec.lambda_w = 0.3f;
  spec.count = 2;
  spec.depth = 0.2f;
  spec.shape = 1.f;
  spec.phi_c = float(20 * kDeg);
  // D, theta: in (5, 10), out (2, 0: lambda .2), in (9, 30: attenuated), out (12, 0: lambda
  // 1.2), in (10, 5), out (5, 45: gamma > 1), out (-3, 0: behind), in (4, -15).
  const std::vector<float3> pts = {Polar(5, 10), Polar(2, 0),  Polar(9, 30), Polar(12, 0),
                                   Polar(10, 5), Polar(5, 45), Polar(-3, 0), Polar(4, -15)};
  CsrTable adjacency;
  adjacency.offsets.assign(pts.size() + 1, 0);
  MuscleWrinkleTable table;
  Diagnostics diag;
  ASSERT_TRUE(BuildMuscleWrinkleTable(spec, m, pts, adjacency, "muscles[0].wrinkles", &table, &diag))
      << diag.Format();
  ASSERT_EQ(table.points, (std::vector<uint32_t>{0, 2, 4, 7}));
  const double u = 0.7 * 10 / 4;  // (1 - lambda_w) R / (2 n_w)
  EXPECT_NEAR(table.half_cycle, u, 1e-6);
  const double l[4] = {5 * std::cos(10 * kDeg), 9 * std::cos(30 * kDeg), 10 * std::cos(5 * kDeg),
                       4 * std::cos(15 * kDeg)};
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(table.phase[i], std::fmod(l[i] - 3.0, 2 * u), 1e-5) << i;
  EXPECT_NEAR(table.attenuation[0], 1.0, 1e-6);                        // 10 deg <= phi_c
  EXPECT_NEAR(table.attenuation[1], 1.0 - 0.5 * 1.25 * 0.5, 1e-5);     // q = (30-20)/(40-20)
  EXPECT_NEAR(table.attenuation[2], 1.0, 1e-6);
  EXPECT_NEAR(table.attenuation[3], 1.0, 1e-6);
  // Contraction direction x_i -> mA.
  EXPECT_NEAR(table.directions[1].x, -std::cos(30 * kDeg), 1e-6);
  EXPECT_NEAR(table.directions[1].y, -std::sin(30 * kDeg), 1e-6);
}

TEST(MuscleRegion, SheetMatchesEq13to15) {  // 001 eq. 13-15
  WrinkleMuscleGeometry m;
  m.kind = WrinkleMuscleKind::kSheet;
  m.attachment_line[0] = {0, -2, 0};
  m.attachment_line[1] = {0, 2, 0};
  m.insertion_line[0] = {4, -2, 0};
  m.insertion_line[1] = {4, 2, 0};
  m.length = 4.f;
  m.width = 4.f;
  MuscleWrinkleSpec spec;
  spec.lambda_w = 0.25f;
  spec.count = 1;
  spec.h_c = 1.f;
  const std::vector<float3> pts = {{2, 0.5f, 0}, {3, 1.5f, 0}, {0.5f, 0, 0}, {2, 2.5f, 0}, {2, 0, 1}};
  CsrTable adjacency;
  adjacency.offsets.assign(pts.size() + 1, 0);
  MuscleWrinkleTable table;
  Diagnostics diag;
  ASSERT_TRUE(BuildMuscleWrinkleTable(spec, m, pts, adjacency, "w", &table, &diag));
  ASSERT_EQ(table.points, (std::vector<uint32_t>{0, 1, 4}));
  const double u = 0.75 * 4 / 2;
  EXPECT_NEAR(table.half_cycle, u, 1e-6);
  EXPECT_NEAR(table.phase[0], 2 - 1, 1e-6);  // l - lambda_w Ls
  EXPECT_NEAR(table.phase[1], 3 - 1, 1e-6);
  EXPECT_NEAR(table.attenuation[0], 1.0, 1e-6);
  EXPECT_NEAR(table.attenuation[1], 0.6875, 1e-6);  // q = (1.5 - 1)/(2 - 1)
  EXPECT_NEAR(table.attenuation[2], 1.0, 1e-6);     // h = 1 = h_c
  EXPECT_NEAR(table.directions[0].x, 1.0, 1e-6);    // along the fiber
}

TEST(MuscleRegion, BadSpecsAreAllReported) {
  WrinkleMuscleGeometry m;
  m.attachment = {0, 0, 0};
  m.insertion = {1, 0, 0};
  m.zone_angle = 0.5f;
  m.radius = 1.f;
  MuscleWrinkleSpec spec;
  spec.lambda_w = 1.5f;
  spec.count = 0;
  spec.phi_c = 0.7f;
  spec.gate = std::nanf("");
  std::vector<float3> pts = {{0.5f, 0, 0}};
  CsrTable adjacency;
  adjacency.offsets.assign(2, 0);
  MuscleWrinkleTable table;
  Diagnostics diag;
  EXPECT_FALSE(BuildMuscleWrinkleTable(spec, m, pts, adjacency, "muscles[1].wrinkles", &table, &diag));
  EXPECT_EQ(diag.ErrorCount(), 4u) << diag.Format();
  EXPECT_TRUE(diag.Contains("muscles[1].wrinkles.lambda_w"));
  EXPECT_TRUE(diag.Contains("muscles[1].wrinkles.count"));
  EXPECT_TRUE(diag.Contains("muscles[1].wrinkles.phi_c"));
  EXPECT_NE(diag.Format().find("muscles[1].wrinkles.gate: got nan, expected an activation in [0, 1]"), std::string::npos)
      << diag.Format();
  // A gate above 1 alone.
  MuscleWrinkleSpec over;
  over.gate = 1.5f;
  Diagnostics d2;
  EXPECT_FALSE(BuildMuscleWrinkleTable(over, m, pts, adjacency, "w", &table, &d2));
  EXPECT_EQ(d2.ErrorCount(), 1u) << d2.Format();
  EXPECT_NE(d2.Format().find("w.gate: got 1.5, expected an activation in [0, 1] (0: no gate)"), std::string::npos)
      << d2.Format();
}

TEST(ShrinkageProbe, FindsBothSidesAndCrossing) {  // 000 eq. 4 geometry
  // Centre 0, corners 1 (1,-1), 2 (1,1), 3 (-1,1), 4 (-1,-1); uv = xy.
  const std::vector<float3> pts = {{0, 0, 0}, {1, -1, 0}, {1, 1, 0}, {-1, 1, 0}, {-1, -1, 0}};
  const std::vector<uint32_t> tris = {0, 1, 2, 0, 2, 3, 0, 3, 4, 0, 4, 1};
  std::vector<float2> uvs;
  for (uint32_t v : tris) uvs.push_back({pts[v].x, pts[v].y});
  const CsrTable pt = BuildPointTriangles(tris, pts.size());
  const float n = 1.f / std::sqrt(1.25f);
  const ShrinkageProbe probe = BuildShrinkageProbe(0, {1 * n, 0.5f * n}, pts, tris, uvs, pt);
  ASSERT_EQ(probe.side_count, 2u);
  // +dp hits triangle 0 at (1, 0.5): 3/4 of the way from (1,-1) to (1,1).
  EXPECT_EQ(probe.sides[0].v2, 1u);
  EXPECT_EQ(probe.sides[0].v3, 2u);
  EXPECT_NEAR(probe.sides[0].beta, 0.75, 1e-6);
  EXPECT_NEAR(probe.sides[0].rest_length2, std::sqrt(2.0), 1e-6);
  // -dp hits triangle 2 at (-1, -0.5): 3/4 of the way from (-1,1) to (-1,-1).
  EXPECT_EQ(probe.sides[1].v2, 3u);
  EXPECT_EQ(probe.sides[1].v3, 4u);
  EXPECT_NEAR(probe.sides[1].beta, 0.75, 1e-6);
  // A boundary point (corner 1) pointing out of the mesh has at most one side.
  EXPECT_LE(BuildShrinkageProbe(1, {1, 0}, pts, tris, uvs, pt).side_count, 1u);
}

TEST(CurveTable, StraightWrinkleOnAGrid) {
  // 11 x 11 grid on [0, 2] x [0, 2] in mesh units with uv = xy / 2 (scale 2 mesh units per
  // texture unit); a vertical furrow at u = 0.5 (x = 1).
  const int n = 11;
  std::vector<float3> pts;
  for (int j = 0; j < n; ++j) for (int i = 0; i < n; ++i) pts.push_back({0.2f * i, 0.2f * j, 0});
  std::vector<uint32_t> tris;
  for (int j = 0; j + 1 < n; ++j) {
    for (int i = 0; i + 1 < n; ++i) {
      const uint32_t a = j * n + i, b = a + 1, c = a + n, d = c + 1;
      tris.insert(tris.end(), {a, b, d, a, d, c});
    }
  }
  std::vector<float2> uvs;
  for (uint32_t v : tris) uvs.push_back({pts[v].x / 2, pts[v].y / 2});
  CurveWrinkleSpec spec;
  spec.control[0] = {0.5f, -1.f};
  spec.control[1] = {0.5f, 0.f};
  spec.control[2] = {0.5f, 1.f};
  spec.control[3] = {0.5f, 2.f};
  spec.depth = 0.1f;
  spec.width = 0.0825f;  // support 8 w = 0.66 mesh units: columns x = 0.4 .. 1.6
  spec.rest_amplitude = 0.5f;
  CurveWrinkleTable table;
  Diagnostics diag;
  ASSERT_TRUE(BuildCurveWrinkleTable({&spec, 1}, pts, tris, uvs, "wrinkles", &table, &diag))
      << diag.Format();
  ASSERT_EQ(table.offsets.size(), table.points.size() + 1);
  ASSERT_EQ(table.entries.size(), table.probes.size());
  EXPECT_EQ(table.points.size(), size_t(7 * n));
  for (size_t r = 0; r < table.points.size(); ++r) {
    const float3 x = pts[table.points[r]];
    EXPECT_NEAR(table.entries[r].distance, std::fabs(x.x - 1.0), 1e-5);  // mesh units
    const ShrinkageProbe& probe = table.probes[r];
    EXPECT_EQ(probe.point, table.points[r]);
    if (x.x > 0.1f && x.x < 1.9f && x.y > 0.1f && x.y < 1.9f) {
      EXPECT_EQ(probe.side_count, 2u);
    }
  }
  EXPECT_NEAR(CurveWrinkleSupport(spec), 0.66, 1e-6);
  EXPECT_NEAR(table.wrinkles[0].rest_length,
              YangZhangSpanLength(spec.width, spec.depth, YangZhangSpan::kFlank), 1e-6);

  spec.width = -1.f;
  spec.rest_amplitude = 2.f;
  Diagnostics bad;
  EXPECT_FALSE(BuildCurveWrinkleTable({&spec, 1}, pts, tris, uvs, "wrinkles", &table, &bad));
  EXPECT_TRUE(bad.Contains("wrinkles[0].width"));
  EXPECT_TRUE(bad.Contains("wrinkles[0].r"));
}

TEST(ThicknessMap, BilinearSamples) {
  const std::vector<uint8_t> img = {0, 255, 255, 0};  // 2 x 2
  std::vector<float> h;
  Diagnostics diag;
  const std::vector<float2> uvs = {{0.25f, 0.25f}, {0.75f, 0.25f}, {0.5f, 0.5f}, {0.f, 0.f}};
  ASSERT_TRUE(SampleThicknessMap(img, 2, 2, 4.f, uvs, "thickness_map", &h, &diag));
  EXPECT_NEAR(h[0], 0.f, 1e-6);
  EXPECT_NEAR(h[1], 4.f, 1e-6);
  EXPECT_NEAR(h[2], 2.f, 1e-6);  // centre: mean of the four
  EXPECT_NEAR(h[3], 0.f, 1e-6);  // clamped at the border
  EXPECT_FALSE(SampleThicknessMap(img, 3, 2, -1.f, uvs, "thickness_map", &h, &diag));
  EXPECT_EQ(diag.ErrorCount(), 2u);
}

}  // namespace
}  // namespace mimetic

// Fine-scale wrinkle textures (docs/model.md §20-22): direction fields, texture space, furrow
// carving and the normal map. Expectations from 000 eq. 1 and §3/§5, 003 eq. 3.1-3.2 and §4.1,
// computed here by hand or by a second method (brute force over all segments).
#include <algorithm>
#include <random>
#include "wrinkles/offline/fine_scale.h"

#include <gtest/gtest.h>

#include <cmath>

namespace mimetic {
namespace {



// An n x n grid of points on [0, 1]^2 (z = 0), two triangles per cell, uv = (x, 1 - y).
struct Grid {
  std::vector<float3> points;
  std::vector<uint32_t> triangles;
  std::vector<float2> corner_uvs;
  FineScaleMesh mesh() const { return {points, triangles, corner_uvs}; }
};
Grid MakeGrid(int n) {
  Grid g;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) g.points.push_back({float(i) / (n - 1), float(j) / (n - 1), 0.f});
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      const uint32_t a = j * n + i, b = a + 1, c = a + n, d = c + 1;
      for (uint32_t v : {a, b, d, a, d, c}) g.triangles.push_back(v);
    }
  for (uint32_t v : g.triangles) g.corner_uvs.push_back({g.points[v].x, 1.f - g.points[v].y});
  return g;
}

// A field image with direction dir(x, y) and magnitude mag(x, y) at pixel centres, mapped
// where mapped(x, y).
template <class Dir, class Mag, class Mapped>
FieldImage MakeField(int size, Dir dir, Mag mag, Mapped mapped) {
  FieldImage f;
  f.size = size;
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const float px = x + 0.5f, py = y + 0.5f;
      f.direction.push_back(dir(px, py));
      f.magnitude.push_back(mag(px, py));
      f.mapped.push_back(mapped(px, py) ? 1 : 0);
    }
  return f;
}

float SegDistance(float2 c, float2 p, float2 q) {
  const float dx = q.x - p.x, dy = q.y - p.y, l2 = dx * dx + dy * dy;
  float t = l2 > 0.f ? ((c.x - p.x) * dx + (c.y - p.y) * dy) / l2 : 0.f;
  t = std::fmin(1.f, std::fmax(0.f, t));
  return std::hypot(c.x - p.x - t * dx, c.y - p.y - t * dy);
}

TEST(FineScale, FurrowParametersAreEquationOneAtHandPoints) {
  // 000 eq. 1 at m = 0.5: N = floor(20) = 20, theta bound 0.3, D = 5, I = 0.75, W_h = 1, W_o = 7.
  FurrowParams p = FurrowParamsFor(FurrowParameterSet::kBando2002, 0.5f, 1.f);
  EXPECT_EQ(p.segments, 20);
  EXPECT_FLOAT_EQ(p.max_angle, 0.3f);
  EXPECT_FLOAT_EQ(p.length, 5.f);
  EXPECT_FLOAT_EQ(p.intensity, 0.75f);
  EXPECT_FLOAT_EQ(p.width, 1.f);
  EXPECT_FLOAT_EQ(p.spacing, 7.f);
  // m = 0.75: N = floor(15) = 15, 0.2, 5.5, 1 - 0.5625, 1.5, 10.
  p = FurrowParamsFor(FurrowParameterSet::kBando2002, 0.75f, 1.f);
  EXPECT_EQ(p.segments, 15);
  EXPECT_NEAR(p.max_angle, 0.2f, 1e-6f);
  EXPECT_FLOAT_EQ(p.length, 5.5f);
  EXPECT_FLOAT_EQ(p.intensity, 0.4375f);
  // Magnitudes clamp to [0, 1]; NaN counts as 0.
  EXPECT_EQ(FurrowParamsFor(FurrowParameterSet::kBando2002, 3.f, 1.f).segments, 10);
  EXPECT_EQ(FurrowParamsFor(FurrowParameterSet::kBando2002, NAN, 1.f).segments, 30);
  // 003 eq. 5.1-5.6 at x = 1, k_scale = 2: limit floor(20), angle 0.6, length 10, density 14,
  // width 2, depth 0.25 below white.
  p = FurrowParamsFor(FurrowParameterSet::kBando2001, 1.f, 2.f);
  EXPECT_EQ(p.segments, 20);
  EXPECT_FLOAT_EQ(p.max_angle, 0.6f);
  EXPECT_FLOAT_EQ(p.length, 10.f);
  EXPECT_FLOAT_EQ(p.spacing, 14.f);
  EXPECT_FLOAT_EQ(p.width, 2.f);
  EXPECT_FLOAT_EQ(p.intensity, 0.75f);
}

TEST(FineScale, HarmonicFieldIsLinearAcrossAStripAndInverseDistanceIsEquationThreeOne) {
  const int n = 9;
  Grid g = MakeGrid(n);
  std::vector<uint32_t> anchors;
  std::vector<float3> vectors;
  std::vector<float> weights;
  for (int j = 0; j < n; ++j) {  // left column (1, 0, 0), right column (0, 0.5, 0)
    anchors.push_back(j * n);
    vectors.push_back({1.f, 0.f, 0.f});
    anchors.push_back(j * n + n - 1);
    vectors.push_back({0.f, 0.5f, 0.f});
    weights.push_back(1.f);
    weights.push_back(1.f);
  }
  Diagnostics diag;
  std::vector<float3> field;
  ASSERT_TRUE(InterpolateDirectionField(g.mesh(), anchors, vectors, weights,
                                        FieldInterpolation::kHarmonic, "f", &field, &diag))
      << diag.Format();
  // The harmonic function with these boundary values on a strip is linear in x.
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const float x = float(i) / (n - 1);
      const float3 v = field[j * n + i];
      EXPECT_NEAR(v.x, 1.f - x, 1e-4f) << i << "," << j;
      EXPECT_NEAR(v.y, 0.5f * x, 1e-4f) << i << "," << j;
      EXPECT_NEAR(v.z, 0.f, 1e-6f);
    }
  // 003 eq. 3.1 with two anchors, lambda = (1, 3): at point (0.25, 0) the distances are 0.25
  // and 0.75, weights 4 and 4: the mean.
  const std::vector<uint32_t> two = {0, uint32_t(n - 1)};
  const std::vector<float3> tv = {{1.f, 0.f, 0.f}, {0.f, 1.f, 0.f}};
  const std::vector<float> tw = {1.f, 3.f};
  ASSERT_TRUE(InterpolateDirectionField(g.mesh(), two, tv, tw, FieldInterpolation::kInverseDistance,
                                        "f", &field, &diag));
  const float3 v = field[2];  // x = 0.25
  EXPECT_NEAR(v.x, 0.5f, 1e-6f);
  EXPECT_NEAR(v.y, 0.5f, 1e-6f);
  // At (0.5, 0.5): d1 = d2 = sqrt(0.5); weights 1 and 3 -> (0.25, 0.75).
  const float3 c = field[(n / 2) * n + n / 2];
  EXPECT_NEAR(c.x, 0.25f, 1e-6f);
  EXPECT_NEAR(c.y, 0.75f, 1e-6f);
  // Anchors keep their vectors.
  EXPECT_FLOAT_EQ(field[0].x, 1.f);
}

TEST(FineScale, TwoFieldsWithOneFactorisationEqualTwoSeparateSolves) {
  // A bumpy grid (cotangent weights differ everywhere); field A anchored at three points,
  // field B at two others: the joint solve treats each field's points that anchor only the
  // other field as unknowns.
  Grid g = MakeGrid(11);
  for (size_t p = 0; p < g.points.size(); ++p)
    g.points[p].z = 0.1f * std::sin(3.f * g.points[p].x) * std::cos(2.f * g.points[p].y);
  const std::vector<uint32_t> pa = {0, 60, 120}, pb = {10, 110};
  const std::vector<float3> va = {{1, 0, 0}, {0, 1, 0}, {0.5f, 0.5f, 0}}, vb = {{0, 0.3f, 0}, {0.6f, 0, 0}};
  const FieldAnchors both[2] = {{pa, va, {}}, {pb, vb, {}}};
  std::vector<float3> joint[2], a, b;
  Diagnostics diag;
  ASSERT_TRUE(InterpolateDirectionFields(g.mesh(), both, FieldInterpolation::kHarmonic, "f", joint, &diag))
      << diag.Format();
  ASSERT_TRUE(InterpolateDirectionField(g.mesh(), pa, va, {}, FieldInterpolation::kHarmonic, "f", &a, &diag));
  ASSERT_TRUE(InterpolateDirectionField(g.mesh(), pb, vb, {}, FieldInterpolation::kHarmonic, "f", &b, &diag));
  for (size_t p = 0; p < g.points.size(); ++p) {
    EXPECT_NEAR(joint[0][p].x, a[p].x, 1e-5f) << p;
    EXPECT_NEAR(joint[0][p].y, a[p].y, 1e-5f) << p;
    EXPECT_NEAR(joint[1][p].x, b[p].x, 1e-5f) << p;
    EXPECT_NEAR(joint[1][p].y, b[p].y, 1e-5f) << p;
  }
  // Each field keeps its own anchors and is harmonic at the other field's anchors: the value
  // at point 60 (an anchor of A) in field B is not B's anchor value but interpolated.
  EXPECT_GT(joint[0][60].y, 0.95f);  // (0, 1, 0) projected onto the bumpy tangent plane
  EXPECT_GT(joint[1][60].x, 0.f);
  EXPECT_LT(joint[1][60].x, 0.6f);
}

TEST(FineScale, FieldVectorsLieInTheTangentPlane) {
  Grid g = MakeGrid(5);
  const std::vector<uint32_t> a = {12};
  const std::vector<float3> v = {{0.3f, 0.4f, 0.5f}};  // a normal part of 0.5 on the z = 0 plane
  Diagnostics diag;
  std::vector<float3> field;
  ASSERT_TRUE(InterpolateDirectionField(g.mesh(), a, v, {}, FieldInterpolation::kHarmonic, "f",
                                        &field, &diag));
  for (const float3& f : field) {
    EXPECT_NEAR(f.z, 0.f, 1e-6f);
    EXPECT_NEAR(f.x, 0.3f, 1e-4f);  // one anchor: a constant field
    EXPECT_NEAR(f.y, 0.4f, 1e-4f);
  }
}

TEST(FineScale, ProjectionsFollowBando2001EquationThreeTwo) {
  // Four points on a unit cylinder about y through the origin, two heights.
  const std::vector<float3> pts = {{0, 0, 1}, {1, 0, 0}, {0, 2, 1}, {1, 2, 0}, {0, 1, -1}, {-1, 1, 0}};
  const std::vector<uint32_t> tris = {0, 1, 3, 0, 3, 2, 1, 4, 5};
  Diagnostics diag;
  std::vector<float2> uv;
  ASSERT_TRUE(MakeTextureSpace({pts, tris, {}}, TextureProjection::kCylindrical, false, "fs", &uv, &diag))
      << diag.Format();
  // s = acos(pz / r) for px > 0: (0, 0, 1) -> 0; (1, 0, 0) -> pi/2 -> u = 0.25; t = y -> v = 1 - y/2.
  EXPECT_NEAR(uv[0].x, 0.f, 1e-6f);
  EXPECT_NEAR(uv[0].y, 1.f, 1e-6f);
  EXPECT_NEAR(uv[1].x, 0.25f, 1e-6f);
  EXPECT_NEAR(uv[2].x, 0.25f, 1e-6f);
  EXPECT_NEAR(uv[2].y, 0.f, 1e-6f);
  // (0, 1, -1) -> pi -> 0.5; (-1, 1, 0) -> 3 pi / 2 -> 0.75.
  EXPECT_NEAR(uv[7].x, 0.5f, 1e-6f);
  EXPECT_NEAR(uv[8].x, 0.75f, 1e-6f);
  // Planar: x, 1 - y over the bounding square (2 x 2 here), centred.
  ASSERT_TRUE(MakeTextureSpace({pts, tris, {}}, TextureProjection::kPlanar, false, "fs", &uv, &diag));
  EXPECT_NEAR(uv[1].x, 0.5f + 1.f / 2.f, 1e-6f);
  EXPECT_NEAR(uv[1].y, 0.5f + 1.f / 2.f, 1e-6f);  // y = 0, centre y = 1
  // "uv" without uvs is an error naming the key.
  EXPECT_FALSE(MakeTextureSpace({pts, tris, {}}, TextureProjection::kUv, false, "fs", &uv, &diag));
  EXPECT_NE(diag.Format().find("fs.texture_space"), std::string::npos);
}

TEST(FineScale, DistortionMinimisationKeepsTheBoundaryAndMakesInteriorHarmonic) {
  // A grid whose interior points were pushed around: planar projection + minimisation puts
  // them back on the regular grid (the cotangent-harmonic map of a flat regular grid with its
  // boundary fixed is the identity).
  Grid g = MakeGrid(6);
  for (size_t p = 0; p < g.points.size(); ++p) {
    const float x = g.points[p].x, y = g.points[p].y;
    if (x > 0.f && x < 1.f && y > 0.f && y < 1.f) g.points[p].z = 0.05f * std::sin(7.f * p);
  }
  Diagnostics diag;
  std::vector<float2> uv;
  ASSERT_TRUE(MakeTextureSpace({g.points, g.triangles, {}}, TextureProjection::kPlanar, true, "fs",
                               &uv, &diag)) << diag.Format();
  for (size_t c = 0; c < g.triangles.size(); ++c) {
    const float3 p = g.points[g.triangles[c]];
    if (p.x == 0.f || p.x == 1.f || p.y == 0.f || p.y == 1.f) {  // boundary: the projection
      EXPECT_NEAR(uv[c].x, p.x, 1e-6f);
      EXPECT_NEAR(uv[c].y, 1.f - p.y, 1e-6f);
    }
  }
  // Interior: each point is the weighted mean of its neighbours; on a near-flat grid that is
  // close to its grid position.
  for (size_t c = 0; c < g.triangles.size(); ++c) {
    const float3 p = g.points[g.triangles[c]];
    EXPECT_NEAR(uv[c].x, p.x, 0.03f);
  }
}

// Carves a rotating field (circles about the centre) at constant m = 0.5 over a disk with a
// hole: crossings, border ends and budget ends all occur.
CarveResult CarveRotating(int size, uint64_t seed) {
  const float c = 0.5f * size;
  FieldImage f = MakeField(
      size,
      [&](float x, float y) {
        const float dx = x - c, dy = y - c, r = std::hypot(dx, dy);
        return r > 0.f ? float2{-dy / r, dx / r} : float2{1.f, 0.f};
      },
      [](float, float) { return 0.5f; },
      [&](float x, float y) {
        const float r = std::hypot(x - c, y - c);
        return r < 0.48f * size && r > 0.1f * size;
      });
  CarveOptions o;
  o.seed = seed;
  o.record = true;
  CarveResult r;
  CarveFurrows(f, o, &r);
  return r;
}

TEST(FineScale, FurrowsFollowTheirFieldWithinThePerturbationBound) {
  const int size = 256;
  const CarveResult r = CarveRotating(size, 7);
  ASSERT_GT(r.segments.size(), 500u);
  const float c = 0.5f * size;
  double sum = 0.0, worst = 0.0;
  for (const FurrowSegment& s : r.segments) {
    const float dx = s.q.x - s.p.x, dy = s.q.y - s.p.y;
    if (std::hypot(dx, dy) < 1.f) continue;  // a cut stub
    // The field at P, analytically: tangent of the circle through P.
    const float rx = s.p.x - c, ry = s.p.y - c, rl = std::hypot(rx, ry);
    const float tx = -ry / rl, ty = rx / rl;
    const float cosang = std::fabs(dx * tx + dy * ty) / std::hypot(dx, dy);
    const double ang = std::acos(std::fmin(1.f, cosang));  // furrows have no sign
    sum += ang;
    worst = std::fmax(worst, ang);
  }
  const double mean = sum / double(r.segments.size());
  const double theta = FurrowParamsFor(FurrowParameterSet::kBando2002, 0.5f, 1.f).max_angle;
  EXPECT_LT(mean, theta);                // the bound of eq. 1's theta
  EXPECT_NEAR(mean, theta / 2, 0.05);    // uniform theta in (-0.3, 0.3): mean |theta| = 0.15
  EXPECT_LT(worst, theta + 0.05);        // plus the field's change across a pixel
}

TEST(FineScale, AFurrowThatStopsEarlyEndsOnAnotherFurrowOrOnTheBorder) {
  const int size = 256;
  const CarveResult r = CarveRotating(size, 11);
  const float c = 0.5f * size;
  const int budget = FurrowParamsFor(FurrowParameterSet::kBando2002, 0.5f, 1.f).segments + 1;
  int early = 0, on_furrow = 0, on_border = 0;
  for (size_t fi = 0; fi < r.furrows.size(); ++fi) {
    const Furrow& f = r.furrows[fi];
    for (const FurrowSide& side : f.sides) {
      if (int(side.segments) >= budget) continue;
      ++early;
      // Brute force over every segment of every other furrow.
      float best = 1e9f;
      for (const FurrowSegment& s : r.segments)
        if (s.furrow != fi) best = std::fmin(best, SegDistance(side.end_point, s.p, s.q));
      const float rad = std::hypot(side.end_point.x - c, side.end_point.y - c);
      const bool border = std::fabs(rad - 0.48f * size) < 1.5f || std::fabs(rad - 0.1f * size) < 1.5f;
      if (best < 1e-3f) {
        ++on_furrow;
      } else if (border) {
        ++on_border;
      } else {
        ADD_FAILURE() << "furrow " << fi << " stopped after " << side.segments << " of "
                         << budget << " segments at (" << side.end_point.x << ", "
                         << side.end_point.y << "), " << best << " px from any other furrow";
      }
    }
  }
  EXPECT_GT(on_furrow, 10);
  EXPECT_GT(on_border, 10);
  EXPECT_EQ(early, on_furrow + on_border);
}

// What Draw leaves, against a brute force over the recorded segments (a second method: each
// pixel centre's distance to each segment). The height is 1 - (1 - I) times the box-filtered
// coverage of the deepest segment of width W_h (docs/model.md §21). Occupancy never marks a
// pixel no segment reaches: the scan phase starts a furrow at every free pixel in row order, so
// each mapped pixel it passed without starting one lay within W_o of a segment drawn before
// (the random phase's, or a scan furrow started earlier in row order). On a constant magnitude
// every segment has one set of parameters.
TEST(FineScale, TheHeightAndTheOccupancyAreWhatTheSegmentsDraw) {
  const int size = 128;
  const CarveResult r = CarveRotating(size, 13);
  ASSERT_GT(r.segments.size(), 100u);
  ASSERT_GT(r.scan_starts, 0u);
  const FurrowParams p = FurrowParamsFor(FurrowParameterSet::kBando2002, 0.5f, 1.f);
  const float c = 0.5f * size, half_width = 0.5f * p.width, depth = 1.f - p.intensity;
  // Row-order index of each furrow's start (random-phase furrows: before every pixel).
  const size_t randoms = r.random_starts;
  std::vector<long> start_at(r.furrows.size(), -1);
  std::vector<char> is_start(size_t(size) * size, 0);
  for (size_t f = randoms; f < r.furrows.size(); ++f) {
    const long at = long(r.furrows[f].start.y) * size + long(r.furrows[f].start.x);
    start_at[f] = at;
    is_start[size_t(at)] = 1;
  }
  int passed_over = 0;
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) {
      const float2 centre{x + 0.5f, y + 0.5f};
      const long at = long(y) * size + x;
      float before = 1e9f, expect = 1.f;
      for (const FurrowSegment& s : r.segments) {
        const float d = SegDistance(centre, s.p, s.q);
        if (start_at[s.furrow] < at) before = std::fmin(before, d);
        const float cover =
            std::fmin(1.f, std::fmax(0.f, std::fmin(d + 0.5f, half_width) - std::fmax(d - 0.5f, -half_width)));
        expect = std::fmin(expect, 1.f - depth * cover);
      }
      ASSERT_NEAR(r.height[size_t(at)], expect, 1e-4f) << "pixel " << x << ", " << y;
      const float rad = std::hypot(centre.x - c, centre.y - c);
      if (rad < 0.48f * size && rad > 0.1f * size && !is_start[size_t(at)]) {
        ++passed_over;
        ASSERT_LE(before, p.spacing + 1e-3f)
            << "pixel " << x << ", " << y << " was free and no furrow started there";
      }
    }
  EXPECT_GT(passed_over, size * size / 2);
}

TEST(FineScale, NoTwoFurrowsStartCloserThanTheirSpacing) {
  const CarveResult r = CarveRotating(192, 3);
  const float spacing = FurrowParamsFor(FurrowParameterSet::kBando2002, 0.5f, 1.f).spacing;
  ASSERT_GT(r.furrows.size(), 20u);
  EXPECT_GT(r.random_starts, 0u);
  for (size_t i = 0; i < r.furrows.size(); ++i)
    for (size_t j = i + 1; j < r.furrows.size(); ++j) {
      const float d = std::hypot(r.furrows[i].start.x - r.furrows[j].start.x,
                                 r.furrows[i].start.y - r.furrows[j].start.y);
      ASSERT_GE(d, spacing) << i << " " << j;
    }
  // And every start lies farther than W_o from every earlier furrow's centre line.
  for (size_t j = 0; j < r.furrows.size(); ++j)
    for (const FurrowSegment& s : r.segments)
      if (s.furrow < j) {
        ASSERT_GT(SegDistance(r.furrows[j].start, s.p, s.q), spacing);
      }
}

TEST(FineScale, DepthAndWidthGrowWithTheMagnitudeAsEquationOneSays) {
  // Horizontal field, m = 0.3 on the left half and 0.8 on the right (no crossing, no border
  // inside a half except where the halves meet).
  const int size = 256;
  const float m[2] = {0.3f, 0.8f};
  FieldImage f = MakeField(
      size, [](float, float) { return float2{1.f, 0.f}; },
      [&](float x, float) { return x < 128.f ? m[0] : m[1]; }, [](float, float) { return true; });
  CarveOptions o;
  o.seed = 5;
  o.record = true;
  CarveResult r;
  CarveFurrows(f, o, &r);
  for (int half = 0; half < 2; ++half) {
    const FurrowParams p = FurrowParamsFor(FurrowParameterSet::kBando2002, m[half], 1.f);
    // Inside the half, away from the middle and the edges.
    const int x0 = half ? 150 : 20, x1 = half ? 236 : 106;
    double ink = 0.0, length = 0.0;
    float deepest = 1.f;
    for (int y = 8; y < size - 8; ++y)
      for (int x = x0; x < x1; ++x) {
        const float h = r.height[size_t(y) * size + x];
        ink += 1.0 - h;
        deepest = std::fmin(deepest, h);
      }
    for (const FurrowSegment& s : r.segments) {  // the part of each segment inside the box
      const float a = std::fmax(float(x0), std::fmin(s.p.x, s.q.x));
      const float b = std::fmin(float(x1), std::fmax(s.p.x, s.q.x));
      const float my = 0.5f * (s.p.y + s.q.y);
      if (b > a && my >= 8.f && my < size - 8.f)
        length += (b - a) / std::fabs(s.q.x - s.p.x) * std::hypot(s.q.x - s.p.x, s.q.y - s.p.y);
    }
    // Depth: the darkest pixel is I (a line width over 1 covers a whole pixel: m = 0.8), or
    // 1 - (1 - I) W_h when the line is narrower than a pixel (m = 0.3: at most W_h of a pixel).
    const float expect = 1.f - (1.f - p.intensity) * std::fmin(1.f, p.width);
    EXPECT_NEAR(deepest, expect, 0.03f) << "m = " << m[half];
    // Width: the ink per unit of furrow length is (1 - I) W_h (box-filtered real width).
    const double width = ink / length / (1.0 - p.intensity);
    EXPECT_NEAR(width, p.width, 0.12 * p.width) << "m = " << m[half];
  }
}

TEST(FineScale, TheSameSeedGivesTheSameMapsWithOneOrTwoThreads) {
  Grid g = MakeGrid(12);
  FineScaleSpec spec;
  spec.fields[0].anchors = {{0, {0.6f, 0.f, 0.f}}, {143, {0.2f, 0.2f, 0.f}}};
  spec.fields[1].anchors = {{5, {0.f, 0.5f, 0.f}}};
  spec.k_noise = 0.1f;
  const std::vector<uint32_t> anchors[2] = {{0, 143}, {5}};
  FineScaleTextureOptions o;
  o.size = 160;
  o.seed = 42;
  FineScaleMaps a, b, c;
  Diagnostics diag;
  ASSERT_TRUE(MakeFineScaleMaps(spec, g.mesh(), anchors, o, &a, &diag)) << diag.Format();
  o.threads = 2;
  ASSERT_TRUE(MakeFineScaleMaps(spec, g.mesh(), anchors, o, &b, &diag));
  EXPECT_EQ(a.height[0], b.height[0]);
  EXPECT_EQ(a.height[1], b.height[1]);
  EXPECT_EQ(a.merged, b.merged);
  EXPECT_EQ(a.normal, b.normal);
  o.seed = 43;
  ASSERT_TRUE(MakeFineScaleMaps(spec, g.mesh(), anchors, o, &c, &diag));
  EXPECT_NE(a.height[0], c.height[0]);
  // The merge is the minimum of the two maps (before noise, so compare where noise is 0:
  // k_noise = 0 below).
  spec.k_noise = 0.f;
  ASSERT_TRUE(MakeFineScaleMaps(spec, g.mesh(), anchors, o, &c, &diag));
  for (size_t i = 0; i < c.merged.size(); ++i)
    ASSERT_EQ(c.merged[i], std::fmin(c.height[0][i], c.height[1][i]));
}

TEST(FineScale, BumpNormalMapIsTheNormalOfTheHeightSlope) {
  // h = 0.01 x: dh/dx = 0.01 inside; k_bump = 20 -> n = normalize(-0.2, 0, 1).
  const int size = 16;
  std::vector<float> h(size * size);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) h[y * size + x] = 0.01f * x;
  const std::vector<uint8_t> n = BumpNormalMap(h, size, 20.f, 1);
  const float len = std::sqrt(0.04f + 1.f);
  const uint8_t* o = &n[3 * (5 * size + 7)];
  EXPECT_EQ(o[0], uint8_t(std::lround(127.5f * (1.f - 0.2f / len))));
  EXPECT_EQ(o[1], 128);  // 127.5 rounds to 128
  EXPECT_EQ(o[2], uint8_t(std::lround(127.5f * (1.f + 1.f / len))));
  // A slope down the rows (h grows with y: the surface rises toward the bottom, i.e. falls
  // toward image-up): the normal leans up in the image (+y).
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x) h[y * size + x] = 0.01f * y;
  const std::vector<uint8_t> m = BumpNormalMap(h, size, 20.f, 1);
  EXPECT_GT(m[3 * (5 * size + 7) + 1], 128);
}

TEST(FineScale, RasterizedFieldsAreEveryPixelsTriangleWalkedInOrder) {
  // A brute force over every pixel and every triangle in order (the barycentric test and the
  // interpolation as docs/model.md says, each triangle's vectors in its own chart) against
  // RasterizeField and the two-field RasterizeFields, to the bit: overlapping triangles (the
  // later wins), slivers, triangles partly off the image, one folded over (negative area).
  const int size = 61;
  std::mt19937 rng{7u};
  std::uniform_real_distribution<float> u(-0.15f, 1.15f), z(-1.f, 1.f);
  std::vector<float3> pts;
  std::vector<uint32_t> tris;
  std::vector<float2> uvs;
  for (int t = 0; t < 60; ++t) {
    const float2 a{u(rng), u(rng)};
    float2 b{u(rng), u(rng)}, c{u(rng), u(rng)};
    if (t % 7 == 3) c = float2{0.5f * (a.x + b.x) + 1e-4f, 0.5f * (a.y + b.y)};  // a sliver
    if (t % 5 == 0) b = float2{a.x + 0.08f * z(rng), a.y + 0.08f * z(rng)}, c = float2{a.x + 0.08f * z(rng), a.y + 0.08f * z(rng)};
    for (float2 w : {a, b, c}) {
      tris.push_back(uint32_t(pts.size()));
      pts.push_back(float3{w.x, w.y, 0.1f * z(rng)});
      uvs.push_back(w);
    }
  }
  std::vector<float3> f1(pts.size()), f2(pts.size());
  for (size_t i = 0; i < pts.size(); ++i) {
    f1[i] = float3{z(rng), z(rng), 0.f};
    f2[i] = float3{0.3f * z(rng), z(rng), 0.05f};
  }
  f2[4] = float3{0.f, 0.f, 0.f};  // a vanishing vector
  const FineScaleMesh mesh{pts, tris, uvs};
  auto brute = [&](const std::vector<float3>& field) {
    FieldImage img;
    img.size = size;
    img.direction.assign(size_t(size) * size, float2{0.f, 0.f});
    img.magnitude.assign(size_t(size) * size, 0.f);
    img.mapped.assign(size_t(size) * size, 0);
    auto unit = [](float x, float y) {
      const float l = std::sqrt(x * x + y * y);
      return l > 1e-30f ? float2{x / l, y / l} : float2{0.f, 0.f};
    };
    for (size_t t = 0; t < tris.size() / 3; ++t) {
      float2 px[3];
      float3 v3[3];
      for (int k = 0; k < 3; ++k) {
        px[k] = float2{uvs[3 * t + k].x * size, uvs[3 * t + k].y * size};
        v3[k] = field[tris[3 * t + k]];
      }
      const float area = (px[1].x - px[0].x) * (px[2].y - px[0].y) - (px[2].x - px[0].x) * (px[1].y - px[0].y);
      if (!(std::abs(area) > 1e-12f)) continue;
      // The chart: v = a e1 + b e2 in 3D (least squares) -> a g1 + b g2 in pixels.
      const float3 e1 = pts[tris[3 * t + 1]] - pts[tris[3 * t]], e2 = pts[tris[3 * t + 2]] - pts[tris[3 * t]];
      const float2 g1{px[1].x - px[0].x, px[1].y - px[0].y}, g2{px[2].x - px[0].x, px[2].y - px[0].y};
      float2 vec[3];
      float mag[3];
      for (int k = 0; k < 3; ++k) {
        const double a11 = Dot(e1, e1), a12 = Dot(e1, e2), a22 = Dot(e2, e2), det = a11 * a22 - a12 * a12;
        const double b1 = Dot(v3[k], e1), b2 = Dot(v3[k], e2);
        const double ca = (a22 * b1 - a12 * b2) / det, cb = (a11 * b2 - a12 * b1) / det;
        const float2 d = unit(float(ca * g1.x + cb * g2.x), float(ca * g1.y + cb * g2.y));
        mag[k] = Length(v3[k]);
        vec[k] = float2{d.x * mag[k], d.y * mag[k]};
      }
      const float inv = 1.f / area;
      for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
          const float2 p{x + 0.5f, y + 0.5f};
          const float w0 = ((px[1].x - p.x) * (px[2].y - p.y) - (px[2].x - p.x) * (px[1].y - p.y)) * inv;
          const float w1 = ((px[2].x - p.x) * (px[0].y - p.y) - (px[0].x - p.x) * (px[2].y - p.y)) * inv;
          const float w2 = 1.f - w0 - w1;
          if (w0 < -1e-5f || w1 < -1e-5f || w2 < -1e-5f) continue;
          const size_t i = size_t(y) * size + size_t(x);
          img.direction[i] = unit(w0 * vec[0].x + w1 * vec[1].x + w2 * vec[2].x,
                                  w0 * vec[0].y + w1 * vec[1].y + w2 * vec[2].y);
          img.magnitude[i] = w0 * mag[0] + w1 * mag[1] + w2 * mag[2];
          img.mapped[i] = 1;
        }
    }
    return img;
  };
  const FieldImage want[2] = {brute(f1), brute(f2)};
  FieldImage two[2];
  RasterizeFields(mesh, uvs, f1, f2, size, two);
  const FieldImage one[2] = {RasterizeField(mesh, uvs, f1, size), RasterizeField(mesh, uvs, f2, size)};
  size_t mapped = 0;
  for (int f = 0; f < 2; ++f)
    for (const FieldImage* got : {&one[f], static_cast<const FieldImage*>(&two[f])}) {
      ASSERT_EQ(got->size, size);
      for (size_t i = 0; i < want[f].mapped.size(); ++i) {
        ASSERT_EQ(got->mapped[i], want[f].mapped[i]) << "field " << f << " pixel " << i;
        ASSERT_EQ(got->magnitude[i], want[f].magnitude[i]) << "field " << f << " pixel " << i;
        ASSERT_EQ(got->direction[i].x, want[f].direction[i].x) << "field " << f << " pixel " << i;
        ASSERT_EQ(got->direction[i].y, want[f].direction[i].y) << "field " << f << " pixel " << i;
        mapped += got->mapped[i];
      }
    }
  EXPECT_GT(mapped, size_t(size) * size);  // most of the image, in all four
}

TEST(FineScale, BumpNormalMapIsEveryTexelsDefinitionToTheByte) {
  // Each texel from its definition (clamped central differences, the normal of
  // (-k dx, k dy, 1), lround of 127.5 (n + 1)), on random heights with NaN and infinities
  // among them, at sizes whose borders are most of the image, with 1 and 2 threads.
  for (int size : {1, 2, 3, 67}) {
    std::mt19937 rng{uint32_t(size)};
    std::uniform_real_distribution<float> u(0.f, 1.f);
    std::vector<float> h(size_t(size) * size);
    for (float& v : h) v = u(rng);
    if (size > 3) h[5] = NAN, h[70] = INFINITY, h[140] = -INFINITY;
    for (int threads : {1, 2}) {
      const std::vector<uint8_t> n = BumpNormalMap(h, size, 7.f, threads);
      ASSERT_EQ(n.size(), size_t(size) * size * 3);
      for (int y = 0; y < size; ++y)
        for (int x = 0; x < size; ++x) {
          auto at = [&](int xx, int yy) {
            return h[size_t(std::clamp(yy, 0, size - 1)) * size + size_t(std::clamp(xx, 0, size - 1))];
          };
          const double dx = 0.5 * (double(at(x + 1, y)) - at(x - 1, y));
          const double dy = 0.5 * (double(at(x, y + 1)) - at(x, y - 1));
          double v[3] = {-7.0 * dx, 7.0 * dy, 1.0};
          const double len = std::sqrt(v[0] * v[0] + v[1] * v[1] + 1.0);
          if (std::isfinite(len))
            for (double& c : v) c /= len;
          else
            v[0] = v[1] = 0.0, v[2] = 1.0;
          for (int c = 0; c < 3; ++c) {
            // The float pass may round a value within 1e-5 of a half the other way.
            const double want = 127.5 * (v[c] + 1.0);
            const int got = n[3 * (size_t(y) * size + x) + c];
            if (std::abs(want - std::floor(want) - 0.5) > 1e-4)
              ASSERT_EQ(got, int(std::lround(want))) << size << " " << x << "," << y << " c" << c;
            else
              ASSERT_NEAR(got, want, 0.5 + 1e-4) << size << " " << x << "," << y << " c" << c;
          }
        }
    }
  }
}

TEST(FineScale, BadSpecsAreNamed) {
  FineScaleSpec spec;
  spec.fields[0].anchors = {{3, {NAN, 0.f, 0.f}}, {99, {0.f, 0.f, 0.f}}};
  spec.fields[1].anchors = {{0, {2.f, 0.f, 0.f}}};
  spec.k_noise = 2.f;
  Diagnostics diag;
  EXPECT_FALSE(ValidateFineScaleSpec(spec, 10, "fine_scale", &diag));
  const std::string text = diag.Format();
  EXPECT_NE(text.find("fine_scale.fields[0].anchors[0].vector: must be finite"), std::string::npos) << text;
  EXPECT_NE(text.find("fine_scale.fields[0].anchors[1].vertex: vertex 99 is out of range"), std::string::npos) << text;
  EXPECT_NE(text.find("fine_scale.fields[0].anchors[1].vector: has zero length"), std::string::npos) << text;
  EXPECT_NE(text.find("fine_scale.fields[1].anchors[0].vector: magnitude"), std::string::npos) << text;
  EXPECT_NE(text.find("fine_scale.k_noise"), std::string::npos) << text;
  Grid g = MakeGrid(3);
  FineScaleMaps maps;
  const std::vector<uint32_t> anchors[2] = {{0}, {0}};
  spec = FineScaleSpec();
  spec.fields[0].anchors = spec.fields[1].anchors = {{0, {0.5f, 0.f, 0.f}}};
  FineScaleTextureOptions o;
  o.size = 0;
  EXPECT_FALSE(MakeFineScaleMaps(spec, g.mesh(), anchors, o, &maps, &diag));
  o.size = 100000;
  EXPECT_FALSE(MakeFineScaleMaps(spec, g.mesh(), anchors, o, &maps, &diag));
  EXPECT_NE(diag.Format().find("--size: must be in [1, 8192]"), std::string::npos);
}

}  // namespace
}  // namespace mimetic

// Known answers for Waters' muscles, computed by hand from docs/model.md §2-3.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "geometry/normal_field.h"
#include "muscles/offline/muscle_builder.h"
#include "muscles/offline/waters.h"

namespace mimetic {
namespace {

constexpr double kPi = 3.14159265358979323846;
const double kR2 = std::sqrt(2.0) / 2.0;  // cos(pi/4)

// v1 at the origin, axis +X, Omega = 60 degrees, Rs = 5, Rf = 10.
LinearMuscleSpec Linear() {
  LinearMuscleSpec m;
  m.attachment = {0, 0, 0};
  m.insertion = {10, 0, 0};
  m.zone_angle = float(kPi / 3);
  m.falloff_start = 5;
  m.falloff_end = 10;
  return m;
}

// Attachment line x = 0, insertion line x = 20, both y in [-10, 10]; Ls = 20, Ws = 20, Rs = 5.
SheetMuscleSpec Sheet() {
  SheetMuscleSpec m;
  m.attachment[0] = {0, -10, 0};
  m.attachment[1] = {0, 10, 0};
  m.insertion[0] = {20, -10, 0};
  m.insertion[1] = {20, 10, 0};
  m.length = 20;
  m.width = 20;
  m.falloff_start = 5;
  return m;
}

void ExpectNear3(float3 got, double x, double y, double z, double tol = 1e-6) {
  EXPECT_NEAR(got.x, x, tol);
  EXPECT_NEAR(got.y, y, tol);
  EXPECT_NEAR(got.z, z, tol);
}

TEST(WatersFactors, AngularFactorAtCentreHalfAndEdge) {
  const double omega = kPi / 3;
  EXPECT_DOUBLE_EQ(WatersAngularFactor(0, omega), 1.0);                  // cos(0)
  EXPECT_NEAR(WatersAngularFactor(omega / 2, omega), kR2, 1e-15);        // cos(pi/4)
  EXPECT_NEAR(WatersAngularFactor(omega, omega), 0.0, 1e-15);            // cos(pi/2)
  EXPECT_EQ(WatersAngularFactor(omega * 1.0001, omega), 0.0);            // outside the zone
}

TEST(WatersFactors, RadialFactorRisesToRsAndFallsToRf) {
  EXPECT_NEAR(WatersRadialFactor(0, 5, 10), 0.0, 1e-15);    // cos(pi/2)
  EXPECT_NEAR(WatersRadialFactor(2.5, 5, 10), kR2, 1e-15);  // cos((1 - 0.5) pi/2)
  EXPECT_DOUBLE_EQ(WatersRadialFactor(5, 5, 10), 1.0);      // cos(0)
  EXPECT_NEAR(WatersRadialFactor(7.5, 5, 10), kR2, 1e-15);  // cos(2.5/5 pi/2)
  EXPECT_NEAR(WatersRadialFactor(10, 5, 10), 0.0, 1e-15);
  EXPECT_EQ(WatersRadialFactor(10.001, 5, 10), 0.0);
  // Continuous at Rs from both sides.
  EXPECT_NEAR(WatersRadialFactor(5 - 1e-9, 5, 10), WatersRadialFactor(5 + 1e-9, 5, 10), 1e-8);
}

TEST(WatersFactors, SheetFalloffs) {
  EXPECT_NEAR(SheetLengthFalloff(0.0, 0.25), 0.0, 1e-15);
  EXPECT_NEAR(SheetLengthFalloff(0.125, 0.25), kR2, 1e-15);
  EXPECT_DOUBLE_EQ(SheetLengthFalloff(0.25, 0.25), 1.0);
  EXPECT_NEAR(SheetLengthFalloff(0.625, 0.25), kR2, 1e-15);  // (0.625-0.25)/0.75 = 1/2
  EXPECT_NEAR(SheetLengthFalloff(1.0, 0.25), 0.0, 1e-15);
  EXPECT_EQ(SheetLengthFalloff(-0.01, 0.25), 0.0);
  EXPECT_EQ(SheetLengthFalloff(1.01, 0.25), 0.0);
  EXPECT_DOUBLE_EQ(SheetWidthFalloff(0.0), 1.0);
  EXPECT_NEAR(SheetWidthFalloff(0.5), kR2, 1e-15);
  EXPECT_NEAR(SheetWidthFalloff(1.0), 0.0, 1e-15);
  EXPECT_EQ(SheetWidthFalloff(1.01), 0.0);
}

TEST(LinearMuscle, DisplacementAtInteriorPoints) {
  const LinearMuscleSpec m = Linear();
  const float k = 2.f;
  // On the axis at D = Rs: A = 1, R = 1, unit direction (-1, 0, 0).
  ExpectNear3(LinearMuscleDisplacement(m, {5, 0, 0}, k), -2.0, 0, 0);
  // D = 2.5: R = cos(pi/4).
  ExpectNear3(LinearMuscleDisplacement(m, {2.5f, 0, 0}, k), -2.0 * kR2, 0, 0);
  // D = 7.5: R = cos(pi/4).
  ExpectNear3(LinearMuscleDisplacement(m, {7.5f, 0, 0}, k), -2.0 * kR2, 0, 0);
  // mu = 30 degrees (half the zone), D = 5: A = cos(pi/4), R = 1; direction -p/5.
  const double c = std::cos(kPi / 6), s = std::sin(kPi / 6);
  const float3 p{float(5 * c), float(5 * s), 0.f};
  ExpectNear3(LinearMuscleDisplacement(m, p, k), -2.0 * kR2 * c, -2.0 * kR2 * s, 0, 1e-6);
}

TEST(SmoothFalloff, IsWatersSquared) {
  // docs/model.md §2-3: the smooth fall-off is each Waters factor squared. At D = 2.5 on the
  // axis R = cos(pi/4), so the smooth R is 1/2; at mu = 30 deg and D = 7.5, A = R = cos(pi/4)
  // and the smooth displacement is k A^2 R^2 = k / 4 along -p/|p|.
  const LinearMuscleSpec m = Linear();
  const float k = 2.f;
  ExpectNear3(LinearMuscleDisplacement(m, {2.5f, 0, 0}, k, MuscleFalloff::kSmooth), -1.0, 0, 0);
  const double c = std::cos(kPi / 6), s = std::sin(kPi / 6);
  const float3 p{float(7.5 * c), float(7.5 * s), 0.f};
  ExpectNear3(LinearMuscleDisplacement(m, p, k, MuscleFalloff::kSmooth), -0.5 * c, -0.5 * s, 0);
  // The peak is unchanged: on the axis at D = Rs both give k.
  ExpectNear3(LinearMuscleDisplacement(m, {5, 0, 0}, k, MuscleFalloff::kSmooth), -2.0, 0, 0);
  // Sheet at l = 12.5 (lambda 0.625: Fl = cos(pi/4)), h = 5 (gamma 0.5: Fw = cos(pi/4)):
  // Waters k/2, smooth k/4, both along -x.
  const SheetMuscleSpec sh = Sheet();
  ExpectNear3(SheetMuscleDisplacement(sh, {12.5f, 5, 0}, k), -1.0, 0, 0);
  ExpectNear3(SheetMuscleDisplacement(sh, {12.5f, 5, 0}, k, MuscleFalloff::kSmooth), -0.5, 0, 0);
  // MuscleDisplacement follows the spec's falloff.
  MuscleSpec spec;
  spec.type = MuscleType::kSheet;
  spec.sheet = sh;
  spec.falloff = MuscleFalloff::kSmooth;
  ExpectNear3(MuscleDisplacement(spec, {12.5f, 5, 0}, k), -0.5, 0, 0);
}

TEST(SmoothFalloff, ReachesZeroWithZeroSlope) {
  // The slope of |U| toward the zone's edges, by central differences of step h: Waters' is
  // k pi / (2 (Rf - Rs)) at Rf and k pi / (2 Omega) per radian at Omega; the smooth one's is
  // O(h) (its derivative 2 F F' vanishes with F).
  const LinearMuscleSpec m = Linear();
  const float k = 1.f;
  const double h = 1e-3;
  auto along_axis = [&](double d, MuscleFalloff f) {
    return double(Length(LinearMuscleDisplacement(m, {float(d), 0.f, 0.f}, k, f)));
  };
  // Radial edge at Rf = 10, from inside: one-sided difference over [Rf - 2h, Rf - h].
  const double waters_r = (along_axis(10 - 2 * h, MuscleFalloff::kWaters) -
                           along_axis(10 - h, MuscleFalloff::kWaters)) / h;
  const double smooth_r = (along_axis(10 - 2 * h, MuscleFalloff::kSmooth) -
                           along_axis(10 - h, MuscleFalloff::kSmooth)) / h;
  EXPECT_NEAR(waters_r, kPi / (2 * 5), 1e-3);
  EXPECT_LT(std::fabs(smooth_r), 1e-2);
  // Angular edge at Omega = 60 degrees, D = Rs = 5.
  auto at_angle = [&](double mu, MuscleFalloff f) {
    return double(Length(LinearMuscleDisplacement(
        m, {float(5 * std::cos(mu)), float(5 * std::sin(mu)), 0.f}, k, f)));
  };
  const double omega = kPi / 3, dmu = 1e-4;
  const double waters_a = (at_angle(omega - 2 * dmu, MuscleFalloff::kWaters) -
                           at_angle(omega - dmu, MuscleFalloff::kWaters)) / dmu;
  const double smooth_a = (at_angle(omega - 2 * dmu, MuscleFalloff::kSmooth) -
                           at_angle(omega - dmu, MuscleFalloff::kSmooth)) / dmu;
  EXPECT_NEAR(waters_a, kPi / (2 * omega), 2e-3);
  EXPECT_LT(std::fabs(smooth_a), 1e-2);
}

TEST(LinearMuscle, ZoneBoundariesGiveZero) {
  const LinearMuscleSpec m = Linear();
  const double a = kPi / 3;
  // On the angular boundary A = cos(pi/2) ~ 0; just outside exactly 0.
  const float3 edge{float(5 * std::cos(a)), float(5 * std::sin(a)), 0};
  EXPECT_LT(Length(LinearMuscleDisplacement(m, edge, 1.f)), 1e-6f);
  const float3 outside{float(5 * std::cos(a + 0.01)), float(5 * std::sin(a + 0.01)), 0};
  EXPECT_EQ(LinearMuscleDisplacement(m, outside, 1.f), float3{});
  // Radial boundary and beyond; behind the attachment; at the attachment itself.
  EXPECT_LT(Length(LinearMuscleDisplacement(m, {10, 0, 0}, 1.f)), 1e-6f);
  EXPECT_EQ(LinearMuscleDisplacement(m, {10.01f, 0, 0}, 1.f), float3{});
  EXPECT_EQ(LinearMuscleDisplacement(m, {-5, 0, 0}, 1.f), float3{});
  EXPECT_EQ(LinearMuscleDisplacement(m, {0, 0, 0}, 1.f), float3{});
}

TEST(LinearMuscle, MovesTowardTheAttachment) {
  const LinearMuscleSpec m = Linear();
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-10.f, 10.f);
  int inside = 0;
  for (int i = 0; i < 2000; ++i) {
    const float3 p{u(rng), u(rng), u(rng)};
    const float3 d = LinearMuscleDisplacement(m, p, 1.f);
    if (d == float3{}) continue;
    ++inside;
    const float3 to_v1 = m.attachment - p;
    // Parallel to (v1 - p) and pointing the same way.
    EXPECT_GT(Dot(d, to_v1), 0.f);
    EXPECT_LT(Length(Cross(d, to_v1)), 1e-4f * Length(d) * Length(to_v1));
  }
  EXPECT_GT(inside, 50);
}

TEST(SheetMuscle, DisplacementAtInteriorPoints) {
  const SheetMuscleSpec m = Sheet();
  const float k = 3.f;
  ExpectNear3(SheetMuscleDisplacement(m, {5, 0, 0}, k), -3.0, 0, 0);        // Fl = Fw = 1
  ExpectNear3(SheetMuscleDisplacement(m, {2.5f, 5, 0}, k), -1.5, 0, 0);     // kR2 * kR2
  ExpectNear3(SheetMuscleDisplacement(m, {12.5f, 0, 0}, k), -3.0 * kR2, 0, 0);
  // h is the distance to the central fiber in 3D: (5, 0, 5) has h = 5 -> gamma = 0.5.
  ExpectNear3(SheetMuscleDisplacement(m, {5, 0, 5}, k), -3.0 * kR2, 0, 0);
}

TEST(SheetMuscle, OutsideTheAreaOfInfluenceGivesZero) {
  const SheetMuscleSpec m = Sheet();
  EXPECT_EQ(SheetMuscleDisplacement(m, {-0.5f, 0, 0}, 1.f), float3{});  // lambda < 0
  EXPECT_EQ(SheetMuscleDisplacement(m, {20.5f, 0, 0}, 1.f), float3{});  // lambda > 1
  EXPECT_EQ(SheetMuscleDisplacement(m, {5, 10.5f, 0}, 1.f), float3{});  // gamma > 1
  EXPECT_LT(Length(SheetMuscleDisplacement(m, {5, 10, 0}, 1.f)), 1e-6f);  // gamma = 1
  EXPECT_LT(Length(SheetMuscleDisplacement(m, {20, 0, 0}, 1.f)), 1e-6f);  // lambda = 1
}

TEST(SheetMuscle, MovesAlongTheFiberTowardTheAttachmentLine) {
  SheetMuscleSpec m = Sheet();
  // Tilt the muscle: fiber along (1, 1, 0)/sqrt2.
  m.attachment[0] = {-7, 7, 0};
  m.attachment[1] = {7, -7, 0};
  m.insertion[0] = {7, 21, 0};
  m.insertion[1] = {21, 7, 0};
  const float3 p{5, 5, 0};  // on the fiber, l = sqrt(50) ~ 7.07, inside
  const float3 d = SheetMuscleDisplacement(m, p, 1.f);
  EXPECT_LT(d.x, 0.f);
  EXPECT_NEAR(d.x, d.y, 1e-6f);
  EXPECT_EQ(d.z, 0.f);
}

std::vector<MuscleSpec> TwoMuscles() {
  MuscleSpec a;
  a.name = "lin";
  a.type = MuscleType::kLinear;
  a.strength = 2.f;
  a.linear = Linear();
  MuscleSpec b;
  b.name = "sheet";
  b.type = MuscleType::kSheet;
  b.strength = 1.5f;
  b.sheet = Sheet();
  return {a, b};
}

std::vector<float3> GridPoints() {
  std::vector<float3> pts;
  for (int j = -12; j <= 12; ++j)
    for (int i = -4; i <= 24; ++i) pts.push_back({float(i) * 0.93f, float(j) * 0.91f, 0.3f});
  return pts;
}

TEST(MuscleTable, AgreesWithDirectEvaluation) {
  const std::vector<MuscleSpec> muscles = TwoMuscles();
  const std::vector<float3> rest = GridPoints();
  const MuscleTable table = BuildMuscleTable(muscles, rest);
  ASSERT_EQ(table.point_count(), rest.size());
  const std::vector<float> activations = {0.37f, 0.81f};
  std::vector<float3> out(rest.size());
  MuscleDeformJob job;
  job.table = &table;
  job.activations = activations;
  job.rest_points = rest;
  job.out_points = out;
  job.begin = 0;
  job.end = uint32_t(rest.size());
  ASSERT_TRUE(job.Run());
  size_t moved = 0;
  for (size_t p = 0; p < rest.size(); ++p) {
    float3 expect = rest[p];
    for (size_t m = 0; m < muscles.size(); ++m)
      expect += MuscleDisplacement(muscles[m], rest[p], activations[m] * muscles[m].strength);
    EXPECT_NEAR(out[p].x, expect.x, 1e-6f) << p;
    EXPECT_NEAR(out[p].y, expect.y, 1e-6f) << p;
    EXPECT_NEAR(out[p].z, expect.z, 1e-6f) << p;
    moved += out[p] != rest[p];
  }
  EXPECT_GT(moved, 100u);
  // The table holds only points some muscle reaches: fewer entries than points x muscles.
  EXPECT_LT(table.entries.size(), rest.size() * muscles.size());
}

TEST(MuscleTable, ZeroActivationReturnsRestBitForBit) {
  const std::vector<MuscleSpec> muscles = TwoMuscles();
  const std::vector<float3> rest = GridPoints();
  const MuscleTable table = BuildMuscleTable(muscles, rest);
  const std::vector<float> zero = {0.f, 0.f};
  std::vector<float3> out(rest.size(), float3{9, 9, 9});
  MuscleDeformJob job{.table = &table,
                      .activations = zero,
                      .rest_points = rest,
                      .out_points = out,
                      .begin = 0,
                      .end = uint32_t(rest.size())};
  ASSERT_TRUE(job.Run());
  EXPECT_EQ(std::memcmp(out.data(), rest.data(), rest.size() * sizeof(float3)), 0);
}

TEST(MuscleTable, ActivationsAreClampedAndNaNIsZero) {
  const std::vector<MuscleSpec> muscles = TwoMuscles();
  const std::vector<float3> rest = GridPoints();
  const MuscleTable table = BuildMuscleTable(muscles, rest);
  std::vector<float3> a(rest.size()), b(rest.size());
  const std::vector<float> wild = {7.f, std::nanf("")};
  const std::vector<float> tame = {1.f, 0.f};
  MuscleDeformJob ja{.table = &table,
                     .activations = wild,
                     .rest_points = rest,
                     .out_points = a,
                     .begin = 0,
                     .end = uint32_t(rest.size())};
  MuscleDeformJob jb{.table = &table,
                     .activations = tame,
                     .rest_points = rest,
                     .out_points = b,
                     .begin = 0,
                     .end = uint32_t(rest.size())};
  ASSERT_TRUE(ja.Run());
  ASSERT_TRUE(jb.Run());
  EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(float3)), 0);
}

TEST(MuscleDeformJob, ValidityTable) {
  const std::vector<MuscleSpec> muscles = TwoMuscles();
  const std::vector<float3> rest = GridPoints();
  const MuscleTable table = BuildMuscleTable(muscles, rest);
  const uint32_t n = uint32_t(rest.size());
  std::vector<float> act(2, 0.5f);
  std::vector<float3> out(n);
  const MuscleDeformJob good{.table = &table,
                             .activations = act,
                             .rest_points = rest,
                             .out_points = out,
                             .begin = 0,
                             .end = n};
  EXPECT_TRUE(good.Validate());
  MuscleDeformJob j = good;
  j.table = nullptr;
  EXPECT_FALSE(j.Validate());
  j = good;
  j.activations = span<const float>(act).first(1);
  EXPECT_FALSE(j.Validate());
  j = good;
  j.rest_points = span<const float3>(rest).first(n - 1);
  EXPECT_FALSE(j.Validate());
  j = good;
  j.out_points = span<float3>(out).first(n - 1);
  EXPECT_FALSE(j.Validate());
  j = good;
  j.end = n + 1;
  EXPECT_FALSE(j.Validate());
  j = good;
  j.begin = 5;
  j.end = 4;
  EXPECT_FALSE(j.Validate());
  // Invalid jobs leave the output untouched.
  std::vector<float3> before = out;
  j.Run();
  EXPECT_EQ(std::memcmp(before.data(), out.data(), n * sizeof(float3)), 0);
}

}  // namespace
}  // namespace mimetic

namespace mimetic {
namespace {

// docs/model.md §2-3 "Motion": a linear muscle whose attachment lies 2 under a plane z = 0.
// Chord motion points at the attachment, so it goes into the plane; tangent motion is the
// same vector without its z part, computed here by hand.
TEST(MuscleMotion, TangentDropsThePartAlongTheNormal) {
  MuscleSpec chord;
  chord.name = "m";
  chord.type = MuscleType::kLinear;
  chord.strength = 1.f;
  chord.linear.attachment = {0, 0, -2};
  chord.linear.insertion = {10, 0, -2};
  chord.linear.zone_angle = float(kPi / 3);
  chord.linear.falloff_start = 5;
  chord.linear.falloff_end = 12;
  MuscleSpec tangent = chord;
  tangent.motion = MuscleMotion::kTangent;
  const std::vector<float3> rest = {{4, 0, 0}, {6, 1, 0}, {8, -1.5f, 0}};
  const std::vector<float3> normals(rest.size(), float3{0, 0, 1});
  const MuscleTable a = BuildMuscleTable(std::vector<MuscleSpec>{chord}, rest, normals);
  const MuscleTable b = BuildMuscleTable(std::vector<MuscleSpec>{tangent}, rest, normals);
  ASSERT_EQ(a.entries.size(), rest.size());
  ASSERT_EQ(b.entries.size(), rest.size());
  for (size_t p = 0; p < rest.size(); ++p) {
    const float3 c = a.entries[p].displacement, t = b.entries[p].displacement;
    // Waters (§2): toward v1 = (0, 0, -2), so z < 0 on the plane.
    const float3 to = float3{0, 0, -2} - rest[p];
    EXPECT_LT(c.z, 0.f) << p;
    EXPECT_NEAR(c.x * to.z - c.z * to.x, 0.f, 1e-5f) << p;  // parallel to the chord
    ExpectNear3(t, c.x, c.y, 0.0, 1e-6);
  }
  // Without normals the table keeps Waters' chord (the documented fallback).
  const MuscleTable no_normals = BuildMuscleTable(std::vector<MuscleSpec>{tangent}, rest);
  for (size_t p = 0; p < rest.size(); ++p)
    ExpectNear3(no_normals.entries[p].displacement, a.entries[p].displacement.x,
                a.entries[p].displacement.y, a.entries[p].displacement.z, 0.0);
}

// Each tangent muscle projects on the rest normals averaged over its own tangent_radius
// (geometry/normal_field.h, checked against its definition in normal_field_test.cpp): on a
// wavy sheet, two copies of one muscle with radii 0 and 3 give, entry by entry, the chord's
// displacement with its part along field.At(0) resp. field.At(3) removed, and the two differ.
TEST(MuscleMotion, TangentRadiusChoosesTheAveragedNormals) {
  std::vector<float3> rest;
  std::vector<uint32_t> tris;
  const int n = 30;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const float x = -15.f + i, y = -15.f + j;
      rest.push_back({x, y, 0.8f * std::sin(0.9f * x) * std::cos(0.5f * y)});
    }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const uint32_t a = uint32_t(j * (n + 1) + i), b = a + 1, c = a + uint32_t(n + 1) + 1, d = a + uint32_t(n + 1);
      tris.insert(tris.end(), {a, b, c, a, c, d});
    }
  MuscleSpec m;
  m.type = MuscleType::kLinear;
  m.strength = 1.f;
  m.motion = MuscleMotion::kTangent;
  m.linear.attachment = {-12, 0, -3};
  m.linear.insertion = {4, 0, 0};
  m.linear.zone_angle = float(kPi / 4);
  m.linear.falloff_start = 8;
  m.linear.falloff_end = 20;
  MuscleSpec own = m, wide = m;
  own.name = "own";
  wide.name = "wide";
  wide.tangent_radius = 3.f;
  MuscleSpec chord = m;
  chord.name = "chord";
  chord.motion = MuscleMotion::kChord;
  chord.tangent_radius = 3.f;  // read by tangent muscles only
  NormalField field(rest, tris);
  const MuscleTable table = BuildMuscleTable(std::vector<MuscleSpec>{own, wide, chord}, rest, &field);
  const std::vector<float3>& n0 = field.At(0.f);
  const std::vector<float3>& n3 = field.At(3.f);
  size_t seen = 0;
  double most_apart = 0;
  float3 by_muscle[3];
  for (size_t p = 0; p < rest.size(); ++p) {
    if (table.offsets[p + 1] == table.offsets[p]) continue;
    ASSERT_EQ(table.offsets[p + 1] - table.offsets[p], 3u) << p;
    for (uint32_t e = table.offsets[p]; e < table.offsets[p + 1]; ++e)
      by_muscle[table.entries[e].muscle] = table.entries[e].displacement;
    const float3 d = by_muscle[2];  // the chord
    const float3 t0 = d - Dot(d, n0[p]) * n0[p], t3 = d - Dot(d, n3[p]) * n3[p];
    ExpectNear3(by_muscle[0], t0.x, t0.y, t0.z, 1e-6);
    ExpectNear3(by_muscle[1], t3.x, t3.y, t3.z, 1e-6);
    most_apart = std::max(most_apart, double(Length(t0 - t3)));
    ++seen;
  }
  EXPECT_GT(seen, 100u);
  EXPECT_GT(most_apart, 0.01);  // the radius matters on this surface
}

TEST(MuscleMotion, TangentIsPerpendicularToAnyUnitNormal) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(-1.f, 1.f);
  for (int i = 0; i < 200; ++i) {
    const float3 d{u(rng), u(rng), u(rng)};
    float3 n{u(rng), u(rng), u(rng)};
    n = n * (1.f / std::sqrt(Dot(n, n)));
    const float3 t = ApplyMuscleMotion(d, n, MuscleMotion::kTangent);
    EXPECT_NEAR(Dot(t, n), 0.f, 1e-6f);
    // d = t + (d.n) n: nothing but the normal part is removed.
    const float3 back = t + Dot(d, n) * n;
    ExpectNear3(back, d.x, d.y, d.z, 1e-6);
    const float3 same = ApplyMuscleMotion(d, n, MuscleMotion::kChord);
    ExpectNear3(same, d.x, d.y, d.z, 0.0);
  }
  EXPECT_STREQ(MuscleMotionName(MuscleMotion::kChord), "chord");
  EXPECT_STREQ(MuscleMotionName(MuscleMotion::kTangent), "tangent");
}

// Random linear and sheet muscles over a grid: the table is, entry for entry and bit for bit,
// what evaluating every muscle at every point gives (the grid search may skip only points that
// no muscle can reach).
TEST(MuscleTable, SameEntriesAsEvaluatingEveryPair) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> pos(-6.f, 26.f), size(0.5f, 12.f);
  std::vector<MuscleSpec> muscles;
  for (int m = 0; m < 200; ++m) {
    MuscleSpec s;
    s.name = "m" + std::to_string(m);
    s.strength = 1.f + float(m % 3);
    if (m % 2 == 0) {
      s.type = MuscleType::kLinear;
      s.linear.attachment = {pos(rng), pos(rng) - 10.f, size(rng) - 6.f};
      s.linear.insertion = {pos(rng), pos(rng) - 10.f, 0.3f};
      s.linear.zone_angle = 0.2f + 0.002f * float(m);
      s.linear.falloff_start = size(rng) * 0.5f;
      s.linear.falloff_end = s.linear.falloff_start + size(rng);
    } else {
      s.type = MuscleType::kSheet;
      const float3 a = {pos(rng), pos(rng) - 10.f, 0.f}, i = {pos(rng), pos(rng) - 10.f, 1.f};
      s.sheet.attachment[0] = a;
      s.sheet.attachment[1] = a + float3{0.f, 3.f, 0.f};
      s.sheet.insertion[0] = i;
      s.sheet.insertion[1] = i + float3{0.f, 3.f, 0.f};
      s.sheet.length = size(rng);
      s.sheet.width = size(rng);
      s.sheet.falloff_start = 0.4f * s.sheet.length;
    }
    muscles.push_back(s);
  }
  const std::vector<float3> rest = GridPoints();
  const MuscleTable table = BuildMuscleTable(muscles, rest);
  ASSERT_EQ(table.offsets.size(), rest.size() + 1);
  std::vector<MuscleInfluence> expect;
  std::vector<uint32_t> expect_offsets = {0};
  for (const float3& p : rest) {
    for (uint32_t m = 0; m < muscles.size(); ++m) {
      const float3 d = MuscleDisplacement(muscles[m], p, muscles[m].strength);
      if (d.x != 0.f || d.y != 0.f || d.z != 0.f) expect.push_back({m, d});
    }
    expect_offsets.push_back(uint32_t(expect.size()));
  }
  EXPECT_EQ(table.offsets, expect_offsets);
  ASSERT_EQ(table.entries.size(), expect.size());
  ASSERT_GT(expect.size(), 1000u);
  for (size_t e = 0; e < expect.size(); ++e) {
    EXPECT_EQ(table.entries[e].muscle, expect[e].muscle) << e;
    EXPECT_EQ(std::memcmp(&table.entries[e].displacement, &expect[e].displacement, 12), 0) << e;
  }
}

// 5000 tiny muscles (issue 11: thousands of muscles took quadratic time in the number of
// influences). Grid points (i, j, 0), 0 <= i, j <= 100; a linear muscle over every cell with
// i + j even, attachment 1 above the cell's centre, axis straight down, Rs = 0.5, Rf = 1.5: it
// reaches the plane within sqrt(1.5^2 - 1) = 1.118 of the centre, i.e. exactly the cell's 4
// corners (0.707 away; the next points are 1.58 away), at 35 degrees from the axis (< 80).
TEST(MuscleTable, FiveThousandTinyMusclesEachMoveTheirFourCorners) {
  constexpr int n = 100;
  std::vector<float3> rest;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) rest.push_back({float(i), float(j), 0.f});
  std::vector<MuscleSpec> muscles;
  std::vector<int> muscle_of_cell(n * n, -1);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      if ((i + j) % 2) continue;
      MuscleSpec s;
      s.name = "tiny_" + std::to_string(muscles.size());
      s.type = MuscleType::kLinear;
      s.strength = 0.25f;
      s.linear.attachment = {float(i) + 0.5f, float(j) + 0.5f, 1.f};
      s.linear.insertion = {float(i) + 0.5f, float(j) + 0.5f, 0.f};
      s.linear.zone_angle = 80.f * kPi / 180.f;
      s.linear.falloff_start = 0.5f;
      s.linear.falloff_end = 1.5f;
      muscle_of_cell[j * n + i] = int(muscles.size());
      muscles.push_back(s);
    }
  ASSERT_EQ(muscles.size(), 5000u);
  const MuscleTable table = BuildMuscleTable(muscles, rest);
  ASSERT_EQ(table.point_count(), rest.size());
  EXPECT_EQ(table.entries.size(), 4u * 5000u);
  const std::vector<uint32_t> counts = CountInfluencedPoints(table);
  ASSERT_EQ(counts.size(), 5000u);
  for (uint32_t m = 0; m < 5000; ++m) EXPECT_EQ(counts[m], 4u) << m;
  // Point (i, j) is a corner of cells (i-1..i, j-1..j): its muscles, ascending.
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const uint32_t p = uint32_t(j * (n + 1) + i);
      std::vector<uint32_t> want;
      for (int cj = j - 1; cj <= j; ++cj)
        for (int ci = i - 1; ci <= i; ++ci)
          if (ci >= 0 && cj >= 0 && ci < n && cj < n && muscle_of_cell[cj * n + ci] >= 0)
            want.push_back(uint32_t(muscle_of_cell[cj * n + ci]));
      std::sort(want.begin(), want.end());
      std::vector<uint32_t> got;
      for (uint32_t k = table.offsets[p]; k < table.offsets[p + 1]; ++k) {
        got.push_back(table.entries[k].muscle);
        const float3 d = MuscleDisplacement(muscles[table.entries[k].muscle], rest[p], 0.25f);
        EXPECT_EQ(table.entries[k].displacement, d) << p;
        // Toward the attachment: up, and toward the cell's centre.
        EXPECT_GT(table.entries[k].displacement.z, 0.f);
      }
      ASSERT_EQ(got, want) << "point (" << i << ", " << j << ")";
    }
}

// docs/model.md §11: MuscleFalloffCurvature, by hand (per unit strength: pi^2/2 times the terms).
MuscleSpec LinearOf(float strength) {
  MuscleSpec m;
  m.type = MuscleType::kLinear;
  m.linear = Linear();
  m.strength = strength;
  return m;
}

TEST(FalloffCurvature, LinearByHand) {
  const MuscleSpec m = LinearOf(2.f);
  const double bend = kPi * kPi / 2;  // pi^2 / 2
  auto at = [&](double d, double mu) {
    return MuscleFalloffCurvature(m, {float(d * std::cos(mu)), float(d * std::sin(mu)), 0.f});
  };
  // On the axis (A = 1) in the outer fall-off, W = Rf - Rs = 5: pi^2/2 / 25, which beats the
  // angular term R^2 / (Omega D)^2 <= 1 / (pi/3 * 7.5)^2 = 0.0162.
  EXPECT_NEAR(at(7.5, 0), bend / 25, 1e-6);
  EXPECT_NEAR(at(10, 0), bend / 25, 1e-6);
  // Beyond Rf by less than half the fall-off width (2.5): the edge's value; beyond it, 0.
  EXPECT_NEAR(at(12, 0), bend / 25, 1e-6);
  EXPECT_EQ(at(13, 0), 0.0);
  // On the angular edge at D = Rs (R = 1, A = 0): pi^2/2 / (Omega Rs)^2 = pi^2/2 / (5 pi / 3)^2
  // = 4.5 / 25; past it up to 1.5 Omega the same, farther 0.
  EXPECT_NEAR(at(5, kPi / 3), 4.5 / 25, 1e-5);
  EXPECT_NEAR(at(5, 1.4 * kPi / 3), 4.5 / 25, 1e-5);
  EXPECT_EQ(at(5, 1.6 * kPi / 3), 0.0);
  // At the attachment R^2 / D^2 tends to (pi / (2 Rs))^2, so the angular term is
  // (pi/10)^2 / (pi/3)^2 = 0.09 > 1 / Rs^2 = 0.04: pi^2/2 * 0.09.
  EXPECT_NEAR(at(0, 0), bend * 0.09, 1e-5);
  EXPECT_NEAR(at(1e-3, 0), bend * 0.09, 1e-4);
  // The strength does not enter (tuning it never changes the refined mesh); Rf <= Rs bends nothing.
  EXPECT_EQ(MuscleFalloffCurvature(LinearOf(0.f), {7.5f, 0, 0}), at(7.5, 0));
  EXPECT_EQ(MuscleFalloffCurvature(LinearOf(40.f), {7.5f, 0, 0}), at(7.5, 0));
  MuscleSpec flat = LinearOf(2.f);
  flat.linear.falloff_end = flat.linear.falloff_start;
  EXPECT_EQ(MuscleFalloffCurvature(flat, {5, 0, 0}), 0.0);
}

TEST(FalloffCurvature, SheetByHand) {
  MuscleSpec m;
  m.type = MuscleType::kSheet;
  m.sheet = Sheet();  // Ls = 20, Ws = 20, Rs = 5
  m.strength = 2.f;
  const double bend = kPi * kPi / 2;  // pi^2 / 2
  // On the central fibre at l = Rs (Fl = Fw = 1): max(1 / Rs^2, 1 / (Ws/2)^2) = 1 / 25.
  EXPECT_NEAR(MuscleFalloffCurvature(m, {5, 0, 0}), bend / 25, 1e-6);
  // At the width edge h = 10 (Fw = 0), l = Rs: 1 / 10^2; past it up to 0.75 Ws = 15 the same.
  EXPECT_NEAR(MuscleFalloffCurvature(m, {5, 10, 0}), bend / 100, 1e-6);
  EXPECT_NEAR(MuscleFalloffCurvature(m, {5, 14, 0}), bend / 100, 1e-6);
  EXPECT_EQ(MuscleFalloffCurvature(m, {5, 16, 0}), 0.0);
  // At the far end l = Ls (Fl = 0), h = 0: Fw^2 / (Ls - Rs)^2 = 1 / 225; beyond it by up to
  // half of Ls - Rs (7.5) the same.
  EXPECT_NEAR(MuscleFalloffCurvature(m, {20, 0, 0}), bend / 225, 1e-6);
  EXPECT_NEAR(MuscleFalloffCurvature(m, {27, 0, 0}), bend / 225, 1e-6);
  EXPECT_EQ(MuscleFalloffCurvature(m, {28, 0, 0}), 0.0);
  // Behind the attachment line by up to Rs / 2 = 2.5: the line's value (Fl = 0,
  // Fw^2 / Rs^2 = 1 / 25); farther, 0.
  EXPECT_NEAR(MuscleFalloffCurvature(m, {-2, 0, 0}), bend / 25, 1e-6);
  EXPECT_EQ(MuscleFalloffCurvature(m, {-3, 0, 0}), 0.0);
}

// A second method: where the bound is reached (at a fall-off's edge, where cos^2's second
// derivative is pi^2/2 per width squared), it equals the smooth displacement magnitude's second
// difference along that direction, over the strength.
TEST(FalloffCurvature, IsTheSmoothProfilesSecondDerivativeAtAnEdge) {
  const MuscleSpec lin = LinearOf(2.f);
  const double h = 2e-3;
  auto second = [&](auto f, double x) { return (f(x + h) - 2 * f(x) + f(x - h)) / (h * h); };
  auto radial = [&](double d) {
    return double(Length(LinearMuscleDisplacement(lin.linear, {float(d), 0, 0}, lin.strength,
                                                   MuscleFalloff::kSmooth)));
  };
  const double d = 10 - 0.01;  // just inside Rf
  EXPECT_NEAR(second(radial, d) / 2, MuscleFalloffCurvature(lin, {float(d), 0, 0}), 2e-3);
  // Around the axis at D = Rs, arc length s = Rs mu, just inside Omega.
  auto around = [&](double s) {
    const double mu = s / 5.0;
    return double(Length(LinearMuscleDisplacement(
        lin.linear, {float(5 * std::cos(mu)), float(5 * std::sin(mu)), 0}, lin.strength,
        MuscleFalloff::kSmooth)));
  };
  const double s = 5 * (kPi / 3 - 0.002);
  const float3 ps{float(5 * std::cos(s / 5)), float(5 * std::sin(s / 5)), 0};
  EXPECT_NEAR(second(around, s) / 2, MuscleFalloffCurvature(lin, ps), 5e-3);
  // Sheet: across the fibre just inside Ws / 2 at l = Rs, and along it just inside Ls.
  MuscleSpec sh;
  sh.type = MuscleType::kSheet;
  sh.sheet = Sheet();
  sh.strength = 2.f;
  auto across = [&](double y) {
    return double(Length(SheetMuscleDisplacement(sh.sheet, {5, float(y), 0}, sh.strength,
                                                 MuscleFalloff::kSmooth)));
  };
  EXPECT_NEAR(second(across, 9.99) / 2, MuscleFalloffCurvature(sh, {5, 9.99f, 0}), 2e-3);
  auto along = [&](double x) {
    return double(Length(SheetMuscleDisplacement(sh.sheet, {float(x), 0, 0}, sh.strength,
                                                 MuscleFalloff::kSmooth)));
  };
  EXPECT_NEAR(second(along, 19.99) / 2, MuscleFalloffCurvature(sh, {19.99f, 0, 0}), 2e-3);
}

// The ball outside which the bound is 0: by hand, then against the bound itself on a grid
// through both zones (every point where it bends lies inside; the ball is not loose: points
// just inside its rim along the axis still bend).
TEST(FalloffCurvature, TheBallHoldsEveryPointWhereItBends) {
  const MuscleSpec lin = LinearOf(2.f);
  MuscleSpec sh;
  sh.type = MuscleType::kSheet;
  sh.sheet = Sheet();
  // Linear: about v1, Rf + (Rf - Rs) / 2 = 12.5. Sheet: l from -Rs/2 = -2.5 to
  // Ls + (Ls - Rs)/2 = 27.5 about l = 12.5 on the fibre, h up to 0.75 Ws = 15: radius
  // hypot(15, 15).
  const MuscleBall a = MuscleFalloffCurvatureBall(lin), b = MuscleFalloffCurvatureBall(sh);
  ASSERT_FALSE(a.all);
  ASSERT_FALSE(b.all);
  EXPECT_NEAR(a.x, 0, 1e-12);
  EXPECT_NEAR(a.r, 12.5, 1e-4);
  EXPECT_NEAR(b.x, 12.5, 1e-12);
  EXPECT_NEAR(b.y, 0, 1e-12);
  EXPECT_NEAR(b.r, std::hypot(15.0, 15.0), 1e-4);
  EXPECT_GT(MuscleFalloffCurvature(lin, {12.45f, 0, 0}), 0.0);
  EXPECT_TRUE(a.Holds({12.45f, 0, 0}));
  EXPECT_FALSE(a.Holds({12.6f, 0, 0}));
  const MuscleSpec* both[] = {&lin, &sh};
  for (const MuscleSpec* m : both) {
    const MuscleBall ball = MuscleFalloffCurvatureBall(*m);
    size_t bends = 0, outside = 0;
    for (float x = -30; x <= 45; x += 0.5f)
      for (float y = -30; y <= 30; y += 0.5f)
        for (float z : {0.f, 4.f, 11.f}) {
          const float3 p{x, y, z};
          if (MuscleFalloffCurvature(*m, p) > 0.0) {
            ++bends;
            EXPECT_TRUE(ball.Holds(p)) << p.x << " " << p.y << " " << p.z;
          }
          outside += !ball.Holds(p);
        }
    EXPECT_GT(bends, 1000u);
    EXPECT_GT(outside, 1000u);
  }
  // No geometry to bound: a fibre of no length, a NaN radius.
  MuscleSpec none = sh;
  none.sheet.insertion[0] = none.sheet.attachment[0];
  none.sheet.insertion[1] = none.sheet.attachment[1];
  EXPECT_TRUE(MuscleFalloffCurvatureBall(none).all);
  MuscleSpec nan = lin;
  nan.linear.falloff_end = std::nanf("");
  EXPECT_TRUE(MuscleFalloffCurvatureBall(nan).all);
}

}  // namespace
}  // namespace mimetic

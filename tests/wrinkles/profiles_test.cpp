// Known-answer tests of the scalar wrinkle functions (docs/model.md §6-8): expected values come from
// the formulas written out again here, from hand values, or from numeric quadrature.
#include "wrinkles/runtime/profiles.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

namespace mimetic {
namespace {

constexpr double kPiD = 3.14159265358979323846;

// Composite Simpson over [a, b] with n (even) intervals.
double Simpson(const std::function<double(double)>& f, double a, double b, int n) {
  const double h = (b - a) / n;
  double s = f(a) + f(b);
  for (int i = 1; i < n; ++i) s += (i % 2 ? 4.0 : 2.0) * f(a + i * h);
  return s * h / 3.0;
}

// --- docs/model.md §6 (001) ------------------------------------------------------------------------

TEST(ZhangShape, ZeroMeanOverACycle) {  // 001 eq. 8, accept d
  for (double alpha : {-2.0, -1.0, -0.5, 0.0, 0.7, 2.0, 3.5}) {
    for (double u : {0.3, 1.0, 2.7}) {
      const double k0 = 1.7;
      auto H = [&](double w) { return ZhangShape(w, u, k0, alpha); };
      // Split at the bulge w = u (H has a corner there).
      const double integral = Simpson(H, 0.0, u, 4000) + Simpson(H, u, 2.0 * u, 4000);
      EXPECT_NEAR(integral / (2.0 * u), 0.0, 1e-9) << "alpha " << alpha << " u " << u;
    }
  }
}

TEST(ZhangShape, HandValues) {  // 001 eq. 5
  const double k0 = 2.0, alpha = 1.0, u = 1.0;
  const double d = k0 * (4.0 - 1.0) / (2.0 * 2.0);  // 2^(alpha+1) = 4
  EXPECT_NEAR(ZhangBulge(k0, alpha), d, 1e-15);
  EXPECT_NEAR(ZhangShape(0.0, u, k0, alpha), d - k0 * 2.0, 1e-12);  // furrow, t = -1
  EXPECT_NEAR(ZhangShape(u, u, k0, alpha), d, 1e-12);               // bulge, t = 0
  EXPECT_NEAR(ZhangShape(2.0 * u, u, k0, alpha), d - k0 * 2.0, 1e-12);
  // w = 0.5: t = -0.5, H = k0 (1.25) (-0.5) + d.
  EXPECT_NEAR(ZhangShape(0.5, u, k0, alpha), k0 * 1.25 * -0.5 + d, 1e-12);
  // w = 1.5: t = 0.5, H = -k0 (1.25)(0.5) + d.
  EXPECT_NEAR(ZhangShape(1.5, u, k0, alpha), -k0 * 1.25 * 0.5 + d, 1e-12);
  // alpha = -1 limit: d = k0 ln2 / 2.
  EXPECT_NEAR(ZhangBulge(1.0, -1.0), std::log(2.0) / 2.0, 1e-12);
  EXPECT_NEAR(ZhangBulge(1.0, -1.0 + 1e-6), ZhangBulge(1.0, -1.0), 1e-6);
  EXPECT_EQ(ZhangShape(0.5, 0.0, 1.0, 1.0), 0.0);  // degenerate half cycle
}

TEST(Anisotropy, BoundaryValuesAndContinuity) {  // 001 eq. 11
  EXPECT_NEAR(Anisotropy(0.0), 0.0, 1e-15);
  EXPECT_NEAR(Anisotropy(1.0), 1.0, 1e-15);
  EXPECT_EQ(Anisotropy(-0.3), 0.0);
  EXPECT_EQ(Anisotropy(-1e-9), 0.0);
  EXPECT_NEAR(Anisotropy(1e-9), 0.0, 1e-8);  // continuous at 0 from the right
  EXPECT_NEAR(Anisotropy(0.5), std::cos(kPiD / 4.0), 1e-15);
  EXPECT_EQ(Anisotropy(1.5), 1.0);
  EXPECT_EQ(Anisotropy(std::nan("")), 0.0);
  EXPECT_NEAR(Anisotropy(0.5f), 0.70710678f, 1e-6f);
}

TEST(WrinkleGate, SmoothstepOfTheMusclesOwnActivation) {  // docs/model.md §6, a choice
  // G = x^2 (3 - 2 x), x = a / gate: by hand at a few points.
  EXPECT_NEAR(WrinkleGate(0.5, 1.0), 0.25 * 2.0, 1e-15);
  EXPECT_NEAR(WrinkleGate(0.25, 1.0), 0.0625 * 2.5, 1e-15);
  EXPECT_NEAR(WrinkleGate(0.3, 0.6), 0.5, 1e-15);  // the middle of a shorter gate
  EXPECT_NEAR(WrinkleGate(0.1, 0.4), 0.0625 * 2.5, 1e-15);
  EXPECT_EQ(WrinkleGate(0.0, 1.0), 0.0);             // shut at rest
  EXPECT_EQ(WrinkleGate(0.6, 0.6), 1.0);             // open from a = gate on
  EXPECT_EQ(WrinkleGate(0.9, 0.6), 1.0);
  EXPECT_NEAR(WrinkleGate(1e-6, 1.0), 0.0, 1e-11);   // continuous at both ends, flat there:
  EXPECT_NEAR(WrinkleGate(1.0 - 1e-6, 1.0), 1.0, 1e-11);  // slope 6 x (1 - x) -> 0
  // No gate: 001's amplitude, G = 1 whatever the activation.
  EXPECT_EQ(WrinkleGate(0.0, 0.0), 1.0);
  EXPECT_EQ(WrinkleGate(0.4, 0.0), 1.0);
  EXPECT_EQ(WrinkleGate(0.4, std::nan("")), 1.0);
  EXPECT_EQ(WrinkleGate(std::nan(""), 1.0), 0.0);
  EXPECT_EQ(WrinkleGate(-0.2, 1.0), 0.0);
  // Monotone on a fine grid (a second check of the shape, not of the formula).
  double last = 0.0;
  for (int i = 0; i <= 1000; ++i) {
    const double g = WrinkleGate(i / 1000.0, 0.7);
    EXPECT_GE(g, last);
    last = g;
  }
  EXPECT_NEAR(WrinkleGate(0.5f, 1.f), 0.5f, 1e-7f);
}

TEST(Attenuation, BoundaryValuesAndContinuity) {  // 001 eq. 12 / 15
  EXPECT_EQ(Attenuation(0.0), 1.0);
  EXPECT_EQ(Attenuation(-0.5), 1.0);
  EXPECT_NEAR(Attenuation(1.0), 0.0, 1e-15);
  EXPECT_NEAR(Attenuation(1e-9), 1.0, 1e-8);       // continuous at phi_c
  EXPECT_NEAR(Attenuation(1.0 - 1e-9), 0.0, 1e-8);  // and at phi
  EXPECT_NEAR(Attenuation(0.5), 1.0 - 0.5 * 1.25 * 0.5, 1e-15);
  EXPECT_EQ(Attenuation(2.0), 0.0);
}

// --- docs/model.md §7 (000, 002) -------------------------------------------------------------------

TEST(CurveProfile, ShapeAndZeroVolume) {  // 000 eq. 2-3
  const double d = 0.7, w = 0.3;
  EXPECT_NEAR(CurveProfile(0.0, d, w), -d, 1e-15);
  EXPECT_NEAR(CurveProfile(w, d, w), 0.0, 1e-15);
  EXPECT_NEAR(CurveProfile(2 * w, d, w), d * std::exp(-2.0), 1e-15);
  EXPECT_NEAR(CurveProfile(-2 * w, d, w), d * std::exp(-2.0), 1e-15);  // symmetric
  const double integral =
      Simpson([&](double l) { return CurveProfile(l, d, w); }, 0.0, 80 * w, 200000);
  EXPECT_NEAR(integral, 0.0, 1e-9 * d * w);
}

TEST(Modulation, DirectionalIsC1AndHitsEnds) {  // 000 eq. 5
  for (double r : {0.1, 0.5, 0.9, 1.0}) {
    EXPECT_NEAR(DirectionalModulation(0.0, r), r, 1e-15);
    EXPECT_NEAR(DirectionalModulation(1.0, r), 1.0, 1e-15);
    const double e = 1e-6;
    const double left = (DirectionalModulation(0.0, r) - DirectionalModulation(-e, r)) / e;
    const double right = (DirectionalModulation(e, r) - DirectionalModulation(0.0, r)) / e;
    EXPECT_NEAR(left, 1.0 - r, 1e-5);   // d/ds r exp((1/r - 1) s) at 0 = 1 - r
    EXPECT_NEAR(right, 1.0 - r, 1e-5);
    EXPECT_NEAR(DirectionalModulation(-2.0, r), r * std::exp((1.0 / r - 1.0) * -2.0), 1e-15);
  }
  EXPECT_EQ(DirectionalModulation(-0.5, 0.0), 0.0);  // r = 0: no wrinkle until shrinking
  EXPECT_NEAR(DirectionalModulation(0.25, 0.0), 0.25, 1e-15);
  EXPECT_TRUE(std::isfinite(DirectionalModulation(-1e30f, 1e-30f)));
}

TEST(Modulation, AreaIsC1AndHitsEnds) {  // 002 eq. 6
  for (double kr : {0.1, 0.5, 1.0}) {
    EXPECT_NEAR(AreaModulation(1.0, kr), kr, 1e-15);
    EXPECT_NEAR(AreaModulation(0.0, kr), 1.0, 1e-15);
    const double e = 1e-6;
    const double left = (AreaModulation(1.0, kr) - AreaModulation(1.0 - e, kr)) / e;
    const double right = (AreaModulation(1.0 + e, kr) - AreaModulation(1.0, kr)) / e;
    EXPECT_NEAR(left, kr - 1.0, 1e-5);
    EXPECT_NEAR(right, kr - 1.0, 1e-5);  // kr (1 - 1/kr) = kr - 1
  }
  EXPECT_EQ(AreaModulation(1.5, 0.0), 0.0);
  EXPECT_NEAR(AreaModulation(0.5, 0.0), 0.5, 1e-15);
}

// --- docs/model.md §8 (004) ------------------------------------------------------------------------

// The profile written out again from 004 eq. 1-2 in expanded polynomial form (the seed text
// of eq. 2 has a garbled sign in the constant term; this is the expansion of the Hermite
// h/8 (A - x)^2 (2x + A - 6a) / (A - 2a)^3).
double RefF(double x, double a, double h) {
  const double A = 20.0 * a / 3.0;
  if (x <= 2 * a) {
    return 5 * h / (32 * a * a * a) * x * x * x - 29 * h / (32 * a * a) * x * x + 7 * h / (4 * a) * x - h;
  }
  if (x >= A) return 0.0;
  const double L = A - 2 * a;
  return h / (4 * L * L * L) * x * x * x - 3 * h * (A + 2 * a) / (8 * L * L * L) * x * x +
         3 * h * A * a / (2 * L * L * L) * x + h * (A * A * A - 6 * A * A * a) / (8 * L * L * L);
}
double RefSlope(double x, double a, double h) {
  const double A = 20.0 * a / 3.0;
  if (x <= 2 * a) return 15 * h / (32 * a * a * a) * x * x - 58 * h / (32 * a * a) * x + 7 * h / (4 * a);
  if (x >= A) return 0.0;
  const double L = A - 2 * a;
  return 3 * h / (4 * L * L * L) * x * x - 3 * h * (A + 2 * a) / (4 * L * L * L) * x +
         3 * h * A * a / (2 * L * L * L);
}
double RefArc(double a, double h, double x_end) {
  auto g = [&](double x) { return std::sqrt(1.0 + RefSlope(x, a, h) * RefSlope(x, a, h)); };
  const double m = std::fmin(x_end, 2 * a);
  double s = Simpson(g, 0.0, m, 20000);
  if (x_end > 2 * a) s += Simpson(g, 2 * a, x_end, 20000);
  return s;
}

TEST(YangZhang, ProfileMatchesEquations) {  // 004 eq. 1-2
  const double a = 0.8, h = 0.3, A = YangZhangWidth(a);
  EXPECT_NEAR(A, 20.0 * 0.8 / 3.0, 1e-15);
  EXPECT_NEAR(YangZhangProfile(0.0, a, h), -h, 1e-15);
  EXPECT_NEAR(YangZhangProfile(a, a, h), 0.0, 1e-15);
  EXPECT_NEAR(YangZhangProfile(2 * a, a, h), h / 8, 1e-15);
  EXPECT_NEAR(YangZhangProfile(A, a, h), 0.0, 1e-15);
  EXPECT_EQ(YangZhangProfile(A * 1.01, a, h), 0.0);
  for (double x = 0.0; x <= A; x += A / 97) {
    EXPECT_NEAR(YangZhangProfile(x, a, h), RefF(x, a, h), 1e-12) << x;
    EXPECT_NEAR(YangZhangSlope(x, a, h), RefSlope(x, a, h), 1e-12) << x;
  }
  EXPECT_NEAR(YangZhangSlope(2 * a, a, h), 0.0, 1e-12);  // flat at 2a (both pieces)
  EXPECT_NEAR(YangZhangSlope(A * (1 - 1e-12), a, h), 0.0, 1e-9);
  EXPECT_EQ(YangZhangProfile(0.1, 0.0, h), 0.0);  // zero width: no NaN
}

TEST(YangZhang, ZeroVolumeAtA) {  // 004 eq. 3-5, accept e
  for (double a : {0.2, 1.0, 3.0}) {
    const double h = 0.4, A = 20.0 * a / 3.0;
    auto f = [&](double x) { return YangZhangProfile(x, a, h); };
    const double vol = Simpson(f, 0.0, 2 * a, 2000) + Simpson(f, 2 * a, A, 2000);
    EXPECT_NEAR(vol, 0.0, 1e-9 * h * a) << a;
    // Same with the reference polynomial (the check is not circular).
    auto g = [&](double x) { return RefF(x, a, h); };
    EXPECT_NEAR(Simpson(g, 0.0, 2 * a, 2000) + Simpson(g, 2 * a, A, 2000), 0.0, 1e-9 * h * a);
  }
}

TEST(YangZhang, Eq9KeepsTheFlankLengthWithinOnePercent) {  // 004 eq. 8-9, accept e
  const double a0 = 1.0, h0 = 0.5;
  const double rest = RefArc(a0, h0, a0);  // the flank [0, a] that eq. 9 models by its chord
  for (double S : {0.5, 0.6, 0.8, 0.9, 1.0, 1.05, 1.1}) {
    const double h = YangZhangDepth(h0, a0, S);
    EXPECT_NEAR(h, std::sqrt(h0 * h0 + (1 - S * S) * a0 * a0), 1e-12);
    const double a = S * a0;
    EXPECT_NEAR(RefArc(a, h, a) / rest, 1.0, 0.01) << "S " << S;
  }
  EXPECT_EQ(YangZhangDepth(h0, a0, std::sqrt(1.0 + h0 * h0 / (a0 * a0)) + 1e-9), 0.0);
  EXPECT_EQ(YangZhangDepth(h0, a0, 3.0), 0.0);
  EXPECT_NEAR(YangZhangDepth(h0, a0, 0.0), std::sqrt(h0 * h0 + a0 * a0), 1e-12);  // max depth
}

TEST(YangZhang, NewtonKeepsTheLengthTo1e6) {  // 004 eq. 6, accept e
  const double a0 = 1.0, h0 = 0.5;
  for (YangZhangSpan span : {YangZhangSpan::kFlank, YangZhangSpan::kFull}) {
    const double end0 = span == YangZhangSpan::kFlank ? a0 : 20.0 * a0 / 3.0;
    const double rest = RefArc(a0, h0, end0);
    EXPECT_NEAR(YangZhangSpanLength(a0, h0, span) / rest, 1.0, 1e-9);
    for (double S : {0.3, 0.6, 0.8, 0.95, 1.0, 1.02}) {
      const double h = YangZhangDepthNewton(h0, a0, S, span);
      const double a = S * a0;
      const double end = span == YangZhangSpan::kFlank ? a : 20.0 * a / 3.0;
      EXPECT_GT(h, 0.0);
      EXPECT_NEAR(RefArc(a, h, end) / rest, 1.0, 1e-6) << "S " << S;
    }
    // Stretched past the rest length: no depth left.
    EXPECT_EQ(YangZhangDepthNewton(h0, a0, 1.5, span), 0.0);
  }
  // At rest the Newton solution is h0.
  EXPECT_NEAR(YangZhangDepthNewton(h0, a0, 1.0, YangZhangSpan::kFlank), h0, 1e-9);
  // Non-finite input falls back to eq. 9 (and never hangs).
  EXPECT_EQ(YangZhangDepthNewton(h0, a0, std::nan(""), YangZhangSpan::kFlank), h0);
  EXPECT_TRUE(std::isfinite(YangZhangDepthNewton(h0, a0, 0.0, YangZhangSpan::kFull)));
  EXPECT_TRUE(std::isfinite(YangZhangDepthNewton(1e-8, 1e3, 1e-6, YangZhangSpan::kFull)));
}

}  // namespace
}  // namespace mimetic

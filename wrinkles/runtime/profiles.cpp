// wrinkles/runtime/profiles.cpp: Yang-Zhang arc length and exact depth update (004 eq. 6),
// docs/model.md §8. Allocation-free, bounded work, no exceptions.
#include "wrinkles/runtime/profiles.h"

#include <cmath>

namespace mimetic {
namespace {

// 8-point Gauss-Legendre nodes and weights on [-1, 1] (symmetric: +-x_i share w_i).
constexpr double kGlX[4] = {0.1834346424956498, 0.5255324099163290, 0.7966664774136267,
                            0.9602898564975363};
constexpr double kGlW[4] = {0.3626837833783620, 0.3137066458778873, 0.2223810344533745,
                            0.1012285362903763};
constexpr int kSubintervals = 16;  // per piece ([0, 2a] and [2a, A])
constexpr double kEnd = 20.0 / 3.0;  // A / a

// Slope of the unit-depth profile (h = 1) in units where a = 1, at t = x/a in [0, 20/3].
double UnitSlope(double t) { return YangZhangSlope(t, 1.0, 1.0); }

// Integrates sqrt(1 + (rho g'(t))^2) and its rho-derivative over [t0, t1] (units of a).
void IntegratePiece(double rho, double t0, double t1, double* len, double* dlen) {
  if (!(t1 > t0)) return;
  const double step = (t1 - t0) / kSubintervals;
  for (int k = 0; k < kSubintervals; ++k) {
    const double mid = t0 + (k + 0.5) * step;
    const double half = 0.5 * step;
    for (int i = 0; i < 4; ++i) {
      for (int sign = -1; sign <= 1; sign += 2) {
        const double g = UnitSlope(mid + sign * half * kGlX[i]);
        const double q = rho * g;
        const double root = std::sqrt(1.0 + q * q);
        *len += kGlW[i] * half * root;
        *dlen += kGlW[i] * half * (g * q / root);
      }
    }
  }
}

// Length of the profile (a, rho = h/a) over [0, te] in units of a, and its derivative in rho.
void UnitLength(double rho, double te, double* len, double* dlen) {
  *len = 0.0;
  *dlen = 0.0;
  IntegratePiece(rho, 0.0, std::fmin(te, 2.0), len, dlen);
  IntegratePiece(rho, 2.0, std::fmin(te, kEnd), len, dlen);
  if (te > kEnd) *len += te - kEnd;
}

}  // namespace

double YangZhangArcLength(double a, double h, double x_end) {
  if (!(x_end > 0.0)) return 0.0;
  if (!(a > 0.0)) return x_end;
  double len = 0.0, dlen = 0.0;
  UnitLength(h / a, x_end / a, &len, &dlen);
  return len * a;
}

double YangZhangSpanLength(double a, double h, YangZhangSpan span) {
  const double x_end = span == YangZhangSpan::kFlank ? a : YangZhangWidth(a);
  return YangZhangArcLength(a, h, x_end);
}

double YangZhangDepthNewton(double h0, double a0, double S, double rest_length,
                            YangZhangSpan span) {
  const double approx = YangZhangDepth(h0, a0, S);
  if (!std::isfinite(h0) || !std::isfinite(a0) || !std::isfinite(S) ||
      !std::isfinite(rest_length) || !(a0 > 0.0)) {
    return approx;
  }
  if (S < 0.0) S = 0.0;
  const double a = S * a0;
  if (!(a > 1e-300)) return approx;  // zero-width profile: f = 0 whatever h is
  const double te = span == YangZhangSpan::kFlank ? 1.0 : kEnd;
  const double target = rest_length / a;  // in units of a
  if (!(target > te)) return 0.0;  // even a flat profile is too long: stretched skin
  // The length is convex and increasing in rho, and >= rho * (total variation of g) >= rho on
  // either span, so the root lies in [0, target].
  double lo = 0.0, hi = target;
  double rho = approx / a;
  if (!(rho > lo && rho < hi)) rho = 0.5 * (lo + hi);
  for (int it = 0; it < 64; ++it) {
    double len = 0.0, dlen = 0.0;
    UnitLength(rho, te, &len, &dlen);
    const double f = len - target;
    if (std::fabs(f) <= 1e-14 * target) return rho * a;
    if (f > 0.0) {
      hi = rho;
    } else {
      lo = rho;
    }
    if (hi - lo <= 1e-15 * hi) return rho * a;
    double next = dlen > 0.0 ? rho - f / dlen : 0.5 * (lo + hi);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    rho = next;
  }
  const double h = rho * a;
  return std::isfinite(h) ? h : approx;
}

double YangZhangDepthNewton(double h0, double a0, double S, YangZhangSpan span) {
  return YangZhangDepthNewton(h0, a0, S, YangZhangSpanLength(a0, h0, span), span);
}

}  // namespace mimetic

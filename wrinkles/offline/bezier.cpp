// wrinkles/offline/bezier.cpp: see bezier.h.
#include "wrinkles/offline/bezier.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace mimetic {
namespace {

struct D2 {
  double x, y;
};

D2 Eval(const float2 c[4], double t, int derivative) {
  const double s = 1.0 - t;
  double w[4];
  D2 q[4];
  for (int k = 0; k < 4; ++k) q[k] = {c[k].x, c[k].y};
  if (derivative == 0) {
    w[0] = s * s * s; w[1] = 3 * s * s * t; w[2] = 3 * s * t * t; w[3] = t * t * t;
    return {w[0] * q[0].x + w[1] * q[1].x + w[2] * q[2].x + w[3] * q[3].x,
            w[0] * q[0].y + w[1] * q[1].y + w[2] * q[2].y + w[3] * q[3].y};
  }
  if (derivative == 1) {
    const double a = 3 * s * s, b = 6 * s * t, d = 3 * t * t;
    return {a * (q[1].x - q[0].x) + b * (q[2].x - q[1].x) + d * (q[3].x - q[2].x),
            a * (q[1].y - q[0].y) + b * (q[2].y - q[1].y) + d * (q[3].y - q[2].y)};
  }
  const double a = 6 * s, b = 6 * t;
  return {a * (q[2].x - 2 * q[1].x + q[0].x) + b * (q[3].x - 2 * q[2].x + q[1].x),
          a * (q[2].y - 2 * q[1].y + q[0].y) + b * (q[3].y - 2 * q[2].y + q[1].y)};
}

double Dist2(const float2 c[4], double t, D2 p) {
  const D2 b = Eval(c, t, 0);
  return (b.x - p.x) * (b.x - p.x) + (b.y - p.y) * (b.y - p.y);
}

constexpr int kSamples = 64;

}  // namespace

float2 BezierPoint(const float2 c[4], double t) {
  const D2 b = Eval(c, t, 0);
  return {static_cast<float>(b.x), static_cast<float>(b.y)};
}

BezierReach ClassifyBezierReach(const float2 c[4], float2 query, double reach) {
  for (int k = 0; k < 4; ++k)
    if (!std::isfinite(c[k].x) || !std::isfinite(c[k].y)) return BezierReach::kUnsure;
  if (!std::isfinite(query.x) || !std::isfinite(query.y) || !(reach >= 0.0))
    return BezierReach::kUnsure;
  constexpr int kChords = 16;
  const double ax = double(c[2].x) - 2.0 * c[1].x + c[0].x, ay = double(c[2].y) - 2.0 * c[1].y + c[0].y;
  const double bx = double(c[3].x) - 2.0 * c[2].x + c[1].x, by = double(c[3].y) - 2.0 * c[2].y + c[1].y;
  const double second = 6.0 * std::sqrt(std::max(ax * ax + ay * ay, bx * bx + by * by));
  const double h = 1.0 / kChords;
  const double deviation = second * h * h / 8.0;
  const D2 p = {query.x, query.y};
  // Compared squared: the distance to every chord must exceed reach + deviation (with a
  // relative margin for rounding).
  const double need = (reach + deviation) * (1.0 + 1e-9) + 1e-12;
  const double need2 = need * need;
  const double reach2 = reach * reach;
  bool beyond = true;
  D2 a = Eval(c, 0.0, 0);
  if ((a.x - p.x) * (a.x - p.x) + (a.y - p.y) * (a.y - p.y) <= reach2) return BezierReach::kWithin;
  for (int i = 1; i <= kChords; ++i) {
    const D2 b = Eval(c, double(i) / kChords, 0);
    if ((b.x - p.x) * (b.x - p.x) + (b.y - p.y) * (b.y - p.y) <= reach2) return BezierReach::kWithin;
    const double ex = b.x - a.x, ey = b.y - a.y;
    const double l2 = ex * ex + ey * ey;
    double u = l2 > 0.0 ? ((p.x - a.x) * ex + (p.y - a.y) * ey) / l2 : 0.0;
    u = u < 0.0 ? 0.0 : (u > 1.0 ? 1.0 : u);
    const double dx = a.x + u * ex - p.x, dy = a.y + u * ey - p.y;
    if (dx * dx + dy * dy <= need2) beyond = false;
    a = b;
  }
  return beyond ? BezierReach::kBeyond : BezierReach::kUnsure;
}

BezierClosest ClosestPointOnBezier(const float2 c[4], float2 query) {
  BezierClosest out;
  out.distance = std::numeric_limits<double>::infinity();
  out.tangent = {1.f, 0.f};
  for (int k = 0; k < 4; ++k) {
    if (!std::isfinite(c[k].x) || !std::isfinite(c[k].y)) return out;
  }
  if (!std::isfinite(query.x) || !std::isfinite(query.y)) return out;
  const D2 p = {query.x, query.y};
  double d2[kSamples + 1];
  for (int i = 0; i <= kSamples; ++i) d2[i] = Dist2(c, double(i) / kSamples, p);
  double best_t = 0.0, best = d2[0];
  for (int i = 0; i <= kSamples; ++i) {
    const bool left_ok = i == 0 || d2[i] <= d2[i - 1];
    const bool right_ok = i == kSamples || d2[i] <= d2[i + 1];
    if (!left_ok || !right_ok) continue;  // not a sampled local minimum
    double lo = double(i == 0 ? 0 : i - 1) / kSamples;
    double hi = double(i == kSamples ? kSamples : i + 1) / kSamples;
    // Golden-section search on [lo, hi].
    const double g = 0.6180339887498949;
    double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo);
    double f1 = Dist2(c, x1, p), f2 = Dist2(c, x2, p);
    for (int it = 0; it < 48; ++it) {
      if (f1 <= f2) {
        hi = x2; x2 = x1; f2 = f1; x1 = hi - g * (hi - lo); f1 = Dist2(c, x1, p);
      } else {
        lo = x1; x1 = x2; f1 = f2; x2 = lo + g * (hi - lo); f2 = Dist2(c, x2, p);
      }
    }
    double t = f1 <= f2 ? x1 : x2;
    double f = f1 <= f2 ? f1 : f2;
    const double blo = double(i == 0 ? 0 : i - 1) / kSamples;
    const double bhi = double(i == kSamples ? kSamples : i + 1) / kSamples;
    // Newton polish on g(t) = (B - p).B'.
    for (int it = 0; it < 4; ++it) {
      const D2 b = Eval(c, t, 0), d1 = Eval(c, t, 1), dd = Eval(c, t, 2);
      const double gt = (b.x - p.x) * d1.x + (b.y - p.y) * d1.y;
      const double gp = d1.x * d1.x + d1.y * d1.y + (b.x - p.x) * dd.x + (b.y - p.y) * dd.y;
      if (!(gp > 0.0)) break;
      const double tn = t - gt / gp;
      if (!(tn >= blo && tn <= bhi)) break;
      const double fn = Dist2(c, tn, p);
      if (!(fn < f)) break;
      t = tn;
      f = fn;
    }
    // The sample itself (an end point, or a flat minimum) may still be the best.
    const double ti = double(i) / kSamples;
    if (d2[i] < f) {
      t = ti;
      f = d2[i];
    }
    if (f < best || (f == best && t < best_t)) {
      best = f;
      best_t = t;
    }
  }
  out.t = best_t;
  out.distance = std::sqrt(best);
  out.point = BezierPoint(c, best_t);
  D2 d = Eval(c, best_t, 1);
  double len = std::sqrt(d.x * d.x + d.y * d.y);
  if (!(len > 1e-12)) {
    const double t0 = std::fmax(0.0, best_t - 1e-3), t1 = std::fmin(1.0, best_t + 1e-3);
    const D2 a = Eval(c, t0, 0), b = Eval(c, t1, 0);
    d = {b.x - a.x, b.y - a.y};
    len = std::sqrt(d.x * d.x + d.y * d.y);
  }
  if (!(len > 1e-12)) {
    d = {double(c[3].x) - c[0].x, double(c[3].y) - c[0].y};
    len = std::sqrt(d.x * d.x + d.y * d.y);
  }
  if (len > 1e-12) out.tangent = {static_cast<float>(d.x / len), static_cast<float>(d.y / len)};
  return out;
}

}  // namespace mimetic

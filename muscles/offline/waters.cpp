#include "muscles/offline/waters.h"

#include <algorithm>
#include <cmath>

namespace mimetic {
namespace {
constexpr double kHalfPi = 1.57079632679489661923;

struct D3 {
  double x, y, z;
};
D3 ToD(float3 v) { return {v.x, v.y, v.z}; }
D3 Sub(D3 a, D3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
double DotD(D3 a, D3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
double LenD(D3 a) { return std::sqrt(DotD(a, a)); }

// A linear muscle's polar coordinates of p: D = |p - v1| and mu, the angle from the axis v2 - v1
// (0 when D = 0). False when the axis has no length.
struct Polar {
  D3 rel;  // p - v1
  double d = 0.0, mu = 0.0;
};
// `max_d`: beyond it the angle is not wanted (mu is left 0 and D is still exact), which spares
// the arc cosine for the many points a caller rejects on D alone.
bool LinearPolar(const LinearMuscleSpec& m, float3 p, Polar* out, double max_d = HUGE_VAL) {
  const D3 v1 = ToD(m.attachment);
  const D3 axis = Sub(ToD(m.insertion), v1);
  const double axis_len = LenD(axis);
  if (!(axis_len > 0.0)) return false;
  out->rel = Sub(ToD(p), v1);
  out->d = LenD(out->rel);
  out->mu = 0.0;
  if (out->d > 0.0 && out->d <= max_d) {
    const double c = DotD(axis, out->rel) / (axis_len * out->d);
    out->mu = std::acos(c < -1.0 ? -1.0 : (c > 1.0 ? 1.0 : c));
  }
  return true;
}

// A sheet muscle's frame at p: f, the unit fibre mAc -> mIc; l = (p - mAc) . f; h, the distance
// from p to the central fibre's line. False when the fibre has no length.
struct SheetFrame {
  D3 f;
  double l = 0.0, h = 0.0;
};
bool SheetCoordinates(const SheetMuscleSpec& m, float3 p, SheetFrame* out) {
  const D3 a1 = ToD(m.attachment[0]), a2 = ToD(m.attachment[1]);
  const D3 i1 = ToD(m.insertion[0]), i2 = ToD(m.insertion[1]);
  const D3 ac = {(a1.x + a2.x) * 0.5, (a1.y + a2.y) * 0.5, (a1.z + a2.z) * 0.5};
  const D3 ic = {(i1.x + i2.x) * 0.5, (i1.y + i2.y) * 0.5, (i1.z + i2.z) * 0.5};
  const D3 fiber = Sub(ic, ac);
  const double fiber_len = LenD(fiber);
  if (!(fiber_len > 0.0)) return false;
  const D3 f = {fiber.x / fiber_len, fiber.y / fiber_len, fiber.z / fiber_len};
  const D3 rel = Sub(ToD(p), ac);
  const double l = DotD(rel, f);
  const D3 perp = {rel.x - l * f.x, rel.y - l * f.y, rel.z - l * f.z};
  *out = {f, l, LenD(perp)};
  return true;
}
}  // namespace

double WatersAngularFactor(double mu, double omega) {
  if (!(mu >= 0.0) || !(mu <= omega) || !(omega > 0.0)) return 0.0;
  return std::cos(mu / omega * kHalfPi);
}

double WatersRadialFactor(double d, double rs, double rf) {
  if (!(d >= 0.0) || !(d <= rf) || !(rs > 0.0) || !(rf > rs)) return 0.0;
  if (d <= rs) return std::cos((1.0 - d / rs) * kHalfPi);
  return std::cos((d - rs) / (rf - rs) * kHalfPi);
}

double SheetLengthFalloff(double lambda, double rs_over_ls) {
  if (!(lambda >= 0.0) || !(lambda <= 1.0) || !(rs_over_ls > 0.0) || !(rs_over_ls < 1.0))
    return 0.0;
  if (lambda <= rs_over_ls) return std::cos((1.0 - lambda / rs_over_ls) * kHalfPi);
  return std::cos((lambda - rs_over_ls) / (1.0 - rs_over_ls) * kHalfPi);
}

double SheetWidthFalloff(double gamma) {
  if (!(gamma >= 0.0) || !(gamma <= 1.0)) return 0.0;
  return std::cos(gamma * kHalfPi);
}

double ApplyFalloff(double f, MuscleFalloff falloff) {
  return falloff == MuscleFalloff::kSmooth ? f * f : f;
}

float3 LinearMuscleDisplacement(const LinearMuscleSpec& m, float3 p, float k,
                                MuscleFalloff falloff) {
  Polar q;
  if (!LinearPolar(m, p, &q, m.falloff_end) || !(q.d > 0.0) || q.d > m.falloff_end) return {};
  const double a = ApplyFalloff(WatersAngularFactor(q.mu, m.zone_angle), falloff);
  const double r = ApplyFalloff(WatersRadialFactor(q.d, m.falloff_start, m.falloff_end), falloff);
  const double s = double(k) * a * r / q.d;  // (v1 - p) / D = -rel / d
  return {float(-q.rel.x * s), float(-q.rel.y * s), float(-q.rel.z * s)};
}

float3 SheetMuscleDisplacement(const SheetMuscleSpec& m, float3 p, float k,
                               MuscleFalloff falloff) {
  SheetFrame q;
  if (!SheetCoordinates(m, p, &q) || !(m.length > 0.f) || !(m.width > 0.f)) return {};
  const double lambda = q.l / m.length;
  const double gamma = 2.0 * q.h / m.width;
  const double fl = ApplyFalloff(SheetLengthFalloff(lambda, double(m.falloff_start) / m.length),
                                 falloff);
  const double fw = ApplyFalloff(SheetWidthFalloff(gamma), falloff);
  const double s = double(k) * fl * fw;
  return {float(-q.f.x * s), float(-q.f.y * s), float(-q.f.z * s)};
}

double MuscleFalloffCurvature(const MuscleSpec& m, float3 p) {
  constexpr double kBend = 2.0 * kHalfPi * kHalfPi;  // pi^2 / 2
  auto sq = [](double v) { return v * v; };
  if (m.type == MuscleType::kLinear) {
    const LinearMuscleSpec& l = m.linear;
    const double rs = l.falloff_start, rf = l.falloff_end, omega = l.zone_angle;
    Polar q;
    const double reach = rf + 0.5 * (rf - rs);
    if (!(rs > 0.0) || !(rf > rs) || !(omega > 0.0) || !LinearPolar(l, p, &q, reach)) return 0.0;
    if (!(q.d <= reach) || !(q.mu <= 1.5 * omega)) return 0.0;
    const double dc = std::min(q.d, rf), muc = std::min(q.mu, omega);
    const double a2 = sq(WatersAngularFactor(muc, omega));
    const double r2 = sq(WatersRadialFactor(dc, rs, rf));
    const double wr = dc <= rs ? rs : rf - rs;
    // R^2 / D^2 stays bounded as D -> 0 (R ~ pi D / (2 Rs) there): its limit is used at D = 0.
    const double r2_over_d2 = dc > 0.0 ? r2 / sq(dc) : sq(kHalfPi / rs);
    return kBend * std::max(a2 / sq(wr), r2_over_d2 / sq(omega));
  }
  const SheetMuscleSpec& s = m.sheet;
  const double ls = s.length, ws = s.width, rs = s.falloff_start;
  SheetFrame q;
  if (!(ls > 0.0) || !(ws > 0.0) || !(rs > 0.0) || !(rs < ls) || !SheetCoordinates(s, p, &q))
    return 0.0;
  if (!(q.l >= -0.5 * rs) || !(q.l <= ls + 0.5 * (ls - rs)) || !(q.h <= 0.75 * ws)) return 0.0;
  const double lc = std::min(std::max(q.l, 0.0), ls), hc = std::min(q.h, 0.5 * ws);
  const double fl2 = sq(SheetLengthFalloff(lc / ls, rs / ls));
  const double fw2 = sq(SheetWidthFalloff(2.0 * hc / ws));
  const double wl = lc <= rs ? rs : ls - rs;
  return kBend * std::max(fw2 / sq(wl), fl2 / sq(0.5 * ws));
}

MuscleBall MuscleFalloffCurvatureBall(const MuscleSpec& m) {
  MuscleBall b;
  if (m.type == MuscleType::kLinear) {
    const LinearMuscleSpec& l = m.linear;
    const double rs = l.falloff_start, rf = l.falloff_end;
    b = {l.attachment.x, l.attachment.y, l.attachment.z, rf + 0.5 * (rf - rs), false};
  } else {
    // l in [-Rs / 2, Ls + (Ls - Rs) / 2] along the central fibre, h <= 3/4 Ws from it.
    const SheetMuscleSpec& s = m.sheet;
    const double ls = s.length, ws = s.width, rs = s.falloff_start;
    const D3 a1 = ToD(s.attachment[0]), a2 = ToD(s.attachment[1]);
    const D3 i1 = ToD(s.insertion[0]), i2 = ToD(s.insertion[1]);
    const D3 ac = {(a1.x + a2.x) * 0.5, (a1.y + a2.y) * 0.5, (a1.z + a2.z) * 0.5};
    const D3 fiber = Sub({(i1.x + i2.x) * 0.5, (i1.y + i2.y) * 0.5, (i1.z + i2.z) * 0.5}, ac);
    const double len = LenD(fiber);
    if (!(len > 0.0)) return {};
    const double from = -0.5 * rs, to = ls + 0.5 * (ls - rs), mid = 0.5 * (from + to) / len;
    b = {ac.x + fiber.x * mid, ac.y + fiber.y * mid, ac.z + fiber.z * mid,
         std::hypot(0.5 * (to - from), 0.75 * ws), false};
  }
  b.r = b.r * (1.0 + 1e-6) + 1e-9;
  if (!std::isfinite(b.x) || !std::isfinite(b.y) || !std::isfinite(b.z) || !std::isfinite(b.r) ||
      !(b.r >= 0.0))
    return {};
  return b;
}

float3 MuscleDisplacement(const MuscleSpec& m, float3 p, float k) {
  return m.type == MuscleType::kLinear ? LinearMuscleDisplacement(m.linear, p, k, m.falloff)
                                       : SheetMuscleDisplacement(m.sheet, p, k, m.falloff);
}

}  // namespace mimetic

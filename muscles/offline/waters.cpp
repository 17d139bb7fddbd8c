#include "muscles/offline/waters.h"

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
  const D3 v1 = ToD(m.attachment);
  const D3 axis = Sub(ToD(m.insertion), v1);
  const D3 rel = Sub(ToD(p), v1);  // p - v1
  const double d = LenD(rel);
  const double axis_len = LenD(axis);
  if (!(d > 0.0) || !(axis_len > 0.0) || d > m.falloff_end) return {};
  const double cos_mu = DotD(axis, rel) / (axis_len * d);
  const double mu = std::acos(cos_mu < -1.0 ? -1.0 : (cos_mu > 1.0 ? 1.0 : cos_mu));
  const double a = ApplyFalloff(WatersAngularFactor(mu, m.zone_angle), falloff);
  const double r = ApplyFalloff(WatersRadialFactor(d, m.falloff_start, m.falloff_end), falloff);
  const double s = double(k) * a * r / d;  // (v1 - p) / D = -rel / d
  return {float(-rel.x * s), float(-rel.y * s), float(-rel.z * s)};
}

float3 SheetMuscleDisplacement(const SheetMuscleSpec& m, float3 p, float k,
                               MuscleFalloff falloff) {
  const D3 a1 = ToD(m.attachment[0]), a2 = ToD(m.attachment[1]);
  const D3 i1 = ToD(m.insertion[0]), i2 = ToD(m.insertion[1]);
  const D3 ac = {(a1.x + a2.x) * 0.5, (a1.y + a2.y) * 0.5, (a1.z + a2.z) * 0.5};
  const D3 ic = {(i1.x + i2.x) * 0.5, (i1.y + i2.y) * 0.5, (i1.z + i2.z) * 0.5};
  const D3 fiber = Sub(ic, ac);
  const double fiber_len = LenD(fiber);
  if (!(fiber_len > 0.0) || !(m.length > 0.f) || !(m.width > 0.f)) return {};
  const D3 f = {fiber.x / fiber_len, fiber.y / fiber_len, fiber.z / fiber_len};
  const D3 rel = Sub(ToD(p), ac);
  const double l = DotD(rel, f);
  const D3 perp = {rel.x - l * f.x, rel.y - l * f.y, rel.z - l * f.z};
  const double h = LenD(perp);
  const double lambda = l / m.length;
  const double gamma = 2.0 * h / m.width;
  const double fl = ApplyFalloff(SheetLengthFalloff(lambda, double(m.falloff_start) / m.length),
                                 falloff);
  const double fw = ApplyFalloff(SheetWidthFalloff(gamma), falloff);
  const double s = double(k) * fl * fw;
  return {float(-f.x * s), float(-f.y * s), float(-f.z * s)};
}

float3 MuscleDisplacement(const MuscleSpec& m, float3 p, float k) {
  return m.type == MuscleType::kLinear ? LinearMuscleDisplacement(m.linear, p, k, m.falloff)
                                       : SheetMuscleDisplacement(m.sheet, p, k, m.falloff);
}

}  // namespace mimetic

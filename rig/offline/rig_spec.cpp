#include "rig/offline/rig_spec.h"

#include <cmath>
#include <numbers>

namespace mimetic {

float Smoothstep(float lo, float hi, float x) {
  if (!(hi > lo)) return x < lo ? 0.f : 1.f;
  const float t = std::fmin(std::fmax((x - lo) / (hi - lo), 0.f), 1.f);
  return t * t * (3.f - 2.f * t);
}

bool MakeJawFrame(const JawSpec& jaw, JawFrame* out) {
  JawFrame f;
  f.pivot = (jaw.condyles[0] + jaw.condyles[1]) * 0.5f;
  const float3 across = jaw.condyles[1] - jaw.condyles[0];
  const float len = Length(across);
  if (!(len > 0.f) || !std::isfinite(len)) return false;
  f.axis = across * (1.f / len);
  float3 fwd = jaw.mouth - f.pivot;
  fwd = fwd - f.axis * Dot(fwd, f.axis);
  const float reach = Length(fwd);
  if (!(reach > 1e-3f * len) || !std::isfinite(reach)) return false;
  f.forward = fwd * (1.f / reach);
  f.up = Cross(f.forward, f.axis);
  f.reach = reach;
  *out = f;
  return true;
}

float JawRegionWeight(const JawSpec& jaw, const JawFrame& f, float3 p, float3 n) {
  const float3 r = p - f.pivot;
  const float x = Dot(r, f.axis), z = Dot(r, f.forward), y = Dot(r, f.up);
  const float phi = std::atan2(y, z) * float(180.0 / std::numbers::pi);
  const float half = 0.5f * jaw.mouth_width;
  const float e = jaw.mouth_width > 0.f ? Smoothstep(0.f, 1.f, (std::fabs(x) - half) / jaw.mouth_width)
                                        : 1.f;
  const float beta = jaw.lip_blend_deg + (jaw.cheek_blend_deg - jaw.lip_blend_deg) * e;
  const float corner = jaw.corner_fade > 0.f
                           ? Smoothstep(half - jaw.corner_fade * jaw.mouth_width, half, std::fabs(x))
                           : (std::fabs(x) >= half ? 1.f : 0.f);
  const float side = std::fmin(std::fmax(2.f * Dot(n, f.up), -1.f), 1.f) * (1.f - corner);
  const float phi0 = -jaw.cheek_drop_deg * e + beta * (1.f - e) * side;
  const float open = 1.f - Smoothstep(phi0 - beta, phi0 + beta, phi);
  const float front = Smoothstep(jaw.back[0] * f.reach, jaw.back[1] * f.reach, z);
  const float neck = Smoothstep(-jaw.neck_deg[1], -jaw.neck_deg[0], phi);
  return open * front * neck;
}

WrinkleMuscleGeometry WrinkleGeometryOf(const MuscleSpec& m) {
  WrinkleMuscleGeometry g;
  if (m.type == MuscleType::kLinear) {
    g.kind = WrinkleMuscleKind::kLinear;
    g.attachment = m.linear.attachment;
    g.insertion = m.linear.insertion;
    g.zone_angle = m.linear.zone_angle;
    g.radius = m.linear.falloff_end;  // 001's R is Waters' Rf
  } else {
    g.kind = WrinkleMuscleKind::kSheet;
    for (int k = 0; k < 2; ++k) {
      g.attachment_line[k] = m.sheet.attachment[k];
      g.insertion_line[k] = m.sheet.insertion[k];
    }
    g.length = m.sheet.length;
    g.width = m.sheet.width;
  }
  return g;
}

float EyeSlideWeight(float d, const float band[2]) {
  if (!(d < band[1])) return 0.f;  // also NaN
  if (d <= band[0]) return 1.f;
  const float t = (band[1] - d) / (band[1] - band[0]);
  return t * t * (3.f - 2.f * t);
}

}  // namespace mimetic

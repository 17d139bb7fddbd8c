// fitting/muscle_template.cpp: evaluating a landmark-relative muscle template. The template
// file format is io/template_file.cpp.
#include "fitting/muscle_template.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace mimetic {

double TemplateDigits(double v) {
  if (!std::isfinite(v)) return v;
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.4g", v);
  return std::strtod(buf, nullptr);
}

float EvaluateTemplateThickness(const TemplateThickness& t, float3 p) {
  const float w0 = std::exp(-2.f);
  // F(z) = smoothstep(front[0], front[1], z).
  float u = (p.z - t.front[0]) / (t.front[1] - t.front[0]);
  u = ClampOrLow(u, 0.f, 1.f);
  const float front = u * u * (3.f - 2.f * u);
  double num = double(w0) * t.base, den = w0;
  for (const ThicknessRegion& r : t.regions) {
    const float dx = (p.x - r.center.x) / r.radius.x, dy = (p.y - r.center.y) / r.radius.y;
    const double g = std::exp(-0.5 * double(dx * dx + dy * dy)) * front;
    num += g * r.value;
    den += g;
  }
  return float(num / den);
}

float EvaluateTensionRegion(const TemplateTensionRegion& r, const float front[2], float3 p) {
  float u = (p.z - front[0]) / (front[1] - front[0]);
  u = ClampOrLow(u, 0.f, 1.f);
  const float fade = u * u * (3.f - 2.f * u);
  const float dx = (p.x - r.center.x) / r.radius.x, dy = (p.y - r.center.y) / r.radius.y;
  const float g = std::exp(-0.5f * (dx * dx + dy * dy)) * fade;
  return g >= kTensionRegionCut ? std::min(g, 1.f) : 0.f;
}

}  // namespace mimetic

// viewer/core/skin_shading.cpp: see skin_shading.h (docs/model.md §12).
#include "viewer/core/skin_shading.h"

#include <algorithm>
#include <cmath>

namespace mimetic::viewer {
namespace {

float Clamp01(float x) { return std::clamp(x, 0.f, 1.f); }

}  // namespace

float3 SkinAlbedo(float melanin, float hemoglobin) {
  const float m = Clamp01(std::isfinite(melanin) ? melanin : 0.f);
  const float h = Clamp01(std::isfinite(hemoglobin) ? hemoglobin : 0.f);
  const float3 c = kSkinBase - m * kMelaninAbsorption - h * kHemoglobinAbsorption;
  return {Clamp01(c.x), Clamp01(c.y), Clamp01(c.z)};
}

float3 ShadeSkin(const float3& albedo, float3 n, const float3& l, const float3& v,
                 const SkinLighting& lighting) {
  if (Dot(n, v) < 0.f) n = -1.f * n;  // two-sided
  const float diffuse = std::max(0.f, Dot(n, l));
  const float3 half = NormalizeOr(l + v, n);
  const float spec = diffuse > 0.f
                         ? lighting.specular * std::pow(std::max(0.f, Dot(n, half)), lighting.exponent)
                         : 0.f;
  const float3 c = (lighting.ambient + lighting.light * diffuse) * albedo + float3{spec, spec, spec};
  return {Clamp01(c.x), Clamp01(c.y), Clamp01(c.z)};
}

float3 LightDirection(float azimuth_deg, float elevation_deg) {
  const float az = azimuth_deg * 0.017453292f, el = elevation_deg * 0.017453292f;
  return {std::cos(el) * std::sin(az), std::sin(el), std::cos(el) * std::cos(az)};
}

}  // namespace mimetic::viewer

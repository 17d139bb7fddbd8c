// viewer/core/skin_shading.h: the viewer's skin colour and lighting (docs/model.md §12).
//
//   c = b - m a_m - h a_h     b = (0.97, 0.87, 0.67), a_m = (0.69, 0.71, 0.90),
//                             a_h = (0.00, 0.24, 0.24)           (000 eq. 6; 003 eq. 5.7)
// m (melanin) and h (hemoglobin) in [0, 1]; each channel of c clamped to [0, 1]. c is the
// ambient and diffuse reflectance of Blinn-Phong with ambient 0.3 and light 0.7 (003 §5.3):
//   colour = 0.3 c + 0.7 max(0, n.l) c + k_s max(0, n.h)^e,   h = normalize(l + v)
// two-sided (n flipped toward the viewer). The viewer's fragment shader computes the same
// expression (viewer/app/renderer.cpp); ShadeSkin is its reference.
#pragma once

#include "core/math.h"

namespace mimetic::viewer {

inline constexpr float3 kSkinBase{0.97f, 0.87f, 0.67f};
inline constexpr float3 kMelaninAbsorption{0.69f, 0.71f, 0.90f};
inline constexpr float3 kHemoglobinAbsorption{0.00f, 0.24f, 0.24f};

struct SkinLighting {
  float ambient = 0.3f;    // 003 §5.3
  float light = 0.7f;      // 003 §5.3
  float specular = 0.08f;  // choice (docs/model.md §12): a faint white highlight
  float exponent = 24.f;
};

// c = b - m a_m - h a_h, clamped to [0, 1] per channel (m and h clamped to [0, 1] first).
float3 SkinAlbedo(float melanin, float hemoglobin);

// The lit colour of albedo c at unit normal n, unit direction toward the light l and toward the
// viewer v (all in one space), clamped to [0, 1] per channel.
float3 ShadeSkin(const float3& albedo, float3 n, const float3& l, const float3& v,
                 const SkinLighting& lighting = {});

// The unit direction toward the light from azimuth and elevation in degrees, in camera space
// (+X right, +Y up, +Z toward the viewer): (cos el sin az, sin el, cos el cos az).
float3 LightDirection(float azimuth_deg, float elevation_deg);

}  // namespace mimetic::viewer

// Skin colour (docs/model.md §12: c = b - m a_m - h a_h) and its Blinn-Phong lighting
// (ambient 0.3, light 0.7), at values computed by hand from the equations.
#include "viewer/core/skin_shading.h"

#include <cmath>

#include <gtest/gtest.h>

namespace mimetic::viewer {
namespace {

void ExpectColor(const float3& c, float r, float g, float b) {
  EXPECT_NEAR(c.x, r, 1e-6f);
  EXPECT_NEAR(c.y, g, 1e-6f);
  EXPECT_NEAR(c.z, b, 1e-6f);
}

TEST(ViewerSkinShading, AlbedoFollowsTheMelaninHemoglobinPlane) {
  ExpectColor(SkinAlbedo(0.f, 0.f), 0.97f, 0.87f, 0.67f);  // b
  // m = 0.2, h = 0.5: (0.97 - 0.138, 0.87 - 0.142 - 0.12, 0.67 - 0.18 - 0.12)
  ExpectColor(SkinAlbedo(0.2f, 0.5f), 0.832f, 0.608f, 0.37f);
  // m = 0.5, h = 1: blue 0.67 - 0.45 - 0.24 < 0 clamps to 0; red 0.97 - 0.345.
  ExpectColor(SkinAlbedo(0.5f, 1.f), 0.625f, 0.275f, 0.f);
  // Inputs outside [0, 1] clamp first; NaN counts as 0.
  ExpectColor(SkinAlbedo(-1.f, NAN), 0.97f, 0.87f, 0.67f);
}

TEST(ViewerSkinShading, BlinnPhongWithAmbientPoint3AndLightPoint7) {
  const float3 c{0.8f, 0.6f, 0.4f};
  SkinLighting no_spec;
  no_spec.specular = 0.f;
  // Light along the normal: (0.3 + 0.7) c = c.
  ExpectColor(ShadeSkin(c, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}, no_spec), 0.8f, 0.6f, 0.4f);
  // Light at 60 degrees: n.l = 0.5, (0.3 + 0.35) c.
  const float3 l{std::sqrt(0.75f), 0.f, 0.5f};
  ExpectColor(ShadeSkin(c, {0, 0, 1}, l, {0, 0, 1}, no_spec), 0.52f, 0.39f, 0.26f);
  // Light behind: ambient only; a normal facing away from the viewer is flipped (two-sided).
  ExpectColor(ShadeSkin(c, {0, 0, 1}, {0, 0, -1}, {0, 0, 1}, no_spec), 0.24f, 0.18f, 0.12f);
  ExpectColor(ShadeSkin(c, {0, 0, -1}, {0, 0, 1}, {0, 0, 1}, no_spec), 0.8f, 0.6f, 0.4f);
  // The highlight: l = v = n gives h = n, + k_s on every channel.
  const float3 lit = ShadeSkin({0.5f, 0.5f, 0.5f}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1});
  ExpectColor(lit, 0.58f, 0.58f, 0.58f);
}

TEST(ViewerSkinShading, LightDirectionFromAzimuthAndElevation) {
  const float3 front = LightDirection(0.f, 0.f);
  ExpectColor(front, 0.f, 0.f, 1.f);
  const float3 up = LightDirection(0.f, 90.f);
  EXPECT_NEAR(up.y, 1.f, 1e-6f);
  const float3 right = LightDirection(90.f, 0.f);
  EXPECT_NEAR(right.x, 1.f, 1e-6f);
  EXPECT_NEAR(right.z, 0.f, 1e-6f);
}

}  // namespace
}  // namespace mimetic::viewer

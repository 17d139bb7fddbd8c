// The orbit camera (viewer/core/camera.h): preset view directions, framing, orbit/pan/zoom
// and the picking ray, against values computed by hand.
#include "viewer/core/camera.h"

#include <cmath>

#include <gtest/gtest.h>

namespace mimetic::viewer {
namespace {

void ExpectVec(const glm::vec3& v, float x, float y, float z, float tol = 1e-5f) {
  EXPECT_NEAR(v.x, x, tol);
  EXPECT_NEAR(v.y, y, tol);
  EXPECT_NEAR(v.z, z, tol);
}

TEST(ViewerCamera, PresetsLookAlongTheirAxes) {
  OrbitCamera cam;
  cam.target = {1.f, 2.f, 3.f};
  cam.distance = 10.f;
  cam.SetPreset(ViewPreset::kFront);  // the camera on +Z looks along -Z at the face
  ExpectVec(cam.Forward(), 0.f, 0.f, -1.f);
  ExpectVec(cam.Eye(), 1.f, 2.f, 13.f);
  cam.SetPreset(ViewPreset::kSide);  // on +X (the subject's left), looking along -X
  ExpectVec(cam.Forward(), -1.f, 0.f, 0.f);
  ExpectVec(cam.Eye(), 11.f, 2.f, 3.f, 1e-4f);
  cam.SetPreset(ViewPreset::kThreeQuarter);  // halfway: -(1, 0, 1) / sqrt 2
  const float h = 1.f / std::sqrt(2.f);
  ExpectVec(cam.Forward(), -h, 0.f, -h);
  ExpectVec(cam.Up(), 0.f, 1.f, 0.f);
  ExpectVec(cam.Right(), h, 0.f, -h);
}

TEST(ViewerCamera, PresetNamesRoundTrip) {
  for (ViewPreset p : {ViewPreset::kFront, ViewPreset::kSide, ViewPreset::kThreeQuarter}) {
    ViewPreset q = ViewPreset::kFront;
    ASSERT_TRUE(ParseViewPreset(ViewPresetName(p), &q));
    EXPECT_EQ(q, p);
  }
  ViewPreset q = ViewPreset::kSide;
  EXPECT_FALSE(ParseViewPreset("top", &q));
  EXPECT_EQ(q, ViewPreset::kSide);
}

TEST(ViewerCamera, FrameFitsTheBoundingSphereInTheFieldOfView) {
  OrbitCamera cam;
  cam.fov_y = 2.f * std::asin(0.25f);  // sin(fov/2) = 1/4
  cam.Frame({-3.f, -4.f, 0.f}, {3.f, 4.f, 0.f});  // diagonal 10: R = 5
  ExpectVec(cam.target, 0.f, 0.f, 0.f);
  EXPECT_NEAR(cam.scene_radius, 5.f, 1e-6f);
  EXPECT_NEAR(cam.distance, 20.f, 1e-4f);  // R / sin(fov/2)
}

TEST(ViewerCamera, OrbitPanZoom) {
  OrbitCamera cam;
  cam.distance = 10.f;
  cam.scene_radius = 1.f;
  cam.Orbit(-100.f, 50.f);  // yaw += 1 rad, pitch += 0.5 rad
  EXPECT_NEAR(cam.yaw, 1.f, 1e-6f);
  EXPECT_NEAR(cam.pitch, 0.5f, 1e-6f);
  cam.Orbit(0.f, 1e6f);
  EXPECT_FLOAT_EQ(cam.pitch, OrbitCamera::kMaxPitch);
  cam.Zoom(2.f);
  EXPECT_NEAR(cam.distance, 10.f * 0.81f, 1e-4f);
  cam.Zoom(-1000.f);
  EXPECT_FLOAT_EQ(cam.distance, 100.f);  // 100 scene radii at most

  OrbitCamera pan;
  pan.distance = 10.f;
  pan.fov_y = 2.f * std::atan(0.5f);  // 2 d tan(fov/2) = 10 units over the viewport
  pan.Pan(-50.f, 0.f, 100.f);  // half the viewport to the left: the target moves right by 5
  ExpectVec(pan.target, 5.f, 0.f, 0.f, 1e-4f);
}

TEST(ViewerCamera, PixelRayThroughTheCentreIsTheViewDirection) {
  OrbitCamera cam;
  cam.distance = 5.f;
  cam.fov_y = 2.f * std::atan(0.5f);
  const Ray centre = cam.PixelRay(50.f, 50.f, 100.f, 100.f);
  ExpectVec(centre.origin, 0.f, 0.f, 5.f);
  ExpectVec(centre.direction, 0.f, 0.f, -1.f);
  // The top edge: tan = 0.5 above the axis.
  const Ray top = cam.PixelRay(50.f, 0.f, 100.f, 100.f);
  const float n = std::sqrt(1.25f);
  ExpectVec(top.direction, 0.f, 0.5f / n, -1.f / n);
}

}  // namespace
}  // namespace mimetic::viewer

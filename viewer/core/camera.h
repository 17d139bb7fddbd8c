// viewer/core/camera.h: the viewer's orbit camera (GLM), with the presets and picking ray.
//
// The rig's frame (the sample head's, README "Conventions"): +Y up, the face looks toward +Z,
// the subject's left is +X. The camera orbits `target` at `distance`; yaw turns it about +Y
// (0: on the +Z axis, in front of the face; +pi/2: on +X, the subject's left side), pitch lifts
// it (positive: above the target, looking down). Angles in radians.
#pragma once

#include <string>

#include <glm/glm.hpp>

namespace mimetic::viewer {

enum class ViewPreset { kFront, kSide, kThreeQuarter };

// "front", "side", "three-quarter".
const char* ViewPresetName(ViewPreset preset);
// False (and *out untouched) for any other text.
bool ParseViewPreset(const std::string& text, ViewPreset* out);

struct Ray {
  glm::vec3 origin{0.f};
  glm::vec3 direction{0.f, 0.f, -1.f};  // unit
};

struct OrbitCamera {
  glm::vec3 target{0.f};
  float distance = 1.f;           // > 0, mesh units
  float yaw = 0.f;                // radians about +Y
  float pitch = 0.f;              // radians, in [-kMaxPitch, kMaxPitch]
  float fov_y = 0.5235988f;       // vertical field of view, radians (30 degrees)
  float scene_radius = 1.f;       // of what Frame() fitted; sets the clip planes

  static constexpr float kMaxPitch = 1.5533430f;  // 89 degrees: never looks straight down

  // target + distance * (sin(yaw) cos(pitch), sin(pitch), cos(yaw) cos(pitch)).
  glm::vec3 Eye() const;
  // Unit vector from the eye toward the target.
  glm::vec3 Forward() const;
  // Unit right and up vectors of the view (right = forward x +Y normalised; up = right x forward).
  glm::vec3 Right() const;
  glm::vec3 Up() const;
  glm::mat4 View() const;
  // Perspective with near/far bracketing the scene sphere (near >= distance / 1000).
  glm::mat4 Projection(float aspect) const;

  // The presets: yaw 0 (front), pi/2 (side, from the subject's left), pi/4 (three-quarter);
  // pitch 0. Target and distance are kept.
  void SetPreset(ViewPreset preset);
  // Centres the target on the box [lo, hi] and sets the distance so that its bounding sphere
  // (radius R = |hi - lo| / 2) fills the vertical field of view: distance = R / sin(fov_y / 2).
  void Frame(const glm::vec3& lo, const glm::vec3& hi);
  // Mouse drag in pixels: yaw -= dx * kOrbitRate, pitch += dy * kOrbitRate (clamped).
  void Orbit(float dx, float dy);
  // Drag in pixels over a viewport `viewport_height` pixels high: the target moves with the
  // cursor in the plane through the target (world units per pixel = 2 distance tan(fov/2) / h).
  void Pan(float dx, float dy, float viewport_height);
  // Wheel steps: distance *= kZoomStep^steps (positive steps move closer), kept in
  // [scene_radius / 100, scene_radius * 100].
  void Zoom(float steps);
  // The ray through pixel (x, y) of a width x height viewport (pixel centres at +0.5, y down).
  Ray PixelRay(float x, float y, float width, float height) const;

  static constexpr float kOrbitRate = 0.01f;  // radians per pixel
  static constexpr float kZoomStep = 0.9f;
};

}  // namespace mimetic::viewer

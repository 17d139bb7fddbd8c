// viewer/core/camera.cpp: see camera.h.
#include "viewer/core/camera.h"

#include <algorithm>
#include <cmath>

#include <glm/gtc/matrix_transform.hpp>

namespace mimetic::viewer {

const char* ViewPresetName(ViewPreset preset) {
  switch (preset) {
    case ViewPreset::kFront: return "front";
    case ViewPreset::kSide: return "side";
    case ViewPreset::kThreeQuarter: return "three-quarter";
  }
  return "front";
}

bool ParseViewPreset(const std::string& text, ViewPreset* out) {
  for (ViewPreset p : {ViewPreset::kFront, ViewPreset::kSide, ViewPreset::kThreeQuarter}) {
    if (text == ViewPresetName(p)) {
      *out = p;
      return true;
    }
  }
  return false;
}

glm::vec3 OrbitCamera::Eye() const {
  const float c = std::cos(pitch);
  return target + distance * glm::vec3(std::sin(yaw) * c, std::sin(pitch), std::cos(yaw) * c);
}

glm::vec3 OrbitCamera::Forward() const { return glm::normalize(target - Eye()); }

glm::vec3 OrbitCamera::Right() const {
  return glm::normalize(glm::cross(Forward(), glm::vec3(0.f, 1.f, 0.f)));
}

glm::vec3 OrbitCamera::Up() const { return glm::cross(Right(), Forward()); }

glm::mat4 OrbitCamera::View() const { return glm::lookAt(Eye(), target, Up()); }

glm::mat4 OrbitCamera::Projection(float aspect) const {
  const float r = std::max(scene_radius, 1e-6f);
  const float near_plane = std::max(distance - 2.f * r, distance / 1000.f);
  const float far_plane = distance + 2.f * r;
  return glm::perspective(fov_y, aspect > 0.f ? aspect : 1.f, near_plane, far_plane);
}

void OrbitCamera::SetPreset(ViewPreset preset) {
  pitch = 0.f;
  switch (preset) {
    case ViewPreset::kFront: yaw = 0.f; break;
    case ViewPreset::kSide: yaw = 1.5707963f; break;
    case ViewPreset::kThreeQuarter: yaw = 0.7853982f; break;
  }
}

void OrbitCamera::Frame(const glm::vec3& lo, const glm::vec3& hi) {
  target = 0.5f * (lo + hi);
  scene_radius = std::max(0.5f * glm::length(hi - lo), 1e-6f);
  distance = scene_radius / std::sin(0.5f * fov_y);
}

void OrbitCamera::Orbit(float dx, float dy) {
  yaw -= dx * kOrbitRate;
  pitch = std::clamp(pitch + dy * kOrbitRate, -kMaxPitch, kMaxPitch);
}

void OrbitCamera::Pan(float dx, float dy, float viewport_height) {
  if (!(viewport_height > 0.f)) return;
  const float per_pixel = 2.f * distance * std::tan(0.5f * fov_y) / viewport_height;
  // The scene follows the cursor: dragging right moves the target left in view space.
  target += per_pixel * (-dx * Right() + dy * Up());
}

void OrbitCamera::Zoom(float steps) {
  distance = std::clamp(distance * std::pow(kZoomStep, steps), scene_radius / 100.f,
                        scene_radius * 100.f);
}

Ray OrbitCamera::PixelRay(float x, float y, float width, float height) const {
  const float ndc_x = 2.f * x / width - 1.f, ndc_y = 1.f - 2.f * y / height;
  const float t = std::tan(0.5f * fov_y);
  const float aspect = height > 0.f ? width / height : 1.f;
  Ray ray;
  ray.origin = Eye();
  ray.direction = glm::normalize(Forward() + ndc_x * t * aspect * Right() + ndc_y * t * Up());
  return ray;
}

}  // namespace mimetic::viewer

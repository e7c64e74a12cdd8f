#include "apps/viewer/camera_controller.h"

#include <algorithm>

namespace candela {

// Unit view direction for yaw about +y (0 = -z) and pitch above the horizon.
static vec3 direction(float yaw, float pitch) {
  return {std::sin(yaw) * std::cos(pitch), std::sin(pitch), -std::cos(yaw) * std::cos(pitch)};
}

static const float kMaxPitch = glm::radians(89.0f);

CameraController::CameraController(const CameraDesc& start) : desc_(start) {
  vec3 d = start.target - start.position;
  distance_ = std::max(glm::length(d), 1e-4f);
  d /= distance_;
  yaw_ = std::atan2(d.x, -d.z);
  pitch_ = std::clamp(std::asin(std::clamp(d.y, -1.0f, 1.0f)), -kMaxPitch, kMaxPitch);
  fly_speed_ = 0.5f * distance_;
}

vec3 CameraController::forward() const { return direction(yaw_, pitch_); }

// Rebuilds the description from the state with the eye at `eye` (target = eye + forward * distance).
void CameraController::update_desc(const vec3& eye) {
  desc_.position = eye;
  desc_.target = eye + forward() * distance_;
  desc_.up = vec3(0.0f, 1.0f, 0.0f);
}

void CameraController::orbit(float yaw_degrees, float pitch_degrees) {
  vec3 target = desc_.target;
  yaw_ += glm::radians(yaw_degrees);
  pitch_ = std::clamp(pitch_ + glm::radians(pitch_degrees), -kMaxPitch, kMaxPitch);
  update_desc(target - forward() * distance_);
}

void CameraController::zoom(float steps) {
  vec3 target = desc_.target;
  distance_ = std::max(distance_ * std::pow(0.9f, steps), 1e-3f);
  update_desc(target - forward() * distance_);
}

void CameraController::look(float yaw_degrees, float pitch_degrees) {
  yaw_ += glm::radians(yaw_degrees);
  pitch_ = std::clamp(pitch_ + glm::radians(pitch_degrees), -kMaxPitch, kMaxPitch);
  update_desc(desc_.position);
}

void CameraController::move(const vec3& right_up_forward) {
  vec3 f = forward();
  vec3 right = glm::normalize(glm::cross(f, vec3(0.0f, 1.0f, 0.0f)));
  vec3 up = glm::cross(right, f);
  update_desc(desc_.position + right * right_up_forward.x + up * right_up_forward.y + f * right_up_forward.z);
}

}  // namespace candela

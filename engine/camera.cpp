#include "engine/camera.h"

#include "engine/check.h"

namespace candela {

Camera::Camera(const CameraDesc& desc, int width, int height)
    : position_(desc.position), width_(width), height_(height) {
  CHECK(width > 0 && height > 0);
  vec3 f = desc.target - desc.position;
  forward_ = glm::length(f) > 0.0f ? glm::normalize(f) : vec3(0.0f, 0.0f, -1.0f);
  vec3 r = glm::cross(forward_, desc.up);
  if (glm::length(r) < 1e-6f) r = glm::cross(forward_, std::abs(forward_.y) < 0.9f ? vec3(0, 1, 0) : vec3(1, 0, 0));
  right_ = glm::normalize(r);
  up_ = glm::cross(right_, forward_);
  tan_half_y_ = std::tan(glm::radians(0.5f * desc.vfov_degrees));
  tan_half_x_ = tan_half_y_ * float(width) / float(height);
}

bool Camera::project(const vec3& p, vec2& film) const {
  vec3 d = p - position_;
  float z = glm::dot(d, forward_);
  if (z <= 0.0f) return false;
  float sx = glm::dot(d, right_) / (z * tan_half_x_);
  float sy = glm::dot(d, up_) / (z * tan_half_y_);
  film = vec2((sx + 1.0f) * 0.5f * width_, (1.0f - sy) * 0.5f * height_);
  return true;
}

}  // namespace candela

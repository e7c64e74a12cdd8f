#pragma once
// Pinhole camera: primary rays through jittered pixel positions and projection of world points back to
// pixel coordinates (for motion vectors).
#include "engine/math.h"
#include "engine/scene.h"

namespace candela {

class Camera {
 public:
  Camera() = default;
  Camera(const CameraDesc& desc, int width, int height);

  // Direction (unit) through film position (x, y) in pixels, (0, 0) the top-left corner.
  vec3 direction(float x, float y) const {
    vec3 d = forward_ + right_ * ((2.0f * x / width_ - 1.0f) * tan_half_x_) -
             up_ * ((2.0f * y / height_ - 1.0f) * tan_half_y_);
    return glm::normalize(d);
  }
  const vec3& position() const { return position_; }
  const vec3& forward() const { return forward_; }
  const vec3& right() const { return right_; }
  const vec3& up() const { return up_; }
  float tan_half_x() const { return tan_half_x_; }
  float tan_half_y() const { return tan_half_y_; }
  // Film position (pixels) of world point p; false when p is behind the camera.
  bool project(const vec3& p, vec2& film) const;
  // Distance along the view axis (linear depth).
  float view_depth(const vec3& p) const { return glm::dot(p - position_, forward_); }
  int width() const { return width_; }
  int height() const { return height_; }
  bool operator==(const Camera&) const = default;

 private:
  vec3 position_{0.0f}, forward_{0.0f, 0.0f, -1.0f}, right_{1.0f, 0.0f, 0.0f}, up_{0.0f, 1.0f, 0.0f};
  float tan_half_x_ = 1.0f, tan_half_y_ = 1.0f;
  int width_ = 1, height_ = 1;
};

}  // namespace candela

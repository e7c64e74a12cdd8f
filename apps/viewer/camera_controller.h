#pragma once
// Interactive camera math, free of any window or GL: orbit (around a target at a distance) and fly
// (look around from the eye, move along the view), sharing one state, so switching modes keeps the view.
// The CameraDesc handed to the Renderer changes only when the camera moves, bit for bit, so a still
// camera keeps the Renderer's progressive accumulation going.
#include "engine/scene.h"

namespace candela {

class CameraController {
 public:
  explicit CameraController(const CameraDesc& start);

  // Orbit: turns the eye around the target by yaw (about world up) and pitch (degrees); the distance to
  // the target stays the same. Pitch is kept within +-89 degrees.
  void orbit(float yaw_degrees, float pitch_degrees);
  // Orbit: moves the eye towards the target (steps > 0) or away; each step scales the distance by 0.9.
  void zoom(float steps);
  // Fly: turns the view direction about the eye (the target moves, the eye stays).
  void look(float yaw_degrees, float pitch_degrees);
  // Fly: moves eye and target together by (right, up, forward) in scene units; forward is the view direction.
  void move(const vec3& right_up_forward);

  const CameraDesc& desc() const { return desc_; }
  vec3 forward() const;
  float distance() const { return distance_; }
  // Scene units per second a fly key moves the camera: the start distance to the target, per 2 seconds.
  float fly_speed() const { return fly_speed_; }

 private:
  void update_desc(const vec3& eye);

  CameraDesc desc_;
  float yaw_ = 0.0f, pitch_ = 0.0f;  // radians; yaw 0 looks down -z
  float distance_ = 1.0f;
  float fly_speed_ = 1.0f;
};

}  // namespace candela

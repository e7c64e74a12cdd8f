#pragma once
// Keyframed animation the scene plays back in Scene::set_time: tracks of keys (time in seconds, value)
// interpolated by step, linear or smooth (Catmull-Rom) rules; instance transforms composed of
// translation, rotation and scale tracks; power scale factors of punctual lights and emissive materials.
// glTF animation channels (engine/gltf_loader) and shot scripts (apps/shot_script) both produce these.
#include <string>
#include <vector>

#include <glm/gtc/quaternion.hpp>

#include "engine/math.h"

namespace candela {

using glm::quat;

enum class Interpolation : uint8_t {
  Step,    // the value of the last key at or before t
  Linear,  // straight lines between keys (quaternions: shortest-arc slerp)
  Smooth,  // Catmull-Rom spline through the keys (C1; end tangents one-sided); quaternions fall back to slerp
};

// Keys sorted by strictly increasing time; before the first key the first value holds, after the last
// the last one. An empty track has no value (callers check empty()).
template <class T>
struct Track {
  std::vector<float> times;
  std::vector<T> values;
  Interpolation interpolation = Interpolation::Linear;
  bool empty() const { return times.empty(); }
  T at(float t) const;
};

// The instance transform at time t: after * T(t) * R(t) * S(t) * before. Unanimated channels are empty
// tracks (identity). `rotation` (quaternions) comes from glTF; `euler_degrees` (X then Y then Z, about
// fixed axes) from scripts, so that keys 0 and 360 make a full turn.
struct InstanceAnimation {
  int instance = 0;
  mat4 before{1.0f}, after{1.0f};
  Track<vec3> translation, euler_degrees, scale;
  Track<quat> rotation;
  mat4 transform_at(float t) const;
};

// Scales a light's power over time: a punctual light's intensity or an emissive material's emission is
// `base * scale(t)`.
struct PowerAnimation {
  enum class Target : uint8_t { Punctual, Material };
  Target target = Target::Punctual;
  int index = 0;    // into Scene::punctual_lights or Scene::materials
  vec3 base{0.0f};  // intensity or emission at scale 1
  Track<float> scale;
};

// Rotation from Euler angles in degrees: about X, then Y, then Z (fixed axes), i.e. Rz * Ry * Rx.
mat4 euler_rotation(const vec3& degrees);

extern template struct Track<float>;
extern template struct Track<vec3>;
extern template struct Track<quat>;

}  // namespace candela

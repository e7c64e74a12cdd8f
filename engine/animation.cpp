#include "engine/animation.h"

#include <glm/gtc/matrix_transform.hpp>

#include "engine/check.h"

namespace candela {

namespace {

// Catmull-Rom (uniform parameter within the segment, tangents scaled to the segment's duration so that
// unevenly spaced keys keep a continuous derivative in time).
template <class T>
T catmull_rom(const Track<T>& track, size_t i, float u) {
  const std::vector<float>& t = track.times;
  const std::vector<T>& v = track.values;
  size_t n = t.size();
  float dt = t[i + 1] - t[i];
  auto slope = [&](size_t k) -> T {  // derivative in time at key k
    if (k == 0) return (v[1] - v[0]) / (t[1] - t[0]);
    if (k == n - 1) return (v[k] - v[k - 1]) / (t[k] - t[k - 1]);
    return (v[k + 1] - v[k - 1]) / (t[k + 1] - t[k - 1]);
  };
  T m0 = slope(i) * dt, m1 = slope(i + 1) * dt;
  float u2 = u * u, u3 = u2 * u;
  return (2 * u3 - 3 * u2 + 1) * v[i] + (u3 - 2 * u2 + u) * m0 + (-2 * u3 + 3 * u2) * v[i + 1] + (u3 - u2) * m1;
}

template <class T>
T mix_values(const T& a, const T& b, float u) {
  if constexpr (std::is_same_v<T, quat>)
    return glm::slerp(a, glm::dot(a, b) < 0.0f ? -b : b, u);
  else
    return a + (b - a) * u;
}

}  // namespace

template <class T>
T Track<T>::at(float t) const {
  CHECK(!times.empty() && times.size() == values.size());
  if (t <= times.front()) return values.front();
  if (t >= times.back()) return values.back();
  size_t i = size_t(std::upper_bound(times.begin(), times.end(), t) - times.begin()) - 1;
  if (interpolation == Interpolation::Step) return values[i];
  float u = (t - times[i]) / (times[i + 1] - times[i]);
  if constexpr (!std::is_same_v<T, quat>)
    if (interpolation == Interpolation::Smooth) return catmull_rom(*this, i, u);
  return mix_values(values[i], values[i + 1], u);
}

template struct Track<float>;
template struct Track<vec3>;
template struct Track<quat>;

mat4 euler_rotation(const vec3& degrees) {
  mat4 m(1.0f);
  m = glm::rotate(m, glm::radians(degrees.z), vec3(0.0f, 0.0f, 1.0f));
  m = glm::rotate(m, glm::radians(degrees.y), vec3(0.0f, 1.0f, 0.0f));
  return glm::rotate(m, glm::radians(degrees.x), vec3(1.0f, 0.0f, 0.0f));
}

mat4 InstanceAnimation::transform_at(float t) const {
  mat4 m = after;
  if (!translation.empty()) m = glm::translate(m, translation.at(t));
  if (!rotation.empty()) m *= glm::mat4_cast(glm::normalize(rotation.at(t)));
  if (!euler_degrees.empty()) m *= euler_rotation(euler_degrees.at(t));
  if (!scale.empty()) m = glm::scale(m, scale.at(t));
  return m * before;
}

}  // namespace candela

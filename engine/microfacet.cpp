#include "engine/microfacet.h"

namespace candela {

float ggx_d(float cos_h, float alpha) {
  if (cos_h <= 0.0f) return 0.0f;
  float a2 = alpha * alpha;
  float d = cos_h * cos_h * (a2 - 1.0f) + 1.0f;
  return a2 / (kPi * d * d);
}

float ggx_lambda(float cos_theta, float alpha) {
  float c2 = cos_theta * cos_theta;
  float tan2 = std::max(1.0f - c2, 0.0f) / std::max(c2, 1e-12f);
  return 0.5f * (std::sqrt(1.0f + alpha * alpha * tan2) - 1.0f);
}

vec3 sample_cosine_hemisphere(vec2 u) {
  // Concentric mapping of the square to the disk, then projection up to the hemisphere.
  vec2 o = 2.0f * u - vec2(1.0f);
  vec2 d(0.0f);
  if (o.x != 0.0f || o.y != 0.0f) {
    float r, theta;
    if (std::abs(o.x) > std::abs(o.y)) {
      r = o.x;
      theta = (kPi / 4.0f) * (o.y / o.x);
    } else {
      r = o.y;
      theta = kPi / 2.0f - (kPi / 4.0f) * (o.x / o.y);
    }
    float sine, cosine;
    sin_cos(theta, sine, cosine);
    d = r * vec2(cosine, sine);
  }
  float z = std::sqrt(std::max(0.0f, 1.0f - d.x * d.x - d.y * d.y));
  return vec3(d.x, d.y, z);
}

vec3 ggx_sample_visible_normal(const vec3& wo, float alpha, vec2 u) {
  // Stretch the view vector to the unit-roughness configuration, sample the projected hemisphere, unstretch.
  vec3 vh = glm::normalize(vec3(alpha * wo.x, alpha * wo.y, wo.z));
  float len2 = vh.x * vh.x + vh.y * vh.y;
  vec3 t1 = len2 > 0.0f ? vec3(-vh.y, vh.x, 0.0f) / std::sqrt(len2) : vec3(1.0f, 0.0f, 0.0f);
  vec3 t2 = glm::cross(vh, t1);
  float r = std::sqrt(u.x);
  float phi = 2.0f * kPi * u.y, sine, cosine;
  sin_cos(phi, sine, cosine);
  float p1 = r * cosine, p2 = r * sine;
  float s = 0.5f * (1.0f + vh.z);
  p2 = (1.0f - s) * std::sqrt(std::max(0.0f, 1.0f - p1 * p1)) + s * p2;
  vec3 nh = p1 * t1 + p2 * t2 + std::sqrt(std::max(0.0f, 1.0f - p1 * p1 - p2 * p2)) * vh;
  return glm::normalize(vec3(alpha * nh.x, alpha * nh.y, std::max(1e-6f, nh.z)));
}

}  // namespace candela

#include "samplers/light_bounds.h"

namespace candela {

static float safe_sqrt(float x) { return std::sqrt(std::max(0.0f, x)); }

// cos(max(0, a - b)) and sin(max(0, a - b)) from the sines and cosines of a and b.
static float cos_sub_clamped(float sin_a, float cos_a, float sin_b, float cos_b) {
  return cos_a > cos_b ? 1.0f : cos_a * cos_b + sin_a * sin_b;
}
static float sin_sub_clamped(float sin_a, float cos_a, float sin_b, float cos_b) {
  return cos_a > cos_b ? 0.0f : sin_a * cos_b - cos_a * sin_b;
}

float LightBounds::importance(const vec3& p, const vec3& n) const {
  if (phi <= 0.0f) return 0.0f;
  vec3 pc = bounds.center();
  vec3 to_p = p - pc;
  float d2 = glm::dot(to_p, to_p);
  // Points close to (or inside) the box would get unbounded importance: clamp the distance term.
  d2 = std::max(d2, 0.5f * bounds.diagonal());
  // Angle theta_b of the cone from p that contains the box's bounding sphere (-1: p is inside it).
  float radius = 0.5f * bounds.diagonal();
  float dist = std::sqrt(glm::dot(to_p, to_p));
  float cos_b = -1.0f;
  if (dist > radius) cos_b = safe_sqrt(1.0f - (radius * radius) / (dist * dist));
  float sin_b = safe_sqrt(1.0f - cos_b * cos_b);
  vec3 dir = dist > 0.0f ? to_p / dist : vec3(0.0f, 0.0f, 1.0f);
  // Smallest angle between an emitter normal in the cone and a direction towards p: theta_w - theta_o - theta_b.
  float cos_w = glm::dot(w, dir);
  if (two_sided) cos_w = std::abs(cos_w);
  float sin_w = safe_sqrt(1.0f - cos_w * cos_w);
  float sin_o = safe_sqrt(1.0f - cos_theta_o * cos_theta_o);
  float cos_x = cos_sub_clamped(sin_w, cos_w, sin_o, cos_theta_o);
  float sin_x = sin_sub_clamped(sin_w, cos_w, sin_o, cos_theta_o);
  float cos_p = cos_sub_clamped(sin_x, cos_x, sin_b, cos_b);
  if (cos_p <= cos_theta_e) return 0.0f;
  float value = phi * cos_p / d2;
  // Receiver side: the smallest angle between n and a direction into the box.
  if (n != vec3(0.0f)) {
    float cos_i = std::abs(glm::dot(dir, n));
    float sin_i = safe_sqrt(1.0f - cos_i * cos_i);
    value *= cos_sub_clamped(sin_i, cos_i, sin_b, cos_b);
  }
  return std::max(value, 0.0f);
}

// Smallest cone containing two cones (axis w, half-angle theta): the construction of pbrt-v4's
// DirectionCone Union.
static void merge_cones(const vec3& wa, float cos_a, const vec3& wb, float cos_b, vec3& w, float& cos_theta) {
  float theta_a = std::acos(std::clamp(cos_a, -1.0f, 1.0f)), theta_b = std::acos(std::clamp(cos_b, -1.0f, 1.0f));
  float theta_d = std::acos(std::clamp(glm::dot(wa, wb), -1.0f, 1.0f));
  if (std::min(theta_d + theta_b, kPi) <= theta_a) { w = wa; cos_theta = cos_a; return; }
  if (std::min(theta_d + theta_a, kPi) <= theta_b) { w = wb; cos_theta = cos_b; return; }
  float theta_o = 0.5f * (theta_a + theta_d + theta_b);
  if (theta_o >= kPi) { w = wa; cos_theta = -1.0f; return; }
  // Rotate wa towards wb by theta_o - theta_a.
  float theta_r = theta_o - theta_a;
  vec3 axis = glm::cross(wa, wb);
  if (glm::dot(axis, axis) < 1e-12f) { w = wa; cos_theta = -1.0f; return; }
  axis = glm::normalize(axis);
  // Rodrigues' rotation of wa about axis by theta_r.
  w = wa * std::cos(theta_r) + glm::cross(axis, wa) * std::sin(theta_r) + axis * glm::dot(axis, wa) * (1.0f - std::cos(theta_r));
  w = glm::normalize(w);
  cos_theta = std::cos(theta_o);
}

LightBounds merge(const LightBounds& a, const LightBounds& b) {
  if (a.empty()) return b;
  if (b.empty()) return a;
  LightBounds m;
  m.bounds = a.bounds;
  m.bounds.extend(b.bounds);
  merge_cones(a.w, a.cos_theta_o, b.w, b.cos_theta_o, m.w, m.cos_theta_o);
  m.cos_theta_e = std::min(a.cos_theta_e, b.cos_theta_e);
  m.phi = a.phi + b.phi;
  m.two_sided = a.two_sided || b.two_sided;
  return m;
}

bool is_infinite_light(const LightList& lights, size_t index) {
  return index >= lights.triangle_count() &&
         lights.punctual()[index - lights.triangle_count()].type == PunctualType::Directional;
}

LightBounds light_bounds(const LightList& lights, size_t index) {
  LightBounds b;
  if (index < lights.triangle_count()) {
    const TriangleLight& t = lights.triangles()[index];
    b.bounds.extend(t.p0);
    b.bounds.extend(t.p0 + t.e1);
    b.bounds.extend(t.p0 + t.e2);
    b.w = t.normal;
    b.phi = t.power();
    b.cos_theta_o = 1.0f;
    b.cos_theta_e = 0.0f;  // emits over the whole hemisphere: theta_e = pi / 2
    b.two_sided = t.two_sided;
    return b;
  }
  const PunctualLight& l = lights.punctual()[index - lights.triangle_count()];
  if (l.type == PunctualType::Directional) return b;
  b.bounds.extend(l.position);
  b.phi = lights.power(index);
  if (l.type == PunctualType::Point) {
    b.cos_theta_o = -1.0f;  // all directions
    b.cos_theta_e = 0.0f;
  } else {
    b.w = l.direction;
    b.cos_theta_o = std::cos(l.inner_cone);
    b.cos_theta_e = std::cos(std::max(0.0f, l.outer_cone - l.inner_cone));
  }
  return b;
}

float cone_measure(float cos_theta_o, float cos_theta_e) {
  float theta_o = std::acos(std::clamp(cos_theta_o, -1.0f, 1.0f));
  float theta_e = std::acos(std::clamp(cos_theta_e, -1.0f, 1.0f));
  float theta_w = std::min(theta_o + theta_e, kPi);
  float sin_o = std::sin(theta_o);
  return 2.0f * kPi * (1.0f - cos_theta_o) +
         0.5f * kPi * (2.0f * theta_w * sin_o - std::cos(theta_o - 2.0f * theta_w) - 2.0f * theta_o * sin_o + cos_theta_o);
}

}  // namespace candela

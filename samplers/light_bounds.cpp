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

float cos_of_sum(float cos_a, float cos_b, float sin_b) {
  cos_a = std::clamp(cos_a, -1.0f, 1.0f);
  if (cos_b <= -cos_a) return -1.0f;  // beta >= pi - alpha
  return cos_a * cos_b - safe_sqrt(1.0f - cos_a * cos_a) * sin_b;
}

float LightBounds::importance(const vec3& p, const vec3& n) const {
  if (phi <= 0.0f) return 0.0f;
  vec3 to_p = p - center;
  float dist2 = glm::dot(to_p, to_p);
  // Points close to (or inside) the bounds would get unbounded importance: clamp the distance term
  // (pbrt-v4 clamps with half the box diagonal, which is the radius here).
  float d2 = std::max({dist2, radius, 1e-20f});
  float dist = std::sqrt(dist2);
  // theta_b: half-angle of the cone from p around the bounding sphere (pi when p is inside it).
  float cos_b = -1.0f, sin_b = 0.0f;
  if (dist > radius) {
    sin_b = radius / dist;
    cos_b = safe_sqrt(1.0f - sin_b * sin_b);
  }
  vec3 dir = dist > 0.0f ? to_p / dist : vec3(0.0f, 0.0f, 1.0f);
  // Smallest angle between an emitter's normal and a direction towards p: theta_w - theta_o - theta_b.
  float cos_w = glm::dot(w, dir);
  if (two_sided) cos_w = std::abs(cos_w);
  float sin_w = safe_sqrt(1.0f - cos_w * cos_w);
  float cos_x = cos_sub_clamped(sin_w, cos_w, sin_theta_o, cos_theta_o);
  float sin_x = sin_sub_clamped(sin_w, cos_w, sin_theta_o, cos_theta_o);
  float cos_p = cos_sub_clamped(sin_x, cos_x, sin_b, cos_b);
  if (cos_p < cos_theta_e) return 0.0f;
  float value = phi * cos_p / d2;
  // Receiver side: the smallest angle between n and a direction into the sphere.
  if (n != vec3(0.0f)) {
    float cos_i = std::abs(glm::dot(dir, n));
    float sin_i = safe_sqrt(1.0f - cos_i * cos_i);
    value *= cos_sub_clamped(sin_i, cos_i, sin_b, cos_b);
  }
  return std::max(value, 0.0f);
}

LightBounds merge(const LightBounds& a, const LightBounds& b) {
  if (a.empty()) return b;
  if (b.empty()) return a;
  LightBounds m;
  // Sphere union.
  vec3 d = b.center - a.center;
  float dist = glm::length(d);
  if (dist + b.radius <= a.radius) { m.center = a.center; m.radius = a.radius; }
  else if (dist + a.radius <= b.radius) { m.center = b.center; m.radius = b.radius; }
  else {
    m.radius = 0.5f * (dist + a.radius + b.radius);
    m.center = a.center + d * ((m.radius - a.radius) / dist);
  }
  // Cone around the power-weighted mean axis, wide enough for both cones.
  vec3 axis = a.w * a.phi + b.w * b.phi;
  float len = glm::length(axis);
  m.w = len > 1e-12f * (a.phi + b.phi) ? axis / len : a.w;
  m.set_cos_theta_o(std::min(cos_of_sum(glm::dot(m.w, a.w), a.cos_theta_o, a.sin_theta_o),
                             cos_of_sum(glm::dot(m.w, b.w), b.cos_theta_o, b.sin_theta_o)));
  m.cos_theta_e = std::min(a.cos_theta_e, b.cos_theta_e);
  m.phi = a.phi + b.phi;
  m.two_sided = a.two_sided | b.two_sided;
  return m;
}

bool is_infinite_light(const LightList& lights, size_t index) {
  return index >= lights.triangle_count() &&
         lights.punctual()[index - lights.triangle_count()].type == PunctualType::Directional;
}

LightBounds light_bounds(const LightList& lights, size_t index, Bounds3* box) {
  LightBounds b;
  Bounds3 local;
  if (index < lights.triangle_count()) {
    const TriangleLight& t = lights.triangles()[index];
    local.extend(t.p0);
    local.extend(t.p0 + t.e1);
    local.extend(t.p0 + t.e2);
    b.w = t.normal;
    b.phi = t.power();
    b.set_cos_theta_o(1.0f);
    b.cos_theta_e = 0.0f;  // emits over the whole hemisphere: theta_e = pi / 2
    b.two_sided = t.two_sided;
  } else {
    const PunctualLight& l = lights.punctual()[index - lights.triangle_count()];
    if (l.type == PunctualType::Directional) return b;
    local.extend(l.position);
    b.phi = lights.power(index);
    if (l.type == PunctualType::Point) {
      b.set_cos_theta_o(-1.0f);  // all directions
      b.cos_theta_e = 0.0f;
    } else {
      b.w = l.direction;
      b.set_cos_theta_o(std::cos(l.inner_cone));
      // A little slack: with inner == outer (legal in glTF) cos(theta_e) would round to 1 and exclude
      // even the cone's axis from the importance's strict test.
      b.cos_theta_e = std::cos(std::min(kPi, std::max(0.0f, l.outer_cone - l.inner_cone) + 1e-3f));
    }
  }
  b.center = local.center();
  b.radius = 0.5f * local.diagonal();
  if (box) *box = local;
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

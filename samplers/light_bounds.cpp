#include "samplers/light_bounds.h"

namespace candela {

float cos_of_sum(float cos_a, float cos_b, float sin_b) {
  cos_a = std::clamp(cos_a, -1.0f, 1.0f);
  if (cos_b <= -cos_a) return -1.0f;  // beta >= pi - alpha
  return cos_a * cos_b - light_bounds_detail::safe_sqrt(1.0f - cos_a * cos_a) * sin_b;
}

LightBounds merge(const LightBounds& a, const LightBounds& b) {
  if (a.empty()) return b;
  if (b.empty()) return a;
  LightBounds m;
  // Sphere union.
  vec3 d = b.center - a.center;
  float dist = glm::length(d);
  if (dist + b.radius <= a.radius) {
    m.center = a.center;
    m.radius = a.radius;
  } else if (dist + a.radius <= b.radius) {
    m.center = b.center;
    m.radius = b.radius;
  } else {
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
  // Area emitters (theta_e = pi/2) whose normals spread at most pi/2, the common case among the build's
  // split costs: with theta_w = theta_o + pi/2 the formula needs no inverse trigonometry,
  // 2 pi (1 - cos theta_o) + pi/2 (pi sin theta_o + 2 cos theta_o).
  if (cos_theta_e == 0.0f && cos_theta_o >= 0.0f) {
    const float sin_o = light_bounds_detail::safe_sqrt(1.0f - cos_theta_o * cos_theta_o);
    return 2.0f * kPi * (1.0f - cos_theta_o) + 0.5f * kPi * (kPi * sin_o + 2.0f * cos_theta_o);
  }
  float theta_o = std::acos(std::clamp(cos_theta_o, -1.0f, 1.0f));
  float theta_e = std::acos(std::clamp(cos_theta_e, -1.0f, 1.0f));
  float theta_w = std::min(theta_o + theta_e, kPi);
  float sin_o = std::sin(theta_o);
  return 2.0f * kPi * (1.0f - cos_theta_o) +
         0.5f * kPi *
             (2.0f * theta_w * sin_o - std::cos(theta_o - 2.0f * theta_w) - 2.0f * theta_o * sin_o + cos_theta_o);
}

}  // namespace candela

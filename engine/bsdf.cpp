#include "engine/bsdf.h"

namespace candela {

static vec3 schlick(const vec3& f0, float cos_theta) {
  float m = 1.0f - std::clamp(cos_theta, 0.0f, 1.0f);
  float m5 = (m * m) * (m * m) * m;
  return f0 + (vec3(1.0f) - f0) * m5;
}

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
    if (std::abs(o.x) > std::abs(o.y)) { r = o.x; theta = (kPi / 4.0f) * (o.y / o.x); }
    else { r = o.y; theta = kPi / 2.0f - (kPi / 4.0f) * (o.x / o.y); }
    d = r * vec2(std::cos(theta), std::sin(theta));
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
  float phi = 2.0f * kPi * u.y;
  float p1 = r * std::cos(phi), p2 = r * std::sin(phi);
  float s = 0.5f * (1.0f + vh.z);
  p2 = (1.0f - s) * std::sqrt(std::max(0.0f, 1.0f - p1 * p1)) + s * p2;
  vec3 nh = p1 * t1 + p2 * t2 + std::sqrt(std::max(0.0f, 1.0f - p1 * p1 - p2 * p2)) * vh;
  return glm::normalize(vec3(alpha * nh.x, alpha * nh.y, std::max(1e-6f, nh.z)));
}

Bsdf::Bsdf(const vec3& n, const vec3& base_color, float metallic, float roughness, float specular)
    : frame_(Frame::from_normal(n)),
      diffuse_(base_color * (1.0f - metallic)),
      f0_(glm::mix(vec3(0.04f), base_color, metallic)),
      specular_(std::clamp(specular, 0.0f, 1.0f)) {
  float r = std::clamp(roughness, 0.03f, 1.0f);
  alpha_ = r * r;
}

// Probability of sampling the specular lobe: its Fresnel-weighted share at the outgoing angle.
float Bsdf::specular_probability(float cos_o) const {
  if (specular_ == 0.0f) return 0.0f;
  vec3 f = specular_ * schlick(f0_, cos_o);
  float spec = luminance(f);
  float diff = luminance(diffuse_ * (vec3(1.0f) - f0_));
  if (spec + diff <= 0.0f) return 0.5f;
  return std::clamp(spec / (spec + diff), 0.1f, 0.9f);
}

// eval and pdf need only three cosines, no change of frame: with h = (wo + wi) / |wo + wi|,
// n.h = (n.wo + n.wi) / |wo + wi| and wo.h = (1 + wo.wi) / |wo + wi|, |wo + wi| = sqrt(2 + 2 wo.wi).
vec3 Bsdf::eval(const vec3& wo, const vec3& wi) const {
  float cos_o = glm::dot(frame_.n, wo), cos_i = glm::dot(frame_.n, wi);
  if (cos_o <= 0.0f || cos_i <= 0.0f) return vec3(0.0f);
  float cos_oi = glm::dot(wo, wi);
  float inv_len = 1.0f / std::sqrt(std::max(2.0f + 2.0f * cos_oi, 1e-12f));
  vec3 F = specular_ * schlick(f0_, (1.0f + cos_oi) * inv_len);
  // G2 / (4 cos_o cos_i) with G2 = 1 / (1 + Lambda_o + Lambda_i), written without the tangents:
  // 1 + 2 Lambda(c) = sqrt(c^2 (1 - a^2) + a^2) / c, so the term is 1 / (2 (cos_i s_o + cos_o s_i)).
  float a2 = alpha_ * alpha_;
  float s_o = std::sqrt(cos_o * cos_o * (1.0f - a2) + a2), s_i = std::sqrt(cos_i * cos_i * (1.0f - a2) + a2);
  float visibility = 0.5f / (cos_i * s_o + cos_o * s_i);
  vec3 specular = F * (ggx_d((cos_o + cos_i) * inv_len, alpha_) * visibility);
  auto grazing = [](float c) { float m = 1.0f - 0.5f * c; return 1.0f - (m * m) * (m * m) * m; };
  vec3 coupled = (28.0f / 23.0f) * (vec3(1.0f) - f0_) * (grazing(cos_o) * grazing(cos_i));
  return diffuse_ * kInvPi * ((1.0f - specular_) + specular_ * coupled) + specular;
}

float Bsdf::pdf(const vec3& wo, const vec3& wi) const {
  float cos_o = glm::dot(frame_.n, wo), cos_i = glm::dot(frame_.n, wi);
  if (cos_o <= 0.0f || cos_i <= 0.0f) return 0.0f;
  float cos_h = (cos_o + cos_i) / std::sqrt(std::max(2.0f + 2.0f * glm::dot(wo, wi), 1e-12f));
  // Visible-normal density mapped to wi: D_wo(h) / (4 wo.h) = G1(wo) D(h) / (4 wo.z).
  float g1 = 1.0f / (1.0f + ggx_lambda(cos_o, alpha_));
  float pdf_spec = g1 * ggx_d(cos_h, alpha_) / (4.0f * cos_o);
  float pdf_diff = cos_i * kInvPi;
  float ps = specular_probability(cos_o);
  return ps * pdf_spec + (1.0f - ps) * pdf_diff;
}

bool Bsdf::sample(const vec3& wo_world, vec2 u, float u_lobe, BsdfSample& out) const {
  vec3 wo = frame_.to_local(wo_world);
  if (wo.z <= 0.0f) return false;
  vec3 wi;
  if (u_lobe < specular_probability(wo.z)) {
    vec3 h = ggx_sample_visible_normal(wo, alpha_, u);
    wi = glm::reflect(-wo, h);
    if (wi.z <= 0.0f) return false;
  } else {
    wi = sample_cosine_hemisphere(u);
    if (wi.z <= 0.0f) return false;
  }
  out.wi = frame_.to_world(wi);
  out.f = eval(wo_world, out.wi);
  out.pdf = pdf(wo_world, out.wi);
  return out.pdf > 0.0f;
}

}  // namespace candela

#pragma once
// glTF metallic-roughness BSDF: a diffuse lobe and a GGX microfacet specular lobe with Schlick Fresnel and
// the height-correlated Smith masking-shadowing term:
//   f_spec = s F(wo.h) D(h) G2 / (4 |n.wo| |n.wi|),  F0 = mix(0.04, base, metallic)   (Walter et al. 2007)
//   f_diff = (1 - s) diffuse / pi + s (28 / 23 pi) diffuse (1 - F0) (1 - (1 - |n.wi|/2)^5) (1 - (1 - |n.wo|/2)^5)
// with diffuse = base * (1 - metallic) and s the specular factor. The diffuse term couples to the specular
// lobe as in Ashikhmin & Shirley 2000 (eq. 5), which keeps the sum reciprocal and energy-conserving at
// grazing angles, where the glTF specification's (1 - F) weighting reflects up to 1.3x the incident energy;
// with s = 0 it is exactly Lambert. Directions are world-space unit vectors pointing away from the surface;
// eval returns f without the cosine. Reflection only (no transmission).
#include "engine/math.h"

namespace candela {

struct BsdfSample {
  vec3 wi{0.0f};
  vec3 f{0.0f};     // BSDF value for (wo, wi)
  float pdf = 0.0f; // solid-angle density of wi under sample() (both lobes)
};

class Bsdf {
 public:
  Bsdf() = default;
  // n: unit shading normal on the side of wo; base colour linear RGB; roughness in [0, 1] (perceptual);
  // specular scales the specular lobe (KHR_materials_specular's factor; 0 leaves a pure Lambert lobe).
  Bsdf(const vec3& n, const vec3& base_color, float metallic, float roughness, float specular = 1.0f);

  vec3 eval(const vec3& wo, const vec3& wi) const;
  float pdf(const vec3& wo, const vec3& wi) const;
  // u: two uniforms for the direction, u_lobe: one uniform for the lobe choice. False if no sample.
  bool sample(const vec3& wo, vec2 u, float u_lobe, BsdfSample& out) const;

  const vec3& normal() const { return n_; }
  float alpha() const { return alpha_; }

 private:
  float specular_probability(float cos_o) const;

  vec3 n_{0.0f, 0.0f, 1.0f};  // the tangent frame is built in sample() only: most Bsdfs only evaluate
  vec3 diffuse_{0.0f};  // base * (1 - metallic)
  vec3 f0_{0.04f};
  float specular_ = 1.0f;
  float alpha_ = 1.0f;  // GGX alpha = roughness^2
};

// The per-sample functions are inline: reservoir resampling calls eval and pdf tens of times per pixel
// from other files, and inlining them there (dropping what a caller does not use) was measured faster.

// Schlick's Fresnel approximation.
inline vec3 schlick(const vec3& f0, float cos_theta) {
  float m = 1.0f - std::clamp(cos_theta, 0.0f, 1.0f);
  float m5 = (m * m) * (m * m) * m;
  return f0 + (vec3(1.0f) - f0) * m5;
}

// GGX normal distribution D(h) for cos_h = n.h (Walter et al. 2007, eq. 33).
inline float ggx_d(float cos_h, float alpha) {
  if (cos_h <= 0.0f) return 0.0f;
  float a2 = alpha * alpha;
  float d = cos_h * cos_h * (a2 - 1.0f) + 1.0f;
  return a2 / (kPi * d * d);
}

// Smith Lambda for GGX (Heitz 2014, "Understanding the Masking-Shadowing Function", eq. 72).
inline float ggx_lambda(float cos_theta, float alpha) {
  float c2 = cos_theta * cos_theta;
  float tan2 = std::max(1.0f - c2, 0.0f) / std::max(c2, 1e-12f);
  return 0.5f * (std::sqrt(1.0f + alpha * alpha * tan2) - 1.0f);
}

// Probability of sampling the specular lobe: its Fresnel-weighted share at the outgoing angle.
inline float Bsdf::specular_probability(float cos_o) const {
  if (specular_ == 0.0f) return 0.0f;
  vec3 f = specular_ * schlick(f0_, cos_o);
  float spec = luminance(f);
  float diff = luminance(diffuse_ * (vec3(1.0f) - f0_));
  if (spec + diff <= 0.0f) return 0.5f;
  return std::clamp(spec / (spec + diff), 0.1f, 0.9f);
}

// eval and pdf need only three cosines, no change of frame: with h = (wo + wi) / |wo + wi|,
// n.h = (n.wo + n.wi) / |wo + wi| and wo.h = (1 + wo.wi) / |wo + wi|, |wo + wi| = sqrt(2 + 2 wo.wi).
inline vec3 Bsdf::eval(const vec3& wo, const vec3& wi) const {
  float cos_o = glm::dot(n_, wo), cos_i = glm::dot(n_, wi);
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

inline float Bsdf::pdf(const vec3& wo, const vec3& wi) const {
  float cos_o = glm::dot(n_, wo), cos_i = glm::dot(n_, wi);
  if (cos_o <= 0.0f || cos_i <= 0.0f) return 0.0f;
  float cos_h = (cos_o + cos_i) / std::sqrt(std::max(2.0f + 2.0f * glm::dot(wo, wi), 1e-12f));
  // Visible-normal density mapped to wi: D_wo(h) / (4 wo.h) = G1(wo) D(h) / (4 wo.z).
  float g1 = 1.0f / (1.0f + ggx_lambda(cos_o, alpha_));
  float pdf_spec = g1 * ggx_d(cos_h, alpha_) / (4.0f * cos_o);
  float pdf_diff = cos_i * kInvPi;
  float ps = specular_probability(cos_o);
  return ps * pdf_spec + (1.0f - ps) * pdf_diff;
}

// Samples a visible normal (Heitz 2018, "Sampling the GGX Distribution of Visible Normals") in local space.
vec3 ggx_sample_visible_normal(const vec3& wo_local, float alpha, vec2 u);
// Cosine-weighted hemisphere direction around +z (Malley's method, concentric disk of Shirley & Chiu 1997).
vec3 sample_cosine_hemisphere(vec2 u);

}  // namespace candela

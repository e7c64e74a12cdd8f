#include "engine/bsdf.h"

namespace candela {

vec3 dielectric_f0(float ior, const vec3& specular_color) {
  float r = (ior - 1.0f) / (ior + 1.0f);
  return glm::min(r * r * specular_color, vec3(1.0f));
}

// Kulla & Conty's F_ms for Schlick's Fresnel (F0, F90) at average single-scattering albedo a_avg; 0 when
// the lobe has no Fresnel at all (F90 = 0).
static vec3 multiple_scattering_fresnel(const vec3& f0, float f90, float a_avg) {
  if (f90 <= 0.0f) return vec3(0.0f);
  vec3 f_avg = f0 + (vec3(f90) - f0) * (1.0f / 21.0f);
  return f_avg * f_avg * a_avg / (vec3(1.0f) - f_avg * (1.0f - a_avg));
}

Bsdf::Bsdf(const vec3& n, const vec3& base_color, float metallic, float roughness, float specular,
           const vec3& specular_f0)
    : frame_(Frame::from_normal(n)), alpha_(ggx_alpha(roughness)), albedo_(roughness) {
  float m = std::clamp(metallic, 0.0f, 1.0f), s = std::clamp(specular, 0.0f, 1.0f);
  d_f0_ = s * specular_f0;
  d_f90_ = s;
  f0_ = glm::mix(d_f0_, base_color, m);
  f90_ = glm::mix(s, 1.0f, m);
  GgxAlbedo avg = albedo_.average();
  d_ms_ = m < 1.0f ? multiple_scattering_fresnel(d_f0_, d_f90_, avg.a) : vec3(0.0f);
  vec3 f_ms = m > 0.0f ? glm::mix(d_ms_, multiple_scattering_fresnel(base_color, 1.0f, avg.a), m) : d_ms_;
  ms_ = f_ms * (kInvPi / std::max(1.0f - avg.a, 1e-6f));
  vec3 base = base_color * (1.0f - m);
  vec3 layer_avg = layer_albedo(avg);
  base_scale_ = glm::mix(base * kInvPi / glm::max(vec3(1.0f) - layer_avg, vec3(1e-4f)), vec3(0.0f),
                         glm::greaterThanEqual(layer_avg, vec3(0.9999f)));
  lum_ = {luminance(f0_), luminance(f_ms), luminance(base), luminance(base * d_f0_), luminance(base * d_ms_)};
}

// Probability of sampling the single-scattering lobe: its share of the albedo at the outgoing angle (the
// multiple-scattering and base lobes are sampled by the cosine). Luminance is linear, so the albedos'
// luminances come from the constructor's five.
float Bsdf::specular_probability(const GgxAlbedo& e_o) const {
  float a = e_o.a, b = e_o.b;
  float spec = lum_.f0 * (a - b) + f90_ * b;
  if (spec <= 0.0f) return 0.0f;
  float layer = lum_.base_d_f0 * (a - b) + lum_.base * d_f90_ * b + lum_.base_d_ms * (1.0f - a);
  float rest = lum_.ms * (1.0f - a) + std::max(lum_.base - layer, 0.0f);
  return std::clamp(spec / (spec + rest), 0.1f, 0.9f);
}

// D(h) for the unnormalised half vector hv = wo + wi, written as alpha^2 |hv|^4 / (pi (alpha^2 (n.hv)^2 +
// |n x hv|^2)^2): the sine comes from a cross product, so near the peak of a smooth lobe D does not
// depend on the rounding of a cosine close to 1 (a one-ulp change there moved D by 4% at alpha 0.0025).
// eval and pdf both call it, so their ratio is exact.
static float ggx_d_half_vector(const vec3& n, const vec3& hv, float alpha) {
  float c = glm::dot(n, hv);
  if (c <= 0.0f) return 0.0f;
  vec3 s = glm::cross(n, hv);
  float a2 = alpha * alpha, len2 = glm::dot(hv, hv);
  float d = a2 * c * c + glm::dot(s, s);
  return d > 0.0f ? a2 * len2 * len2 / (kPi * d * d) : 0.0f;
}

// The terms eval reads of wo (s_o, ms_o, base_o) for t.cos_o > 0; returns the albedo-table entry at cos_o.
GgxAlbedo Bsdf::eval_terms(BsdfWoTerms& t) const {
  float a2 = alpha_ * alpha_;
  t.s_o = std::sqrt(t.cos_o * t.cos_o * (1.0f - a2) + a2);
  GgxAlbedo e_o = albedo_.at(t.cos_o);
  t.ms_o = std::max(1.0f - e_o.a, 0.0f);
  t.base_o = base_scale_ * glm::max(vec3(1.0f) - layer_albedo(e_o), vec3(0.0f));
  return e_o;
}

// The terms pdf reads of wo (g1_o, p_specular) for t.cos_o > 0, with e_o the albedo-table entry at cos_o.
void Bsdf::pdf_terms(BsdfWoTerms& t, const GgxAlbedo& e_o) const {
  t.g1_o = 1.0f / (1.0f + ggx_lambda(t.cos_o, alpha_));
  t.p_specular = specular_probability(e_o);
}

// eval and pdf need only cosines and the half vector, no change of frame: with hv = wo + wi,
// wo.h = (1 + wo.wi) / |hv| and |hv| = sqrt(2 + 2 wo.wi).
vec3 Bsdf::eval(const BsdfWoTerms& t, const vec3& wo, const vec3& wi) const {
  const float cos_o = t.cos_o, cos_i = glm::dot(frame_.n, wi);
  if (cos_o <= 0.0f || cos_i <= 0.0f) return vec3(0.0f);
  float cos_oi = glm::dot(wo, wi);
  float inv_len = 1.0f / std::sqrt(std::max(2.0f + 2.0f * cos_oi, 1e-12f));
  float m = 1.0f - std::clamp((1.0f + cos_oi) * inv_len, 0.0f, 1.0f);
  vec3 F = f0_ + (vec3(f90_) - f0_) * ((m * m) * (m * m) * m);
  // G2 / (4 cos_o cos_i) with G2 = 1 / (1 + Lambda_o + Lambda_i), written without the tangents:
  // 1 + 2 Lambda(c) = sqrt(c^2 (1 - a^2) + a^2) / c, so the term is 1 / (2 (cos_i s_o + cos_o s_i)).
  float a2 = alpha_ * alpha_;
  float s_i = std::sqrt(cos_i * cos_i * (1.0f - a2) + a2);
  float visibility = 0.5f / (cos_i * t.s_o + cos_o * s_i);
  vec3 single = F * (ggx_d_half_vector(frame_.n, wo + wi, alpha_) * visibility);
  GgxAlbedo e_i = albedo_.at(cos_i);
  vec3 multiple = ms_ * (t.ms_o * std::max(1.0f - e_i.a, 0.0f));
  vec3 base = t.base_o * glm::max(vec3(1.0f) - layer_albedo(e_i), vec3(0.0f));
  return single + multiple + base;
}

vec3 Bsdf::eval(const vec3& wo, const vec3& wi) const {
  BsdfWoTerms t;
  t.cos_o = glm::dot(frame_.n, wo);
  if (t.cos_o <= 0.0f || glm::dot(frame_.n, wi) <= 0.0f) return vec3(0.0f);
  eval_terms(t);
  return eval(t, wo, wi);
}

float Bsdf::pdf(const BsdfWoTerms& t, const vec3& wo, const vec3& wi) const {
  const float cos_o = t.cos_o, cos_i = glm::dot(frame_.n, wi);
  if (cos_o <= 0.0f || cos_i <= 0.0f) return 0.0f;
  // Visible-normal density mapped to wi: D_wo(h) / (4 wo.h) = G1(wo) D(h) / (4 wo.z).
  float pdf_spec = t.g1_o * ggx_d_half_vector(frame_.n, wo + wi, alpha_) / (4.0f * cos_o);
  float pdf_diff = cos_i * kInvPi;
  return t.p_specular * pdf_spec + (1.0f - t.p_specular) * pdf_diff;
}

float Bsdf::pdf(const vec3& wo, const vec3& wi) const {
  BsdfWoTerms t;
  t.cos_o = glm::dot(frame_.n, wo);
  if (t.cos_o <= 0.0f || glm::dot(frame_.n, wi) <= 0.0f) return 0.0f;
  pdf_terms(t, albedo_.at(t.cos_o));
  return pdf(t, wo, wi);
}

BsdfWoTerms Bsdf::wo_terms(const vec3& wo) const {
  BsdfWoTerms t;
  t.n = frame_.n;
  t.cos_o = glm::dot(frame_.n, wo);
  t.alpha = alpha_;
  t.f0 = f0_;
  t.f90 = f90_;
  t.ms = ms_;
  t.d_f0 = d_f0_;
  t.d_ms = d_ms_;
  t.d_f90 = d_f90_;
  t.albedo_row = albedo_.row_offset();
  t.albedo_weight = albedo_.row_weight();
  if (t.cos_o <= 0.0f) return t;
  pdf_terms(t, eval_terms(t));
  return t;
}

// sample_bsdf_direction after its change of frame: wo in the frame's local coordinates, wo.z > 0.
static bool sample_local_direction(const Frame& frame, float alpha, const vec3& wo, vec2 u, float u_lobe,
                                   float p_specular, vec3& wi_world) {
  vec3 wi;
  if (u_lobe < p_specular) {
    vec3 h = ggx_sample_visible_normal(wo, alpha, u);
    wi = glm::reflect(-wo, h);
    if (wi.z <= 0.0f) return false;
  } else {
    wi = sample_cosine_hemisphere(u);
    if (wi.z <= 0.0f) return false;
  }
  wi_world = frame.to_world(wi);
  return true;
}

bool sample_bsdf_direction(const Frame& frame, float alpha, const vec3& wo_world, vec2 u, float u_lobe,
                           float p_specular, vec3& wi_world) {
  vec3 wo = frame.to_local(wo_world);
  return wo.z > 0.0f && sample_local_direction(frame, alpha, wo, u, u_lobe, p_specular, wi_world);
}

bool Bsdf::sample(const BsdfWoTerms& t, const vec3& wo_world, vec2 u, float u_lobe, BsdfSample& out) const {
  vec3 wo = frame_.to_local(wo_world);  // wo.z is t.cos_o: the same products, summed in the same order
  if (wo.z <= 0.0f || !sample_local_direction(frame_, alpha_, wo, u, u_lobe, t.p_specular, out.wi)) return false;
  out.f = eval(t, wo_world, out.wi);
  out.pdf = pdf(t, wo_world, out.wi);
  return out.pdf > 0.0f;
}

bool Bsdf::sample(const vec3& wo, vec2 u, float u_lobe, BsdfSample& out) const {
  return sample(wo_terms(wo), wo, u, u_lobe, out);
}

}  // namespace candela

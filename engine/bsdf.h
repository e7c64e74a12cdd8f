#pragma once
// glTF metallic-roughness BSDF with KHR_materials_specular and KHR_materials_ior, energy-preserving:
//   f = f_ss + f_ms + f_base
//   f_ss   = F(wo.h) D(h) G2 / (4 |n.wo| |n.wi|)        GGX, height-correlated Smith G2 (Walter et al. 2007;
//            F = F0 + (F90 - F0)(1 - wo.h)^5            Heitz 2014), Schlick Fresnel with
//            F0 = mix(s F0_d, base, metallic), F90 = mix(s, 1, metallic)   (glTF 2.0 appendix B, the
//            KHR_materials_specular "fresnel_mix": s = specular factor, F0_d = min(((ior-1)/(ior+1))^2
//            specularColor, 1), 0.04 for the defaults)
//   f_ms   = F_ms (1 - a(mu_o)) (1 - a(mu_i)) / (pi (1 - a_avg))
//            the energy single scattering loses, returned as a diffuse-like lobe (Kulla & Conty 2017,
//            "Revisiting Physically Based Shading at Imageworks"), F_ms = F_avg^2 a_avg / (1 - F_avg (1 - a_avg))
//            per Fresnel, F_avg = F0 + (F90 - F0) / 21; a(mu) is the albedo of the lobe with F = 1
//   f_base = (1 - metallic) base (1 - E_d(mu_o)) (1 - E_d(mu_i)) / (pi (1 - E_d_avg))
//            the diffuse base keeps exactly the energy the dielectric's specular layer (single and multiple
//            scattering, albedo E_d) does not reflect: Kulla & Conty's albedo scaling in its reciprocal form
//            (the same layering OpenPBR and Autodesk Standard Surface specify).
// A white dielectric therefore reflects all incident energy at every angle, a white metal all of it too
// (up to the tables' interpolation: 0.1%, 0.2% at grazing angles), and s = 0 leaves exactly Lambert. Albedo tables:
// ggx_albedo.h. Directions are world-space unit vectors pointing away from the surface; eval returns f without the
// cosine. Reflection only (no transmission).
#include "engine/ggx_albedo.h"
#include "engine/microfacet.h"
#include "engine/math.h"

namespace candela {

struct BsdfSample {
  vec3 wi{0.0f};
  vec3 f{0.0f};      // BSDF value for (wo, wi)
  float pdf = 0.0f;  // solid-angle density of wi under sample() (both lobes)
};

// What Bsdf::eval and Bsdf::pdf compute from wo alone, for kernels that evaluate one wo against many wi in
// SIMD lanes (restir/target_lanes.cpp). The expressions are eval's and pdf's, so such a kernel can give
// their bits (tests/test_target_lanes.cpp checks that it does).
struct BsdfWoTerms {
  vec3 n{0.0f};        // shading normal
  float cos_o = 0.0f;  // n.wo (eval and pdf are 0 unless positive)
  float alpha = 1.0f;
  float s_o = 1.0f;  // sqrt(cos_o^2 (1 - alpha^2) + alpha^2)
  vec3 f0{0.0f};
  float f90 = 0.0f;
  vec3 ms{0.0f};                // f_ms = ms (ms_o (1 - a(mu_i)))
  float ms_o = 0.0f;            // max(1 - a(mu_o), 0)
  vec3 base_o{0.0f};            // f_base = base_o max(1 - E_d(mu_i), 0)
  vec3 d_f0{0.0f}, d_ms{0.0f};  // the dielectric layer, for E_d(mu_i)
  float d_f90 = 0.0f;
  size_t albedo_row = 0;       // GgxAlbedoRow::row_offset
  float albedo_weight = 0.0f;  // GgxAlbedoRow::row_weight
  float g1_o = 0.0f;           // G1(wo), for pdf
  float p_specular = 0.0f;     // probability of the single-scattering lobe at wo, for pdf
};

class Bsdf {
 public:
  Bsdf() = default;
  // n: unit shading normal on the side of wo; base colour linear RGB; roughness in [0, 1] (perceptual);
  // specular: KHR_materials_specular's factor s (0 leaves a pure Lambert lobe); specular_f0: the dielectric's
  // F0_d (specular colour and ior, see dielectric_f0).
  Bsdf(const vec3& n, const vec3& base_color, float metallic, float roughness, float specular = 1.0f,
       const vec3& specular_f0 = vec3(0.04f));

  vec3 eval(const vec3& wo, const vec3& wi) const;
  float pdf(const vec3& wo, const vec3& wi) const;
  BsdfWoTerms wo_terms(const vec3& wo) const;
  // u: two uniforms for the direction, u_lobe: one uniform for the lobe choice. False if no sample.
  bool sample(const vec3& wo, vec2 u, float u_lobe, BsdfSample& out) const;
  // The same at a wo whose terms t = wo_terms(wo) are computed once for several calls (a path vertex's
  // light sample and BSDF sample): the same bits, without recomputing the albedo lookups at wo.
  vec3 eval(const BsdfWoTerms& t, const vec3& wo, const vec3& wi) const;
  float pdf(const BsdfWoTerms& t, const vec3& wo, const vec3& wi) const;
  bool sample(const BsdfWoTerms& t, const vec3& wo, vec2 u, float u_lobe, BsdfSample& out) const;

  const vec3& normal() const { return frame_.n; }
  float alpha() const { return alpha_; }

 private:
  // Albedo of the dielectric's specular layer (single + multiple scattering) at albedo-table entry e.
  vec3 layer_albedo(const GgxAlbedo& e) const { return d_f0_ * (e.a - e.b) + d_f90_ * e.b + d_ms_ * (1.0f - e.a); }
  float specular_probability(const GgxAlbedo& e_o) const;
  GgxAlbedo eval_terms(BsdfWoTerms& t) const;
  void pdf_terms(BsdfWoTerms& t, const GgxAlbedo& e_o) const;

  Frame frame_{vec3(1, 0, 0), vec3(0, 1, 0), vec3(0, 0, 1)};
  vec3 f0_{0.04f};               // F0 of the single-scattering lobe
  float f90_ = 1.0f;             // F90 of it
  vec3 ms_{0.0f};                // F_ms / (pi (1 - a_avg)): f_ms = ms_ (1 - a(mu_o)) (1 - a(mu_i))
  vec3 base_scale_{0.0f};        // (1 - metallic) base / (pi (1 - E_d_avg)):
                                 // f_base = base_scale_ (1 - E_d(mu_o)) (1 - E_d(mu_i))
  struct {                       // luminances for the lobe choice, with base = (1 - metallic) base colour:
    float f0, ms, base;          //   of f0_, F_ms, base,
    float base_d_f0, base_d_ms;  // base d_f0_ and base d_ms_
  } lum_{};
  vec3 d_f0_{0.0f}, d_ms_{0.0f};  // the dielectric layer's s F0_d and its F_ms
  float d_f90_ = 0.0f;            // and its F90 = s
  float alpha_ = 1.0f;            // GGX alpha = roughness^2
  GgxAlbedoRow albedo_;           // a(mu), b(mu) at this roughness
};

// The direction Bsdf::sample draws at wo, without evaluating it, for a BSDF with shading frame `frame`
// (Frame::from_normal of its normal) and GGX alpha: the single-scattering lobe's visible normals with
// probability p_specular (BsdfWoTerms::p_specular), else the cosine lobe. False if there is none.
bool sample_bsdf_direction(const Frame& frame, float alpha, const vec3& wo, vec2 u, float u_lobe, float p_specular,
                           vec3& wi);

// F0 of the glTF dielectric: ((ior - 1) / (ior + 1))^2 times the specular colour, at most 1
// (KHR_materials_ior, KHR_materials_specular); ior 1.5 and white give 0.04.
vec3 dielectric_f0(float ior, const vec3& specular_color);

}  // namespace candela

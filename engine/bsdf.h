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

  const vec3& normal() const { return frame_.n; }
  float alpha() const { return alpha_; }

 private:
  float specular_probability(float cos_o) const;

  Frame frame_{vec3(1, 0, 0), vec3(0, 1, 0), vec3(0, 0, 1)};
  vec3 diffuse_{0.0f};  // base * (1 - metallic)
  vec3 f0_{0.04f};
  float specular_ = 1.0f;
  float alpha_ = 1.0f;  // GGX alpha = roughness^2
};

// GGX normal distribution D(h) for cos_h = n.h (Walter et al. 2007, eq. 33).
float ggx_d(float cos_h, float alpha);
// Smith G1 for GGX (Heitz 2014, "Understanding the Masking-Shadowing Function", eq. 72 via Lambda).
float ggx_lambda(float cos_theta, float alpha);
// Samples a visible normal (Heitz 2018, "Sampling the GGX Distribution of Visible Normals") in local space.
vec3 ggx_sample_visible_normal(const vec3& wo_local, float alpha, vec2 u);
// Cosine-weighted hemisphere direction around +z (Malley's method, concentric disk of Shirley & Chiu 1997).
vec3 sample_cosine_hemisphere(vec2 u);

}  // namespace candela

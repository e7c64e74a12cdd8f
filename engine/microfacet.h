#pragma once
// The GGX microfacet distribution and the hemisphere samplers the BSDF and its albedo tables share.
#include "engine/math.h"

namespace candela {

// The GGX alpha for a perceptual roughness (clamped so that D stays finite in float).
inline float ggx_alpha(float roughness) {
  float r = std::clamp(roughness, 0.03f, 1.0f);
  return r * r;
}
// GGX normal distribution D(h) for cos_h = n.h (Walter et al. 2007, eq. 33).
float ggx_d(float cos_h, float alpha);
// Smith G1 for GGX (Heitz 2014, "Understanding the Masking-Shadowing Function", eq. 72 via Lambda).
float ggx_lambda(float cos_theta, float alpha);
// Samples a visible normal (Heitz 2018, "Sampling the GGX Distribution of Visible Normals") in local space.
vec3 ggx_sample_visible_normal(const vec3& wo_local, float alpha, vec2 u);
// Cosine-weighted hemisphere direction around +z (Malley's method, concentric disk of Shirley & Chiu 1997).
vec3 sample_cosine_hemisphere(vec2 u);

}  // namespace candela

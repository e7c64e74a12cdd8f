#pragma once
// Spatial and directional bounds of a set of lights, and the importance they may have for a shading
// point: the bounding-cone model of Conty Estevez & Kulla 2018 ("Importance Sampling of Many Lights with
// Adaptive Tree Splitting"), in the conservative form pbrt-v4 uses for its BVH light sampler
// (Pharr, Jakob & Humphreys 2023, section 12.6.3). Zero importance means no light in the set can
// illuminate the point; otherwise the value is a heuristic of how much they may.
//
// Space is bounded by a sphere (all the importance needs), directions by a cone around w holding every
// emitter normal (theta_o) plus how far beyond its normal an emitter still emits (theta_e). Sines are
// stored beside cosines so that evaluating importance needs no trigonometry. 48 bytes.
#include "engine/lights.h"
#include "engine/math.h"

namespace candela {

struct LightBounds {
  vec3 center{0.0f};
  float radius = 0.0f;
  vec3 w{0.0f, 0.0f, 1.0f};
  float phi = 0.0f;            // total power (luminance)
  float cos_theta_o = 1.0f, sin_theta_o = 0.0f;
  float cos_theta_e = 0.0f;    // 0: emits over the hemisphere around its normal (area lights)
  uint32_t two_sided = 0;

  bool empty() const { return phi <= 0.0f; }
  // Importance for a receiver at p with unit normal n (n = 0: any orientation).
  float importance(const vec3& p, const vec3& n) const;
  void set_cos_theta_o(float c) { cos_theta_o = std::clamp(c, -1.0f, 1.0f); sin_theta_o = std::sqrt(1.0f - cos_theta_o * cos_theta_o); }
};

// Bounds of both: the sphere around both spheres, a cone around the power-weighted mean axis that holds
// both cones, summed power. Conservative, trigonometry-free.
LightBounds merge(const LightBounds& a, const LightBounds& b);

// cos(alpha + beta) for alpha = acos(cos_a) and beta = acos(cos_b) in [0, pi], or -1 once alpha + beta >= pi.
float cos_of_sum(float cos_a, float cos_b, float sin_b);

// Bounds of light `index` of the list (and its box, if asked); empty (phi = 0) for lights at infinity
// (directional), which the samplers treat separately.
LightBounds light_bounds(const LightList& lights, size_t index, Bounds3* box = nullptr);
bool is_infinite_light(const LightList& lights, size_t index);

// Solid-angle measure of a bounding cone (Conty Estevez & Kulla 2018, eq. 1), used by the tree builder.
float cone_measure(float cos_theta_o, float cos_theta_e);

}  // namespace candela

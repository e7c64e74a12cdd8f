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
#include "engine/light_sampler.h"
#include "engine/lights.h"
#include "engine/math.h"

namespace candela {

struct LightBounds {
  vec3 center{0.0f};
  float radius = 0.0f;
  vec3 w{0.0f, 0.0f, 1.0f};  // cone axis; any length (importance divides it out), unit where built
  float phi = 0.0f;          // total power (luminance)
  float cos_theta_o = 1.0f, sin_theta_o = 0.0f;
  float cos_theta_e = 0.0f;  // 0: emits over the hemisphere around its normal (area lights)
  uint32_t two_sided = 0;

  bool empty() const { return phi <= 0.0f; }
  // Importance for a receiver at ctx.position with unit normal ctx.normal (0: any orientation). For a
  // region (ctx.radius > 0) the bounding sphere grows by the region's radius: the directions from any point
  // q of the region to the lights are the directions from the region's centre to the lights moved by
  // (centre - q), which the grown sphere holds, so a light that can reach some point of the region keeps
  // a positive importance.
  float importance(const ShadingContext& ctx) const;
  void set_cos_theta_o(float c) {
    cos_theta_o = std::clamp(c, -1.0f, 1.0f);
    sin_theta_o = std::sqrt(1.0f - cos_theta_o * cos_theta_o);
  }
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

namespace light_bounds_detail {
inline float safe_sqrt(float x) { return std::sqrt(std::max(0.0f, x)); }

// cos(max(0, a - b)) from the sines and cosines of a and b.
inline float cos_sub_clamped(float sin_a, float cos_a, float sin_b, float cos_b) {
  return cos_a > cos_b ? 1.0f : cos_a * cos_b + sin_a * sin_b;
}

}  // namespace light_bounds_detail

// The arithmetic is ordered for a short chain of dependent operations (a tree descent waits for each
// level's importances): everything that needs the distance waits for one square root and one reciprocal;
// the other square roots (sines from cross products, the sphere's cone) run beside it, and the power over
// the squared distance is divided early. wide_importance.cpp repeats it operation for operation.
inline float LightBounds::importance(const ShadingContext& ctx) const {
  using namespace light_bounds_detail;
  if (phi <= 0.0f) return 0.0f;
  const vec3& n = ctx.normal;
  const float radius = this->radius + ctx.radius;
  vec3 to_p = ctx.position - center;
  const float dist2 = glm::dot(to_p, to_p);
  // Points close to (or inside) the bounds would get unbounded importance: clamp the distance term
  // (pbrt-v4 clamps with half the box diagonal, which is the radius here).
  const float power = phi / std::max({dist2, radius, 1e-20f});
  const bool away = dist2 > 0.0f;
  if (!away) to_p = vec3(0.0f, 0.0f, 1.0f);  // p at the centre: any direction will do
  const float dist = std::sqrt(away ? dist2 : 1.0f);
  const float inv_dist = 1.0f / dist;
  // theta_b: half-angle of the cone from p around the bounding sphere (pi when p is inside it).
  const bool outside = away && dist > radius;
  const float sin_b = outside ? radius * inv_dist : 0.0f;
  const float cos_b = outside ? safe_sqrt(dist2 - radius * radius) * inv_dist : -1.0f;
  // Smallest angle between an emitter's normal and a direction towards p: theta_w - theta_o - theta_b.
  // The tree's axes are rounded and not quite unit (wide_importance.h): cos and sin of theta_w come scaled
  // by |w| (w_cos, w_sin); cos and sin of max(0, theta_w - theta_o) are taken on them, comparing against
  // |w| cos theta_o and dividing by |w| after (a reciprocal computed beside the distance's), so that
  // normalising w adds no step between the distance and the importance.
  const float w_len = std::sqrt(glm::dot(w, w)), inv_w_len = 1.0f / w_len;
  float w_cos = glm::dot(w, to_p) * inv_dist;
  if (two_sided) w_cos = std::abs(w_cos);
  const vec3 w_cross = glm::cross(w, to_p);
  const float w_sin = std::sqrt(glm::dot(w_cross, w_cross)) * inv_dist;
  const bool within_o = w_cos > cos_theta_o * w_len;
  const float cos_x = within_o ? 1.0f : (w_cos * cos_theta_o + w_sin * sin_theta_o) * inv_w_len;
  const float sin_x = within_o ? 0.0f : (w_sin * cos_theta_o - w_cos * sin_theta_o) * inv_w_len;
  const float cos_p = cos_sub_clamped(sin_x, cos_x, sin_b, cos_b);
  if (cos_p < cos_theta_e) return 0.0f;
  float value = power * cos_p;
  // Receiver side: the smallest angle between n and a direction into the sphere.
  if (n != vec3(0.0f)) {
    const float cos_i = std::abs(glm::dot(to_p, n)) * inv_dist;
    const vec3 n_cross = glm::cross(n, to_p);
    const float sin_i = std::sqrt(glm::dot(n_cross, n_cross)) * inv_dist;
    value *= cos_sub_clamped(sin_i, cos_i, sin_b, cos_b);
  }
  return std::max(value, 0.0f);
}

// Solid-angle measure of a bounding cone (Conty Estevez & Kulla 2018, eq. 1), used by the tree builder.
float cone_measure(float cos_theta_o, float cos_theta_e);

}  // namespace candela

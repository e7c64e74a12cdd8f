#pragma once
// Spatial and directional bounds of a set of lights, and the importance they may have for a shading
// point: the bounding-cone model of Conty Estevez & Kulla 2018 ("Importance Sampling of Many Lights with
// Adaptive Tree Splitting"), in the conservative form pbrt-v4 uses for its BVH light sampler
// (Pharr, Jakob & Humphreys 2023, section 12.6.3). Zero importance means no light in the set can
// illuminate the point; otherwise the value is a heuristic of how much they may.
#include "engine/lights.h"
#include "engine/math.h"

namespace candela {

struct LightBounds {
  Bounds3 bounds;              // where the emitters are
  vec3 w{0.0f, 0.0f, 1.0f};    // axis of the cone of emitter normals (or spot directions)
  float phi = 0.0f;            // total power (luminance)
  float cos_theta_o = 1.0f;    // spread of the normals around w
  float cos_theta_e = 0.0f;    // how far beyond its normal an emitter still emits (pi/2 for area lights)
  bool two_sided = false;

  bool empty() const { return phi <= 0.0f; }
  // Importance for a receiver at p with unit normal n (n = 0: any orientation).
  float importance(const vec3& p, const vec3& n) const;
};

// The union of two bounds: box union, the smallest cone containing both cones, summed power.
LightBounds merge(const LightBounds& a, const LightBounds& b);

// Bounds of light `index` of the list; empty (phi = 0) for lights at infinity (directional), which the
// samplers treat separately.
LightBounds light_bounds(const LightList& lights, size_t index);
bool is_infinite_light(const LightList& lights, size_t index);

// Solid-angle measure of a bounding cone (Conty Estevez & Kulla 2018, eq. 1), used by the tree builder.
float cone_measure(float cos_theta_o, float cos_theta_e);

}  // namespace candela

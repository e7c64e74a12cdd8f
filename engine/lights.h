#pragma once
// The light list the samplers index: emissive triangles that really emit (their emission integrated over
// the triangle, since most glTF emissive textures are black almost everywhere), punctual lights in world
// space, and the uniform environment. Index space: [0, triangles) triangle lights, then punctual lights.
// Also the per-light geometry sampling used by next-event estimation.
#include <utility>
#include <vector>

#include "engine/prefetch.h"
#include "engine/scene.h"
#include "engine/tracer.h"

namespace candela {

struct TriangleLight {
  vec3 p0, e1, e2;  // world corner and edges
  vec3 normal;      // unit, by winding (the emitting side of one-sided emitters)
  float area = 0.0f;
  vec3 average_radiance{0.0f};  // emission averaged over the triangle
  uint32_t instance = 0, prim = 0;
  bool two_sided = false;
  bool textured = false;  // emission varies over the triangle (else it is average_radiance everywhere)
  float power() const { return luminance(average_radiance) * area * kPi * (two_sided ? 2.0f : 1.0f); }
};

// Per mesh, which primitives emit and their averaged emission (computed once, shared by instances).
struct MeshEmission {
  std::vector<uint32_t> prims;         // emitting primitives
  std::vector<vec3> average_radiance;  // per entry of prims
  std::vector<int32_t> light_of_prim;  // prim -> position in prims, or -1
};

// A point on a light as seen from a shading point: where, how bright towards it, and its density.
struct LightSample {
  vec3 position{0.0f};
  vec3 normal{0.0f};      // zero for punctual lights
  vec3 wi{0.0f};          // unit direction from the shading point to the light
  float distance = 0.0f;  // kInfinity for directional lights
  vec3 radiance{0.0f};    // incident radiance (area lights) or irradiance-like intensity / d^2 (delta lights)
  float pdf = 0.0f;       // solid-angle density for area lights; 1 for delta lights
  bool is_delta = false;
};

// A point on a triangle light, independent of who looks at it: where it is, which way it faces and what it
// emits from its emitting side(s).
struct LightPoint {
  vec3 position{0.0f};
  vec3 normal{0.0f};
  vec3 radiance{0.0f};
  bool two_sided = false;
};

// The light sample a triangle light's point gives at shading point p, with pdf left 0 (the caller knows
// how the point was chosen). Zero radiance when p sees its back or lies in its plane.
inline LightSample light_sample_towards(const LightPoint& lp, const vec3& p) {
  LightSample s;
  s.position = lp.position;
  vec3 d = lp.position - p;
  float dist2 = glm::dot(d, d);
  if (dist2 <= 0.0f) return s;
  s.distance = std::sqrt(dist2);
  s.wi = d / s.distance;
  float cos_l = glm::dot(lp.normal, s.wi);
  if (std::abs(cos_l) <= 1e-7f) return s;
  s.normal = lp.normal;
  if (lp.two_sided || cos_l < 0.0f) s.radiance = lp.radiance;
  return s;
}

// The shadow ray from surface point p (geometric normal ng) to a light sample: to its point (offset at
// both ends; delta lights have no surface, so their end is offset along the ray) or, for lights at
// infinity, unbounded along wi.
inline Ray shadow_ray(const Tracer& tracer, const vec3& p, const vec3& ng, const LightSample& ls) {
  if (ls.distance >= kInfinity) return tracer.spawn_ray(p, ng, ls.wi);
  return tracer.spawn_ray_to(p, ng, ls.position, ls.is_delta ? -ls.wi : ls.normal);
}

// Emitted radiance above which a triangle counts as a light (linear, per channel).
inline constexpr float kEmissionThreshold = 1e-3f;

class LightList {
 public:
  LightList() = default;
  // Integrates emission per mesh and places lights through instances. Cost: O(emissive triangles * samples).
  explicit LightList(const Scene& scene);
  // Re-places lights of animated instances after Scene::set_time (O(their lights)).
  void update(const Scene& scene);
  // The index ranges [first, end) of the lights update() rewrites (those of animated instances, then the
  // punctual lights attached to an instance); every other light keeps its geometry and power.
  std::vector<std::pair<size_t, size_t>> movable() const;

  size_t size() const { return triangles_.size() + punctual_.size(); }
  size_t triangle_count() const { return triangles_.size(); }
  // Starts loading light `index`'s record (area, point placement; it may span two cache lines) where it is a
  // triangle light: punctual lights are few and stay in cache.
  void prefetch(size_t index) const {
    if (index < triangles_.size()) prefetch_object(triangles_[index]);
  }
  // Whether light `index` is a triangle light that every list built from this scene places and lights alike: none of
  // an animated instance's, its material's emission not animated. A sample's point on it stored from another frame's
  // list is the point this list gives, to the bit, so temporal reuse need not place it anew (nor read its record).
  bool fixed(size_t index) const { return index < triangles_.size() && !(changing_[index >> 6] >> (index & 63) & 1u); }
  const std::vector<TriangleLight>& triangles() const { return triangles_; }
  const std::vector<PunctualLight>& punctual() const { return punctual_; }
  vec3 environment() const { return environment_; }
  float power(size_t index) const;
  // Light index of an emitting triangle, or -1 if (instance, prim) is not in the list.
  int64_t light_index(uint32_t instance, uint32_t prim) const;
  // Samples a point on light `index` as seen from p, with u in [0,1)^2.
  LightSample sample(const Scene& scene, size_t index, const vec3& p, vec2 u) const;
  // The point that sample() places on triangle light `index` for u (uniform over its area).
  LightPoint triangle_point(const Scene& scene, size_t index, vec2 u) const {
    LightPoint point;
    triangle_point(scene, index, u, point);
    return point;
  }
  // The same written into `out` field by field, for callers that keep the point inside a larger struct: a returned
  // point assigned there was copied with wide loads of the callee's narrower stores, which stalled on store
  // forwarding (a third of the light tiles' drawing in a profile, docs/performance.md).
  void triangle_point(const Scene& scene, size_t index, vec2 u, LightPoint& out) const;
  // sample() for punctual light `index` (>= triangle_count()): its position or direction, pdf 1.
  LightSample sample_punctual(size_t index, const vec3& p) const;
  // Solid-angle density with which sample() picks the point y (normal ny) on triangle light `index` from p.
  float pdf_solid_angle(size_t index, const vec3& p, const vec3& y) const;

 private:
  void place_instance(const Scene& scene, uint32_t instance);
  void mark_changing(const Scene& scene);
  static PunctualLight to_world(const Scene& scene, const PunctualLight& light);

  std::vector<MeshEmission> mesh_emission_;
  std::vector<uint32_t> instance_mesh_;
  std::vector<int64_t> instance_first_light_;  // per instance: index of its first triangle light, or -1
  std::vector<uint32_t> animated_emitters_;    // the animated instances with triangle lights
  std::vector<TriangleLight> triangles_;
  std::vector<uint64_t> changing_;  // bit per triangle light: not fixed() (on an animated instance, or power-animated)
  std::vector<PunctualLight> punctual_;
  vec3 environment_{0.0f};
  float scene_radius_ = 0.0f;
};

// Averages a material's emission over a mesh triangle by stratified sampling of its UV footprint.
vec3 integrate_triangle_emission(const Scene& scene, const Mesh& mesh, uint32_t prim);

}  // namespace candela

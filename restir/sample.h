#pragma once
// What ReSTIR DI and ReSTIR GI resample, and the one target function both use: the sample a reservoir holds (a point
// on a light, or a surface point reflecting light), the domain and receivers targets are evaluated at, a sample's
// unshadowed contribution (whose luminance is the target, p_hat) and its shadow ray. Every reuse stage (restir/reuse.h)
// and the shading (restir/shade.h) read samples through these, whichever estimator drew them.
#include <algorithm>
#include <span>

#include "engine/gbuffer.h"
#include "engine/packed_surface.h"
#include "engine/path_tracer.h"
#include "restir/reservoir.h"

namespace candela {

// A sample that reservoirs hold and reuse moves between pixels and frames. ReSTIR DI's is a point on a light: which
// light and the uniforms LightList::sample maps to the point (its identity, valid in every frame), plus, for triangle
// lights, the point they give with the light placement of the frame whose reservoirs hold the sample (so that targets
// at other pixels cost no light lookup). ReSTIR GI's is a surface point (kSurfacePointSample, below).
struct ReuseSample {
  uint32_t light = 0;
  vec2 uv{0.0f};
  LightPoint point;
  uint16_t age = 0;  // frames since the sample was drawn (temporal reuse counts it)
};

// The `light` of a sample that is no light but a point on a surface reflecting light, stored whole in
// `point` (ReSTIR GI's sample point: position, normal, outgoing radiance; see restir/gi.h). Such samples
// are never re-placed, and `uv` holds a random tag that tells two of them apart.
inline constexpr uint32_t kSurfacePointSample = 0xffffffffu;
using ReuseReservoir = Reservoir<ReuseSample>;

// A sample's age after `frames` more frames (saturating at the field's largest value).
inline uint16_t aged_by(uint16_t age, int frames) { return uint16_t(std::min(int(age) + frames, 0xffff)); }

// Where targets are evaluated: a frame's packed surfaces, the eye they were seen from and the frame's light
// placement (this frame's, or the previous frame's for temporal reuse, so that moving lights are judged
// where they were).
struct ReuseDomain {
  std::span<const PackedSurface> surfaces;
  int width, height;
  vec3 eye;
  const LightList& lights;
};

// A G-buffer pixel seen as a receiver of light: built once per pixel, then evaluated against many samples.
struct ReuseReceiver {
  vec3 position, geometric_normal, shading_normal, wo;
  Bsdf bsdf;
  const LightList* lights;  // the light placement of the receiver's frame
};
// The receiver whose target function resampling uses: the packed surface of pixel i.
inline ReuseReceiver reuse_receiver(const ReuseDomain& domain, size_t i) {
  const PackedSurface& s = domain.surfaces[i];
  vec3 n = s.shading_n();
  return {s.position, s.geometric_n(), n, glm::normalize(domain.eye - s.position), s.bsdf(n), &domain.lights};
}
// The exact receiver of pixel i, from the G-buffer: for sampling densities and the final shading.
inline ReuseReceiver exact_receiver(const GBuffer& g, const vec3& eye, const LightList& lights, size_t i) {
  return {g.position[i], g.geometric_normal[i], g.shading_normal[i], glm::normalize(eye - g.position[i]), g.bsdf(i),
          &lights};
}

// Whether sample s, stored with the point the lights `own` (its frame's) gave it, has that point under the lights
// `here` too: the same list, a light no frame moves or dims (LightList::fixed, to the bit), or a surface point (never
// re-placed). Reuse places the others anew on `here` (di_resolve, restir/di.h).
inline bool placed_alike(const LightList& own, const LightList& here, const ReuseSample& s) {
  return &own == &here || s.light == kSurfacePointSample || here.fixed(s.light);
}

// Whether sample s stores its point (a triangle light's or a surface point): punctual lights store none.
inline bool stored_point(const LightList& lights, const ReuseSample& s) {
  return s.light < lights.triangle_count() || s.light == kSurfacePointSample;
}
// The light sample that sample s gives at point p (direction, distance, its point's normal and radiance):
// the stored point's, or for a punctual light the one `lights` places.
inline LightSample light_sample_of(const LightList& lights, const vec3& p, const ReuseSample& s) {
  return stored_point(lights, s) ? light_sample_towards(s.point, p) : lights.sample_punctual(s.light, p);
}

// The shadow ray from p (geometric normal ng), of a frame whose lights are `lights`, to sample s placed by them,
// where s contributes there (a positive target or contribution at p): shadow_ray of light_sample_of's sample. A
// stored point's ray is the segment to it, which needs neither the direction nor the distance: built straight
// from the point (light_sample_of's sample, a 64-byte struct, cost more than the segment).
inline Ray sample_shadow_ray(const Tracer& tracer, const vec3& p, const vec3& ng, const LightList& lights,
                             const ReuseSample& s) {
  if (stored_point(lights, s)) return tracer.spawn_ray_to(p, ng, s.point.position, s.point.normal);
  return shadow_ray(tracer, p, ng, lights.sample_punctual(s.light, p));
}
// The same from a packed surface.
inline Ray sample_shadow_ray(const Tracer& tracer, const PackedSurface& surface, const LightList& lights,
                             const ReuseSample& s) {
  return sample_shadow_ray(tracer, surface.position, surface.geometric_n(), lights, s);
}

// The unshadowed contribution of a light sample to a G-buffer pixel, in area measure:
// f * L_e * |cos at the receiver| * |cos at the light| / d^2 (delta lights: f * I / d^2 * |cos|).
// Uses the sample's stored point, which must be placed with the receiver's lights.
struct SampleContribution {
  vec3 value{0.0f};
  LightSample light;
};
SampleContribution sample_contribution(const ReuseReceiver& receiver, const ReuseSample& s);

// Target function p_hat: luminance of the unshadowed contribution.
inline float sample_target(const SampleContribution& c) { return luminance(c.value); }

}  // namespace candela

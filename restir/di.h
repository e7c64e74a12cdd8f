#pragma once
// ReSTIR DI (Bitterli et al. 2020, section 3 and Alg. 3): its samples, receivers and target function, and
// shading with one shadow ray (the candidate stage that fills the reservoirs is in di_candidates.h, the
// reuse stages between it and shading in di_reuse.h). Samples live in the lights' area measure (a light
// index and the two uniforms that place the point on it), so that a reservoir's contribution weight W
// stays valid when the sample is reused at another pixel or frame; light indices are stable for a scene's
// lifetime (LightList keeps one per emitting triangle of each instance and per punctual light), so a
// sample's identity needs no remap between frames, and a light that moved, dimmed or went dark is simply
// re-evaluated where it is now.
#include <algorithm>
#include <span>
#include <vector>

#include "engine/gbuffer.h"
#include "engine/image.h"
#include "engine/path_tracer.h"
#include "engine/packed_surface.h"
#include "restir/reservoir.h"

namespace candela {

// A point on a light: which light and the uniforms LightList::sample maps to the point (its identity,
// valid in every frame), plus, for triangle lights, the point they give with the light placement of the
// frame whose reservoirs hold the sample (so that targets at other pixels cost no light lookup).
struct DiSample {
  uint32_t light = 0;
  vec2 uv{0.0f};
  LightPoint point;
  uint16_t age = 0;  // frames since the sample was drawn (temporal reuse counts it)
};

// The `light` of a sample that is no light but a point on a surface reflecting light, stored whole in
// `point` (ReSTIR GI's sample point: position, normal, outgoing radiance; see restir/gi.h). Such samples
// are never re-placed, and `uv` holds a random tag that tells two of them apart.
inline constexpr uint32_t kSurfacePointSample = 0xffffffffu;
using DiReservoir = Reservoir<DiSample>;

// A sample's age after `frames` more frames (saturating at the field's largest value).
inline uint16_t di_aged(uint16_t age, int frames) { return uint16_t(std::min(int(age) + frames, 0xffff)); }

struct DiParams {
  // M_l: candidates per pixel from the light sampler (cost: M_l light samples + BSDF evaluations); 4 beat 8 at
  // equal time on manylights, city and occluded_room (docs/restir.md, "Spatial neighbours and light candidates")
  int light_candidates = 4;
  // M_l for the pixels whose temporal history was found (di_find_history), at most light_candidates: their
  // history already stands for up to history_cap times their candidates.
  int history_light_candidates = 1;
  int bsdf_candidates = 1;  // M_b: candidates from BSDF sampling that hit an emitter (cost: one ray each)
  // Each BSDF candidate is drawn (and its ray traced) with this probability, and counts as this fraction of a
  // candidate in every candidate's MIS weight (see effective_bsdf_candidates); below 1 it pays on manylights and
  // occluded_room, but not on city, whose sky only BSDF candidates reach (docs/restir.md, "BSDF candidates at
  // equal time").
  float bsdf_probability = 1.0f;
  // M_b as the MIS weights and the reservoir's confidence count it: the expected number of BSDF candidates.
  float effective_bsdf_candidates() const { return float(bsdf_candidates) * bsdf_probability; }
  // Trace a shadow ray to the chosen candidate and drop it if occluded (1 ray per pixel).
  bool candidate_visibility = false;
  // Evaluate light candidates in SIMD lanes (target_lanes.h); false: the scalar reference, which gives the
  // same bits.
  bool simd = true;
  // > 0: light candidates read presampled light tiles (light_tiles.h): this many shared ones per frame (power,
  // uniform), or one per 16x16 block (tree, exhaustive).
  int light_tiles = 0;
  int light_tile_size = 0;  // entries per tile; 0: 1,024 per shared tile, 128 per region tile
  uint64_t seed = 0;
};

// Where targets are evaluated: a frame's packed surfaces, the eye they were seen from and the frame's light
// placement (this frame's, or the previous frame's for temporal reuse, so that moving lights are judged
// where they were).
struct DiDomain {
  std::span<const PackedSurface> surfaces;
  int width, height;
  vec3 eye;
  const LightList& lights;
};

// A G-buffer pixel seen as a receiver of light: built once per pixel, then evaluated against many samples.
struct DiReceiver {
  vec3 position, geometric_normal, shading_normal, wo;
  Bsdf bsdf;
  const LightList* lights;  // the light placement of the receiver's frame
};
// The receiver whose target function resampling uses: the packed surface of pixel i.
inline DiReceiver di_receiver(const DiDomain& domain, size_t i) {
  const PackedSurface& s = domain.surfaces[i];
  vec3 n = s.shading_n();
  return {s.position, s.geometric_n(), n, glm::normalize(domain.eye - s.position), s.bsdf(n), &domain.lights};
}
// The exact receiver of pixel i, from the G-buffer: for sampling densities and the final shading.
inline DiReceiver di_exact_receiver(const GBuffer& g, const vec3& eye, const LightList& lights, size_t i) {
  return {g.position[i], g.geometric_normal[i], g.shading_normal[i], glm::normalize(eye - g.position[i]), g.bsdf(i),
          &lights};
}

// The sample (light, uv) with its point placed by `lights` (punctual lights have no point to store).
inline DiSample di_resolve(const Scene& scene, const LightList& lights, uint32_t light, vec2 uv) {
  DiSample s{light, uv, {}, 0};
  if (light < lights.triangle_count()) s.point = lights.triangle_point(scene, light, uv);
  return s;
}

// Whether sample s, stored with the point the lights `own` (its frame's) gave it, has that point under the lights
// `here` too: the same list, a light no frame moves or dims (LightList::fixed, to the bit), or a surface point (never
// re-placed). Reuse places the others anew on `here` (di_resolve).
inline bool di_placed_alike(const LightList& own, const LightList& here, const DiSample& s) {
  return &own == &here || s.light == kSurfacePointSample || here.fixed(s.light);
}

// Density of a fresh light sample over its light's area given the light was chosen (1 for delta lights).
inline float di_area_pdf(const LightList& lights, uint32_t light) {
  return light < lights.triangle_count() ? 1.0f / lights.triangles()[light].area : 1.0f;
}

// A light candidate: the sample that uv places on the chosen light, and the area density it was drawn
// with, pmf / area (pmf for delta lights; 0: no light chosen, and no sample).
struct DiLightCandidate {
  DiSample sample;
  float p_light = 0.0f;
};
// The area density of a chosen light's sample: pmf / area (pmf for delta lights; 0: no light chosen).
inline float di_light_pdf(const LightList& lights, SampledLight chosen) {
  return chosen.pmf > 0.0f ? chosen.pmf * di_area_pdf(lights, chosen.index) : 0.0f;
}
inline DiLightCandidate di_light_candidate(const Scene& scene, const LightList& lights, SampledLight chosen, vec2 uv) {
  if (chosen.pmf <= 0.0f) return {};
  return {di_resolve(scene, lights, chosen.index, uv), di_light_pdf(lights, chosen)};
}

// Whether sample s stores its point (a triangle light's or a surface point): punctual lights store none.
inline bool di_stored_point(const LightList& lights, const DiSample& s) {
  return s.light < lights.triangle_count() || s.light == kSurfacePointSample;
}
// The light sample that sample s gives at point p (direction, distance, its point's normal and radiance):
// the stored point's, or for a punctual light the one `lights` places.
inline LightSample di_light_sample(const LightList& lights, const vec3& p, const DiSample& s) {
  return di_stored_point(lights, s) ? light_sample_towards(s.point, p) : lights.sample_punctual(s.light, p);
}

// The shadow ray from p (geometric normal ng), of a frame whose lights are `lights`, to sample s placed by them,
// where s contributes there (a positive target or contribution at p): shadow_ray of di_light_sample's sample. A
// stored point's ray is the segment to it, which needs neither the direction nor the distance: built straight
// from the point (di_light_sample's sample, a 64-byte struct, cost more than the segment).
inline Ray di_shadow_ray(const Tracer& tracer, const vec3& p, const vec3& ng, const LightList& lights,
                         const DiSample& s) {
  if (di_stored_point(lights, s)) return tracer.spawn_ray_to(p, ng, s.point.position, s.point.normal);
  return shadow_ray(tracer, p, ng, lights.sample_punctual(s.light, p));
}
// The same from a packed surface.
inline Ray di_shadow_ray(const Tracer& tracer, const PackedSurface& surface, const LightList& lights,
                         const DiSample& s) {
  return di_shadow_ray(tracer, surface.position, surface.geometric_n(), lights, s);
}

// The unshadowed contribution of a light sample to a G-buffer pixel, in area measure:
// f * L_e * |cos at the receiver| * |cos at the light| / d^2 (delta lights: f * I / d^2 * |cos|).
// Uses the sample's stored point, which must be placed with the receiver's lights.
struct DiContribution {
  vec3 value{0.0f};
  LightSample light;
};
DiContribution di_contribution(const DiReceiver& receiver, const DiSample& s);

// Target function p_hat: luminance of the unshadowed contribution.
inline float di_target(const DiContribution& c) { return luminance(c.value); }

// The light sample (light and uniforms) that LightList::sample maps to barycentric point b of triangle
// light `light`: the inverse of its uniform triangle mapping.
inline DiSample di_sample_at(const Scene& scene, const LightList& lights, uint32_t light, vec2 b) {
  float su = b.x + b.y;
  vec2 uv(std::min(su * su, 1.0f - 0x1p-24f), su > 0.0f ? std::min(b.y / su, 1.0f - 0x1p-24f) : 0.0f);
  return di_resolve(scene, lights, light, uv);
}

// A debug view of reservoirs: their confidence M, their contribution weight W, or the chosen light
// (a colour hashed from its index); black where there is no surface or no sample.
enum class DiAov : uint8_t { M, W, Light };
Image di_reservoir_image(const GBuffer& g, const std::vector<DiReservoir>& reservoirs, DiAov aov);

// A pixel's final shadow-ray verdict on its sample, handed to the next frame.
struct DiVisibility {
  uint32_t light = 0;
  vec2 uv{0.0f};
  bool valid = false;  // a verdict exists (false where nothing was traced)
  bool visible = false;
  uint8_t age = 0;  // frames this verdict has been reused
};

// Final visibility reuse: a pixel whose sample is the one its temporal history pixel shaded last frame
// takes that pixel's verdict instead of tracing, for at most max_age frames in a row. Biased where
// occluders move (their shadows lag up to max_age frames) and by the sub-pixel move of the surface point.
struct DiVisibilityReuse {
  int max_age = 0;                                      // 0: trace every pixel every frame
  const std::vector<int32_t>* history_pixel = nullptr;  // from temporal reuse (null: no history)
  const std::vector<DiVisibility>* previous = nullptr;  // last frame's verdicts
};

// Stage "di_shade": reads the G-buffer, reservoirs and the unsampled light of the candidates, adds
// f L_e G W of each pixel's sample, with the exact surface, into `sum`, plus, with `unsampled`, the
// emission seen and the unsampled light (ReSTIR GI passes none: emission seen is direct light); writes
// each pixel's verdict to `visibility`; a pixel whose estimate is not finite adds nothing and is counted
// in `non_finite`. With `further` samples (DiReuseParams::shaded_samples) each of the n samples' terms counts 1/n,
// and the further ones' verdicts are not kept; samples of a pixel that shade alike (same sample and W: the copies of
// a pixel without reuse, or picks of one input) are shaded once with their shares summed. One shadow ray per pixel and
// distinct sample (in packets of 16), except where the first sample's verdict is reused. With `simd`, the exact
// receivers (built once per pixel for all its samples) and contributions are evaluated in lanes (target_lanes.h; the
// scalar path, the reference, gives the same bits).
void di_shade(const SceneView& view, const GBuffer& g, const std::vector<DiReservoir>& reservoirs,
              const std::vector<std::vector<DiReservoir>>& further, const std::vector<vec3>* unsampled,
              const DiVisibilityReuse& reuse, bool simd, std::vector<DiVisibility>& visibility, Image& sum,
              RayCounter& rays, Counter& non_finite);

}  // namespace candela

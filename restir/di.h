#pragma once
// ReSTIR DI (Bitterli et al. 2020, section 3 and Alg. 3): its parameters and light samples (the candidate stage that
// fills the reservoirs is in di_candidates.h; the sample type, receivers and target function it shares with ReSTIR GI
// are in sample.h, the reuse stages in reuse.h, the shading in shade.h). Samples live in the lights' area measure (a
// light index and the two uniforms that place the point on it), so that a reservoir's contribution weight W stays valid
// when the sample is reused at another pixel or frame; light indices are stable for a scene's lifetime (LightList keeps
// one per emitting triangle of each instance and per punctual light), so a sample's identity needs no remap between
// frames, and a light that moved, dimmed or went dark is simply re-evaluated where it is now.
#include <vector>

#include "engine/image.h"
#include "restir/sample.h"

namespace candela {

struct DiParams {
  // M_l: candidates per pixel from the light sampler (cost: M_l light samples + BSDF evaluations); 4 beat 8 at
  // equal time on manylights, city and occluded_room (docs/restir.md, "Spatial neighbours and light candidates")
  int light_candidates = 4;
  // M_l for the pixels whose temporal history was found (find_history_pixels), at most light_candidates: their
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

// The sample (light, uv) with its point placed by `lights` (punctual lights have no point to store), written into
// `out` field by field: every caller keeps it inside a reservoir, a tile entry or a batch, and a returned sample
// assigned there was copied with wide loads of narrower stores, which stalled on store forwarding.
inline void di_resolve(const Scene& scene, const LightList& lights, uint32_t light, vec2 uv, ReuseSample& out) {
  out.light = light, out.uv = uv, out.age = 0;
  if (light < lights.triangle_count())
    lights.triangle_point(scene, light, uv, out.point);
  else
    out.point = LightPoint{};
}

// Density of a fresh light sample over its light's area given the light was chosen (1 for delta lights).
inline float di_area_pdf(const LightList& lights, uint32_t light) {
  return light < lights.triangle_count() ? 1.0f / lights.triangles()[light].area : 1.0f;
}

// A light candidate: the sample that uv places on the chosen light, and the area density it was drawn
// with, pmf / area (pmf for delta lights; 0: no light chosen, and no sample).
struct DiLightCandidate {
  ReuseSample sample;
  float p_light = 0.0f;
};
// The area density of a chosen light's sample: pmf / area (pmf for delta lights; 0: no light chosen).
inline float di_light_pdf(const LightList& lights, SampledLight chosen) {
  return chosen.pmf > 0.0f ? chosen.pmf * di_area_pdf(lights, chosen.index) : 0.0f;
}
// The candidate that uv gives on the chosen light, into `out` (field by field, as di_resolve writes).
inline void di_light_candidate(const Scene& scene, const LightList& lights, SampledLight chosen, vec2 uv,
                               DiLightCandidate& out) {
  if (chosen.pmf <= 0.0f) {
    out = DiLightCandidate{};
    return;
  }
  di_resolve(scene, lights, chosen.index, uv, out.sample);
  out.p_light = di_light_pdf(lights, chosen);
}

// The light sample (light and uniforms) that LightList::sample maps to barycentric point b of triangle
// light `light`: the inverse of its uniform triangle mapping. Into `out`, as di_resolve writes.
inline void di_sample_at(const Scene& scene, const LightList& lights, uint32_t light, vec2 b, ReuseSample& out) {
  float su = b.x + b.y;
  vec2 uv(std::min(su * su, 1.0f - 0x1p-24f), su > 0.0f ? std::min(b.y / su, 1.0f - 0x1p-24f) : 0.0f);
  di_resolve(scene, lights, light, uv, out);
}

// A debug view of reservoirs: their confidence M, their contribution weight W, or the chosen light
// (a colour hashed from its index); black where there is no surface or no sample.
enum class DiAov : uint8_t { M, W, Light };
Image di_reservoir_image(const GBuffer& g, const std::vector<ReuseReservoir>& reservoirs, DiAov aov);

}  // namespace candela

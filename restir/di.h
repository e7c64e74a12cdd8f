#pragma once
// ReSTIR DI, first stages (Bitterli et al. 2020, section 3 and Alg. 3): per pixel, resampled importance
// sampling of light samples into a reservoir, then shading with one shadow ray. Samples live in the
// lights' area measure (a light index and the two uniforms that place the point on it), so that a
// reservoir's contribution weight W stays valid when the sample is reused at another pixel (the reuse
// stages come next: temporal and spatial reuse, bias correction).
#include <vector>

#include "engine/gbuffer.h"
#include "engine/image.h"
#include "engine/path_tracer.h"
#include "restir/reservoir.h"

namespace candela {

// A point on a light: which light, and the uniforms LightList::sample maps to the point.
struct DiSample {
  uint32_t light = 0;
  vec2 uv{0.0f};
};
using DiReservoir = Reservoir<DiSample>;

struct DiParams {
  int light_candidates = 8;      // M: candidates per pixel from the light sampler (cost: M light samples + M BSDF evaluations)
  bool candidate_visibility = false;  // trace a shadow ray to the chosen candidate and drop it if occluded (1 ray per pixel)
  uint64_t seed = 0;
};

// Where targets are evaluated: a frame's G-buffer and the eye it was seen from (this frame's, or the
// previous frame's for temporal reuse).
struct DiDomain {
  const GBuffer& g;
  vec3 eye;
};

// A G-buffer pixel seen as a receiver of light: built once per pixel, then evaluated against many samples.
struct DiReceiver {
  vec3 position, geometric_normal, shading_normal, wo;
  Bsdf bsdf;
};
inline DiReceiver di_receiver(const DiDomain& domain, size_t i) {
  const GBuffer& g = domain.g;
  return {g.position[i], g.geometric_normal[i], g.shading_normal[i], glm::normalize(domain.eye - g.position[i]), g.bsdf(i)};
}

// The unshadowed contribution of a light sample to a G-buffer pixel, in area measure:
// f * L_e * |cos at the receiver| * |cos at the light| / d^2 (delta lights: f * I / d^2 * |cos|).
struct DiContribution {
  vec3 value{0.0f};
  LightSample light;
  float area_pdf = 0.0f;  // density of the light sample over the light's area (1 for delta lights)
};
DiContribution di_contribution(const SceneView& view, const DiReceiver& receiver, const DiSample& s);

// Target function p_hat: luminance of the unshadowed contribution.
inline float di_target(const DiContribution& c) { return luminance(c.value); }

// Whether the shadow ray from pixel i to the light sample is blocked.
bool di_occluded(const SceneView& view, const GBuffer& g, size_t pixel, const LightSample& light);

// Stage "di_candidates": reads the G-buffer, writes one reservoir per pixel from M light candidates
// (m_i = 1/M, W_i = 1 / (pmf * area pdf)). Cost per pixel: M light samples and BSDF evaluations, plus
// one shadow ray with candidate_visibility.
template <LightSampler S>
void di_initial_candidates(const SceneView& view, const S& sampler, const GBuffer& g, const DiParams& params, int frame,
                           std::vector<DiReservoir>& out, RayCounter& rays) {
  out.assign(g.size(), DiReservoir{});
  const DiDomain domain{g, view.camera.position()};
  for_each_pixel(g.width, g.height, rays, [&](size_t i, int, int) -> uint64_t {
    if (!g.hit(i)) return 0;
    Rng rng = Rng::for_key(params.seed, i, uint64_t(frame), 0xd1);
    ShadingContext ctx{g.position[i], g.shading_normal[i]};
    const DiReceiver receiver = di_receiver(domain, i);
    DiReservoir& r = out[i];
    const float M = float(params.light_candidates);
    for (int k = 0; k < params.light_candidates; ++k) {
      SampledLight chosen = sampler.sample(ctx, vec2(rng.next_float(), rng.next_float()));
      DiSample s{chosen.index, vec2(rng.next_float(), rng.next_float())};
      float u = rng.next_float();
      if (chosen.pmf <= 0.0f) continue;
      DiContribution c = di_contribution(view, receiver, s);
      float p_hat = di_target(c);
      if (p_hat <= 0.0f) continue;
      r.update(s, p_hat / (M * chosen.pmf * c.area_pdf), p_hat, u);
    }
    r.M = M;
    r.finalize();
    if (!params.candidate_visibility || r.W <= 0.0f) return 0;
    if (di_occluded(view, g, i, di_contribution(view, receiver, r.y).light)) r.W = 0.0f;
    return 1;
  });
}

// A debug view of reservoirs: their confidence M, their contribution weight W, or the chosen light
// (a colour hashed from its index); black where there is no surface or no sample.
enum class DiAov : uint8_t { M, W, Light };
Image di_reservoir_image(const GBuffer& g, const std::vector<DiReservoir>& reservoirs, DiAov aov);

// Stage "di_shade": reads the G-buffer and reservoirs, adds emission seen plus f L_e G W of each
// pixel's sample (one shadow ray per pixel with a sample) into `sum`.
void di_shade(const SceneView& view, const GBuffer& g, const std::vector<DiReservoir>& reservoirs, Image& sum,
              RayCounter& rays);

}  // namespace candela

#pragma once
// The contract between estimators and light-selection policies (which live in samplers/): given a shading
// point and two independent uniforms, pick a light index with a probability, and report that probability
// for any index. Two uniforms, because one float has 24 bits: splitting it between choosing among 1e5
// lights and a second decision (alias or bin, left or right child) leaves too few bits for the second. Estimators
// take the policy as a template parameter constrained by this concept, so engine/ stays policy-free.
#include <concepts>
#include <cstdint>

#include "engine/math.h"

namespace candela {

// Where light is received: a point, or a region (radius > 0: any point within radius of `position`, of any
// orientation, for choices shared by many receivers such as the light tiles of a screen block).
struct ShadingContext {
  vec3 position{0.0f};
  vec3 normal{0.0f};  // zero when unknown (a point in a medium, a region)
  float radius = 0.0f;
};

struct SampledLight {
  uint32_t index = 0;
  float pmf = 0.0f;  // zero: no light could be chosen
};

template <class S>
concept LightSampler = requires(const S& s, const ShadingContext& ctx, vec2 u, uint32_t index) {
  { s.sample(ctx, u) } -> std::same_as<SampledLight>;
  { s.pmf(ctx, index) } -> std::convertible_to<float>;
};

// n lights for one shading point: out[k] = sampler.sample(ctx, u[k]), through the sampler's sample_many
// where it has one (the light tree shares the work of the upper levels between the descents).
template <LightSampler S>
void sample_lights(const S& sampler, const ShadingContext& ctx, const vec2* u, SampledLight* out, int n) {
  if constexpr (requires { sampler.sample_many(ctx, u, out, n); })
    sampler.sample_many(ctx, u, out, n);
  else
    for (int k = 0; k < n; ++k) out[k] = sampler.sample(ctx, u[k]);
}

// Starts loading what sample(ctx, u[k]) of n lights will read, where the sampler can say (prefetch(ctx, u)):
// a caller that draws for many shading points issues these for all of them first, so that their cache misses
// overlap instead of stalling each draw in turn.
template <LightSampler S>
void prefetch_lights(const S& sampler, const ShadingContext& ctx, const vec2* u, int n) {
  if constexpr (requires { sampler.prefetch(ctx, *u); })
    for (int k = 0; k < n; ++k) sampler.prefetch(ctx, u[k]);
}

}  // namespace candela

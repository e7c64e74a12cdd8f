#pragma once
// A pixel's BSDF-sampled ray from its G-buffer surface, drawn and traced once per frame for both chains: ReSTIR DI's
// first BSDF candidate, which ReSTIR GI then takes as its path's first ray (GiParams::share_bsdf_ray). Both
// estimators draw that direction from the same BSDF at the same surface, so each stays unbiased; the pair is
// correlated (one direction serves both), which changes the variance of their sum, not its mean.
#include "engine/tracer.h"

namespace candela {

struct BsdfRay {
  vec3 wi{0.0f};
  float pdf = 0.0f;  // the direction's solid-angle density; 0: no ray (no hit, or no direction accepted)
  Hit hit;           // what the ray hit (where pdf > 0)
};

}  // namespace candela

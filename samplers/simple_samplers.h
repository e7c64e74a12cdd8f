#pragma once
// Context-free light selection: uniform over lights, and proportional to power with Walker's alias
// method (Walker 1977; Vose 1991 for the numerically stable construction), O(1) per sample.
// Both pick among at most 2^24 lights (u.x has 24 random bits); the constructors refuse more.
#include <vector>

#include "engine/light_sampler.h"
#include "engine/lights.h"

namespace candela {

class UniformLightSampler {
 public:
  explicit UniformLightSampler(const LightList& lights);
  SampledLight sample(const ShadingContext&, vec2 u) const {
    if (count_ == 0) return {};
    return {std::min(uint32_t(double(u.x) * count_), count_ - 1), 1.0f / float(count_)};
  }
  float pmf(const ShadingContext&, uint32_t) const { return count_ ? 1.0f / float(count_) : 0.0f; }

 private:
  uint32_t count_;
};

class PowerLightSampler {
 public:
  explicit PowerLightSampler(const LightList& lights);
  SampledLight sample(const ShadingContext&, vec2 u) const;
  float pmf(const ShadingContext&, uint32_t index) const { return pmf_.empty() ? 0.0f : pmf_[index]; }

 private:
  struct Bin {
    float threshold;  // keep the bin's own index when the in-bin uniform is below this
    uint32_t alias;
  };
  std::vector<Bin> bins_;
  std::vector<float> pmf_;
};

static_assert(LightSampler<UniformLightSampler>);
static_assert(LightSampler<PowerLightSampler>);

}  // namespace candela

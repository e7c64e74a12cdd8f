#pragma once
// Context-free light selection: uniform over lights, and proportional to power with Walker's alias
// method (Walker 1977; Vose 1991 for the numerically stable construction), O(1) per sample.
// Both pick among at most 2^24 lights (u.x has 24 random bits); the constructors refuse more.
#include <bit>
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
  // u.x picks the bin, u.y decides between the bin and its alias, without a branch: the choice is a coin flip
  // per sample, and the mispredicted branch cost about half of a sample in the profile.
  SampledLight sample(const ShadingContext&, vec2 u) const {
    if (bins_.empty()) return {};
    const uint32_t bin = bin_of(u);
    const Bin& b = bins_[bin];
    const uint32_t keep = 0u - uint32_t(u.y < b.threshold);
    const uint32_t pmf = (std::bit_cast<uint32_t>(b.pmf) & keep) | (std::bit_cast<uint32_t>(b.alias_pmf) & ~keep);
    return {(bin & keep) | (b.alias & ~keep), std::bit_cast<float>(pmf)};
  }
  float pmf(const ShadingContext&, uint32_t index) const { return pmf_.empty() ? 0.0f : pmf_[index]; }
  // Starts loading the bin that sample(ctx, u) will read, u in [0, 1) (prefetch_lights in
  // engine/light_sampler.h). Unclamped and unconditional: a prefetch never faults, and GCC 12 dropped it
  // behind the clamp's select or an emptiness test (checked in the disassembly).
  void prefetch(const ShadingContext&, vec2 u) const {
    __builtin_prefetch(bins_.data() + uint32_t(double(u.x) * double(bins_.size())));
  }

 private:
  // One bin of the alias table, with both lights' probabilities, so that a sample reads one 16-byte entry
  // (with 1e5 lights, the table and a separate pmf array were two cache misses per sample).
  struct Bin {
    float threshold;  // keep the bin's own index when the in-bin uniform is below this
    uint32_t alias;
    float pmf, alias_pmf;  // of the bin's own light and of its alias
  };
  uint32_t bin_of(vec2 u) const { return std::min(uint32_t(double(u.x) * bins_.size()), uint32_t(bins_.size() - 1)); }
  std::vector<Bin> bins_;
  std::vector<float> pmf_;
};

static_assert(LightSampler<UniformLightSampler>);
static_assert(LightSampler<PowerLightSampler>);

}  // namespace candela

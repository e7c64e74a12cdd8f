#include "samplers/simple_samplers.h"

#include "engine/check.h"

namespace candela {

// Vose's construction: split bins into under- and over-full, pair each under-full bin with an over-full alias.
PowerLightSampler::PowerLightSampler(const LightList& lights) {
  size_t n = lights.size();
  if (n == 0) return;
  std::vector<double> w(n);
  double total = 0.0;
  for (size_t i = 0; i < n; ++i) total += w[i] = std::max(0.0f, lights.power(i));
  if (total <= 0.0) { std::fill(w.begin(), w.end(), 1.0); total = double(n); }
  pmf_.resize(n);
  bins_.resize(n);
  std::vector<double> scaled(n);
  std::vector<uint32_t> small, large;
  for (size_t i = 0; i < n; ++i) {
    pmf_[i] = float(w[i] / total);
    scaled[i] = w[i] / total * double(n);
    (scaled[i] < 1.0 ? small : large).push_back(uint32_t(i));
  }
  while (!small.empty() && !large.empty()) {
    uint32_t s = small.back(), l = large.back();
    small.pop_back();
    bins_[s] = {float(scaled[s]), l};
    scaled[l] -= 1.0 - scaled[s];
    if (scaled[l] < 1.0) { large.pop_back(); small.push_back(l); }
  }
  for (uint32_t i : large) bins_[i] = {1.0f, i};
  for (uint32_t i : small) bins_[i] = {1.0f, i};  // round-off leftovers
}

SampledLight PowerLightSampler::sample(const ShadingContext&, float u) const {
  if (bins_.empty()) return {};
  float x = u * float(bins_.size());
  uint32_t bin = std::min(uint32_t(x), uint32_t(bins_.size() - 1));
  float frac = x - float(bin);
  uint32_t index = frac < bins_[bin].threshold ? bin : bins_[bin].alias;
  return {index, pmf_[index]};
}

}  // namespace candela

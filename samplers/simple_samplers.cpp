#include "samplers/simple_samplers.h"

#include <bit>

#include "engine/check.h"

namespace candela {

static constexpr size_t kMaxLights = size_t(1) << 24;

static void check_light_count(size_t n) {
  if (n > kMaxLights)
    throw InputError("the scene has " + std::to_string(n) +
                     " lights; uniform and power light selection support at most 16777216");
}

UniformLightSampler::UniformLightSampler(const LightList& lights) : count_(uint32_t(lights.size())) {
  check_light_count(lights.size());
}

// Vose's construction: split bins into under- and over-full, pair each under-full bin with an over-full alias.
PowerLightSampler::PowerLightSampler(const LightList& lights) {
  size_t n = lights.size();
  check_light_count(n);
  if (n == 0) return;
  std::vector<double> w(n);
  double total = 0.0;
  for (size_t i = 0; i < n; ++i) total += w[i] = std::max(0.0f, lights.power(i));
  if (total <= 0.0) {
    std::fill(w.begin(), w.end(), 1.0);
    total = double(n);
  }
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
    if (scaled[l] < 1.0) {
      large.pop_back();
      small.push_back(l);
    }
  }
  for (uint32_t i : large) bins_[i] = {1.0f, i};
  for (uint32_t i : small) bins_[i] = {1.0f, i};  // round-off leftovers
  for (uint32_t i = 0; i < n; ++i) bins_[i].pmf = pmf_[i], bins_[i].alias_pmf = pmf_[bins_[i].alias];
}

}  // namespace candela

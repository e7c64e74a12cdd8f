// Light selection: the frequencies with which a sampler picks lights match the pmf it reports, also with
// many lights (where one 24-bit uniform would not be enough for both the bin and the alias decision).
#include <gtest/gtest.h>

#include <algorithm>
#include <map>

#include "engine/builtin_scenes.h"
#include "engine/rng.h"
#include "samplers/simple_samplers.h"
#include "tests/test_util.h"

namespace candela {
namespace {

// Grouped chi-square: lights are grouped by pmf in quarter octaves (log2(pmf) * 4) and by index in 64
// blocks, so that every group expects many samples even when single lights expect less than one, and an
// error that depends on how bright a light is (as precision loss does) or where it is in the list is
// concentrated in its group. Significance 1e-3, fixed seed.
template <class Sampler>
void expect_frequencies_match_pmf(const LightList& lights, int samples) {
  Sampler sampler(lights);
  ShadingContext ctx;
  size_t n = lights.size();
  std::vector<int> group_of(n);
  std::map<int, int> group_index;
  std::vector<double> expected, observed;
  double pmf_sum = 0.0;
  for (uint32_t i = 0; i < n; ++i) {
    double p = sampler.pmf(ctx, i);
    int key = (p > 0.0 ? int(std::floor(std::log2(p) * 4.0)) : -100000) * 64 + int(uint64_t(i) * 64 / n);
    auto [it, inserted] = group_index.emplace(key, int(expected.size()));
    if (inserted) { expected.push_back(0.0); observed.push_back(0.0); }
    group_of[i] = it->second;
    expected[it->second] += p * samples;
    pmf_sum += p;
  }
  const int groups = int(expected.size());
  EXPECT_NEAR(pmf_sum, 1.0, 1e-4);
  Rng rng(17, 3);
  for (int k = 0; k < samples; ++k) {
    SampledLight s = sampler.sample(ctx, vec2(rng.next_float(), rng.next_float()));
    ASSERT_LT(s.index, n);
    ASSERT_EQ(s.pmf, sampler.pmf(ctx, s.index));
    observed[group_of[s.index]] += 1.0;
  }
  double chi2 = 0.0;
  int bins = 0;
  for (int g = 0; g < groups; ++g) {
    if (expected[g] < 5.0) continue;
    chi2 += (observed[g] - expected[g]) * (observed[g] - expected[g]) / expected[g];
    ++bins;
  }
  EXPECT_GT(testing::chi_square_p_value(chi2, bins - 1), 1e-3) << "chi2 " << chi2 << " over " << bins << " groups";
}

TEST(Samplers, PowerFrequenciesMatchPmfWithFewLights) {
  LightList lights(make_manylights_scene(64, 7));
  expect_frequencies_match_pmf<PowerLightSampler>(lights, 400000);
}

// 200k emissive triangles whose powers span three decades.
TEST(Samplers, PowerFrequenciesMatchPmfWithManyLights) {
  LightList lights(make_manylights_scene(100000, 7));
  expect_frequencies_match_pmf<PowerLightSampler>(lights, 10000000);
}

TEST(Samplers, UniformFrequenciesMatchPmfWithManyLights) {
  LightList lights(make_manylights_scene(100000, 7));
  expect_frequencies_match_pmf<UniformLightSampler>(lights, 2000000);
}

}  // namespace
}  // namespace candela

// Light selection: the frequencies with which a sampler picks lights match the pmf it reports, also with
// many lights (where one 24-bit uniform would not be enough for both the bin and the alias decision).
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>

#include "engine/builtin_scenes.h"
#include "engine/rng.h"
#include "samplers/simple_samplers.h"
#include "tests/test_util.h"

namespace candela {
namespace {

// Grouped chi-square: lights sorted by pmf are cut into groups of about equal probability, so that every
// group expects many samples even when single lights expect less than one. Significance 1e-3, fixed seed.
template <class Sampler>
void expect_frequencies_match_pmf(const LightList& lights, int groups, int samples) {
  Sampler sampler(lights);
  ShadingContext ctx;
  size_t n = lights.size();
  std::vector<uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t b) { return sampler.pmf(ctx, a) < sampler.pmf(ctx, b); });
  std::vector<int> group_of(n);
  std::vector<double> expected(groups, 0.0), observed(groups, 0.0);
  double cumulative = 0.0, pmf_sum = 0.0;
  for (uint32_t i : order) {
    double p = sampler.pmf(ctx, i);
    int g = std::min(groups - 1, int(cumulative * groups));
    group_of[i] = g;
    expected[g] += p * samples;
    cumulative += p;
    pmf_sum += p;
  }
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
  expect_frequencies_match_pmf<PowerLightSampler>(lights, 32, 400000);
}

// 200k emissive triangles whose powers span three decades.
TEST(Samplers, PowerFrequenciesMatchPmfWithManyLights) {
  LightList lights(make_manylights_scene(100000, 7));
  expect_frequencies_match_pmf<PowerLightSampler>(lights, 200, 2000000);
}

TEST(Samplers, UniformFrequenciesMatchPmfWithManyLights) {
  LightList lights(make_manylights_scene(100000, 7));
  expect_frequencies_match_pmf<UniformLightSampler>(lights, 200, 2000000);
}

}  // namespace
}  // namespace candela

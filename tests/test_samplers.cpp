// Light selection: the frequencies with which a sampler picks lights match the pmf it reports, also with
// many lights (where one 24-bit uniform would not be enough for both the bin and the alias decision); the
// light tree's SIMD importance equals the scalar one.
#include <gtest/gtest.h>

#include <algorithm>
#include <map>

#include "apps/scene_source.h"
#include "engine/builtin_scenes.h"
#include "engine/rng.h"
#include "engine/simd_targets.h"
#include "restir/light_tiles.h"
#include "samplers/light_tree.h"
#include "samplers/simple_samplers.h"
#include "samplers/wide_importance.h"
#include "tests/light_reach.h"
#include "tests/test_util.h"

namespace candela {
namespace {

// Grouped chi-square: lights are grouped by pmf in quarter octaves (log2(pmf) * 4) and by index in 64
// blocks, so that every group expects many samples even when single lights expect less than one, and an
// error that depends on how bright a light is (as precision loss does) or where it is in the list is
// concentrated in its group. Significance 1e-3, fixed seed.
template <class Sampler>
void expect_frequencies_match_pmf(const Sampler& sampler, const LightList& lights, const ShadingContext& ctx,
                                  int samples, uint64_t seed = 17) {
  size_t n = lights.size();
  std::vector<int> group_of(n);
  std::map<int, int> group_index;
  std::vector<double> expected, observed;
  double pmf_sum = 0.0;
  for (uint32_t i = 0; i < n; ++i) {
    double p = sampler.pmf(ctx, i);
    int key = (p > 0.0 ? int(std::floor(std::log2(p) * 4.0)) : -100000) * 64 + int(uint64_t(i) * 64 / n);
    auto [it, inserted] = group_index.emplace(key, int(expected.size()));
    if (inserted) {
      expected.push_back(0.0);
      observed.push_back(0.0);
    }
    group_of[i] = it->second;
    expected[it->second] += p * samples;
    pmf_sum += p;
  }
  const int groups = int(expected.size());
  EXPECT_NEAR(pmf_sum, 1.0, 1e-4);
  Rng rng(seed, 3);
  for (int k = 0; k < samples; ++k) {
    SampledLight s = sampler.sample(ctx, vec2(rng.next_float(), rng.next_float()));
    ASSERT_LT(s.index, n);
    ASSERT_GT(s.pmf, 0.0f);
    ASSERT_EQ(s.pmf, sampler.pmf(ctx, s.index));
    observed[group_of[s.index]] += 1.0;
  }
  // Groups expecting fewer than 5 samples are pooled into one (so samples landing there still count).
  double chi2 = 0.0, pooled_expected = 0.0, pooled_observed = 0.0;
  int bins = 0;
  for (int g = 0; g < groups; ++g) {
    if (expected[g] < 5.0) {
      pooled_expected += expected[g];
      pooled_observed += observed[g];
      continue;
    }
    chi2 += (observed[g] - expected[g]) * (observed[g] - expected[g]) / expected[g];
    ++bins;
  }
  if (pooled_expected >= 5.0) {
    chi2 += (pooled_observed - pooled_expected) * (pooled_observed - pooled_expected) / pooled_expected;
    ++bins;
  } else {
    EXPECT_LE(pooled_observed, 20.0) << "samples on lights whose pmf says they are (almost) never chosen";
  }
  EXPECT_GT(testing::chi_square_p_value(chi2, bins - 1), 1e-3) << "chi2 " << chi2 << " over " << bins << " groups";
}

TEST(Samplers, PowerFrequenciesMatchPmfWithFewLights) {
  LightList lights(make_manylights_scene(64, 7));
  expect_frequencies_match_pmf(PowerLightSampler(lights), lights, ShadingContext{}, 400000);
}

// 200k emissive triangles whose powers span three decades.
TEST(Samplers, PowerFrequenciesMatchPmfWithManyLights) {
  LightList lights(make_manylights_scene(100000, 7));
  expect_frequencies_match_pmf(PowerLightSampler(lights), lights, ShadingContext{}, 10000000);
}

TEST(Samplers, UniformFrequenciesMatchPmfWithManyLights) {
  LightList lights(make_manylights_scene(100000, 7));
  expect_frequencies_match_pmf(UniformLightSampler(lights), lights, ShadingContext{}, 2000000);
}

// Shading points spread through a scene: positions in its bounds, random normals.
std::vector<ShadingContext> shading_points(const Scene& scene, int count, uint64_t seed) {
  Bounds3 b = scene.bounds();
  Rng rng(seed, 5);
  std::vector<ShadingContext> points;
  for (int k = 0; k < count; ++k) {
    vec3 p = b.lo + (b.hi - b.lo) * vec3(rng.next_float(), rng.next_float(), rng.next_float());
    vec3 n = glm::normalize(vec3(rng.next_float() - 0.5f, rng.next_float() - 0.5f, rng.next_float() - 0.5f));
    points.push_back({p, n});
  }
  return points;
}

// At each shading point: frequencies match pmf (grouped chi-square at 1e-3 per point), pmf sums to 1
// wherever a light can reach, and sample() reports exactly pmf().
template <class Sampler>
void check_sampler_at(const Sampler& sampler, const LightList& lights, const std::vector<ShadingContext>& points,
                      int samples) {
  int k = 0;
  for (const ShadingContext& ctx : points) {
    double sum = 0.0;
    for (uint32_t i = 0; i < lights.size(); ++i) sum += sampler.pmf(ctx, i);
    if (sum == 0.0) continue;  // e.g. behind every emitter: no light can contribute
    EXPECT_NEAR(sum, 1.0, 1e-4) << "shading point " << k;
    expect_frequencies_match_pmf(sampler, lights, ctx, samples, 100 + k++);
  }
  EXPECT_GT(k, int(points.size()) / 2);
}

// The context-dependent samplers at shading points spread through a scene.
template <class Sampler>
void check_context_sampler(const Scene& scene, int points, int samples) {
  LightList lights(scene);
  check_sampler_at(Sampler(lights), lights, shading_points(scene, points, 23), samples);
}

// The cars of builtin:city move with their head- and tail-light triangles and spot lights: after a refit
// the tree still matches its pmf and drops no light that can reach receivers around the cars.
TEST(Samplers, TreeAfterRefitFollowsMovingLights) {
  Scene scene = make_city_scene(7);
  LightList lights(scene);
  LightTreeSampler tree(lights);
  scene.set_time(3.0f);
  lights.update(scene);
  tree.refit(lights);
  Rng rng(8, 8);
  std::vector<ShadingContext> points;
  for (size_t i = 0; i < scene.instances.size() && points.size() < 8; i += 9) {
    if (!scene.instances[i].animated) continue;
    vec3 car = vec3(scene.instances[i].transform[3]);
    vec3 p = car + vec3(rng.next_float() * 8.0f - 4.0f, 0.05f + rng.next_float(), rng.next_float() * 8.0f - 4.0f);
    points.push_back({p, glm::normalize(vec3(rng.next_float() - 0.5f, 0.5f, rng.next_float() - 0.5f))});
  }
  ASSERT_EQ(points.size(), 8u);
  EXPECT_GT(testing::expect_no_dropped_lights(tree, lights, points), 1000u);
  check_sampler_at(tree, lights, std::vector<ShadingContext>(points.begin(), points.begin() + 2), 200000);
}

// A refit after the first visits only the paths above the cars' lights (LightList::movable); the tree it gives
// equals one whose only refit saw the same placement: every pmf the same to the bit at points around the cars
// and through the city, the samples too. Fails if a moving light's path were left stale.
TEST(Samplers, TreeLaterRefitsEqualAWholeOne) {
  Scene scene = make_city_scene(7);
  LightList lights(scene);
  LightTreeSampler twice(lights), once(lights);
  scene.set_time(1.0f);
  lights.update(scene);
  twice.refit(lights);
  scene.set_time(3.0f);
  lights.update(scene);
  twice.refit(lights);
  once.refit(lights);
  std::vector<ShadingContext> points = shading_points(scene, 3, 29);
  for (size_t i = 0; i < scene.instances.size() && points.size() < 6; i += 9)
    if (scene.instances[i].animated)
      points.push_back({vec3(scene.instances[i].transform[3]) + vec3(1.0f, 0.3f, 2.0f), vec3(0.0f, 1.0f, 0.0f)});
  ASSERT_EQ(points.size(), 6u);
  Rng rng(9, 9);
  for (size_t k = 0; k < points.size(); ++k) {
    size_t differ = 0;
    for (uint32_t i = 0; i < lights.size(); ++i) differ += twice.pmf(points[k], i) != once.pmf(points[k], i);
    EXPECT_EQ(differ, 0u) << "point " << k;
    for (int s = 0; s < 64; ++s) {
      const vec2 u(rng.next_float(), rng.next_float());
      const SampledLight a = twice.sample(points[k], u), b = once.sample(points[k], u);
      EXPECT_TRUE(a.index == b.index && a.pmf == b.pmf) << "point " << k << " sample " << s;
    }
  }
}

// One ceiling light of a 20 m room flies 200 km away: its ancestors' spheres outgrow the half-precision radii
// at the scale the build chose (WideBounds), so the refit rebuilds the tree, which keeps every light, the far
// one included. Fails if the refit left the slots that no longer fit empty.
TEST(Samplers, TreeRefitRebuildsWhenALightFliesOutOfRange) {
  Scene scene = make_manylights_scene(64, 7);
  int moved = -1;
  for (size_t k = 0; k < scene.instances.size() && moved < 0; ++k)
    if (scene.material_of(uint32_t(k)).emissive()) moved = int(k);
  ASSERT_GE(moved, 0);
  scene.instances[moved].animated = true;
  scene.motions.push_back({moved, scene.instances[moved].transform, vec3(2e5f, 0.0f, 0.0f), 1e6f, 0.0f});
  LightList lights(scene);
  LightTreeSampler tree(lights);
  scene.set_time(1.0f);
  lights.update(scene);
  tree.refit(lights);
  std::vector<ShadingContext> points = {{vec3(0.0f, 1.0f, 0.0f), vec3(0.0f, 1.0f, 0.0f)},
                                        {vec3(-6.0f, 0.5f, 4.0f), vec3(0.0f, 1.0f, 0.0f)}};
  for (const TriangleLight& t : lights.triangles())
    if (int(t.instance) == moved) points.push_back({t.p0 + vec3(0.1f, -1.0f, 0.1f), vec3(0.0f, 1.0f, 0.0f)});
  ASSERT_GT(points.size(), 2u);
  EXPECT_GT(testing::expect_no_dropped_lights(tree, lights, points), 100u);
  check_sampler_at(tree, lights, points, 100000);
}

TEST(Samplers, TreeFrequenciesMatchPmf) {
  check_context_sampler<LightTreeSampler>(make_manylights_scene(256, 7), 12, 200000);
}

// Regions (ShadingContext::radius: the light tiles of a screen block) spread through a scene, 0.05-2 m.
std::vector<ShadingContext> regions(const Scene& scene, int count, uint64_t seed) {
  std::vector<ShadingContext> out = shading_points(scene, count, seed);
  Rng rng(seed, 6);
  for (ShadingContext& c : out) c.normal = vec3(0.0f), c.radius = 0.05f + 1.95f * rng.next_float();
  return out;
}
TEST(Samplers, TreeFrequenciesMatchPmfForRegions) {
  const Scene scene = make_manylights_scene(256, 7);
  LightList lights(scene);
  check_sampler_at(LightTreeSampler(lights), lights, regions(scene, 6, 29), 200000);
}
// A region's pmf is positive for every light that can reach some receiver in it (16 points of any normal
// in each region). Fails if the tree ignores the region's radius (a point's importance at its centre).
TEST(Samplers, TreeRegionsKeepEveryLightTheirReceiversCanReach) {
  for (const Scene& scene : {make_manylights_scene(256, 7), make_city_scene(7)}) {
    LightList lights(scene);
    LightTreeSampler tree(lights);
    Rng rng(9, 9);
    auto signed_unit = [&] { return 2.0f * rng.next_float() - 1.0f; };
    size_t checked = 0;
    for (const ShadingContext& region : regions(scene, 8, 31)) {
      std::vector<ShadingContext> receivers;
      while (receivers.size() < 16) {
        const vec3 d(signed_unit(), signed_unit(), signed_unit()), n(signed_unit(), signed_unit(), signed_unit());
        if (glm::dot(d, d) <= 1.0f && glm::dot(n, n) > 1e-4f)
          receivers.push_back({region.position + d * region.radius, glm::normalize(n)});
      }
      checked += testing::expect_no_dropped_lights_in(tree, lights, region, receivers);
    }
    EXPECT_GT(checked, 1000u);
  }
}
TEST(Samplers, ExhaustiveFrequenciesMatchPmf) {
  check_context_sampler<ExhaustiveLightSampler>(make_manylights_scene(64, 7), 4, 50000);
}
// With a directional light beside the finite ones (chosen with its own probability).
Scene manylights_with_sun() {
  Scene s = make_manylights_scene(64, 7);
  PunctualLight sun;
  sun.type = PunctualType::Directional;
  sun.direction = glm::normalize(vec3(0.3f, -1.0f, 0.2f));
  sun.intensity = vec3(2.0f);
  s.punctual_lights.push_back(sun);
  return s;
}
TEST(Samplers, TreeFrequenciesMatchPmfWithADirectionalLight) {
  check_context_sampler<LightTreeSampler>(manylights_with_sun(), 4, 100000);
}
TEST(Samplers, ExhaustiveFrequenciesMatchPmfWithADirectionalLight) {
  check_context_sampler<ExhaustiveLightSampler>(manylights_with_sun(), 2, 20000);
}
// A real glTF scene: 13,902 textured emitting triangles of StainedGlassLamp (skipped without ../shared).
TEST(Samplers, TreeFrequenciesMatchPmfInStainedGlassLamp) {
  const std::string path = testing::shared_scene_file("StainedGlassLamp/glTF-JPG-PNG/StainedGlassLamp.gltf");
  if (path.empty()) GTEST_SKIP() << testing::shared_scenes_skip_reason();  // (a failure if only the file is missing)
  check_context_sampler<LightTreeSampler>(load_scene(path), 3, 200000);
}
TEST(Samplers, TreeFrequenciesMatchPmfInTheCity) {
  check_context_sampler<LightTreeSampler>(make_city_scene(7), 3, 200000);
}

// sample_many (one shading point, its descents sorted by uniform, each node's weights computed once) gives
// exactly what sample() gives for each uniform, in whatever order they come (random here; a light tile's come
// stratified), for 1 to 200 draws at a point of manylights with 4,096 lights, with a directional light beside
// the finite ones, and with 200,000 (100,000 quads; a tree of 7 levels, which sample_many walks level by level).
TEST(Samplers, TreeSampleManyEqualsSample) {
  for (const Scene& scene : {make_manylights_scene(2048, 7), manylights_with_sun(), make_manylights_scene(100000, 7)}) {
    LightList lights(scene);
    LightTreeSampler tree(lights);
    Rng rng(12, 3);
    int compared = 0;
    for (const ShadingContext& ctx : shading_points(scene, 16, 41)) {
      for (int n : {1, 8, 200}) {
        std::vector<vec2> u(static_cast<size_t>(n));
        for (vec2& v : u) v = vec2(rng.next_float(), rng.next_float());
        std::vector<SampledLight> many(static_cast<size_t>(n));
        tree.sample_many(ctx, u.data(), many.data(), n);
        for (int k = 0; k < n; ++k, ++compared) {
          const SampledLight one = tree.sample(ctx, u[size_t(k)]);
          ASSERT_EQ(many[size_t(k)].index, one.index) << "draw " << k << " of " << n;
          ASSERT_TRUE(testing::same_bits(many[size_t(k)].pmf, one.pmf)) << "draw " << k << " of " << n;
        }
      }
    }
    EXPECT_EQ(compared, 16 * 209);
  }
}

// A light tile's entries draw stratified uniforms: entry e of n lies in [e / n, (e + 1) / n] (its float rounding
// at most reaching the upper end), never 1, and in order of e, so that a tile's descents come sorted.
TEST(Samplers, TileStrataCoverTheUnitIntervalInOrder) {
  for (int n : {3, 128, 1024}) {
    float last = 0.0f;
    for (int e = 0; e < n; ++e)
      for (float x : {0.0f, 0.5f, 0x1.fffffep-1f}) {
        const float v = stratified_uniform(e, n, x);
        ASSERT_GE(v, float(double(e) / n)) << e << " of " << n;
        ASSERT_LE(v, float(double(e + 1) / n)) << e << " of " << n;
        ASSERT_LT(v, 1.0f);
        ASSERT_GE(v, last);
        last = v;
      }
  }
}

// The cone measure the tree's build weighs splits with (Conty Estevez & Kulla 2018, eq. 1):
// 2 pi times the integral of sin t over [0, theta_o] plus that of cos(t - theta_o) sin t over
// [theta_o, theta_w], theta_w = min(theta_o + theta_e, pi), integrated numerically in double (midpoint rule,
// 20,000 steps) against cone_measure, on its closed form without inverse trigonometry (theta_e = pi/2,
// theta_o <= pi/2) and on the general formula; bound: 1e-4 relative.
TEST(Samplers, ConeMeasureMatchesItsIntegral) {
  static constexpr double kPiDouble = 3.14159265358979323846;
  auto integral = [](double theta_o, double theta_e) {
    const double theta_w = std::min(theta_o + theta_e, kPiDouble);
    const int steps = 20000;
    double sum = 0.0;
    for (int i = 0; i < steps; ++i) {
      const double t = (i + 0.5) / steps;
      sum += std::sin(t * theta_o) * theta_o / steps;
      const double u = theta_o + t * (theta_w - theta_o);
      sum += std::cos(u - theta_o) * std::sin(u) * (theta_w - theta_o) / steps;
    }
    return 2.0 * kPiDouble * sum;
  };
  for (double theta_e : {kPiDouble / 2.0, 0.3, 1.2})
    for (double theta_o = 0.0; theta_o <= kPiDouble + 1e-9; theta_o += kPiDouble / 16.0) {
      const double expected = integral(theta_o, theta_e);
      // (theta_e = pi/2 as area lights give it: cosine exactly 0)
      const float cos_e = theta_e == kPiDouble / 2.0 ? 0.0f : float(std::cos(theta_e));
      const float measured = cone_measure(float(std::cos(theta_o)), cos_e);
      EXPECT_NEAR(measured, expected, 1e-4 * expected) << "theta_o " << theta_o << ", theta_e " << theta_e;
    }
}

// Uniform numbers and unit vectors from one stream, for the tests over random bounds below.
struct RandomNumbers {
  Rng rng;
  float uniform(float lo, float hi) { return lo + (hi - lo) * rng.next_float(); }
  vec3 unit() {
    vec3 v;
    do v = vec3(uniform(-1, 1), uniform(-1, 1), uniform(-1, 1));
    while (glm::dot(v, v) > 1.0f || glm::dot(v, v) < 1e-4f);
    return glm::normalize(v);
  }
};

// The tree's nodes round radii, cone axes and cosines (WideBounds::set); rounding must only loosen the
// bounds. Over random bounds (single directions and whole spheres, radii 0 and 1e-4 to 3 beside a largest
// radius of 16, near cut-offs) and random receivers: wherever the exact bounds give a positive importance, the
// rounded ones do too. Fails if the cone were not widened by the axis' rounding (or rounded to nearest).
TEST(Samplers, RoundedWideBoundsKeepEveryPositiveImportance) {
  RandomNumbers random{Rng(37, 4)};
  auto uniform = [&](float lo, float hi) { return random.uniform(lo, hi); };
  auto unit = [&] { return random.unit(); };
  int positive = 0, kept = 0;
  float worst = 0.0f;
  for (int trial = 0; trial < 200000; ++trial) {
    const float scale = radius_scale_for(16.0f);
    LightBounds b;
    b.center = vec3(uniform(-2, 2), uniform(-2, 2), uniform(-2, 2));
    b.radius = trial % 3 == 0 ? 0.0f : std::pow(10.0f, uniform(-4.0f, 0.5f));
    b.w = unit();
    b.phi = uniform(0.1f, 10.0f);
    b.set_cos_theta_o(trial % 4 == 0 ? 1.0f : std::cos(uniform(0.0f, 0.3f)));
    b.cos_theta_e = trial % 2 ? 0.0f : uniform(-0.5f, 0.9f);
    b.two_sided = trial % 5 == 0;
    WideBounds wide;
    ASSERT_TRUE(wide.set(0, b, scale));
    const LightBounds rounded = wide.get(0, scale);
    // Receivers near the cone's edge, where rounding decides: directions from the centre at angles around
    // theta_o + theta_e, at distances from inside the sphere to far away.
    const vec3 side = glm::normalize(glm::cross(b.w, std::abs(b.w.x) < 0.9f ? vec3(1, 0, 0) : vec3(0, 1, 0)));
    const float edge = std::acos(b.cos_theta_o) + std::acos(b.cos_theta_e) + uniform(-1e-4f, 1e-4f);
    const vec3 dir = b.w * std::cos(edge) + side * std::sin(edge);
    const float dist = b.radius > 0.0f ? std::pow(10.0f, uniform(-3.0f, 2.0f)) : 1.0f;
    const ShadingContext ctx{b.center + dir * dist, trial % 3 ? unit() : vec3(0.0f)};
    if (b.importance(ctx) <= 0.0f) continue;
    ++positive;
    kept += rounded.importance(ctx) > 0.0f;
    EXPECT_GT(rounded.importance(ctx), 0.0f) << "trial " << trial;
    if (::testing::Test::HasFailure()) break;
    // Away from the edge, rounding barely moves the importance: a receiver 0.3 radians outside theta_o
    // (inside theta_e), where the importance follows theta_o, at 1 + 4 radii.
    const float inside_angle = std::acos(b.cos_theta_o) + 0.3f;
    const vec3 inside_dir = b.w * std::cos(inside_angle) + side * std::sin(inside_angle);
    const ShadingContext inside{b.center + inside_dir * (1.0f + 4.0f * b.radius), vec3(0.0f)};
    if (b.importance(inside) > 0.0f)
      worst = std::max(worst, std::abs(rounded.importance(inside) / b.importance(inside) - 1.0f));
  }
  std::printf("  %d of %d positive importances kept; inside the cones, relative change at most %.2g\n", kept, positive,
              worst);
  EXPECT_GT(positive, 20000);
  // Radii round up by at most 2^-11 of themselves, axes by 3e-5 radians, cosines by 1 / 32767, which near
  // cos = 1 is an angle of up to sqrt(2 / 32767) = 0.008 radians (0.0024 here; widening theta_o by 0.01 in
  // its cosine gives 0.034).
  EXPECT_LT(worst, 5e-3f) << "the rounding should loosen the bounds, not change them";
}

// The light tree's 8-wide importance (samplers/wide_importance.h) repeats LightBounds::importance's
// operations in the same order without fused multiply-adds, so the bound is exact equality (0 ulp) on every
// instruction set, over random bounds: spheres of radius 0 to 4 (points inside some), cones from a single
// direction to the whole sphere, emission cut-offs, two-sided and powerless ones, receivers with and
// without a normal. A kernel that fused a multiply-add or reordered a sum fails here.
TEST(Samplers, WideImportanceGivesTheScalarBitsOnRandomBounds) {
  RandomNumbers random{Rng(31, 4)};
  auto uniform = [&](float lo, float hi) { return random.uniform(lo, hi); };
  auto unit = [&] { return random.unit(); };
  int compared = 0, positive = 0;
  std::string targets;
  for (int node = 0; node < 4000 && !::testing::Test::HasFailure(); ++node) {
    WideBounds wide;
    LightBounds scalar[kTreeWidth];
    const float scale = radius_scale_for(node % 2 ? 4.0f : 400.0f);
    for (int k = 0; k < kTreeWidth; ++k) {
      LightBounds b;
      b.center = vec3(uniform(-5, 5), uniform(-5, 5), uniform(-5, 5));
      b.radius = k == 0 ? 0.0f : uniform(0.0f, 4.0f);
      b.w = unit();
      b.phi = k == 1 ? 0.0f : uniform(0.0f, 10.0f);
      b.set_cos_theta_o(k == 2 ? -1.0f : uniform(-1.0f, 1.0f));
      b.cos_theta_e = k == 3 ? 0.0f : uniform(-1.0f, 1.0f);
      b.two_sided = random.rng.next_float() < 0.3f;
      ASSERT_TRUE(wide.set(k, b, scale));
      scalar[k] = wide.get(k, scale);
    }
    const vec3 p = vec3(uniform(-6, 6), uniform(-6, 6), uniform(-6, 6));
    const vec3 n = node % 5 == 0 ? vec3(0.0f) : unit();
    const float region = node % 7 == 0 ? uniform(0.0f, 2.0f) : 0.0f;
    for_each_simd_target([&](const char* target) {
      if (node == 0) targets += std::string(targets.empty() ? "" : ", ") + target;
      float lanes[kTreeWidth];
      wide_importance(wide, ShadingContext{p, n, region}, scale, lanes);
      for (int k = 0; k < kTreeWidth; ++k) {
        const float expected = scalar[k].importance(ShadingContext{p, n, region});
        ++compared;
        positive += expected > 0.0f;
        EXPECT_TRUE(testing::same_bits(lanes[k], expected))
            << target << ", node " << node << " slot " << k << ": lanes " << lanes[k] << ", scalar " << expected;
      }
    });
  }
  std::printf("  %d importances compared (%d positive) on %s\n", compared, positive, targets.c_str());
  EXPECT_GT(positive, compared / 4) << "too few positive importances to test anything";
}

}  // namespace
}  // namespace candela

// The reference path tracer against closed forms, and its determinism across thread counts.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cstring>

#include "engine/builtin_scenes.h"
#include "engine/path_tracer.h"
#include "samplers/simple_samplers.h"

namespace candela {
namespace {

// Renders `spp` paths per pixel of a w x h image and returns the per-pixel means.
Image render(const Scene& scene, int w, int h, int spp, int max_depth, uint64_t seed) {
  Tracer tracer(scene);
  LightList lights(scene);
  PowerLightSampler sampler(lights);
  Camera camera(scene.default_camera(), w, h);
  SceneView view{scene, tracer, lights, camera};
  PathTracerParams params;
  params.spp = spp;
  params.max_depth = max_depth;
  params.seed = seed;
  Image sum(w, h);
  RayCounter rays;
  path_trace(view, sampler, params, 0, sum, rays);
  for (vec3& p : sum.pixels) p /= float(spp);
  return sum;
}

// Inside a closed diffuse sphere of albedo a emitting Le everywhere, every point sees L = Le / (1 - a)
// (the geometric series of bounces). The image mean must be within 1% of it; the standard error over
// 16k paths is about 0.2%, so the 1% bound is also a ~5 sigma test.
TEST(PathTracer, FurnaceMatchesClosedForm) {
  const float albedo = 0.5f, emission = 1.0f;
  Scene scene = make_furnace_scene(albedo, emission);
  Image img = render(scene, 32, 32, 16, 100, 1);
  double mean = 0.0, mean2 = 0.0;
  for (const vec3& p : img.pixels) { mean += p.x; mean2 += double(p.x) * p.x; }
  mean /= img.pixels.size();
  mean2 /= img.pixels.size();
  double stderr_ = std::sqrt(std::max(0.0, mean2 - mean * mean) / img.pixels.size());
  double expected = emission / (1.0 - albedo);
  EXPECT_NEAR(mean, expected, 0.01 * expected) << "standard error " << stderr_;
  EXPECT_LT(stderr_, 0.003 * expected);
}

// With max depth 1 inside the furnace: emission seen directly plus one bounce, Le (1 + a).
TEST(PathTracer, FurnaceDirectOnly) {
  Scene scene = make_furnace_scene(0.5f, 1.0f);
  Image img = render(scene, 32, 32, 16, 1, 2);
  EXPECT_NEAR(img.mean().x, 1.5, 0.015);
}

// Same seed, one thread or two: bit-identical images (randomness is keyed on pixel and sample).
TEST(PathTracer, SameImageForAnyThreadCount) {
  Scene scene = make_cornell_scene();
  Image one, two;
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
    one = render(scene, 48, 32, 4, 8, 3);
  }
  {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
    two = render(scene, 48, 32, 4, 8, 3);
  }
  ASSERT_EQ(one.pixels.size(), two.pixels.size());
  EXPECT_EQ(0, std::memcmp(one.pixels.data(), two.pixels.data(), one.pixels.size() * sizeof(vec3)));
  Image other_seed = render(scene, 48, 32, 4, 8, 4);
  EXPECT_NE(0, std::memcmp(one.pixels.data(), other_seed.pixels.data(), one.pixels.size() * sizeof(vec3)));
}

}  // namespace
}  // namespace candela

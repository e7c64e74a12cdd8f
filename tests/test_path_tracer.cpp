// The reference path tracer against closed forms, and its determinism across thread counts.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cstring>

#include "engine/builtin_scenes.h"
#include "engine/path_tracer.h"
#include "samplers/simple_samplers.h"
#include "tests/render_helpers.h"

namespace candela {
namespace {

template <class Sampler = PowerLightSampler>
Image render(const Scene& scene, int w, int h, int spp, int max_depth, uint64_t seed) {
  return testing::render_paths<Sampler>(scene, w, h, spp, max_depth, seed);
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

// Mean of the red channel over pixels and its standard error (pixels as independent estimates).
std::pair<double, double> mean_and_error(const Image& img) {
  double m = 0.0, m2 = 0.0;
  for (const vec3& p : img.pixels) { m += p.x; m2 += double(p.x) * p.x; }
  m /= img.pixels.size();
  m2 /= img.pixels.size();
  return {m, std::sqrt(std::max(0.0, m2 - m * m) / img.pixels.size())};
}

// Uniform and power light selection are both unbiased: their direct-light images of the furnace-free
// Cornell box agree within 4 combined standard errors (~1e-4 two-sided chance of a false failure).
TEST(PathTracer, LightSamplersAgree) {
  Scene scene = make_cornell_scene();
  auto [mu, eu] = mean_and_error(render<UniformLightSampler>(scene, 32, 24, 64, 1, 5));
  auto [mp, ep] = mean_and_error(render<PowerLightSampler>(scene, 32, 24, 64, 1, 6));
  EXPECT_NEAR(mu, mp, 4.0 * std::hypot(eu, ep));
}

// A point light of intensity I at height h above a white Lambert floor: the floor right below it has
// radiance (1 / pi) I / h^2. A 0.5 degree camera looks straight down at that point.
TEST(PathTracer, PointLightOverLambertFloor) {
  Scene scene;
  Mesh floor;
  floor.positions = {vec3(-5, 0, -5), vec3(5, 0, -5), vec3(5, 0, 5), vec3(-5, 0, 5)};
  floor.triangles = {uvec3(0, 2, 1), uvec3(0, 3, 2)};
  Material white;
  white.specular = 0.0f;
  scene.materials.push_back(white);
  scene.meshes.push_back(floor);
  scene.instances.push_back(Instance{0});
  PunctualLight light;
  light.position = vec3(0.0f, 2.0f, 0.0f);
  light.intensity = vec3(3.0f);
  scene.punctual_lights.push_back(light);
  scene.camera = CameraDesc{vec3(0.0f, 4.0f, 0.0f), vec3(0.0f), vec3(0, 0, 1), 0.5f};
  Image img = render(scene, 8, 8, 4, 1, 7);
  double expected = 3.0 / (4.0 * kPi);
  for (const vec3& p : img.pixels) EXPECT_NEAR(p.x, expected, 1e-3 * expected);
}

}  // namespace
}  // namespace candela

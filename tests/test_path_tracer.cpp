// The reference path tracer against closed forms, and its determinism across thread counts.
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cstring>

#include "engine/builtin_scenes.h"
#include "engine/path_batch.h"
#include "engine/path_tracer.h"
#include "engine/simd_targets.h"
#include "samplers/simple_samplers.h"
#include "tests/render_helpers.h"
#include "tests/settings_builder.h"

namespace candela {
namespace {

template <class Sampler = PowerLightSampler>
Image render(const Scene& scene, int w, int h, int spp, int max_depth, uint64_t seed,
             SampleSequence sequence = SampleSequence::Independent) {
  return testing::render_paths<Sampler>(scene, w, h, spp, max_depth, seed, sequence);
}

// Mean over pixels of each pixel's channel average (minus that of `minus`, if given, pixel by pixel), and
// its standard error with pixels as the units (a pixel's channels come from the same paths, so they are
// averaged first, not counted as samples). Valid where pixels are independent estimates, as the path
// tracer's are. Without `minus` the spread between pixels must be noise alone (a uniform image, the
// furnace); a difference of two renders of one scene removes the image's own variation.
std::pair<double, double> mean_and_error(const Image& img, const Image* minus = nullptr) {
  double m = 0.0, m2 = 0.0;
  for (size_t i = 0; i < img.pixels.size(); ++i) {
    vec3 p = img.pixels[i] - (minus ? minus->pixels[i] : vec3(0.0f));
    double v = (double(p.x) + p.y + p.z) / 3.0;
    m += v;
    m2 += v * v;
  }
  const double n = double(img.pixels.size());
  m /= n;
  return {m, std::sqrt(std::max(0.0, m2 / n - m * m) / (n - 1.0))};
}

// Inside a closed Lambertian enclosure of albedo a emitting Le everywhere, every point sees
// L = Le / (1 - a) (the geometric series of bounces). Albedo 0.5, and 0.9 (L = 10 Le) where paths average
// 10 bounces, so Russian roulette (from bounce 3 on) decides most of the result. Max depth 100 truncates
// the series after a^101 of it (2.4e-5 relative at 0.9). 64x64 pixels x 32 paths: the image mean must
// be within 4 standard errors (pixels independent; two-sided, 6e-5 chance of a false failure) of the
// closed form, and the standard error under 0.3% of it, so that a bias of 1.2% fails.
TEST(PathTracer, FurnaceMatchesClosedForm) {
  for (float albedo : {0.5f, 0.9f}) {
    const float emission = 1.0f;
    Image img = render(make_furnace_scene(albedo, emission), 64, 64, 32, 100, 1);
    auto [mean, standard_error] = mean_and_error(img);
    const double expected = emission / (1.0 - albedo);
    std::printf(
        "furnace, albedo %.1f, pt: mean %.5f, expected %.5f (%+.2f standard errors; standard error %.5f = %.3f%%)\n",
        albedo, mean, expected, (mean - expected) / standard_error, standard_error, 100.0 * standard_error / expected);
    EXPECT_NEAR(mean, expected, 4.0 * standard_error) << "albedo " << albedo;
    EXPECT_LT(standard_error, 0.003 * expected) << "albedo " << albedo;
  }
}

// The same furnace at albedo 0.9 through the renderer's settings, with Russian roulette from the first bounce
// (--rr-depth 1) instead of the third: still unbiased, by the same bound (4 standard errors of the pixels' mean,
// the standard error under 0.3%). Roulette from bounce 1 ends more of the short paths, so the paths are noisier:
// 64 of them per pixel. The same seed with the default gives another image (the setting reaches the paths).
TEST(PathTracer, FurnaceWithRouletteFromTheFirstBounce) {
  const float albedo = 0.9f, emission = 1.0f;
  const Scene scene = make_furnace_scene(albedo, emission);
  auto render_with = [&](int rr_depth) {
    Renderer renderer(scene, testing::settings({{"width", 64},
                                                {"height", 64},
                                                {"method", "pt"},
                                                {"spp", 64},
                                                {"max_depth", 100},
                                                {"rr_depth", rr_depth},
                                                {"sampler", "independent"}}));
    testing::render_checked(renderer, 0, 0.0f, scene.default_camera());
    return renderer.image();
  };
  const Image image = render_with(1);
  EXPECT_NE(std::memcmp(image.pixels.data(), render_with(3).pixels.data(), image.pixels.size() * sizeof(vec3)), 0);
  auto [mean, standard_error] = mean_and_error(image);
  const double expected = emission / (1.0 - albedo);
  std::printf(
      "furnace, albedo %.1f, pt, roulette from bounce 1: mean %.5f, expected %.5f (%+.2f standard errors; "
      "standard error %.5f = %.3f%%)\n",
      albedo, mean, expected, (mean - expected) / standard_error, standard_error, 100.0 * standard_error / expected);
  EXPECT_NEAR(mean, expected, 4.0 * standard_error);
  EXPECT_LT(standard_error, 0.003 * expected);
}

// ReSTIR (DI + GI, default reuse: temporal and spatial, pairwise MIS) in the same enclosure at albedo 0.9,
// GI paths of up to 100 bounces: L = 10 Le. Its neighbouring pixels share samples, so the standard error
// comes from independent runs (seeds), not from pixels: 16 runs of 32x32 pixels, 32 accumulated frames
// each; the mean over runs of the image mean must be within 4 standard errors (t distribution with 15
// degrees of freedom: two-sided 0.12% chance of a false failure) of the closed form, and the standard
// error under 0.5% of it, so that a bias of 2% fails.
TEST(PathTracer, RestirFurnaceMatchesClosedForm) {
  const float albedo = 0.9f, emission = 1.0f;
  const Scene scene = make_furnace_scene(albedo, emission);
  const int runs = 16, frames = 32;
  double sum = 0.0, sum2 = 0.0;
  for (int run = 0; run < runs; ++run) {
    Renderer renderer(
        scene, testing::settings(
                   {{"width", 32}, {"height", 32}, {"method", "restir"}, {"max_depth", 100}, {"seed", 40 + run}}));
    for (int frame = 0; frame < frames; ++frame) testing::render_checked(renderer, frame, 0.0f, scene.default_camera());
    const double m = mean_and_error(renderer.image()).first;
    sum += m;
    sum2 += m * m;
  }
  const double mean = sum / runs, standard_error = std::sqrt(std::max(0.0, sum2 / runs - mean * mean) / (runs - 1));
  const double expected = emission / (1.0 - albedo);
  std::printf(
      "furnace, albedo %.1f, restir: mean %.5f over %d runs, expected %.5f (%+.2f standard errors; standard "
      "error %.5f = %.3f%%)\n",
      albedo, mean, runs, expected, (mean - expected) / standard_error, standard_error,
      100.0 * standard_error / expected);
  EXPECT_NEAR(mean, expected, 4.0 * standard_error);
  EXPECT_LT(standard_error, 0.005 * expected);
}

// With max depth 1 inside the furnace: emission seen directly plus one bounce, Le (1 + a).
TEST(PathTracer, FurnaceDirectOnly) {
  Scene scene = make_furnace_scene(0.5f, 1.0f);
  Image img = render(scene, 32, 32, 16, 1, 2);
  EXPECT_NEAR(img.mean().x, 1.5, 0.015);
}

// Same seed, one thread or two: bit-identical images (randomness is keyed on pixel and sample), with
// independent, Sobol and ZSobol numbers alike; another seed changes the image.
TEST(PathTracer, SameImageForAnyThreadCount) {
  Scene scene = make_cornell_scene();
  for (SampleSequence sequence : {SampleSequence::Independent, SampleSequence::Sobol, SampleSequence::ZSobol}) {
    Image one, two;
    {
      tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 1);
      one = render(scene, 48, 32, 4, 8, 3, sequence);
    }
    {
      tbb::global_control limit(tbb::global_control::max_allowed_parallelism, 2);
      two = render(scene, 48, 32, 4, 8, 3, sequence);
    }
    ASSERT_EQ(one.pixels.size(), two.pixels.size());
    EXPECT_EQ(0, std::memcmp(one.pixels.data(), two.pixels.data(), one.pixels.size() * sizeof(vec3))) << int(sequence);
    Image other_seed = render(scene, 48, 32, 4, 8, 4, sequence);
    EXPECT_NE(0, std::memcmp(one.pixels.data(), other_seed.pixels.data(), one.pixels.size() * sizeof(vec3)))
        << int(sequence);
  }
}

// The Cornell box with a second ceiling light of the same size as the first and `dim` times its radiance,
// so that light selection by power differs from uniform selection.
Scene two_light_cornell(float dim) {
  Scene scene = make_cornell_scene();
  Material light;
  light.base_color = vec4(vec3(0.78f), 1.0f);
  light.emission = vec3(17.0f, 12.0f, 4.0f) * dim;
  scene.materials.push_back(light);
  Mesh quad;  // facing down: cross(p1 - p0, p2 - p0) is -y
  const vec3 c(-0.55f, 1.995f, -0.5f), u(0.25f, 0.0f, 0.0f), v(0.0f, 0.0f, 0.2f);
  quad.positions = {c - u - v, c + u - v, c + u + v, c - u + v};
  quad.triangles = {uvec3(0, 1, 2), uvec3(0, 2, 3)};
  quad.material = int(scene.materials.size() - 1);
  scene.meshes.push_back(quad);
  scene.instances.push_back(Instance{int(scene.meshes.size() - 1)});
  return scene;
}

// Uniform and power light selection are both unbiased, so their direct-light images agree: on the Cornell
// box with a second light of 1/10 the radiance, the mean of the pixel-by-pixel difference of two
// independent renders (48x36, 1024 paths per pixel) is within 4 of its standard errors of zero (pixels as
// units, so the standard error combines both renders' noise; two-sided, 6e-5 chance of a false failure).
// The test means something only because the pmfs differ there: power gives each triangle of the dim light
// 0.18x and of the main light 1.82x uniform's 1/4 (asserted: ratio range above 5x). On the plain Cornell
// box, whose two light triangles have equal power, both were the same sampler. (manylights, whose 64
// light powers span 4 decades, was tried: uniform selection's rare bright samples make the standard
// error itself too noisy to judge with.)
TEST(PathTracer, LightSamplersAgree) {
  Scene scene = two_light_cornell(0.1f);
  LightList lights(scene);
  UniformLightSampler uniform(lights);
  PowerLightSampler power(lights);
  float lo = kInfinity, hi = 0.0f;
  const ShadingContext ctx{vec3(0.0f, 1.0f, 0.0f), vec3(0.0f, 1.0f, 0.0f)};
  for (uint32_t k = 0; k < lights.size(); ++k) {
    lo = std::min(lo, power.pmf(ctx, k) / uniform.pmf(ctx, k));
    hi = std::max(hi, power.pmf(ctx, k) / uniform.pmf(ctx, k));
  }
  std::printf("%zu lights; power pmf / uniform pmf: %.3f .. %.3f\n", lights.size(), lo, hi);
  ASSERT_GT(hi / lo, 5.0f);
  Image uniform_image = render<UniformLightSampler>(scene, 48, 36, 1024, 1, 5);
  Image power_image = render<PowerLightSampler>(scene, 48, 36, 1024, 1, 6);
  const double mean = mean_and_error(power_image).first;
  auto [difference, standard_error] = mean_and_error(uniform_image, &power_image);
  std::printf(
      "two-light cornell, direct light: image mean %.5f (power); uniform - power %+.5f (%+.2f%%), standard "
      "error %.5f, tolerance %.5f (%.2f%% of the mean)\n",
      mean, difference, 100.0 * difference / mean, standard_error, 4.0 * standard_error, 400.0 * standard_error / mean);
  EXPECT_NEAR(difference, 0.0, 4.0 * standard_error);
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

// manylights with its emitters' emission modulated by a striped texture (uv from the vertices' x and z, stripes
// 1/8 of a unit wide): lights whose emission varies over the triangle (TriangleLight::textured).
Scene textured_manylights() {
  Scene s = make_builtin_scene("manylights");
  Texture stripes;
  stripes.width = stripes.height = 8;
  stripes.rgba.resize(8 * 8 * 4);
  for (int y = 0; y < 8; ++y)
    for (int x = 0; x < 8; ++x)
      for (int c = 0; c < 4; ++c) stripes.rgba[size_t(y * 8 + x) * 4 + size_t(c)] = x % 2 ? 255 : 64;
  s.textures.push_back(std::move(stripes));
  for (Material& m : s.materials)
    if (m.emissive()) m.emissive_tex.texture = int(s.textures.size()) - 1;
  for (Mesh& mesh : s.meshes) {
    if (!s.materials[size_t(mesh.material)].emissive()) continue;
    mesh.uv0.clear();
    for (const vec3& p : mesh.positions) mesh.uv0.push_back(vec2(p.x, p.z));
  }
  return s;
}

// trace_paths (many paths bounce by bounce, rays in packets) gives trace_path's bits: each path's
// radiance, its first hit and the number of rays, on manylights (2,048 emitters: NEE, MIS on emission) and
// city (sky: paths that escape; moving cars), 64 paths per pixel row so packets mix lanes of different
// depths. Half the paths start with emission at their first hit not counted, as ReSTIR GI's do. With the
// scene's GBufferInstances too, as ReSTIR GI runs it: the vertices' surfaces from surface_points_lanes. The batch
// runs its kernels (the BSDFs, the triangle lights' samples and weights, the continuation) on every instruction set
// this CPU has. City's headlights are punctual lights and textured manylights' emitters vary over their triangles:
// their light samples take the scalar code's branch.
TEST(PathBatch, GivesTracePathBits) {
  std::vector<std::pair<std::string, Scene>> scenes;
  scenes.emplace_back("manylights", make_builtin_scene("manylights"));
  scenes.emplace_back("city", make_builtin_scene("city"));
  scenes.emplace_back("textured manylights", textured_manylights());
  for (const auto& [name, scene] : scenes)
    for (const bool lanes : {false, true}) {
      const Tracer tracer(scene);
      const LightList lights(scene);
      const PowerLightSampler sampler(lights);
      const int w = 64, h = 32;
      const Camera camera(scene.default_camera(), w, h);
      const SceneView view{scene, tracer, lights, camera};
      PathTracerParams params;
      params.max_depth = 8;
      std::vector<PathState> paths;
      std::vector<Rng> rngs;
      for (int i = 0; i < w * h; ++i) {
        const int x = i % w, y = i / w;
        Ray ray{camera.position(), camera.direction(x + 0.5f, y + 0.5f), 0.0f, kInfinity};
        paths.emplace_back(PathStart{ray, 0, 0.0f, ShadingContext{}, (i % 2) == 0});
        rngs.push_back(Rng::for_key(7, uint64_t(i), 0, 0));
      }
      // trace_path's answers, one path at a time.
      std::vector<vec3> radiance(paths.size());
      std::vector<std::optional<SurfacePoint>> first_hits(paths.size());
      uint64_t rays = 0;
      int lit = 0, escaped = 0;
      for (size_t k = 0; k < paths.size(); ++k) {
        Rng rng = rngs[k];
        PathStart start{paths[k].ray, 0, 0.0f, ShadingContext{}, paths[k].emission_counts};
        radiance[k] = trace_path(view, sampler, params, start, rng, rays, &first_hits[k]);
        lit += max_component(radiance[k]) > 0.0f;
        escaped += !first_hits[k];
      }
      EXPECT_GT(lit, w * h / 2) << name;  // the comparison covers lit paths, not only black ones
      std::printf("%s%s: %d of %d paths lit, %d escaped, %llu rays\n", name.c_str(), lanes ? " (lanes)" : "", lit,
                  w * h, escaped, (unsigned long long)rays);
      if (name == "textured manylights") {  // the scene is here for its textured emitters
        size_t textured = 0;
        for (const TriangleLight& l : lights.triangles()) textured += l.textured;
        EXPECT_EQ(textured, lights.triangle_count());
      }
      // The batch's, with its kernels on every instruction set.
      const GBufferInstances instances(scene);
      for_each_simd_target([&](const char* target) {
        std::vector<PathState> batch = paths;
        std::vector<Rng> batch_rngs = rngs;
        std::vector<std::optional<SurfacePoint>> batch_hits(paths.size());
        const uint64_t batch_rays =
            trace_paths(view, sampler, params, batch, batch_rngs, &batch_hits, lanes ? &instances : nullptr);
        EXPECT_EQ(rays, batch_rays) << name << " " << target;
        for (size_t k = 0; k < paths.size(); ++k) {
          const std::optional<SurfacePoint>& hit = first_hits[k];
          const vec3 batch_L = batch[k].radiance();
          ASSERT_EQ(std::memcmp(&radiance[k], &batch_L, sizeof(vec3)), 0)
              << name << (lanes ? " (lanes) " : " ") << target << " path " << k << ": " << radiance[k].x << " against "
              << batch_L.x;
          ASSERT_EQ(hit.has_value(), batch_hits[k].has_value()) << name << " " << target << " path " << k;
          if (hit) {
            ASSERT_EQ(std::memcmp(&hit->position, &batch_hits[k]->position, sizeof(vec3)), 0)
                << name << " " << target << " path " << k;
            ASSERT_EQ(std::memcmp(&hit->shading_normal, &batch_hits[k]->shading_normal, sizeof(vec3)), 0)
                << name << " " << target << " path " << k;
          }
        }
      });
    }
}

}  // namespace
}  // namespace candela

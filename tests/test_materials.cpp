// Images that agree with other renderers: KHR_materials_specular / KHR_materials_ior are read, a Lambertian
// plane under a point light matches the closed form through every direct-light method, BLEND surfaces let
// through light in proportion to their alpha, the environment is only there when a scene has no light,
// and the Lambertian occluded_room matches pbrt-v4's converged images (../shared/scenes).
#include <gtest/gtest.h>

#include <cstdio>
#include <string>

#include "apps/renderer.h"
#include "apps/scene_source.h"
#include "engine/check.h"
#include "engine/gltf_loader.h"
#include "engine/image_metrics.h"
#include "engine/rng.h"
#include "engine/surface.h"
#include "tests/render_helpers.h"
#include "tests/test_util.h"
#include "tests/settings_builder.h"

namespace candela {
namespace {

std::string material_file(const std::string& name) {
  return std::string(CANDELA_SOURCE_DIR) + "/tests/data/materials/" + name;
}

// A square of side 2 `half` centred on (0, y, 0), facing +y, with its own mesh, material and instance.
void add_square(Scene& scene, float y, float half, const Material& material) {
  Mesh mesh;
  mesh.positions = {vec3(-half, y, -half), vec3(-half, y, half), vec3(half, y, half), vec3(half, y, -half)};
  mesh.triangles = {uvec3(0, 1, 2), uvec3(0, 2, 3)};
  mesh.material = int(scene.materials.size());
  scene.materials.push_back(material);
  Instance inst;
  inst.mesh = int(scene.meshes.size());
  scene.meshes.push_back(std::move(mesh));
  scene.instances.push_back(inst);
}

Material lambert(const vec3& albedo) {
  Material m;
  m.base_color = vec4(albedo, 1.0f);
  m.specular = 0.0f;
  return m;
}

// A Lambertian floor (y = 0) under a point light of intensity I at height h, seen from straight above.
Scene point_lit_floor(float h, const vec3& intensity, const vec3& albedo) {
  Scene scene;
  add_square(scene, 0.0f, 10.0f, lambert(albedo));
  PunctualLight light;
  light.position = vec3(0.0f, h, 0.0f);
  light.intensity = intensity;
  scene.punctual_lights.push_back(light);
  scene.camera = CameraDesc{vec3(0.0f, 5.0f, 0.0f), vec3(0.0f), vec3(0.0f, 0.0f, -1.0f), 30.0f};
  return scene;
}

Image render_image(const Scene& scene, RenderSettings settings, int frames = 1) {
  Renderer renderer(scene, settings);
  for (int f = 0; f < frames; ++f) testing::render_checked(renderer, f, 0.0f, *scene.camera);
  return renderer.image();
}

TEST(MaterialExtensions, SpecularAndIorAreRead) {
  LoadReport report;
  Scene scene = load_gltf(material_file("specular_ior.gltf"), &report);
  for (const std::string& w : report.warnings) ADD_FAILURE() << "unexpected warning: " << w;
  ASSERT_EQ(scene.materials.size(), 4u);
  const Material& lambert_mat = scene.materials[0];
  EXPECT_EQ(lambert_mat.specular, 0.0f);
  const Material& water = scene.materials[1];
  EXPECT_FLOAT_EQ(water.ior, 1.33f);
  EXPECT_EQ(water.specular_color, vec3(0.5f, 1.0f, 2.0f));
  EXPECT_EQ(water.specular, 1.0f);
  const Material& textured = scene.materials[2];
  EXPECT_EQ(textured.specular, 0.5f);
  ASSERT_TRUE(textured.specular_tex.valid());
  ASSERT_TRUE(textured.specular_color_tex.valid());
  EXPECT_FALSE(scene.textures[size_t(textured.specular_tex.texture)].srgb);       // alpha: data
  EXPECT_TRUE(scene.textures[size_t(textured.specular_color_tex.texture)].srgb);  // colour: sRGB
  const Material& plain = scene.materials[3];
  EXPECT_EQ(plain.specular, 1.0f);
  EXPECT_EQ(plain.ior, 1.5f);

  // What the surfaces hand to the BSDF: F0 from ior and colour (at most 1), the factor times the texture's alpha.
  vec3 up(0.0f, 1.0f, 0.0f);
  SurfacePoint w = surface_at(scene, 1, 0, vec2(0.25f), up);
  vec3 f0_water = dielectric_f0(1.33f, vec3(0.5f, 1.0f, 2.0f));
  for (int c = 0; c < 3; ++c) EXPECT_FLOAT_EQ(w.specular_f0[c], f0_water[c]);
  SurfacePoint t = surface_at(scene, 2, 0, vec2(0.25f), up);
  EXPECT_NEAR(t.specular, 0.5f * 128.0f / 255.0f, 1e-3f);
  EXPECT_NEAR(t.specular_f0.x, 0.04f * 0.5f, 0.04f * 0.01f);  // sRGB 188 is linear 0.503
  SurfacePoint l = surface_at(scene, 0, 0, vec2(0.25f), up);
  EXPECT_EQ(l.specular, 0.0f);
  SurfacePoint p = surface_at(scene, 3, 0, vec2(0.25f), up);
  EXPECT_NEAR(p.specular_f0.x, 0.04f, 1e-7f);
}

// L = rho I / (pi h^2) at the point under the light, through the pixel centre that sees it, for the path
// tracer (one bounce), the direct estimator and ReSTIR DI. One light and pixel-centre rays make each
// estimate deterministic, so 0.1% is a bound on the BSDF and the light's normalisation, not on noise.
TEST(MaterialClosedForm, LambertPlaneUnderPointLight) {
  const float h = 2.0f;
  const vec3 intensity(3.0f, 2.0f, 1.0f), albedo(0.5f, 0.6f, 0.7f);
  Scene scene = point_lit_floor(h, intensity, albedo);
  const vec3 expected = albedo * intensity * (kInvPi / (h * h));
  for (const char* method : {"pt", "direct", "restir-di"}) {
    const RenderSettings s =
        testing::settings({{"width", 3}, {"height", 3}, {"jitter", false}, {"max_depth", 1}, {"method", method}});
    vec3 L = render_image(scene, s).at(1, 1);
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(L[c], expected[c], 1e-3f * expected[c]) << "method " << method << " channel " << c;
  }
}

// A floor, a BLEND square of alpha 0.5 at y = 1 that shadows all of it, and a point light at y = 2; the
// camera sits between floor and square and looks down, so that it sees only the floor.
Scene half_covered_floor(bool with_blend) {
  Scene scene = point_lit_floor(2.0f, vec3(4.0f), vec3(0.8f));
  if (with_blend) {
    Material blend = lambert(vec3(0.3f));
    blend.base_color.a = 0.5f;
    blend.alpha_mode = AlphaMode::Blend;
    add_square(scene, 1.0f, 10.0f, blend);
  }
  scene.camera = CameraDesc{vec3(0.0f, 0.5f, 3.0f), vec3(0.0f, -1.0f, 0.0f), vec3(0.0f, 1.0f, 0.0f), 40.0f};
  return scene;
}

// Shadow rays from 40,000 random floor points to the light, and as many rays straight down onto the
// square: half are stopped, within 4 binomial standard errors (0.25%: a 99.994% interval). The same ray
// traced again gets the same answer.
TEST(AlphaBlend, HalfTransparentSquareStopsHalfTheRays) {
  Scene scene = half_covered_floor(true);
  Tracer tracer(scene);
  Rng rng(7, 7);
  const int n = 40000;
  int blocked = 0, hits = 0;
  for (int i = 0; i < n; ++i) {
    vec3 p(8.0f * rng.next_float() - 4.0f, 0.0f, 8.0f * rng.next_float() - 4.0f);
    Ray shadow = tracer.spawn_ray_to(p, vec3(0, 1, 0), vec3(0.0f, 2.0f, 0.0f), vec3(0, -1, 0));
    bool occluded = tracer.occluded(shadow);
    EXPECT_EQ(occluded, tracer.occluded(shadow));
    blocked += occluded;
    Ray down{vec3(p.x, 3.0f, p.z), vec3(0, -1, 0)};
    Hit hit = tracer.intersect(down);
    ASSERT_TRUE(hit.valid());
    hits += hit.instance == 1;
  }
  const double se = 0.5 / std::sqrt(double(n));
  EXPECT_NEAR(double(blocked) / n, 0.5, 4.0 * se);
  EXPECT_NEAR(double(hits) / n, 0.5, 4.0 * se);
}

// The same through a render: the floor's radiance with the square over it is half its radiance without,
// pixel by pixel on average (each pixel's one shadow ray is an independent coin), within 4 standard errors.
TEST(AlphaBlend, HalfTransparentSquareCastsHalfAShadow) {
  const RenderSettings s = testing::settings({{"width", 64}, {"height", 64}, {"jitter", false}, {"method", "direct"}});
  Image with = render_image(half_covered_floor(true), s), without = render_image(half_covered_floor(false), s);
  double sum = 0.0, sum2 = 0.0;
  int n = 0;
  for (size_t i = 0; i < with.pixels.size(); ++i) {
    if (without.pixels[i].x <= 0.0f) continue;
    double r = with.pixels[i].x / without.pixels[i].x;
    sum += r;
    sum2 += r * r;
    ++n;
  }
  ASSERT_GT(n, 3000);
  double mean = sum / n, se = std::sqrt(std::max(0.0, sum2 / n - mean * mean) / n);
  EXPECT_NEAR(mean, 0.5, 4.0 * se) << "standard error " << se;
  EXPECT_LT(se, 0.02);
}

// The default environment: none for a file with emitters, grey 0.3 and a warning for a file without light,
// the built-in scenes' own, and whatever --environment asks for.
TEST(DefaultEnvironment, OnlyWhereTheSceneHasNoLight) {
  ::testing::internal::CaptureStderr();
  Scene lit = load_scene(material_file("emissive_ceiling.gltf"));
  std::string lit_log = ::testing::internal::GetCapturedStderr();
  EXPECT_EQ(lit.environment, vec3(0.0f));
  EXPECT_EQ(lit_log.find("environment"), std::string::npos) << lit_log;

  ::testing::internal::CaptureStderr();
  Scene dark = load_scene(material_file("specular_ior.gltf"));
  std::string dark_log = ::testing::internal::GetCapturedStderr();
  EXPECT_EQ(dark.environment, vec3(kFallbackEnvironment));
  EXPECT_NE(dark_log.find("no emissive material and no punctual light"), std::string::npos) << dark_log;

  EXPECT_EQ(load_scene(material_file("emissive_ceiling.gltf"), {}, 0.25f).environment, vec3(0.25f));
  EXPECT_EQ(load_scene("builtin:city").environment, make_builtin_scene("city", {}).environment);
}

// A scene lit only by its emitters renders with no light from outside: with the emitters switched off, the
// image is black.
TEST(DefaultEnvironment, EmitterLitFileGetsNoOutsideLight) {
  Scene scene = load_scene(material_file("emissive_ceiling.gltf"));
  for (Material& m : scene.materials) m.emission = vec3(0.0f);
  scene.camera = CameraDesc{vec3(0.0f, 1.0f, 3.0f), vec3(0.0f, 1.0f, 0.0f), vec3(0.0f, 1.0f, 0.0f), 60.0f};
  EXPECT_EQ(image_mean(render_image(scene, testing::settings({{"width", 16}, {"height", 16}, {"max_depth", 3}}))), 0.0);
}

// Box filter of a reference down to width x height (each output pixel the mean of a k x k block).
Image downsample(const Image& image, int width, int height) {
  CHECK(image.width % width == 0 && image.height % height == 0);
  int kx = image.width / width, ky = image.height / height;
  Image out(width, height);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) out.at(x / kx, y / ky) += image.at(x, y) / float(kx * ky);
  return out;
}

struct PbrtCase {
  const char* reference;  // under occluded_room/reference/
  int max_depth, size, spp;
  double max_rel_mse;  // 1.5x the measured value (0.019 direct, 0.031 with 5 bounces)
};

// occluded_room_lambert.gltf (KHR_materials_specular 0 everywhere) with the default options against
// pbrt-v4's 512-spp renders of the same Lambertian room, box-filtered to the test's size: the image means
// agree within 4 standard errors of ours (0.5% direct, 0.8% with 5 bounces; pbrt's own error is ~1/8 of
// ours), and relMSE stays under its bound. With the old BSDF and the grey environment the means were
// 11% off.
class PbrtReference : public ::testing::TestWithParam<PbrtCase> {};

TEST_P(PbrtReference, OccludedRoomLambertMatches) {
  const PbrtCase c = GetParam();
  const std::string scene_file = testing::shared_scene_file("occluded_room/occluded_room_lambert.gltf");
  const std::string reference_file = testing::shared_scene_file(std::string("occluded_room/reference/") + c.reference);
  // Skipped without the shared scenes; with them, a missing file has failed the test already.
  if (scene_file.empty() || reference_file.empty()) GTEST_SKIP() << testing::shared_scenes_skip_reason();
  Scene scene = load_scene(scene_file);
  ASSERT_TRUE(scene.camera.has_value());
  Image reference = read_image(reference_file);
  Image image = render_image(
      scene, testing::settings(
                 {{"width", c.size}, {"height", c.size}, {"spp", c.spp}, {"max_depth", c.max_depth}, {"seed", 3}}));
  Image ref = downsample(reference, c.size, c.size);
  ImageError e = compare_images(image, ref);
  double ratio = image_mean(image) / image_mean(ref);
  std::printf("occluded_room_lambert depth %d, %dx%d, %d spp: mean %.5f x pbrt's (+- %.5f), relMSE %.4f\n", c.max_depth,
              c.size, c.size, c.spp, ratio, e.standard_error / image_mean(ref), e.rel_mse);
  EXPECT_NEAR(ratio, 1.0, 4.0 * e.standard_error / image_mean(ref));
  EXPECT_LE(e.rel_mse, c.max_rel_mse);
}

INSTANTIATE_TEST_SUITE_P(Lambert, PbrtReference,
                         ::testing::Values(PbrtCase{"pbrt_direct_512x512_512spp.exr", 1, 128, 64, 0.03},
                                           PbrtCase{"pbrt_gi5_256x256_512spp.exr", 5, 64, 64, 0.045}));

}  // namespace
}  // namespace candela

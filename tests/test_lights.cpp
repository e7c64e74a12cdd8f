// The light list: emission integrated over textured triangles, only real emitters kept, lights placed and
// moved through instances, and light sampling densities that agree with their pdf.
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "apps/scene_source.h"
#include "engine/lights.h"
#include "engine/rng.h"
#include "engine/surface.h"
#include "tests/test_util.h"

namespace candela {
namespace {

using testing::same_bits;

// One triangle covering the lower-left half of UV space, its material emitting through `texture`.
Scene textured_triangle_scene(Texture texture) {
  Scene s;
  Mesh m;
  m.positions = {vec3(0, 0, 0), vec3(1, 0, 0), vec3(0, 1, 0)};
  m.uv0 = {vec2(0, 0), vec2(1, 0), vec2(0, 1)};
  m.triangles = {uvec3(0, 1, 2)};
  Material mat;
  mat.emission = vec3(2.0f);
  mat.emissive_tex.texture = 0;
  texture.srgb = false;
  s.textures.push_back(std::move(texture));
  s.materials.push_back(mat);
  s.meshes.push_back(m);
  s.instances.push_back(Instance{0});
  return s;
}

Texture stripe_texture(int size, float white_from_u) {
  Texture t;
  t.width = t.height = size;
  t.wrap_s = t.wrap_t = Wrap::Clamp;
  t.rgba.resize(size_t(size) * size * 4);
  for (int y = 0; y < size; ++y)
    for (int x = 0; x < size; ++x)
      for (int c = 0; c < 4; ++c) t.rgba[(size_t(y) * size + x) * 4 + c] = (x + 0.5f) / size > white_from_u ? 255 : 0;
  return t;
}

// The part of the triangle u + v <= 1 with u > 1/2 is a quarter of its area: average emission 2 * 1/4.
TEST(Lights, TextureEmissionIsIntegratedOverTheTriangle) {
  Scene s = textured_triangle_scene(stripe_texture(64, 0.5f));
  vec3 avg = integrate_triangle_emission(s, s.meshes[0], 0);
  EXPECT_NEAR(avg.x, 0.5f, 0.02f);
  LightList lights(s);
  ASSERT_EQ(lights.triangle_count(), 1u);
  EXPECT_NEAR(lights.triangles()[0].power(), 0.5f * 0.5f * kPi, 0.02f);
}

// A triangle whose texture is black everywhere it covers is not a light, though its material is emissive.
TEST(Lights, BlackTexturedTrianglesAreNotLights) {
  Scene s = textured_triangle_scene(stripe_texture(64, 2.0f));
  LightList lights(s);
  EXPECT_EQ(lights.triangle_count(), 0u);
  EXPECT_EQ(lights.light_index(0, 0), -1);
}

// Emitting-triangle counts of the shared scenes. ../shared/scenes/README.md counts a triangle when any of
// four point samples exceeds 1e-3; the light list keeps a triangle when its average emission does, so the
// counts may differ a little (the difference is reported) but must agree within 10%.
TEST(Lights, SharedSceneEmitterCounts) {
  if (testing::shared_scenes_dir().empty()) GTEST_SKIP() << testing::shared_scenes_skip_reason();
  struct Case {
    const char* file;
    size_t readme_count;
  };
  for (Case c : {Case{"LightsPunctualLamp/glTF/LightsPunctualLamp.gltf", 358},
                 Case{"StainedGlassLamp/glTF-JPG-PNG/StainedGlassLamp.gltf", 14602},
                 Case{"DamagedHelmet/glTF/DamagedHelmet.gltf", 234},
                 Case{"EmissiveStrengthTest/glTF/EmissiveStrengthTest.gltf", 60}}) {
    const std::string path = testing::shared_scene_file(c.file);
    if (path.empty()) continue;  // missing: shared_scene_file failed the test
    Scene scene = load_scene(path);
    LightList lights(scene);
    std::printf("%s: %zu emitting triangles (README: %zu)\n", c.file, lights.triangle_count(), c.readme_count);
    EXPECT_NEAR(double(lights.triangle_count()), double(c.readme_count), 0.1 * c.readme_count) << c.file;
  }
}

// Lights of animated instances follow them: after set_time + update, every light triangle of a car is
// where the car's mesh triangle is.
TEST(Lights, AnimatedLightsFollowTheirInstances) {
  Scene scene = make_city_scene(7);
  LightList lights(scene);
  scene.set_time(1.5f);
  lights.update(scene);
  size_t moved = 0;
  for (const TriangleLight& l : lights.triangles()) {
    if (!scene.instances[l.instance].animated) continue;
    WorldTriangle w = world_triangle(scene, l.instance, l.prim);
    EXPECT_LT(glm::length(w.p0 - l.p0), 1e-3f);
    EXPECT_LT(glm::length((w.p1 - w.p0) - l.e1), 1e-3f);
    ++moved;
  }
  EXPECT_GT(moved, 0u);
  size_t attached = 0;
  for (size_t k = 0; k < scene.punctual_lights.size(); ++k) {
    const PunctualLight& local = scene.punctual_lights[k];
    if (local.instance < 0) continue;
    vec3 expected = transform_point(scene.instances[local.instance].transform, local.position);
    EXPECT_LT(glm::length(lights.punctual()[k].position - expected), 1e-3f);
    ++attached;
  }
  EXPECT_GT(attached, 0u);
}

// LightList::fixed, on which temporal reuse relies to keep a sample's stored point instead of placing it anew on the
// other frame's list: a fixed light's point is the same bits in every list of the scene (last frame's updated in place,
// or rebuilt as power animations rebuild it), while the lights of the moving cars and of a power-animated material are
// not fixed, and their points or radiance do change.
TEST(Lights, FixedLightsArePlacedAlikeByEveryFramesList) {
  Scene scene = make_city_scene(7);
  // A power animation of the material of the first static emitting instance (a city window material).
  int animated_material = -1;
  for (const Instance& inst : scene.instances)
    if (!inst.animated && scene.materials[scene.meshes[inst.mesh].material].emissive()) {
      animated_material = scene.meshes[inst.mesh].material;
      break;
    }
  ASSERT_GE(animated_material, 0);
  PowerAnimation power;
  power.target = PowerAnimation::Target::Material;
  power.index = animated_material;
  power.base = scene.materials[size_t(animated_material)].emission;
  power.scale.times = {0.0f, 2.0f};
  power.scale.values = {1.0f, 3.0f};
  scene.power_animations.push_back(power);
  scene.set_time(0.0f);
  LightList before(scene), updated(scene);
  scene.set_time(1.5f);
  updated.update(scene);
  const LightList rebuilt(scene);
  ASSERT_EQ(rebuilt.triangle_count(), before.triangle_count());
  auto same = [](const LightPoint& a, const LightPoint& b) {
    for (int c = 0; c < 3; ++c)
      if (!same_bits(a.position[c], b.position[c]) || !same_bits(a.normal[c], b.normal[c]) ||
          !same_bits(a.radiance[c], b.radiance[c]))
        return false;
    return a.two_sided == b.two_sided;
  };
  Rng rng(5, 1);
  size_t fixed = 0, moving = 0, moved = 0, powered = 0, changed = 0;
  for (size_t k = 0; k < before.triangle_count(); ++k) {
    const TriangleLight& l = before.triangles()[k];
    const bool on_car = scene.instances[l.instance].animated;
    const bool on_animated_material = scene.meshes[scene.instances[l.instance].mesh].material == animated_material;
    EXPECT_EQ(before.fixed(k), !on_car && !on_animated_material) << "light " << k;
    EXPECT_EQ(rebuilt.fixed(k), before.fixed(k)) << "light " << k;
    const vec2 u(rng.next_float(), rng.next_float());
    const LightPoint old_point = before.triangle_point(scene, k, u);
    const bool kept =
        same(old_point, updated.triangle_point(scene, k, u)) && same(old_point, rebuilt.triangle_point(scene, k, u));
    if (before.fixed(k)) {
      EXPECT_TRUE(kept) << "fixed light " << k << " placed differently";
      ++fixed;
    } else {
      (on_car ? moving : powered) += 1;
      changed += !kept;
      moved += on_car && !same(old_point, updated.triangle_point(scene, k, u));
    }
  }
  EXPECT_GT(fixed, 1000u);
  EXPECT_GT(moving, 0u);
  EXPECT_GT(powered, 0u);
  EXPECT_EQ(moved, moving) << "every car light moves between t = 0 and 1.5";
  EXPECT_EQ(changed, moving + powered) << "every light that is not fixed changes";
  EXPECT_FALSE(before.fixed(before.triangle_count()));  // punctual lights are never fixed
}

// For triangle lights the density sample() reports is the one pdf_solid_angle() computes for the same
// point, and its Monte Carlo estimate of the solid angle of the triangle (E[1/pdf]) matches the exact
// solid angle (Van Oosterom & Strackee 1983) within 4 standard errors.
TEST(Lights, TriangleSamplingDensityIsConsistent) {
  Scene s = make_cornell_scene();
  LightList lights(s);
  ASSERT_GT(lights.triangle_count(), 0u);
  const TriangleLight& l = lights.triangles()[0];
  vec3 p(0.1f, 0.5f, 0.2f);
  Rng rng(3, 4);
  const int n = 200000;
  double sum = 0.0, sum2 = 0.0;
  for (int i = 0; i < n; ++i) {
    LightSample ls = lights.sample(s, 0, p, vec2(rng.next_float(), rng.next_float()));
    ASSERT_GT(ls.pdf, 0.0f);
    ASSERT_NEAR(ls.pdf, lights.pdf_solid_angle(0, p, ls.position), 1e-3f * ls.pdf);
    sum += 1.0 / ls.pdf;
    sum2 += 1.0 / (double(ls.pdf) * ls.pdf);
  }
  double mean = sum / n, err = std::sqrt((sum2 / n - mean * mean) / n);
  glm::dvec3 a = glm::dvec3(l.p0) - glm::dvec3(p), b = glm::dvec3(l.p0 + l.e1) - glm::dvec3(p),
             c = glm::dvec3(l.p0 + l.e2) - glm::dvec3(p);
  double la = glm::length(a), lb = glm::length(b), lc = glm::length(c);
  double omega =
      2.0 * std::abs(std::atan2(glm::dot(a, glm::cross(b, c)),
                                la * lb * lc + glm::dot(a, b) * lc + glm::dot(a, c) * lb + glm::dot(b, c) * la));
  EXPECT_NEAR(mean, omega, 4.0 * err + 1e-7);
}

// glTF 3.7.4: a transform with negative determinant flips the front side. A triangle wound
// counter-clockwise around +z under scale (-1, 1, 1) still faces +z: its light and its surface agree.
TEST(Lights, MirroredInstancesKeepTheirFrontSide) {
  Scene s;
  Mesh m;
  m.positions = {vec3(0, 0, 0), vec3(1, 0, 0), vec3(0, 1, 0)};
  m.triangles = {uvec3(0, 1, 2)};
  Material mat;
  mat.emission = vec3(1.0f);
  s.materials.push_back(mat);
  s.meshes.push_back(m);
  mat4 mirror = glm::scale(mat4(1.0f), vec3(-1.0f, 1.0f, 1.0f));
  s.instances.push_back(Instance{0, mirror, mirror});
  LightList lights(s);
  ASSERT_EQ(lights.triangle_count(), 1u);
  EXPECT_GT(lights.triangles()[0].normal.z, 0.99f);
  SurfacePoint front = surface_at(s, 0, 0, vec2(0.2f), vec3(0, 0, 1));
  EXPECT_TRUE(front.front_face);
  EXPECT_EQ(front.emission, vec3(1.0f));
  SurfacePoint back = surface_at(s, 0, 0, vec2(0.2f), vec3(0, 0, -1));
  EXPECT_FALSE(back.front_face);
  EXPECT_EQ(back.emission, vec3(0.0f));
}

}  // namespace
}  // namespace candela

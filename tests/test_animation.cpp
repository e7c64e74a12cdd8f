// Keyframe tracks (step, linear, smooth, quaternion slerp), instance and light-power animation through
// Scene::set_time, and glTF node animation channels read by the loader.
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include "engine/animation.h"
#include "engine/gltf_loader.h"
#include "engine/scene.h"

namespace candela {
namespace {

Track<float> track(std::vector<float> times, std::vector<float> values, Interpolation interpolation) {
  Track<float> t;
  t.times = std::move(times);
  t.values = std::move(values);
  t.interpolation = interpolation;
  return t;
}

TEST(Track, StepHoldsTheLastKey) {
  Track<float> t = track({0.0f, 1.0f, 3.0f}, {5.0f, 7.0f, -1.0f}, Interpolation::Step);
  EXPECT_EQ(t.at(-1.0f), 5.0f);
  EXPECT_EQ(t.at(0.5f), 5.0f);
  EXPECT_EQ(t.at(1.0f), 7.0f);
  EXPECT_EQ(t.at(2.99f), 7.0f);
  EXPECT_EQ(t.at(10.0f), -1.0f);
}

TEST(Track, LinearInterpolatesAndClamps) {
  Track<float> t = track({0.0f, 2.0f, 3.0f}, {0.0f, 4.0f, 0.0f}, Interpolation::Linear);
  EXPECT_FLOAT_EQ(t.at(-5.0f), 0.0f);
  EXPECT_FLOAT_EQ(t.at(0.5f), 1.0f);
  EXPECT_FLOAT_EQ(t.at(2.0f), 4.0f);
  EXPECT_FLOAT_EQ(t.at(2.5f), 2.0f);
  EXPECT_FLOAT_EQ(t.at(9.0f), 0.0f);
}

// Catmull-Rom passes through every key, reproduces a straight line exactly (keys on a line, uneven
// spacing), and its derivative is continuous across a key (one-sided differences over 2e-4 agree to 0.01: curvature
// times step plus float rounding).
TEST(Track, SmoothPassesThroughKeysAndIsC1) {
  Track<float> line = track({0.0f, 1.0f, 3.0f, 4.0f}, {1.0f, 3.0f, 7.0f, 9.0f}, Interpolation::Smooth);
  for (float t : {0.0f, 0.3f, 1.0f, 2.2f, 3.7f, 4.0f}) EXPECT_NEAR(line.at(t), 1.0f + 2.0f * t, 1e-5f) << t;
  Track<float> wave = track({0.0f, 1.0f, 2.5f, 3.0f}, {0.0f, 2.0f, -1.0f, 1.0f}, Interpolation::Smooth);
  for (float key : {1.0f, 2.5f}) {
    EXPECT_NEAR(wave.at(key), key == 1.0f ? 2.0f : -1.0f, 1e-6f);
    const float h = 2e-4f;
    float left = (wave.at(key) - wave.at(key - h)) / h, right = (wave.at(key + h) - wave.at(key)) / h;
    EXPECT_NEAR(left, right, 0.01f) << "derivative jumps at key " << key;
  }
}

TEST(Track, QuaternionsTakeTheShortArc) {
  Track<quat> t;
  t.times = {0.0f, 1.0f};
  quat a = glm::angleAxis(0.0f, vec3(0, 1, 0));
  quat b = -glm::angleAxis(glm::radians(90.0f), vec3(0, 1, 0));  // same rotation, opposite hemisphere
  t.values = {a, b};
  vec3 x = glm::mat3_cast(t.at(0.5f)) * vec3(1, 0, 0);
  EXPECT_NEAR(x.x, std::cos(glm::radians(45.0f)), 1e-5f);
  EXPECT_NEAR(x.z, -std::sin(glm::radians(45.0f)), 1e-5f);
}

// Euler keys 0 and 360 degrees turn the instance a full circle (a quaternion track could not tell them
// apart); the rotation happens about the pivot given by `before`/`after`.
TEST(InstanceAnimation, EulerTurnsAboutThePivot) {
  InstanceAnimation a;
  vec3 pivot(2.0f, 0.0f, 0.0f);
  a.after = glm::translate(mat4(1.0f), pivot);
  a.before = glm::translate(mat4(1.0f), -pivot);
  a.euler_degrees.times = {0.0f, 1.0f};
  a.euler_degrees.values = {vec3(0.0f), vec3(0.0f, 360.0f, 0.0f)};
  vec3 p(3.0f, 0.0f, 0.0f);
  vec3 half = transform_point(a.transform_at(0.5f), p);
  EXPECT_NEAR(half.x, 1.0f, 1e-5f);
  EXPECT_NEAR(half.z, 0.0f, 1e-5f);
  vec3 quarter = transform_point(a.transform_at(0.25f), p);
  EXPECT_NEAR(quarter.x, 2.0f, 1e-5f);
  EXPECT_NEAR(quarter.z, -1.0f, 1e-5f);
  EXPECT_NEAR(glm::length(transform_point(a.transform_at(1.0f), p) - p), 0.0f, 1e-5f);
}

TEST(PowerAnimation, ScalesPunctualIntensityAndMaterialEmission) {
  Scene scene;
  scene.punctual_lights.push_back(PunctualLight{});
  scene.materials.push_back(Material{});
  PowerAnimation light{PowerAnimation::Target::Punctual, 0, vec3(2.0f),
                       track({0.0f, 1.0f}, {1.0f, 3.0f}, Interpolation::Linear)};
  PowerAnimation glow{PowerAnimation::Target::Material, 0, vec3(1.0f, 0.5f, 0.0f),
                      track({0.0f}, {4.0f}, Interpolation::Step)};
  scene.power_animations = {light, glow};
  EXPECT_TRUE(scene.animated());
  scene.set_time(0.5f);
  EXPECT_FLOAT_EQ(scene.punctual_lights[0].intensity.x, 4.0f);
  EXPECT_FLOAT_EQ(scene.materials[0].emission.y, 2.0f);
}

// tests/data/animated/moving_quad.gltf: node "mover" (child of "parent" at z = -5) translates LINEARly
// (0,0,0) -> (2,0,0) -> (2,4,0) at t = 0, 1, 2 s and turns 90 degrees about +Y in a STEP at t = 1;
// node "still" carries the same mesh and no animation.
TEST(GltfAnimation, NodeChannelsMoveTheirInstances) {
  Scene scene = load_gltf(std::string(CANDELA_SOURCE_DIR) + "/tests/data/animated/moving_quad.gltf");
  ASSERT_EQ(scene.instances.size(), 2u);
  ASSERT_EQ(scene.instance_animations.size(), 1u);
  const int mover = scene.instance_animations[0].instance;
  EXPECT_EQ(scene.instances[size_t(mover)].name, "mover");
  EXPECT_TRUE(scene.instances[size_t(mover)].animated);
  EXPECT_FALSE(scene.instances[size_t(1 - mover)].animated);
  auto corner = [&](float t) {  // where the quad's (1, 0, 0) corner is at time t
    scene.set_time(t);
    return transform_point(scene.instances[size_t(mover)].transform, vec3(1.0f, 0.0f, 0.0f));
  };
  vec3 p = corner(0.5f);  // translation (1,0,0), no rotation yet, parent at z = -5
  EXPECT_NEAR(p.x, 2.0f, 1e-5f);
  EXPECT_NEAR(p.z, -5.0f, 1e-5f);
  p = corner(1.5f);  // translation (2,2,0), rotated: (1,0,0) -> (0,0,-1)
  EXPECT_NEAR(p.x, 2.0f, 1e-5f);
  EXPECT_NEAR(p.y, 2.0f, 1e-5f);
  EXPECT_NEAR(p.z, -6.0f, 1e-5f);
  p = corner(7.0f);  // after the last key: held
  EXPECT_NEAR(p.y, 4.0f, 1e-5f);
}

}  // namespace
}  // namespace candela

// Direct lighting with every light sampler: no sampler misses a light that contributes, every one is
// unbiased against a converged reference, and the better samplers have lower error at equal samples.
#include <gtest/gtest.h>

#include "engine/builtin_scenes.h"
#include "engine/image_metrics.h"
#include "engine/path_tracer.h"
#include "samplers/light_tree.h"
#include "samplers/simple_samplers.h"
#include "tests/render_helpers.h"

namespace candela {
namespace {

// Can any point of triangle light l reach p with normal n? Tested at the corners, edge midpoints and
// centroid, slightly inside the triangle.
bool contributes(const TriangleLight& l, const vec3& p, const vec3& n) {
  for (vec2 b : {vec2(0.02f, 0.02f), vec2(0.96f, 0.02f), vec2(0.02f, 0.96f), vec2(0.49f, 0.02f), vec2(0.02f, 0.49f),
                 vec2(0.49f, 0.49f), vec2(1.0f / 3.0f)}) {
    vec3 y = l.p0 + l.e1 * b.x + l.e2 * b.y;
    bool emits_towards_p = l.two_sided || glm::dot(l.normal, p - y) > 0.0f;
    if (emits_towards_p && glm::dot(n, y - p) > 0.0f) return true;
  }
  return false;
}

// Receivers behind, beside and among the lights (inside their nodes' boxes): every contributing light
// keeps a non-zero probability under the tree and the exhaustive sampler.
TEST(DirectLight, TreeNeverDropsAContributingLight) {
  Scene scene = make_manylights_scene(256, 7);
  LightList lights(scene);
  LightTreeSampler tree(lights);
  ExhaustiveLightSampler exhaustive(lights);
  Rng rng(31, 1);
  int checked = 0;
  for (int k = 0; k < 300; ++k) {
    // Heights from the floor up into the ceiling's light layer (y = 4.99) and just above it.
    vec3 p(rng.next_float() * 20.0f - 10.0f, 4.0f + rng.next_float() * 1.2f, rng.next_float() * 20.0f - 10.0f);
    if (k % 3 == 0) p.y = 4.99f + (rng.next_float() - 0.5f) * 0.004f;
    vec3 n = glm::normalize(vec3(rng.next_float() - 0.5f, rng.next_float() - 0.5f, rng.next_float() - 0.5f));
    ShadingContext ctx{p, n};
    for (uint32_t i = 0; i < lights.triangle_count(); ++i) {
      if (!contributes(lights.triangles()[i], p, n)) continue;
      ++checked;
      ASSERT_GT(tree.pmf(ctx, i), 0.0f) << "light " << i << " at point " << k;
      ASSERT_GT(exhaustive.pmf(ctx, i), 0.0f) << "light " << i << " at point " << k;
    }
  }
  EXPECT_GT(checked, 10000);
}

// Direct light (max depth 1) of `scene` with a sampler: per-pixel means.
template <class Sampler>
Image render_direct(const Scene& scene, const LightList& lights, int w, int h, int spp, uint64_t seed) {
  return testing::render_paths<Sampler>(scene, lights, w, h, spp, 1, seed);
}

class DirectLightScene : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    scene_ = new Scene(make_manylights_scene(1024, 7));
    lights_ = new LightList(*scene_);
    // Reference: 2048 paths per pixel with the tree (its own error is 1/128 of a 16-spp estimate's).
    reference_ = new Image(render_direct<LightTreeSampler>(*scene_, *lights_, kW, kH, 2048, 999));
  }
  static void TearDownTestSuite() { delete reference_; delete lights_; delete scene_; }
  static constexpr int kW = 32, kH = 18;
  static Scene* scene_;
  static LightList* lights_;
  static Image* reference_;
};
Scene* DirectLightScene::scene_ = nullptr;
LightList* DirectLightScene::lights_ = nullptr;
Image* DirectLightScene::reference_ = nullptr;

// Unbiasedness: with each sampler, the mean difference to the reference is within 4 standard errors
// (two-sided, about 6e-5 chance of a false failure per sampler).
TEST_F(DirectLightScene, EverySamplerIsUnbiased) {
  auto check = [&](const char* name, const Image& img) {
    ImageError e = compare_images(img, *reference_);
    EXPECT_LT(std::abs(e.mean_difference), 4.0 * e.standard_error + 1e-6) << name << ": mean difference " << e.mean_difference;
    std::printf("%-10s mean difference %+.5f (standard error %.5f), MSE %.3e, relMSE %.3e\n", name, e.mean_difference,
                e.standard_error, e.mse, e.rel_mse);
  };
  check("uniform", render_direct<UniformLightSampler>(*scene_, *lights_, kW, kH, 256, 1));
  check("power", render_direct<PowerLightSampler>(*scene_, *lights_, kW, kH, 256, 2));
  check("tree", render_direct<LightTreeSampler>(*scene_, *lights_, kW, kH, 256, 3));
  check("exhaustive", render_direct<ExhaustiveLightSampler>(*scene_, *lights_, kW, kH, 64, 4));
}

// Equal sample count (64 paths per pixel): relative MSE of tree < power < uniform.
TEST_F(DirectLightScene, VarianceOrderingTreePowerUniform) {
  double uniform = compare_images(render_direct<UniformLightSampler>(*scene_, *lights_, kW, kH, 64, 5), *reference_).rel_mse;
  double power = compare_images(render_direct<PowerLightSampler>(*scene_, *lights_, kW, kH, 64, 6), *reference_).rel_mse;
  double tree = compare_images(render_direct<LightTreeSampler>(*scene_, *lights_, kW, kH, 64, 7), *reference_).rel_mse;
  std::printf("relMSE at 64 spp: uniform %.3e, power %.3e, tree %.3e\n", uniform, power, tree);
  EXPECT_LT(tree, power);
  EXPECT_LT(power, uniform);
}

}  // namespace
}  // namespace candela

// ReSTIR DI reuse beyond the core stages: the disocclusion boost, the boiling filter and final visibility
// reuse (moving lights: Unbiased.MovingLights).
#include <gtest/gtest.h>

#include "apps/renderer.h"
#include "engine/builtin_scenes.h"
#include "engine/image_metrics.h"
#include "tests/render_helpers.h"

namespace candela {
namespace {

RenderSettings restir_settings(int w, int h, uint64_t seed) {
  RenderSettings s;
  s.width = w;
  s.height = h;
  s.method = Method::RestirDi;
  s.accumulate = false;
  s.seed = seed;
  return s;
}

// Mean confidence M of the final reservoirs over pixels with a surface.
double mean_confidence(const Renderer& renderer) {
  double m = 0.0;
  int n = 0;
  for (size_t i = 0; i < renderer.gbuffer().size(); ++i)
    if (renderer.gbuffer().hit(i)) m += renderer.di_reservoirs()[i].M, ++n;
  return m / std::max(n, 1);
}

// After a camera cut no pixel finds its history, and the boost gives each pixel 10 spatial neighbours
// instead of 5: the final reservoirs stand for more candidates (M grows with the neighbours merged).
TEST(RestirDiReuse, DisocclusionBoostAddsNeighbours) {
  Scene scene = make_manylights_scene(256, 7);
  CameraDesc a = scene.default_camera(), b = a;
  b.position = vec3(-8.5f, 2.2f, -8.5f);
  b.target = vec3(2.0f, 1.2f, 2.0f);
  auto after_cut = [&](int boost) {
    RenderSettings s = restir_settings(64, 36, 3);
    s.di_reuse.spatial_radius = 5.0f;  // most neighbours on similar surfaces at this small size
    s.di_reuse.disocclusion_neighbours = boost;
    Renderer renderer(scene, s);
    testing::render_checked(renderer, 0, 0.0f, a);
    testing::render_checked(renderer, 1, 0.0f, b);
    return mean_confidence(renderer);
  };
  double plain = after_cut(5), boosted = after_cut(10);
  std::printf("mean M after a camera cut: %.1f with 5 neighbours, %.1f with the boost to 10\n", plain, boosted);
  EXPECT_GT(boosted, 1.4 * plain);
}

// The boiling filter thresholds each reservoir's estimated contribution p_hat(y) W against 10x the mean
// contribution over its 16x16 block's reservoirs with W > 0, and drops (W = w_sum = 0, M kept) those above.
// One 16x16 block: 128 reservoirs with W = 0 (no sample; p_hat 1), 125 with p_hat = W = 1, and
//   A: p_hat 0.01, W 1000 (contribution 10),  B: p_hat 100, W 1 (contribution 100),  C: p_hat 3, W 4 (12).
// Mean contribution over the 128 with W > 0: (125 + 10 + 100 + 12) / 128 = 1.93, limit 19.3: B alone is
// dropped. A filter on W alone would drop A (W 1000 > 10 x mean W 8.8) and keep B; one that averaged over
// all 256 reservoirs (limit 9.65) would also drop A and C. Exact comparisons: the filter only copies
// and zeroes values.
TEST(RestirDiReuse, BoilingFilterDropsOutliersOnly) {
  const int w = 16, h = 16;
  std::vector<DiReservoir> reservoirs(size_t(w) * h);
  auto set = [&](size_t i, float p_hat, float W) {
    reservoirs[i].p_hat_y = p_hat;
    reservoirs[i].W = W;
    reservoirs[i].w_sum = p_hat * W;
    reservoirs[i].M = 1.0f;
  };
  for (size_t i = 0; i < reservoirs.size(); ++i) set(i, 1.0f, i % 2 == 0 ? 0.0f : 1.0f);  // odd: the 128 with W > 0
  const size_t a = 37, b = 39, c = 41;  // odd pixels: three of the 128
  set(a, 0.01f, 1000.0f);
  set(b, 100.0f, 1.0f);
  set(c, 3.0f, 4.0f);
  const std::vector<DiReservoir> before = reservoirs;
  std::vector<DiSurface> surfaces(reservoirs.size());
  LightList lights;
  di_boiling_filter(DiDomain{surfaces, w, h, vec3(0.0f), lights}, 10.0f, reservoirs);
  EXPECT_EQ(reservoirs[b].W, 0.0f);
  EXPECT_EQ(reservoirs[b].w_sum, 0.0f);
  EXPECT_EQ(reservoirs[b].M, 1.0f);  // kept: the reservoir still stands for its candidates
  EXPECT_EQ(reservoirs[b].p_hat_y, 100.0f);
  for (size_t i = 0; i < reservoirs.size(); ++i)
    if (i != b) {
      EXPECT_EQ(reservoirs[i].W, before[i].W) << i;
      EXPECT_EQ(reservoirs[i].w_sum, before[i].w_sum) << i;
      EXPECT_EQ(reservoirs[i].M, before[i].M) << i;
    }
}

// Static scene and camera: final visibility reuse saves shadow rays where pixels keep their sample, and
// changes the image little (the surface point moves within the pixel with the jitter): the mean stays
// within 1% and the relMSE against the traced image is below 1% of the image's own.
TEST(RestirDiReuse, VisibilityReuseSavesShadowRays) {
  Scene scene = make_manylights_scene(256, 7);
  auto run = [&](int reuse_frames, uint64_t& shade_rays) {
    RenderSettings s = restir_settings(96, 54, 9);
    s.di_reuse.visibility_reuse_frames = reuse_frames;
    Renderer renderer(scene, s);
    shade_rays = 0;
    for (int frame = 0; frame < 10; ++frame) {
      FrameStats stats = testing::render_checked(renderer, frame, 0.0f, scene.default_camera());
      for (const StageStats& st : stats.stages)
        if (st.name == "di_shade" && frame > 0) shade_rays += st.rays;
    }
    return renderer.image();
  };
  uint64_t traced = 0, reused = 0;
  Image all = run(0, traced), some = run(4, reused);
  double rel_mse = compare_images(some, all).rel_mse;
  std::printf(
      "shadow rays in frames 1-9: %llu traced every frame, %llu with reuse (%.2fx); image mean %.5f vs %.5f, "
      "relMSE between them %.2e\n",
      (unsigned long long)traced, (unsigned long long)reused, double(reused) / traced, image_mean(some),
      image_mean(all), rel_mse);
  EXPECT_LT(double(reused), 0.9 * double(traced));
  EXPECT_NEAR(image_mean(some) / image_mean(all), 1.0, 0.01);
  EXPECT_LT(rel_mse, 0.01);
}

}  // namespace
}  // namespace candela

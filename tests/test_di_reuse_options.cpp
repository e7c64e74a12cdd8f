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

// A block of equal reservoirs with one outlier 1000x brighter: the filter drops the outlier only.
TEST(RestirDiReuse, BoilingFilterDropsOutliersOnly) {
  const int w = 16, h = 16;
  std::vector<DiReservoir> reservoirs(size_t(w) * h);
  for (DiReservoir& r : reservoirs) r.p_hat_y = r.W = r.M = 1.0f;
  reservoirs[37].W = 1000.0f;
  reservoirs[38].W = 5.0f;  // bright, but below the threshold of 10 x the block mean (about 4.9)
  std::vector<DiSurface> surfaces(reservoirs.size());
  LightList lights;
  di_boiling_filter(DiDomain{surfaces, w, h, vec3(0.0f), lights}, 10.0f, reservoirs);
  EXPECT_EQ(reservoirs[37].W, 0.0f);
  EXPECT_EQ(reservoirs[37].M, 1.0f);  // kept: the reservoir still stands for its candidates
  EXPECT_EQ(reservoirs[38].W, 5.0f);
  for (size_t i = 0; i < reservoirs.size(); ++i)
    if (i != 37 && i != 38) {
      EXPECT_EQ(reservoirs[i].W, 1.0f) << i;
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
  std::printf("shadow rays in frames 1-9: %llu traced every frame, %llu with reuse (%.2fx); image mean %.5f vs %.5f, "
              "relMSE between them %.2e\n", (unsigned long long)traced, (unsigned long long)reused, double(reused) / traced,
              image_mean(some), image_mean(all), rel_mse);
  EXPECT_LT(double(reused), 0.9 * double(traced));
  EXPECT_NEAR(image_mean(some) / image_mean(all), 1.0, 0.01);
  EXPECT_LT(rel_mse, 0.01);
}

}  // namespace
}  // namespace candela

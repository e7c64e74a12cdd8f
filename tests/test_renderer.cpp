// The Renderer's life cycle: new settings taken in place (Renderer::apply_settings, what the viewer does on
// every settings change and dynamic-resolution step) give the frames a new Renderer would; a frame's ray log
// holds the rays it counts.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>

#include "apps/renderer.h"
#include "engine/builtin_scenes.h"
#include "engine/ray_log.h"
#include "tests/render_helpers.h"
#include "tests/settings_builder.h"

namespace candela {
namespace {

// On still manylights: a Renderer that rendered 3 frames with settings A, then took settings B (another
// size, method, light sampler, denoiser, sampler), renders frames 3..5 bit for bit as a new Renderer with
// B does; for several pairs (A, B), including a change of size alone and a change back.
TEST(Renderer, AppliedSettingsEqualANewRenderer) {
  const Scene scene = make_manylights_scene(64, 7);
  const RenderSettings direct =
      testing::settings({{"width", 64}, {"height", 36}, {"method", "direct"}, {"light_sampler", "power"}});
  const RenderSettings restir = testing::settings(
      {{"width", 48}, {"height", 27}, {"method", "restir-di"}, {"light_sampler", "tree"}, {"denoise", "svgf"}}, direct);
  const RenderSettings small =
      testing::settings({{"width", 32}, {"height", 18}, {"sampler", "zsobol"}, {"denoise", "bilateral"}}, direct);
  const RenderSettings pt = testing::settings({{"method", "pt"}, {"max_depth", 3}, {"denoise", "none"}}, restir);
  struct Change {
    const RenderSettings *from, *to;
  };
  for (Change c : {Change{&direct, &restir}, Change{&restir, &small}, Change{&small, &direct}, Change{&restir, &pt}}) {
    Renderer changed(scene, *c.from);
    for (int f = 0; f < 3; ++f) testing::render_checked(changed, f, 0.0f, scene.default_camera());
    changed.apply_settings(*c.to);
    Renderer fresh(scene, *c.to);
    for (int f = 3; f < 6; ++f) {
      testing::render_checked(changed, f, 0.0f, scene.default_camera());
      testing::render_checked(fresh, f, 0.0f, scene.default_camera());
      const Image a = changed.image(), b = fresh.image();
      ASSERT_EQ(a.width, c.to->width);
      ASSERT_EQ(a.pixels.size(), b.pixels.size());
      EXPECT_EQ(0, std::memcmp(a.pixels.data(), b.pixels.data(), a.pixels.size() * sizeof(vec3)))
          << "frame " << f << ", " << a.width << "x" << a.height;
    }
  }
}

// The default light sampler, auto, is the light tree with region light tiles for restir-di and power for the
// other methods: frames bit for bit those of the explicit settings, also after a change of method alone
// (apply_settings). Fails if auto resolved otherwise, or if a method change kept the last method's sampler.
TEST(Renderer, AutoLightSamplerFollowsTheMethod) {
  const Scene scene = make_manylights_scene(64, 7);
  const RenderSettings direct = testing::settings({{"width", 48}, {"height", 27}, {"method", "direct"}});
  const RenderSettings restir = testing::settings({{"method", "restir-di"}}, direct);
  ASSERT_EQ(direct.light_sampler, LightSamplerKind::Auto);
  const RenderSettings direct_power = testing::settings({{"light_sampler", "power"}}, direct);
  const RenderSettings restir_tree = testing::settings({{"light_sampler", "tree"}, {"di_light_tiles", 1}}, restir);
  const RenderSettings restir_power = testing::settings({{"light_sampler", "power"}}, restir);
  auto frames = [&](Renderer& r, int first, int last) {
    for (int f = first; f <= last; ++f) testing::render_checked(r, f, 0.0f, scene.default_camera());
    return r.image().pixels;
  };
  auto fresh = [&](const RenderSettings& s) {
    Renderer r(scene, s);
    return frames(r, 0, 2);
  };
  EXPECT_EQ(fresh(direct), fresh(direct_power));
  EXPECT_EQ(fresh(restir), fresh(restir_tree));
  EXPECT_NE(fresh(restir), fresh(restir_power));
  Renderer changed(scene, direct);
  frames(changed, 0, 2);
  changed.apply_settings(restir);
  Renderer from_start(scene, restir_tree);
  EXPECT_EQ(frames(changed, 3, 5), frames(from_start, 3, 5));
}

}  // namespace
}  // namespace candela

namespace candela {
namespace {

// The ray log (engine/ray_log.h, the benchmark's replay of a frame's rays) records exactly the rays a frame
// counts in its stats, for every method (second frame: ReSTIR's temporal reuse runs), and its replay traces
// as many. A stage that traced rays without counting them (or counted rays it did not trace) fails it, and so
// would a query the log missed.
TEST(Renderer, RayLogRecordsTheFramesCountedRays) {
  for (const char* method : {"pt", "direct", "restir-di", "restir"}) {
    Renderer renderer(make_builtin_scene("manylights"),
                      testing::settings({{"width", 48}, {"height", 32}, {"method", method}, {"accumulate", false}}));
    const CameraDesc camera = renderer.scene().default_camera();
    renderer.render_frame(0, 0.0f, camera);
    RayLog log;
    renderer.set_ray_log(&log);
    const FrameStats stats = renderer.render_frame(1, 0.0f, camera);
    const uint64_t counted = stats.rays();
    renderer.set_ray_log(nullptr);
    EXPECT_GT(counted, uint64_t(48 * 32)) << method;
    EXPECT_EQ(log.rays(), counted) << method;
    // Each stage's queries are tagged with it: its recorded rays are the rays it counted, and replay alone.
    for (const StageStats& stage : stats.stages) {
      const auto k = std::find(log.stages().begin(), log.stages().end(), stage.name) - log.stages().begin();
      if (stage.rays == 0 && k == std::ssize(log.stages())) continue;
      ASSERT_LT(k, std::ssize(log.stages())) << method << ": " << stage.name;
      EXPECT_EQ(log.rays(int(k)), stage.rays) << method << ": " << stage.name;
      EXPECT_EQ(log.replay(renderer.tracer(), int(k)), stage.rays) << method << ": " << stage.name;
    }
    EXPECT_EQ(log.rays(0), 0u) << method << ": no query outside the stages";
    EXPECT_EQ(log.replay(renderer.tracer()), counted) << method;
    EXPECT_EQ(log.rays(), counted) << method << ": the replay recorded nothing more";
  }
}

}  // namespace
}  // namespace candela

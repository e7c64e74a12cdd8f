// The AOV table (apps/aovs.h): one name per plane, each plane's values are the G-buffer's or the
// reservoirs' own, and the displayed pixels map them as the table says.
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "apps/aovs.h"
#include "engine/builtin_scenes.h"
#include "tests/settings_builder.h"

namespace candela {
namespace {

// One restir-di frame of cornell at 32x24 (every AOV available).
Renderer rendered(Method method) {
  Renderer renderer(make_builtin_scene("cornell"),
                    testing::settings({{"width", 32}, {"height", 24}, {"method", name_of(method_names(), method)}}));
  renderer.render_frame(0, 0.0f, renderer.scene().default_camera());
  renderer.render_frame(1, 0.0f, renderer.scene().default_camera());  // motion and temporal reuse have a frame before
  return renderer;
}

TEST(Aovs, EveryNameIsOneAov) {
  std::set<std::string> names;
  for (const AovInfo& info : aov_table()) {
    EXPECT_TRUE(names.insert(info.name).second) << info.name;
    EXPECT_EQ(find_aov(info.name), &info);
    EXPECT_EQ(&aov_info(info.aov), &info);
  }
  EXPECT_EQ(find_aov("none"), nullptr);
  EXPECT_EQ(aov_names().size(), aov_table().size());
}

TEST(Aovs, PlanesHoldTheFramesValues) {
  const Renderer renderer = rendered(Method::RestirDi);
  const GBuffer& g = renderer.gbuffer();
  const std::vector<DiReservoir>& reservoirs = renderer.di_reservoirs();
  ASSERT_EQ(reservoirs.size(), g.size());
  EXPECT_EQ(aov_image(renderer, Aov::Radiance).pixels, renderer.image().pixels);
  const Image albedo = aov_image(renderer, Aov::Albedo), normal = aov_image(renderer, Aov::Normal),
              depth = aov_image(renderer, Aov::Depth), motion = aov_image(renderer, Aov::Motion),
              m = aov_image(renderer, Aov::ReservoirM), w = aov_image(renderer, Aov::ReservoirW);
  size_t hits = 0;
  for (size_t i = 0; i < g.size(); ++i) {
    const bool hit = g.hit(i);
    hits += hit;
    EXPECT_EQ(albedo.pixels[i], hit ? g.albedo[i] : vec3(0.0f)) << i;
    EXPECT_EQ(normal.pixels[i], hit ? g.shading_normal[i] : vec3(0.0f)) << i;
    EXPECT_EQ(depth.pixels[i], hit ? vec3(g.depth[i]) : vec3(0.0f)) << i;
    EXPECT_EQ(motion.pixels[i], hit ? vec3(g.motion[i], 0.0f) : vec3(0.0f)) << i;
    EXPECT_EQ(m.pixels[i], hit ? vec3(reservoirs[i].M) : vec3(0.0f)) << i;
    EXPECT_EQ(w.pixels[i], hit ? vec3(reservoirs[i].W) : vec3(0.0f)) << i;
  }
  EXPECT_GT(hits, g.size() / 2);
}

// Displayed pixels: normals as n * 0.5 + 0.5, depth and M over their largest value (so the farthest hit and
// the largest M are white), background black; radiance tonemapped as PNG files are.
TEST(Aovs, DisplayMapsAsTheTableSays) {
  const Renderer renderer = rendered(Method::RestirDi);
  const GBuffer& g = renderer.gbuffer();
  auto byte = [](float v) { return uint8_t(std::lround(std::clamp(v, 0.0f, 1.0f) * 255.0f)); };
  const Rgba8Image normal = aov_display_pixels(renderer, Aov::Normal, 1.0f);
  const Rgba8Image depth = aov_display_pixels(renderer, Aov::Depth, 1.0f);
  const Rgba8Image radiance = aov_display_pixels(renderer, Aov::Radiance, 2.0f);
  const Image image = renderer.image();
  float farthest = 0.0f;
  for (size_t i = 0; i < g.size(); ++i)
    if (g.hit(i)) farthest = std::max(farthest, g.depth[i]);
  for (size_t i = 0; i < g.size(); ++i) {
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(normal.pixels[4 * i + k], g.hit(i) ? byte(g.shading_normal[i][k] * 0.5f + 0.5f) : 0) << i;
      EXPECT_EQ(depth.pixels[4 * i + k], g.hit(i) ? byte(g.depth[i] / farthest) : 0) << i;
      EXPECT_EQ(radiance.pixels[4 * i + k], byte(tonemap_srgb(image.pixels[i], 2.0f)[k])) << i;
    }
    EXPECT_EQ(normal.pixels[4 * i + 3], 255);
  }
}

TEST(Aovs, ReservoirPlanesNeedRestir) {
  const Renderer renderer = rendered(Method::Direct);
  for (const AovInfo& info : aov_table()) {
    EXPECT_EQ(aov_available(info.aov, renderer), !info.restir) << info.name;
    if (!info.restir) continue;
    const Image image = aov_image(renderer, info.aov);
    EXPECT_EQ(image.width, 32);
    for (const vec3& p : image.pixels) EXPECT_EQ(p, vec3(0.0f)) << info.name;
  }
}

}  // namespace
}  // namespace candela

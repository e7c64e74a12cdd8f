// The AOV table (apps/aovs.h): one name per plane, each plane's values are the G-buffer's or the
// reservoirs' own, and the displayed pixels map them as the table says.
#include <gtest/gtest.h>

#include <bit>
#include <array>
#include <cmath>
#include <limits>
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
  const std::vector<ReuseReservoir>& reservoirs = renderer.di_reservoirs();
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
// srgb8 finds its codes among boundaries instead of by the power: the same code as lround(255 * OETF(m))
// for every 64th float of [0, 1] and every float of each 64-float step where the code changes, so every
// boundary exactly; NaN, negative and large values clamp. Fails if a boundary is off by one float or the
// start table by one code. tonemap_srgb8 is the filmic curve then srgb8 (one spot check here; the display
// test below compares every pixel).
TEST(Aovs, Srgb8CodesAreThoseOfThePowerFormula) {
  // The sRGB OETF (IEC 61966-2-1) as engine/image.cpp computes it, in single precision.
  auto formula = [](float m) {
    const float encoded = m <= 0.0031308f ? 12.92f * m : 1.055f * std::pow(m, 1.0f / 2.4f) - 0.055f;
    return int(std::lround(encoded * 255.0f));
  };
  const uint32_t one = std::bit_cast<uint32_t>(1.0f);
  size_t compared = 0;
  int previous = 0;
  for (uint32_t bits = 0; bits <= one; bits += 64) {
    const int code = formula(std::bit_cast<float>(bits));
    const uint32_t from = code != previous ? bits - 63 : bits;  // the whole step where the code changed
    for (uint32_t b = from; b <= bits; ++b, ++compared)
      ASSERT_EQ(int(srgb8(std::bit_cast<float>(b))), formula(std::bit_cast<float>(b)))
          << "m " << std::bit_cast<float>(b);
    previous = code;
  }
  EXPECT_EQ(previous, 255);
  for (float m : {-1.0f, 2.0f, std::numeric_limits<float>::infinity(), std::nanf("")})
    EXPECT_EQ(int(srgb8(m)), m > 1.0f ? 255 : 0) << m;
  const vec3 linear(0.02f, 0.3f, 7.0f);
  const std::array<uint8_t, 3> codes = tonemap_srgb8(linear, 1.5f);
  for (int k = 0; k < 3; ++k) EXPECT_EQ(int(codes[k]), int(std::lround(tonemap_srgb(linear, 1.5f)[k] * 255.0f)));
  std::printf("  %zu values compared\n", compared);
}

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

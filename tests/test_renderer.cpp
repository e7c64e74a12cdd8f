// The Renderer's life cycle: new settings taken in place (Renderer::apply_settings, what the viewer does on
// every settings change and dynamic-resolution step) give the frames a new Renderer would.
#include <gtest/gtest.h>

#include <cstring>

#include "apps/renderer.h"
#include "engine/builtin_scenes.h"
#include "tests/render_helpers.h"

namespace candela {
namespace {

// On still manylights: a Renderer that rendered 3 frames with settings A, then took settings B (another
// size, method, light sampler, denoiser, sampler), renders frames 3..5 bit for bit as a new Renderer with
// B does; for several pairs (A, B), including a change of size alone and a change back.
TEST(Renderer, AppliedSettingsEqualANewRenderer) {
  const Scene scene = make_manylights_scene(64, 7);
  RenderSettings direct;
  direct.width = 64;
  direct.height = 36;
  direct.method = Method::Direct;
  direct.light_sampler = LightSamplerKind::Power;
  RenderSettings restir = direct;
  restir.width = 48;
  restir.height = 27;
  restir.method = Method::RestirDi;
  restir.light_sampler = LightSamplerKind::Tree;
  restir.denoise.kind = DenoiserKind::Svgf;
  RenderSettings small = direct;
  small.width = 32;
  small.height = 18;
  small.sampler = SampleSequence::ZSobol;
  small.denoise.kind = DenoiserKind::Bilateral;
  RenderSettings pt = restir;
  pt.method = Method::PathTrace;
  pt.max_depth = 3;
  pt.denoise.kind = DenoiserKind::None;
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

}  // namespace
}  // namespace candela

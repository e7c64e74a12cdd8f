// The denoisers: on rendered frames they cut the error against a converged reference; on synthetic
// G-buffers they keep depth/normal edges, textures and emitters sharp, stay stable over time and let go of
// a disoccluded object's history. Fixed seeds throughout; thresholds and their reasons are stated per test.
#include <gtest/gtest.h>

#include <cstring>
#include <functional>
#include <limits>
#include <optional>

#include "apps/renderer.h"
#include "denoise/denoiser.h"
#include "denoise/svgf.h"
#include "denoise/edge_stopping.h"
#include "engine/builtin_scenes.h"
#include "engine/image_metrics.h"
#include "tests/render_helpers.h"
#include "engine/rng.h"
#include "engine/simd_targets.h"
#include "tests/settings_builder.h"

namespace candela {
namespace {

// One frame of `denoiser` (Denoiser, Svgf, ...) into a new image.
template <class D>
Image denoised(D& denoiser, const GBuffer& current, const GBuffer& previous, const Image& noisy, FrameStats& stats) {
  Image out;
  denoiser.denoise(current, previous, noisy, stats, out);
  return out;
}

// --- Rendered frames -------------------------------------------------------------------------------

constexpr int kW = 128, kH = 72;

RenderSettings noisy_settings(uint64_t seed) {
  // Pixel centres, as for the reference; every frame an independent 1-spp estimate.
  return testing::settings({{"width", kW},
                            {"height", kH},
                            {"method", "direct"},
                            {"spp", 1},
                            {"seed", seed},
                            {"jitter", false},
                            {"accumulate", false}});
}

// `frames` noisy frames of a still camera with their G-buffers.
struct Sequence {
  std::vector<Image> noisy;
  std::vector<GBuffer> gbuffers;
};

Sequence render_sequence(const Scene& scene, int frames, uint64_t seed) {
  Renderer renderer(scene, noisy_settings(seed));
  CameraDesc camera = scene.default_camera();
  Sequence s;
  for (int f = 0; f < frames; ++f) {
    testing::render_checked(renderer, f, 0.0f, camera);
    s.noisy.push_back(renderer.image());
    s.gbuffers.push_back(renderer.gbuffer());
  }
  return s;
}

// Converged direct light: 256 paths per pixel (its own relMSE is 1/256 of a 1-spp frame's, negligible
// beside the 5x reduction tested).
Image render_reference(const Scene& scene) {
  RenderSettings s = noisy_settings(777);
  s.spp = 256;
  Renderer renderer(scene, s);
  testing::render_checked(renderer, 0, 0.0f, scene.default_camera());
  return renderer.image();
}

// Denoises the whole sequence with one denoiser (history carried along); returns the last frame.
Image denoise_sequence(DenoiserKind kind, const Sequence& s) {
  Denoiser denoiser(DenoiserParams{kind});
  GBuffer none;
  Image out;
  for (size_t f = 0; f < s.noisy.size(); ++f) {
    FrameStats stats;
    denoiser.denoise(s.gbuffers[f], f > 0 ? s.gbuffers[f - 1] : none, s.noisy[f], stats, out);
  }
  return out;
}

// relMSE of `image` against `reference` over the pixels where pick(i).
double rel_mse_where(const Image& image, const Image& reference, const std::function<bool(size_t)>& pick) {
  double sum = 0.0;
  size_t n = 0;
  for (size_t i = 0; i < image.pixels.size(); ++i) {
    if (!pick(i)) continue;
    vec3 d = image.pixels[i] - reference.pixels[i];
    vec3 e = d * d / (reference.pixels[i] * reference.pixels[i] + vec3(0.01f));
    sum += e.x + e.y + e.z;
    n += 3;
  }
  return sum / double(n);
}

// The relMSE of a 1-spp direct-light frame against the converged reference falls at least 5x over the
// whole image (the requirement), bias from blurring (soft and contact shadows) included:
//  - SVGF, after 8 frames of a still camera with independent noise;
//  - the cross-bilateral filter, last frame alone. It used to be claimed over the pixels it filters only
//    (Guides::filtered: the pixels on either side of an emitter's border keep their input), when the
//    noisy frames were jittered and the whole image reached 1.3x (cornell) and 3.3x (manylights); with
//    frames through pixel centres, as the reference, it measures 7.0x and 7.9x over the whole image
//    (7.0x and 15.0x over the filtered pixels, 55% and 73% of the image, printed).
// No statistical tolerance: fixed seeds; measured margins over 5x: bilateral 7.0x and 7.9x, SVGF 5.6x and
// 62.9x (cornell, manylights).
void expect_five_times_lower(const Scene& scene, const char* name) {
  Image reference = render_reference(scene);
  Sequence s = render_sequence(scene, 8, 5);
  Guides guides;
  compute_guides(s.gbuffers.back(), false, guides);
  auto filtered = [&](size_t i) { return guides.filtered[i] != 0; };
  auto all = [](size_t) { return true; };
  size_t filtered_count = 0;
  for (size_t i = 0; i < guides.filtered.size(); ++i) filtered_count += filtered(i);
  Image bilateral = denoise_sequence(DenoiserKind::Bilateral, s), svgf = denoise_sequence(DenoiserKind::Svgf, s);
  double input = rel_mse_where(s.noisy.back(), reference, all),
         input_filtered = rel_mse_where(s.noisy.back(), reference, filtered);
  double bilateral_all = rel_mse_where(bilateral, reference, all),
         bilateral_filtered = rel_mse_where(bilateral, reference, filtered);
  double svgf_all = rel_mse_where(svgf, reference, all);
  std::printf(
      "%s relMSE, whole image: input %.4f, bilateral %.4f (%.1fx lower), svgf %.4f (%.1fx lower); "
      "filtered pixels (%.1f%% of the image): input %.4f, bilateral %.4f (%.1fx lower)\n",
      name, input, bilateral_all, input / bilateral_all, svgf_all, input / svgf_all,
      100.0 * double(filtered_count) / double(guides.filtered.size()), input_filtered, bilateral_filtered,
      input_filtered / bilateral_filtered);
  EXPECT_LT(svgf_all * 5.0, input) << name;
  EXPECT_LT(bilateral_all * 5.0, input) << name;
}

TEST(DenoiseRendered, CornellErrorFiveTimesLower) { expect_five_times_lower(make_cornell_scene(), "cornell"); }

TEST(DenoiseRendered, ManylightsErrorFiveTimesLower) {
  expect_five_times_lower(make_manylights_scene(1024, 7), "manylights");
}

// The renderer's `denoise` setting on ReSTIR DI frames (still camera, pixel centres, 12 frames of
// `manylights`): the shown image is the denoised one, its relMSE against the converged candidate stage
// (512 accumulated frames) is at least 5x lower than the same frame's noisy image (measured 12x), and the
// noisy image stays available.
TEST(DenoiseRendered, RendererDenoisesRestirFrames) {
  Scene scene = make_manylights_scene(1024, 7);
  const RenderSettings settings =
      testing::settings({{"width", 96}, {"height", 54}, {"method", "restir-di"}, {"jitter", false}});
  Renderer reference(scene, testing::settings({{"di_reuse", "none"}}, settings));
  for (int frame = 0; frame < 512; ++frame) testing::render_checked(reference, frame, 0.0f, scene.default_camera());
  Renderer renderer(scene, testing::settings({{"accumulate", false}, {"denoise", "svgf"}}, settings));
  FrameStats stats;
  for (int frame = 0; frame < 12; ++frame)
    stats = testing::render_checked(renderer, frame, 0.0f, scene.default_camera());
  double noisy = compare_images(renderer.noisy_image(), reference.image()).rel_mse;
  double denoised = compare_images(renderer.image(), reference.image()).rel_mse;
  std::printf("restir-di frame 12: relMSE noisy %.4f, svgf %.4f (%.1fx lower)\n", noisy, denoised, noisy / denoised);
  EXPECT_LT(denoised * 5.0, noisy);
  bool timed = false;
  for (const StageStats& st : stats.stages) timed |= st.name == "svgf_atrous";
  EXPECT_TRUE(timed);
}

// Still camera, 30 frames of cornell: SVGF's output changes from frame to frame (mean absolute change
// over pixels and channels, frames 10..29 once the history has filled) less than 1/5 of the input's.
// Temporal accumulation alone at alpha 0.2 keeps about a third of the per-frame noise amplitude,
// the a-trous filter removes most of the rest.
TEST(DenoiseRendered, SvgfIsTemporallyStable) {
  Sequence s = render_sequence(make_cornell_scene(), 30, 9);
  Svgf svgf;
  GBuffer none;
  std::vector<Image> out;
  for (size_t f = 0; f < s.noisy.size(); ++f) {
    FrameStats stats;
    out.push_back(denoised(svgf, s.gbuffers[f], f > 0 ? s.gbuffers[f - 1] : none, s.noisy[f], stats));
  }
  auto mean_change = [](const std::vector<Image>& frames) {
    double sum = 0.0;
    size_t n = 0;
    for (size_t f = 10; f < frames.size(); ++f)
      for (size_t i = 0; i < frames[f].pixels.size(); ++i, ++n) {
        vec3 d = glm::abs(frames[f].pixels[i] - frames[f - 1].pixels[i]);
        sum += (d.x + d.y + d.z) / 3.0;
      }
    return sum / double(n);
  };
  double input = mean_change(s.noisy), denoised = mean_change(out);
  std::printf("mean frame-to-frame change: input %.4f, svgf %.4f (ratio %.3f)\n", input, denoised, denoised / input);
  EXPECT_LT(denoised, 0.2 * input);
}

// SVGF's temporal stage in SIMD lanes gives the scalar stage's bits: two SVGF denoisers, one with the
// kernel (the default) and one with params.simd off, denoise the same 16 frames: 12 of a camera that moves
// sideways and forwards (motion vectors of fractional pixels: four bilinear taps per pixel, read by
// gathers; jittered samples; surfaces that appear at the borders and behind the boxes take the scalar 3x3
// search), then 4 of a still camera (one tap per pixel, whole vectors read by plain loads). Every output
// pixel must be equal to the bit. Each frame's output depends on the temporal stage of every frame before
// it, through the history.
TEST(DenoiseRendered, SvgfTemporalLanesGiveTheScalarBits) {
  const Scene scene = make_cornell_scene();
  RenderSettings settings = noisy_settings(5);
  settings.jitter = true;
  for_each_simd_target([&](const char* target) {
    Renderer renderer(scene, settings);
    SvgfParams scalar_params;
    scalar_params.simd = false;
    Svgf lanes, scalar(scalar_params);
    GBuffer previous;
    for (int f = 0; f < 16; ++f) {
      const float t = float(std::min(f, 11));
      CameraDesc camera = scene.default_camera();
      camera.position += vec3(0.037f * t, 0.011f * t, -0.05f * t);
      camera.target += vec3(0.037f * t, 0.011f * t, 0.0f);
      testing::render_checked(renderer, f, 0.0f, camera);
      FrameStats stats;
      const Image a = denoised(lanes, renderer.gbuffer(), previous, renderer.image(), stats);
      const Image b = denoised(scalar, renderer.gbuffer(), previous, renderer.image(), stats);
      ASSERT_EQ(a.pixels.size(), b.pixels.size());
      size_t differ = 0;
      for (size_t i = 0; i < a.pixels.size(); ++i) differ += std::memcmp(&a.pixels[i], &b.pixels[i], sizeof(vec3)) != 0;
      EXPECT_EQ(differ, 0u) << target << ", frame " << f << ": " << differ << " of " << a.pixels.size()
                            << " pixels differ";
      previous = renderer.gbuffer();
    }
  });
}

// --- Synthetic G-buffers ---------------------------------------------------------------------------

struct Surface {
  float depth;
  vec3 normal;
  vec3 albedo;
  uint32_t instance;
  vec3 emission{0.0f};
};

// A G-buffer whose pixel (x, y) shows surface(x, y), or nothing; pixel-centre samples, no motion.
GBuffer make_gbuffer(int w, int h, const std::function<std::optional<Surface>(int, int)>& surface) {
  GBuffer g;
  g.resize(w, h);
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      std::optional<Surface> s = surface(x, y);
      if (!s) continue;
      size_t i = size_t(y) * w + x;
      g.depth[i] = s->depth;
      g.shading_normal[i] = g.geometric_normal[i] = s->normal;
      g.albedo[i] = s->albedo;
      g.emission[i] = s->emission;
      g.instance[i] = s->instance;
      g.position[i] = vec3(float(x), float(y), -s->depth);
    }
  return g;
}

// Radiance = emission + albedo * irradiance, irradiance noisy with mean `irradiance(x, y)`: uniform in
// [0, 2) times the mean (a crude one-sample Monte Carlo estimate), its own stream per frame.
Image shade(const GBuffer& g, const std::function<float(int, int)>& irradiance, uint64_t frame, bool noisy = true) {
  Image img(g.width, g.height);
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) {
      size_t i = size_t(y) * g.width + x;
      Rng rng = Rng::for_key(42, i, frame);
      float e = irradiance(x, y) * (noisy ? 2.0f * rng.next_float() : 1.0f);
      img.pixels[i] = g.hit(i) ? g.emission[i] + g.albedo[i] * e : vec3(0.3f + rng.next_float());
    }
  return img;
}

// Mean of the first channel over the pixels where pick(x, y).
double region_mean(const Image& img, const std::function<bool(int, int)>& pick) {
  double sum = 0.0;
  int n = 0;
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x)
      if (pick(x, y)) {
        sum += img.at(x, y).x;
        ++n;
      }
  return n ? sum / n : 0.0;
}

// Runs `frames` frames of a still synthetic scene through a denoiser of `kind`; returns the last output.
Image denoise_still(DenoiserKind kind, const GBuffer& g, const std::function<float(int, int)>& irradiance, int frames) {
  Denoiser denoiser(DenoiserParams{kind});
  GBuffer none;
  Image out;
  for (int f = 0; f < frames; ++f) {
    FrameStats stats;
    denoiser.denoise(g, f > 0 ? g : none, shade(g, irradiance, uint64_t(f)), stats, out);
  }
  return out;
}

// Two planes meeting at x = 32: left at depth 2 facing the camera (albedo 0.8, irradiance 0.5: radiance
// 0.4), right at depth 4 tilted (albedo 0.2, irradiance 20: radiance 4.0, 10x brighter); the last 4
// columns see nothing. The 4 columns on each side of the edge must average within 5% of their true value:
// a leak of 1% of the weight from the right would already raise the left by 9%, while the noise of the
// band's mean after filtering is about 1%. Pixels with no hit keep their input exactly.
TEST(DenoiseSynthetic, EdgesDoNotLeak) {
  GBuffer g = make_gbuffer(64, 32, [](int x, int) -> std::optional<Surface> {
    if (x >= 60) return std::nullopt;
    if (x < 32) return Surface{2.0f, vec3(0.0f, 0.0f, 1.0f), vec3(0.8f), 0};
    return Surface{4.0f, glm::normalize(vec3(1.0f, 0.0f, 1.0f)), vec3(0.2f), 1};
  });
  auto irradiance = [](int x, int) { return x < 32 ? 0.5f : 20.0f; };
  for (DenoiserKind kind : {DenoiserKind::Bilateral, DenoiserKind::Svgf}) {
    Image out = denoise_still(kind, g, irradiance, 4);
    double left = region_mean(out, [](int x, int) { return x >= 28 && x < 32; });
    double right = region_mean(out, [](int x, int) { return x >= 32 && x < 36; });
    const char* name = kind == DenoiserKind::Svgf ? "svgf" : "bilateral";
    std::printf("%s: left band %.4f (true 0.4), right band %.4f (true 4.0)\n", name, left, right);
    EXPECT_NEAR(left, 0.4, 0.02) << name;
    EXPECT_NEAR(right, 4.0, 0.2) << name;
    Image input = shade(g, irradiance, 3);
    for (int y = 0; y < 32; ++y)
      for (int x = 60; x < 64; ++x)
        EXPECT_EQ(out.at(x, y), input.at(x, y)) << name << " background pixel " << x << "," << y;
  }
}

// A checkerboard albedo (0.9 / 0.1, one-pixel cells) on one plane. With constant light the image comes
// through unchanged (relative error 1e-4: demodulation and remodulation use the same albedo, filtering a
// constant gives the constant). With noisy light (SVGF, 8 frames) the checker keeps its contrast: the
// bright and dark cells' means stay within 5% of 0.9 and 0.1; filtering radiance instead of
// illumination would average neighbouring cells towards 0.5.
TEST(DenoiseSynthetic, DemodulationKeepsTextureSharp) {
  GBuffer g = make_gbuffer(64, 64, [](int x, int y) -> std::optional<Surface> {
    return Surface{3.0f, vec3(0.0f, 0.0f, 1.0f), vec3((x + y) % 2 ? 0.9f : 0.1f), 0};
  });
  auto one = [](int, int) { return 1.0f; };
  Image exact = shade(g, one, 0, false);
  for (DenoiserKind kind : {DenoiserKind::Bilateral, DenoiserKind::Svgf}) {
    Denoiser denoiser(DenoiserParams{kind});
    FrameStats stats;
    Image out = denoised(denoiser, g, GBuffer{}, exact, stats);
    for (size_t i = 0; i < out.pixels.size(); ++i)
      ASSERT_NEAR(out.pixels[i].x, exact.pixels[i].x, 1e-4 * exact.pixels[i].x) << "pixel " << i;
  }
  Image out = denoise_still(DenoiserKind::Svgf, g, one, 8);
  double bright = region_mean(out, [](int x, int y) { return (x + y) % 2 == 1; });
  double dark = region_mean(out, [](int x, int y) { return (x + y) % 2 == 0; });
  std::printf("checker under noisy light: bright %.4f (true 0.9), dark %.4f (true 0.1)\n", bright, dark);
  EXPECT_NEAR(bright, 0.9, 0.045);
  EXPECT_NEAR(dark, 0.1, 0.005);
}

// An emissive 6x6 patch (emission 10) on a lit plane (radiance 0.5). Emission is subtracted before
// filtering and added back after, so the patch's 4x4 interior keeps 10 + 0.5 within 5% and the ring
// 2-3 pixels around the patch stays within 5% of 0.5 (blurring the emission would spread about
// 10 * 36 / (filter footprint) into it, several times the tolerance). The pixels on either side of the
// patch's border are not filtered (see Guides::filtered).
TEST(DenoiseSynthetic, EmissionIsNotBlurred) {
  auto box = [](int x, int y, int margin) {
    return x >= 29 - margin && x < 35 + margin && y >= 13 - margin && y < 19 + margin;
  };
  auto patch = [&](int x, int y) { return box(x, y, 0); };
  auto interior = [&](int x, int y) { return box(x, y, -1); };
  auto ring = [&](int x, int y) { return box(x, y, 3) && !box(x, y, 1); };
  GBuffer g = make_gbuffer(64, 32, [&](int x, int y) -> std::optional<Surface> {
    return Surface{3.0f, vec3(0.0f, 0.0f, 1.0f), vec3(0.5f), 0, vec3(patch(x, y) ? 10.0f : 0.0f)};
  });
  for (DenoiserKind kind : {DenoiserKind::Bilateral, DenoiserKind::Svgf}) {
    Image out = denoise_still(
        kind, g, [](int, int) { return 1.0f; }, 4);
    double emitter = region_mean(out, interior), around = region_mean(out, ring);
    const char* name = kind == DenoiserKind::Svgf ? "svgf" : "bilateral";
    std::printf("%s: emitter %.4f (true 10.5), ring around it %.4f (true 0.5)\n", name, emitter, around);
    EXPECT_NEAR(emitter, 10.5, 0.525) << name;
    EXPECT_NEAR(around, 0.5, 0.025) << name;
  }
}

// Emitter borders where the radiance and the G-buffer disagree: the radiance's samples land on the 6x6
// emitter (10) in the one-pixel ring around it too, where the G-buffer's samples missed it (as jittered
// primary samples do). Demodulated, those ring pixels would carry 10 / 0.5 = 20 of "illumination"; the
// guides mark every hit pixel whose 3x3 block emits differently as not filtered, so they keep their input
// and feed no filter. The band 2-3 pixels out (true 0.5; measured 0.517 bilateral, 0.499 SVGF) must stay
// within 5% of it: fed by the ring, with the marking switched off, it measured 1.87 and 0.98.
TEST(DenoiseSynthetic, EmitterBordersFeedNoFilter) {
  auto box = [](int x, int y, int margin) {
    return x >= 29 - margin && x < 35 + margin && y >= 13 - margin && y < 19 + margin;
  };
  auto border = [&](int x, int y) { return box(x, y, 1) && !box(x, y, 0); };
  auto band = [&](int x, int y) { return box(x, y, 3) && !box(x, y, 1); };
  GBuffer g = make_gbuffer(64, 32, [&](int x, int y) -> std::optional<Surface> {
    return Surface{3.0f, vec3(0.0f, 0.0f, 1.0f), vec3(0.5f), 0, vec3(box(x, y, 0) ? 10.0f : 0.0f)};
  });
  for (DenoiserKind kind : {DenoiserKind::Bilateral, DenoiserKind::Svgf}) {
    Denoiser denoiser(DenoiserParams{kind});
    GBuffer none;
    Image out;
    for (int f = 0; f < 4; ++f) {
      Image noisy = shade(
          g, [](int, int) { return 1.0f; }, uint64_t(f));
      for (int y = 0; y < g.height; ++y)
        for (int x = 0; x < g.width; ++x)
          if (border(x, y)) noisy.pixels[size_t(y) * g.width + x] += vec3(10.0f);
      FrameStats stats;
      denoiser.denoise(g, f > 0 ? g : none, noisy, stats, out);
    }
    const char* name = kind == DenoiserKind::Svgf ? "svgf" : "bilateral";
    const double around = region_mean(out, band);
    std::printf("%s: band around the emitter's border %.4f (true 0.5)\n", name, around);
    EXPECT_NEAR(around, 0.5, 0.025) << name;
  }
}

// Disocclusion: a dark object (radiance 0.05) in front of a lit wall (radiance 0.5) for 12 frames, then
// it jumps 32 pixels to the right (motion vectors say so) and stays. The uncovered square must be within
// 10% of the wall's 0.5 from the N = 1st frame after the move on (and every frame after): its reprojected
// history is the object's, which the instance and depth tests reject. Keeping that history would leave it
// near 0.05 * 0.8^n + 0.5 (1 - 0.8^n), about 0.14 after one frame and still 0.32 after four.
TEST(DenoiseSynthetic, NoGhostingAfterDisocclusion) {
  auto wall = Surface{10.0f, vec3(0.0f, 0.0f, 1.0f), vec3(0.5f), 0};
  auto object = Surface{5.0f, vec3(0.0f, 0.0f, 1.0f), vec3(0.5f), 1};
  auto scene_at = [&](int x0) {
    GBuffer g = make_gbuffer(64, 32, [&](int x, int y) -> std::optional<Surface> {
      return x >= x0 && x < x0 + 12 && y >= 10 && y < 22 ? object : wall;
    });
    return g;
  };
  GBuffer before = scene_at(8), after = scene_at(40);
  for (int y = 10; y < 22; ++y)
    for (int x = 40; x < 52; ++x) after.motion[size_t(y) * 64 + x] = vec2(-32.0f, 0.0f);
  auto irradiance = [&](int x, int y) { return x >= 8 && x < 20 && y >= 10 && y < 22 ? 0.1f : 1.0f; };
  auto irradiance_after = [&](int x, int y) { return x >= 40 && x < 52 && y >= 10 && y < 22 ? 0.1f : 1.0f; };
  auto uncovered = [](int x, int y) { return x >= 8 && x < 20 && y >= 10 && y < 22; };
  Svgf svgf;
  GBuffer none;
  FrameStats stats;
  for (int f = 0; f < 12; ++f)
    denoised(svgf, before, f > 0 ? before : none, shade(before, irradiance, uint64_t(f)), stats);
  for (int n = 1; n <= 4; ++n) {
    const GBuffer& prev = n == 1 ? before : after;
    Image out = denoised(svgf, after, prev, shade(after, irradiance_after, uint64_t(100 + n)), stats);
    double value = region_mean(out, uncovered);
    std::printf("frame %d after the move: uncovered region %.4f (true 0.5)\n", n, value);
    EXPECT_NEAR(value, 0.5, 0.05) << "frame " << n << " after the disocclusion";
  }
}

// The guides on a G-buffer built to know them (16x6): depth 1 + 0.25 x + 0.5 y on instance 0 in columns x < 8,
// depth 9 on instance 1 in the other columns but 12, where nothing is hit. The depth slope is |dz/dx| + |dz/dy|
// from the neighbours on the pixel's own instance: 0.25 + 0.5 on instance 0 by central differences inside and
// one-sided ones at the image border and next to instance 1 (a slope taken across instances would be larger),
// 0 on the flat instance 1 and where nothing is hit. Without emission every hit pixel is filtered and keeps
// its normal; a pixel without a hit has depth infinity. The albedo planes exist only when asked for.
// Dropping the vertical slope, or taking slopes across instances, fails it.
TEST(DenoiseSynthetic, GuidesGiveTheDepthSlopeAndMask) {
  GBuffer g = make_gbuffer(16, 6, [](int x, int y) -> std::optional<Surface> {
    if (x == 12) return std::nullopt;
    if (x < 8) return Surface{1.0f + 0.25f * float(x) + 0.5f * float(y), vec3(0.0f, 0.0f, 1.0f), vec3(0.5f), 0};
    return Surface{9.0f, vec3(0.0f, 1.0f, 0.0f), vec3(0.5f), 1};
  });
  for (bool with_albedo : {false, true}) {
    Guides guides;
    compute_guides(g, with_albedo, guides);
    for (int y = 0; y < 6; ++y)
      for (int x = 0; x < 16; ++x) {
        const size_t i = size_t(y) * 16 + size_t(x);
        const float expected = x == 12 ? 0.0f : x < 8 ? 0.75f : 0.0f;
        EXPECT_FLOAT_EQ(guides.depth_slope[i], expected) << "pixel " << x << ", " << y;
        EXPECT_EQ(guides.filtered[i], x == 12 ? 0 : 1) << "pixel " << x << ", " << y;
        EXPECT_EQ(guides.depth[i], x == 12 ? kInfinity : g.depth[i]);
        EXPECT_EQ(guides.ny[i], x == 12 || x < 8 ? 0.0f : 1.0f);
        EXPECT_EQ(guides.nz[i], x < 8 ? 1.0f : 0.0f);
        if (with_albedo) {
          EXPECT_EQ(guides.albedo.g[i], x == 12 ? 0.0f : 0.5f);
        }
      }
    EXPECT_EQ(guides.albedo.size(), with_albedo ? g.size() : 0u);
  }
}

// The exponential of the edge-stopping weights: within 3e-4 (relative) of std::exp on [0, 80] (the
// degree-5 remainder (ln 2)^6 / 720 = 1.5e-4, plus float rounding).
TEST(DenoiseMath, FastExpMatchesExp) {
  double worst = 0.0;
  for (int k = 0; k <= 80000; ++k) {
    float x = float(k) * 1e-3f;
    worst = std::max(worst, std::abs(double(fast_exp_neg(x)) / std::exp(-double(x)) - 1.0));
  }
  std::printf("fast_exp_neg: worst relative error %.2e\n", worst);
  EXPECT_LT(worst, 3e-4);
}

// Stage timings land in the frame's stats under their names.
TEST(DenoiseSynthetic, StagesAreTimed) {
  GBuffer g = make_gbuffer(32, 16, [](int, int) -> std::optional<Surface> {
    return Surface{3.0f, vec3(0.0f, 0.0f, 1.0f), vec3(0.5f), 0};
  });
  Image noisy = shade(
      g, [](int, int) { return 1.0f; }, 0);
  FrameStats svgf_stats, bilateral_stats;
  Denoiser svgf(DenoiserParams{DenoiserKind::Svgf}), bilateral(DenoiserParams{DenoiserKind::Bilateral});
  denoised(svgf, g, GBuffer{}, noisy, svgf_stats);
  denoised(bilateral, g, GBuffer{}, noisy, bilateral_stats);
  auto names = [](const FrameStats& s) {
    std::vector<std::string> n;
    for (const StageStats& st : s.stages) n.push_back(st.name);
    return n;
  };
  EXPECT_EQ(names(svgf_stats), (std::vector<std::string>{"denoise_guides", "denoise_demodulate", "svgf_temporal",
                                                         "svgf_variance", "svgf_atrous", "denoise_remodulate"}));
  EXPECT_EQ(names(bilateral_stats),
            (std::vector<std::string>{"denoise_guides", "denoise_demodulate", "bilateral", "denoise_remodulate"}));
}

// A NaN and an infinite input pixel are dropped (they become 0 in the illumination) and counted in the
// stats, so that expect_all_finite fails the statistical tests that meet them.
TEST(DenoiseSynthetic, NonFiniteInputIsCounted) {
  GBuffer g = make_gbuffer(32, 16, [](int, int) -> std::optional<Surface> {
    return Surface{3.0f, vec3(0.0f, 0.0f, 1.0f), vec3(0.5f), 0};
  });
  Image noisy = shade(
      g, [](int, int) { return 1.0f; }, 0);
  noisy.pixels[40] = vec3(std::numeric_limits<float>::quiet_NaN());
  noisy.pixels[41] = vec3(std::numeric_limits<float>::infinity(), 0.0f, 0.0f);
  FrameStats stats;
  Denoiser svgf(DenoiserParams{DenoiserKind::Svgf});
  const Image out = denoised(svgf, g, GBuffer{}, noisy, stats);
  EXPECT_EQ(stats.non_finite(), 2u);
  for (const StageStats& s : stats.stages) EXPECT_EQ(s.non_finite, s.name == "denoise_demodulate" ? 2u : 0u) << s.name;
  for (const vec3& p : out.pixels) EXPECT_TRUE(is_finite(p));
}

}  // namespace
}  // namespace candela

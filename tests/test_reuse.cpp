// ReSTIR's reuse (restir/reuse.h).
//
// MisWeights: the resampling MIS weights of ReSTIR's reuse, checked exactly (no statistics): for real combinations
// built from a rendered frame, the weights every input gives one sample must sum to one wherever the
// combining pixel's target is positive, and be zero for an input whose target (times visibility, where
// the weights use it) is zero at the sample. A combination whose weights sum to more or less than one
// brightens or darkens the image by that factor, which is how every unbiasedness bug of reuse shows.
//
// RestirDiReuse: ReSTIR DI reuse beyond the core stages: the disocclusion boost, the boiling filter, final
// visibility reuse (moving lights: Unbiased.MovingLights), the shading of repeated shaded samples, the verdicts
// handed between stages and GI's history found in DI's pass.
#include <gtest/gtest.h>

#include <cstdio>
#include <set>
#include <vector>

#include "apps/renderer.h"
#include "engine/builtin_scenes.h"
#include "engine/image_metrics.h"
#include "restir/reuse.h"
#include "tests/flythrough.h"
#include "tests/render_helpers.h"
#include "tests/settings_builder.h"

namespace candela {
namespace {

// manylights (256 lights) whose ceiling lights move half a unit per frame, so that last frame's samples
// must be re-placed for this frame's receivers.
Scene moving_lights_scene() {
  Scene scene = make_manylights_scene(256, 7);
  for (size_t k = 0; k < scene.instances.size(); ++k) {
    if (!scene.material_of(uint32_t(k)).emissive()) continue;
    scene.instances[k].animated = true;
    scene.motions.push_back({int(k), scene.instances[k].transform, vec3(15.0f, 0.0f, 0.0f), 2.5f, 0.0f});
  }
  return scene;
}

// Target and visibility of sample y (stored by an input whose frame placed the lights as `from`) at the
// receiver of pixel `pixel` of `domain`, computed here from the public pieces (not through the weights'
// own code): y is re-placed where the domain placed the lights differently.
struct TargetAt {
  float p;
  bool visible;
};
TargetAt target_and_visibility(const Renderer& renderer, const ReuseDomain& domain, size_t pixel, const ReuseSample& y,
                               const LightList& from) {
  ReuseSample placed = y;
  if (&domain.lights != &from && y.light != kSurfacePointSample)
    di_resolve(renderer.scene(), domain.lights, y.light, y.uv, placed);
  const ReuseReceiver r = reuse_receiver(domain, pixel);
  const SampleContribution c = sample_contribution(r, placed);
  const bool visible =
      !renderer.tracer().occluded(shadow_ray(renderer.tracer(), r.position, r.geometric_normal, c.light));
  return {sample_target(c), visible};
}

// Whether surface b may share samples with a (depth within 10%, normals within cos 0.9: the reuse defaults).
bool similar(const PackedSurface& a, const PackedSurface& b) {
  return b.hit() && std::abs(a.depth - b.depth) <= 0.1f * a.depth && glm::dot(a.shading_n(), b.shading_n()) >= 0.9f;
}

struct Tally {
  int combinations = 0, samples = 0, zero_targets = 0, occluded = 0;
};

// For every 5th pixel with a sample: the pixel's reservoir (input 0), up to 5 similar neighbours within 3
// pixels, and last frame's reservoir of the same pixel (camera still, lights moved). Every input's sample
// y is weighed by all inputs (reuse_mis_weights) and checked.
Tally check_weights(const Renderer& renderer, const std::vector<ReuseReservoir>& current,
                    const std::vector<ReuseReservoir>& history, const ReuseParams& params, const char* what) {
  const ReuseDomain now = renderer.current_domain(), before = renderer.previous_domain();
  EXPECT_NE(&now.lights, &before.lights) << "the lights must have moved between the two frames";
  const int w = now.width, h = now.height;
  const Camera camera(renderer.scene().default_camera(), w, h);  // unused by the weights
  const SceneView view{renderer.scene(), renderer.tracer(), renderer.lights(), camera};
  Tally tally;
  int failures = 0;
  for (size_t i = 0; i < current.size() && failures < 10; i += 5) {
    if (!now.surfaces[i].hit() || current[i].W <= 0.0f) continue;
    const int x = int(i % w), y = int(i / w);
    std::vector<ReuseInput> inputs{{&current[i], &now, i, current[i].M}};
    for (int r = 1; r <= 3 && inputs.size() < 6; ++r)
      for (int dy = -r; dy <= r && inputs.size() < 6; ++dy)
        for (int dx = -r; dx <= r && inputs.size() < 6; ++dx) {
          const int nx = x + dx, ny = y + dy;
          if (std::max(std::abs(dx), std::abs(dy)) != r || nx < 0 || ny < 0 || nx >= w || ny >= h) continue;
          const size_t j = size_t(ny) * w + nx;
          if (similar(now.surfaces[i], now.surfaces[j])) inputs.push_back({&current[j], &now, j, current[j].M});
        }
    if (similar(now.surfaces[i], before.surfaces[i]))
      inputs.push_back({&history[i], &before, i, std::min(history[i].M, params.history_cap * current[i].M)});
    const int count = int(inputs.size());
    if (count < 3) continue;
    ++tally.combinations;
    for (int source = 0; source < count; ++source) {
      const ReuseReservoir& res = *inputs[source].reservoir;
      if (res.W <= 0.0f) continue;
      ++tally.samples;
      std::vector<TargetAt> at(count);
      for (int z = 0; z < count; ++z)
        at[z] =
            target_and_visibility(renderer, *inputs[z].domain, inputs[z].pixel, res.y, inputs[source].domain->lights);
      // The target the source's reservoir stored is its target at its own sample, recomputed.
      EXPECT_NEAR(res.p_hat_y, at[source].p, 1e-5f * std::max(1.0f, at[source].p))
          << what << ": pixel " << i << " input " << source;
      float weights[32];
      reuse_mis_weights(view, inputs.data(), count, source, params, weights);
      float sum = 0.0f;
      for (int z = 0; z < count; ++z) {
        sum += weights[z];
        // Zero where the input's target is zero (times visibility where the weights use it; pairwise
        // leaves the canonical input's visibility out).
        const bool uses_visibility = params.mis_visibility && (params.bias == BiasCorrection::Basic || z > 0);
        const bool zero = at[z].p <= 0.0f || (uses_visibility && !at[z].visible);
        tally.zero_targets += at[z].p <= 0.0f;
        tally.occluded += at[z].p > 0.0f && !at[z].visible;
        if (zero && weights[z] != 0.0f) {
          ADD_FAILURE() << what << ": pixel " << i << " sample of input " << source << ": input " << z << " has target "
                        << at[z].p << (at[z].visible ? "" : " (occluded)") << " but weight " << weights[z];
          ++failures;
        }
      }
      // One where the combining pixel's integrand can be non-zero at y.
      const bool counts =
          at[0].p > 0.0f && (!params.mis_visibility || params.bias == BiasCorrection::Pairwise || at[0].visible);
      if (counts && std::abs(sum - 1.0f) > 1e-5f) {
        ADD_FAILURE() << what << ": pixel " << i << " sample of input " << source << " (" << count
                      << " inputs): weights sum to " << sum;
        ++failures;
      }
    }
  }
  std::printf("%-28s %d combinations, %d samples weighed by every input; %d zero targets, %d occluded\n", what,
              tally.combinations, tally.samples, tally.zero_targets, tally.occluded);
  return tally;
}

// ReSTIR DI and GI (method restir) on the moving-lights scene at 64x36, pixel centres: frame 0's final
// reservoirs become the history, frame 1's final reservoirs the current inputs. Both bias corrections,
// with and without visibility in the weights.
TEST(MisWeights, EveryInputsWeightsOfASampleSumToOne) {
  const Scene scene = moving_lights_scene();
  Renderer renderer(scene, testing::settings({{"width", 64},
                                              {"height", 36},
                                              {"method", "restir"},
                                              {"max_depth", 3},
                                              {"jitter", false},
                                              {"accumulate", false}}));
  testing::render_checked(renderer, 0, 0.0f, scene.default_camera());
  const std::vector<ReuseReservoir> di_history = renderer.di_reservoirs(), gi_history = renderer.gi_reservoirs();
  testing::render_checked(renderer, 1, 1.0f / 30.0f, scene.default_camera());
  for (BiasCorrection bias : {BiasCorrection::Basic, BiasCorrection::Pairwise})
    for (bool visibility : {false, true}) {
      const std::string mode =
          std::string(bias == BiasCorrection::Basic ? "basic" : "pairwise") + (visibility ? "+visibility" : "");
      ReuseParams di = renderer.settings().di_reuse, gi = renderer.settings().gi_reuse;
      di.bias = gi.bias = bias;
      di.mis_visibility = gi.mis_visibility = visibility;
      Tally d = check_weights(renderer, renderer.di_reservoirs(), di_history, di, ("DI " + mode).c_str());
      Tally g = check_weights(renderer, renderer.gi_reservoirs(), gi_history, gi, ("GI " + mode).c_str());
      // The checks must have met every case: many combinations, samples some inputs cannot use, occlusion.
      for (const Tally& t : {d, g}) {
        EXPECT_GT(t.combinations, 200) << mode;
        EXPECT_GT(t.zero_targets, 0) << mode;
        EXPECT_GT(t.occluded, 0) << mode;
      }
    }
}

}  // namespace
}  // namespace candela

namespace candela {
namespace {

RenderSettings restir_settings(int w, int h, uint64_t seed) {
  return testing::settings(
      {{"width", w}, {"height", h}, {"method", "restir-di"}, {"accumulate", false}, {"seed", seed}});
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
  std::vector<ReuseReservoir> reservoirs(size_t(w) * h);
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
  const std::vector<ReuseReservoir> before = reservoirs;
  std::vector<PackedSurface> surfaces(reservoirs.size());
  LightList lights;
  boiling_filter(ReuseDomain{surfaces, w, h, vec3(0.0f), lights}, 10.0f, reservoirs);
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
// changes the image little (the surface point moves within the pixel with the jitter): over the 10 frames
// accumulated, the mean stays within 1% and the relMSE against the traced image is below 1%. (Single frames
// differ by about 1% relMSE through noise alone, 0.6-1.9% over 8 seeds, so the accumulated images are
// compared: their noise is ~6x lower, and a difference that visibility reuse makes stands out more.)
TEST(RestirDiReuse, VisibilityReuseSavesShadowRays) {
  Scene scene = make_manylights_scene(256, 7);
  auto run = [&](int reuse_frames, uint64_t& shade_rays) {
    RenderSettings s = restir_settings(96, 54, 9);
    s.accumulate = true;
    s.di_reuse.visibility_reuse_frames = reuse_frames;
    Renderer renderer(scene, s);
    shade_rays = 0;
    for (int frame = 0; frame < 10; ++frame) {
      FrameStats stats = testing::render_checked(renderer, frame, 0.0f, scene.default_camera());
      if (frame > 0) shade_rays += stats.stage_rays("di_shade");
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

// Temporal reuse ages last frame's sample by a frame each time it carries it on (ReuseInput::age_step); spatial
// reuse keeps ages. On a still camera samples grow older than a frame but none older than the frames rendered, and with
// max_sample_age none older than the limit (temporal reuse drops older history).
TEST(RestirDiReuse, HistorySamplesAgeByAFramePerReuse) {
  Scene scene = make_manylights_scene(256, 7);
  constexpr int kFrames = 6;
  // The oldest sample of the final reservoirs with max_sample_age `limit`, and how many are at least 2 frames old.
  auto oldest = [&](int limit, int& aged) {
    RenderSettings s = restir_settings(64, 36, 3);
    s.di_reuse.max_sample_age = limit;
    Renderer renderer(scene, s);
    for (int frame = 0; frame < kFrames; ++frame)
      testing::render_checked(renderer, frame, 0.0f, scene.default_camera());
    int age = 0;
    aged = 0;
    for (const ReuseReservoir& r : renderer.di_reservoirs())
      if (r.W > 0.0f) age = std::max(age, int(r.y.age)), aged += r.y.age >= 2;
    return age;
  };
  int aged = 0;
  const int unlimited = oldest(0, aged);
  std::printf("oldest sample after %d frames: %d (%d samples at least 2 frames old)\n", kFrames, unlimited, aged);
  EXPECT_GE(unlimited, 3);
  EXPECT_LE(unlimited, kFrames - 1);
  EXPECT_GT(aged, 0);
  const int limited = oldest(2, aged);
  std::printf("with max_sample_age 2: %d (%d at least 2 frames old)\n", limited, aged);
  EXPECT_EQ(limited, 2);
}

// Every spatial pass (up to the option's 8) draws from streams no other pass or name uses, nor the candidates' (0xd1)
// and temporal reuse's (0xd2), ReSTIR GI's first rays' (0x61) or the light tiles' (0x7e).
TEST(RestirDiReuse, SpatialPassesHaveStreamsOfTheirOwn) {
  std::set<uint64_t> streams{0xd1, 0xd2, 0x61, 0x7e};
  for (int pass = 0; pass < 8; ++pass)
    for (SpatialStream name : {kPixelStreams, kBlockStarts, kFurtherPoints})
      EXPECT_TRUE(streams.insert(spatial_stream(name, pass)).second) << "pass " << pass << ", name " << name;
}

// ReSTIR GI with every pixel kept out of reuse (all smoother than a minimum roughness of 2): each further plane holds
// a copy of the pixel's reservoir, so 2 or 3 shaded samples shade alike and must cost the rays of one, and give its
// image bit for bit (the shares of the copies sum to exactly one sample's weight). Shading each copy would trace
// 2x or 3x the rays.
TEST(RestirDiReuse, SamplesThatShadeAlikeAreShadedOnce) {
  const Scene scene = make_manylights_scene(256, 7);
  auto run = [&](int samples, uint64_t& shade_rays) {
    RenderSettings s = testing::settings({{"width", 64},
                                          {"height", 36},
                                          {"method", "restir"},
                                          {"max_depth", 3},
                                          {"accumulate", false},
                                          {"di_shaded_samples", 1},
                                          {"gi_shaded_samples", samples}});
    s.gi_reuse.min_roughness = 2.0f;  // beyond the option's range: no surface is rough enough for reuse
    // Every pixel keeps its own sample, whose verdict spatial reuse traced: the shading would trace no ray at all.
    s.test.retrace_known_visibility = true;
    Renderer renderer(scene, s);
    shade_rays = 0;
    for (int frame = 0; frame < 3; ++frame) {
      FrameStats stats = testing::render_checked(renderer, frame, 0.0f, scene.default_camera());
      shade_rays += stats.stage_rays("gi_shade");
    }
    return renderer.image();
  };
  uint64_t one_rays = 0;
  const Image one = run(1, one_rays);
  ASSERT_GT(one_rays, 1000u);
  for (int samples : {2, 3}) {
    uint64_t rays = 0;
    const Image image = run(samples, rays);
    EXPECT_EQ(rays, one_rays) << samples << " samples";
    ASSERT_EQ(image.pixels.size(), one.pixels.size());
    size_t differing = 0;
    for (size_t i = 0; i < one.pixels.size(); ++i) differing += image.pixels[i] != one.pixels[i];
    EXPECT_EQ(differing, 0u) << samples << " samples";
  }
}

// Still scene and camera, ReSTIR GI (whose MIS weights include visibility): temporal reuse takes last frame's shading
// verdicts on its history's samples (RestirFrame::same_geometry), and the shading takes spatial reuse's verdicts where
// a pixel kept its own sample, instead of tracing those rays again. A verdict answers the very ray it replaces (the
// same origin on the packed surface, the same sample, the same geometry), so the images must be the same bits as with
// every ray traced (the test switch retrace_known_visibility), frame after frame, with fewer rays in both stages: a
// verdict of another pixel, another sample, or one the shading itself reused would change the pairwise weights or the
// shading.
TEST(RestirDiReuse, KnownVerdictsReplaceRays) {
  const Scene scene = make_manylights_scene(256, 7);
  auto run = [&](bool retrace, uint64_t& temporal_rays, uint64_t& shade_rays) {
    RenderSettings s = testing::settings(
        {{"width", 96}, {"height", 54}, {"method", "restir"}, {"max_depth", 3}, {"accumulate", false}, {"seed", 5}});
    s.test.retrace_known_visibility = retrace;
    Renderer renderer(scene, s);
    temporal_rays = shade_rays = 0;
    std::vector<Image> frames;
    for (int frame = 0; frame < 6; ++frame) {
      FrameStats stats = testing::render_checked(renderer, frame, 0.0f, scene.default_camera());
      temporal_rays += stats.stage_rays("gi_temporal");
      shade_rays += stats.stage_rays("gi_shade");
      frames.push_back(renderer.image());
    }
    return frames;
  };
  uint64_t temporal_traced = 0, temporal_known = 0, shade_traced = 0, shade_known = 0;
  const std::vector<Image> all = run(true, temporal_traced, shade_traced);
  const std::vector<Image> some = run(false, temporal_known, shade_known);
  std::printf(
      "rays over 6 frames, all traced / with the verdicts known: gi_temporal %llu / %llu (%.2fx), gi_shade "
      "%llu / %llu (%.2fx)\n",
      (unsigned long long)temporal_traced, (unsigned long long)temporal_known,
      double(temporal_known) / double(temporal_traced), (unsigned long long)shade_traced,
      (unsigned long long)shade_known, double(shade_known) / double(shade_traced));
  ASSERT_GT(temporal_traced, 10000u);
  ASSERT_GT(shade_traced, 10000u);
  EXPECT_LT(double(temporal_known), 0.75 * double(temporal_traced));
  EXPECT_LT(double(shade_known), 0.95 * double(shade_traced));
  for (size_t f = 0; f < all.size(); ++f) {
    size_t differing = 0;
    for (size_t i = 0; i < all[f].pixels.size(); ++i) differing += some[f].pixels[i] != all[f].pixels[i];
    EXPECT_EQ(differing, 0u) << "frame " << f;
  }
}

// ReSTIR GI's history found in DI's stage "di_history" (history_follows, SecondHistory): on a camera flying through
// city, whose dark windows are smoother than GI's roughness bound, it must be the history GI's own pass finds, pixel
// for pixel. The frame runs no "gi_history" stage then, and does where GI's history cannot follow DI's (GI permutes).
TEST(RestirDiReuse, GiHistoryComesWithDis) {
  const Scene scene = make_city_scene(7);
  auto stages = [&](Renderer& renderer) {
    std::set<std::string> names;
    for (int frame = 0; frame < 3; ++frame) {
      const FrameStats stats = testing::render_checked(renderer, frame, float(frame) / 30.0f,
                                                       testing::flythrough_camera(scene.default_camera(), frame));
      names.clear();
      for (const StageStats& st : stats.stages) names.insert(st.name);
    }
    return names;
  };
  const RenderSettings s = testing::settings(
      {{"width", 96}, {"height", 54}, {"method", "restir"}, {"max_depth", 3}, {"accumulate", false}, {"seed", 3}});
  Renderer renderer(scene, s);
  const std::set<std::string> names = stages(renderer);
  EXPECT_TRUE(names.count("di_history"));
  EXPECT_FALSE(names.count("gi_history"));
  ASSERT_TRUE(history_follows(s.di_reuse, s.gi_reuse));
  std::vector<int32_t> di, gi_with_di, gi_own;
  const SecondHistory second{s.gi_reuse.min_roughness, &gi_with_di};
  const ReuseDomain current = renderer.current_domain(), previous = renderer.previous_domain();
  find_history_pixels(renderer.gbuffer(), current, previous, s.di_reuse, 2, di, &second);
  find_history_pixels(renderer.gbuffer(), current, previous, s.gi_reuse, 2, gi_own);
  ASSERT_EQ(gi_with_di.size(), gi_own.size());
  size_t differing = 0, found = 0, lost = 0, smooth = 0;
  for (size_t i = 0; i < gi_own.size(); ++i) {
    differing += gi_with_di[i] != gi_own[i];
    found += gi_own[i] >= 0;
    lost += current.surfaces[i].hit() && di[i] < 0;
    smooth += di[i] >= 0 && gi_own[i] < 0;
  }
  std::printf("%zu pixels: GI's history found for %zu, lost by both chains for %zu, DI's only (smooth) for %zu\n",
              gi_own.size(), found, lost, smooth);
  EXPECT_EQ(differing, 0u);
  EXPECT_GT(found, 1000u);
  EXPECT_GT(lost, 10u);
  EXPECT_GT(smooth, 10u);

  const RenderSettings permuted = testing::settings({{"gi_permutation", true}}, s);
  EXPECT_FALSE(history_follows(permuted.di_reuse, permuted.gi_reuse));
  Renderer own(scene, permuted);
  EXPECT_TRUE(stages(own).count("gi_history"));
}

// ReSTIR GI's paths start with ReSTIR DI's BSDF candidate rays (gi_share_bsdf_ray): DI's stage traces as many rays
// as without sharing, and GI's one fewer per path (its first), so at least one fewer per half of the hit pixels. Where
// DI draws its BSDF candidate only at random (di_bsdf_probability < 1) GI draws its own, and the option changes no bit.
TEST(RestirGiSamples, StartWithDisBsdfRays) {
  struct Frame {
    uint64_t di_rays = 0, gi_rays = 0;
    size_t hits = 0;
    Image image;
  };
  auto render = [](bool share, float bsdf_probability) {
    const RenderSettings s = testing::settings({{"width", 96},
                                                {"height", 54},
                                                {"method", "restir"},
                                                {"max_depth", 3},
                                                {"seed", 3},
                                                {"gi_share_bsdf_ray", share},
                                                {"di_bsdf_probability", bsdf_probability}});
    Scene scene = make_builtin_scene("manylights");
    const CameraDesc camera = scene.default_camera();
    Renderer renderer(std::move(scene), s);
    Frame f;
    for (int frame = 0; frame < 2; ++frame) {
      const FrameStats stats = testing::render_checked(renderer, frame, 0.0f, camera);
      f.di_rays = stats.stage_rays("di_candidates");
      f.gi_rays = stats.stage_rays("gi_samples");
    }
    for (size_t i = 0; i < renderer.gbuffer().size(); ++i) f.hits += renderer.gbuffer().hit(i) ? 1 : 0;
    f.image = renderer.image();
    return f;
  };
  const Frame shared = render(true, 1.0f), own = render(false, 1.0f);
  std::printf("%zu hit pixels; di_candidates %llu rays; gi_samples %llu rays shared, %llu own\n", shared.hits,
              (unsigned long long)shared.di_rays, (unsigned long long)shared.gi_rays, (unsigned long long)own.gi_rays);
  ASSERT_GT(shared.hits, 1000u);
  EXPECT_EQ(shared.di_rays, own.di_rays);
  EXPECT_GT(own.gi_rays, shared.gi_rays + shared.hits / 2);
  const Frame random_on = render(true, 0.5f), random_off = render(false, 0.5f);
  EXPECT_EQ(random_on.gi_rays, random_off.gi_rays);
  size_t differing = 0;
  for (size_t i = 0; i < random_on.image.pixels.size(); ++i)
    differing += random_on.image.pixels[i] != random_off.image.pixels[i];
  EXPECT_EQ(differing, 0u);
}

}  // namespace
}  // namespace candela

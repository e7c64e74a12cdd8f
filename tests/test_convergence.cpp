// Convergence of every estimator `candela converge` runs (apps/converge.h), on builtin:manylights (256
// lights) at 48x27 with primary rays through pixel centres, fixed seeds:
//  - the unbiased estimators' MSE falls as 1/N: the least-squares slope of log MSE against log N lies in
//    [-1.2, -0.8];
//  - their image mean agrees with a reference rendered by a different estimator (another light sampler,
//    see reference_light_sampler), so that a method's bias cannot hide in its own reference;
//  - ReSTIR DI beats the light tree's `direct` estimator at equal samples (accumulated 1-spp frames);
//  - Sobol numbers beat independent ones at 16 samples (here and on the shared occluded_room).
#include <gtest/gtest.h>

#include <map>
#include <utility>

#include "apps/converge.h"
#include "apps/scene_source.h"
#include "apps/settings_names.h"
#include "engine/builtin_scenes.h"
#include "engine/check.h"
#include "tests/test_util.h"
#include "tests/settings_builder.h"

namespace candela {
namespace {

class Convergence : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    scene_ = new Scene(make_manylights_scene(256, 7));
    base_ = new RenderSettings(base());
    references_ = new std::map<std::pair<Transport, LightSamplerKind>, Image>();
  }
  static void TearDownTestSuite() {
    delete references_;
    delete base_;
    delete scene_;
  }
  // The reference of method `m`, rendered when first needed (ctest runs each test in its own process):
  // 4096 samples per pixel of the direct method or the path tracer (4 bounces) with the light sampler
  // reference_light_sampler picks: `direct-tree` and `pt` (tree) are judged against power selection,
  // `direct-uniform` and `direct-power` against the tree, so no estimator against itself; ReSTIR DI, another
  // estimator, against direct light with the tree. Their own MSE is about 1/64 of the methods' at N = 64
  // (power's references: about 1/30) and 1/4 of ReSTIR DI's at N = 1024, which flattens the fitted slopes by
  // a few percent.
  static const Image& reference(const ConvergeMethod& m) {
    const auto key = std::make_pair(m.transport, reference_light_sampler(m, *base_));
    auto it = references_->find(key);
    if (it == references_->end()) {
      const uint64_t seed = m.transport == Transport::Direct ? 7919 : 7920;
      it = references_->emplace(key, render_reference(*scene_, m.transport, *base_, key.second, 4096, seed)).first;
    }
    return it->second;
  }
  static RenderSettings base() {
    // di_drop_occluded false: ReSTIR DI's unbiased configuration; these tests judge convergence to the
    // reference (the default's bias: Unbiased.RestirDi).
    return testing::settings({{"width", 48},
                              {"height", 27},
                              {"jitter", false},
                              {"max_depth", 4},
                              {"light_sampler", "tree"},
                              {"seed", 3},
                              {"di_drop_occluded", false}});
  }
  // Method `name` at N = 1, 2, 4, ..., max_samples; `run` picks the seed; `last_image` receives the image
  // at N = max_samples.
  static std::vector<ConvergePoint> run(const std::string& name, int max_samples, int run = 0,
                                        Image* last_image = nullptr) {
    const ConvergeMethod& m = converge_method_named(name);
    RenderSettings settings = *base_;
    settings.seed += uint64_t(run);
    std::vector<int> counts;
    for (int n = 1; n <= max_samples; n *= 2) counts.push_back(n);
    return run_convergence(*scene_, m, settings, counts, reference(m), 0.0, last_image);
  }
  static Scene* scene_;
  static RenderSettings* base_;
  static std::map<std::pair<Transport, LightSamplerKind>, Image>* references_;
};
Scene* Convergence::scene_ = nullptr;
RenderSettings* Convergence::base_ = nullptr;
std::map<std::pair<Transport, LightSamplerKind>, Image>* Convergence::references_ = nullptr;

// Mean over pixels of (image - reference), each pixel's channels averaged first, and its standard error
// with pixels as the units (a pixel's channels come from the same paths; the spread of the differences
// includes the reference's own noise).
std::pair<double, double> mean_difference(const Image& image, const Image& reference) {
  double m = 0.0, m2 = 0.0;
  for (size_t i = 0; i < image.pixels.size(); ++i) {
    const vec3 d = image.pixels[i] - reference.pixels[i];
    const double v = (double(d.x) + d.y + d.z) / 3.0;
    m += v;
    m2 += v * v;
  }
  const double n = double(image.pixels.size());
  m /= n;
  return {m, std::sqrt(std::max(0.0, m2 / n - m * m) / (n - 1.0))};
}

// Independent samples per pixel (direct with each light sampler, the path tracer): the MSE at each N is
// averaged over 16 runs (seeds), since one run's MSE is a noisy, heavy-tailed estimate (single runs measured
// slopes from -0.85 to -1.21). The slope over N = 4..64 must be in [-1.2, -0.8] (measured -0.97, -0.92,
// -0.97, -0.98 for uniform, power, tree, pt; against same-estimator references they were -0.93, -0.88,
// -1.00, -0.99). Uniform and power
// selection sit above -1 at every range tried (up to N = 256): their rare large samples (dim lights close
// by) are under-represented at small N, so the average MSE is typically below its expectation there.
// Bias: each method is judged against a reference of another estimator (see reference()): direct-uniform
// and direct-power against direct light with tree selection, direct-tree against power selection, pt
// (tree) against the path tracer with power selection. Pixels are independent, so the mean difference of
// the first run's image at N = 64 from its reference must lie within 4 standard errors (pixels as units,
// reference noise included; two-sided, 6e-5 chance of a false failure each). Measured: +0.22, +0.40,
// -1.40, -0.30 standard errors (standard errors 0.65%, 0.44%, 0.19%, 0.20% of the image mean). A tree
// whose pmf is 3% too high everywhere (sample and pmf alike) makes direct-tree 1.5% and pt 1.9% dark
// (-7.5 and -9.4 standard errors here); against the tree's own reference that bias was invisible.
TEST_F(Convergence, IndependentSamplesFallAsOneOverN) {
  const int runs = 16;
  for (const char* name : {"direct-uniform", "direct-power", "direct-tree", "pt"}) {
    Image first_image;
    std::vector<ConvergePoint> mean = run(name, 64, 0, &first_image);
    for (int k = 1; k < runs; ++k) {
      std::vector<ConvergePoint> points = run(name, 64, k);
      for (size_t i = 0; i < mean.size(); ++i) mean[i].error.mse += points[i].error.mse;
    }
    const ConvergeMethod& method = converge_method_named(name);
    const Image& ref = reference(method);
    auto [difference, standard_error] = mean_difference(first_image, ref);
    const double reference_mean = image_mean(ref);
    for (ConvergePoint& p : mean) p.error.mse /= runs;
    double slope = mse_slope(mean, 4, 64);
    std::printf(
        "%-15s MSE slope over N = 4..64: %.3f; at N = 64 against the %s-sampler reference: mean difference %+.2e "
        "(%+.2f%% of %.4f), standard error %.2e (%.2f standard errors)\n",
        name, slope, name_of(light_sampler_names(), reference_light_sampler(method, *base_)).c_str(), difference,
        100.0 * difference / reference_mean, reference_mean, standard_error, difference / standard_error);
    EXPECT_GE(slope, -1.2) << name;
    EXPECT_LE(slope, -0.8) << name;
    EXPECT_LT(std::abs(difference), 4.0 * standard_error) << name;
  }
}

// ReSTIR DI with temporal and spatial reuse, bias corrections basic and pairwise (unbiased): accumulated
// frames are correlated through temporal history (samples live on for up to history_cap frames), so the
// MSE falls slower than 1/N at first (measured slope about -0.4 over N = 4..64) and as 1/N once N is well
// beyond that history: the slope over N = 64..1024 is in [-1.2, -0.8] (measured -0.87). Spatial reuse
// correlates neighbouring pixels, so the standard error treating pixels as independent is too small to
// judge bias with; the image mean at N = 1024 must be within 1% of the reference's (measured 0.2%;
// DirectLightScene.RestirDiReuseIsUnbiasedAndHelps tests the bias over independent runs).
TEST_F(Convergence, RestirDiFallsAsOneOverNBeyondItsHistory) {
  for (const char* name : {"restir-di-basic", "restir-di-pairwise"}) {
    const Image& ref = reference(converge_method_named(name));  // direct light, tree selection
    const double reference_mean = image_mean(ref);
    std::vector<ConvergePoint> points = run(name, 1024);
    double early = mse_slope(points, 4, 64), late = mse_slope(points, 64, 1024);
    const ImageError& e = points.back().error;
    std::printf(
        "%-18s MSE slope over N = 4..64: %.3f, over 64..1024: %.3f; at N = 1024 mean difference %+.2e (%.2f%% of "
        "the mean)\n",
        name, early, late, e.mean_difference, 100.0 * e.mean_difference / reference_mean);
    EXPECT_GE(late, -1.2) << name;
    EXPECT_LE(late, -0.8) << name;
    EXPECT_LT(std::abs(e.mean_difference), 0.01 * reference_mean) << name;
  }
}

// Equal samples, one 1-spp frame (the real-time case) and 2 accumulated frames: ReSTIR DI (pairwise) has
// lower relMSE than the light tree's direct estimator (measured with 4 light candidates, the default:
// 0.208 vs 0.394 and 0.153 vs 0.186; with 8: 0.174 and 0.132). With more accumulated frames the tree wins
// (its samples are independent; ReSTIR's frames share history): the crossover is printed, not tested. It
// lies between 2 and 4 frames since the energy-preserving BSDF (4 frames: 0.117 vs 0.098); with the
// earlier BSDF, which darkened grazing diffuse light, it lay between 4 and 8 (4 frames: 0.076 vs 0.088).
TEST_F(Convergence, RestirDiBeatsTreeAtEqualSamples) {
  std::vector<ConvergePoint> restir = run("restir-di-pairwise", 64), tree = run("direct-tree", 64);
  for (size_t i = 0; i < restir.size(); ++i)
    std::printf("N = %2d: relMSE restir-di-pairwise %.3e, direct-tree %.3e (ratio %.2f)\n", restir[i].samples,
                restir[i].error.rel_mse, tree[i].error.rel_mse, restir[i].error.rel_mse / tree[i].error.rel_mse);
  EXPECT_LT(restir[0].error.rel_mse, 0.7 * tree[0].error.rel_mse) << "one frame";
  EXPECT_LT(restir[1].error.rel_mse, tree[1].error.rel_mse) << "two frames";
}

// relMSE at N = 16 of `method` on `scene` against `reference`, averaged over `runs` seeds.
double rel_mse_at_16(const Scene& scene, const RenderSettings& base, const std::string& method, const Image& reference,
                     int runs) {
  double sum = 0.0;
  for (int run = 0; run < runs; ++run) {
    RenderSettings s = base;
    s.seed += uint64_t(run);
    sum += run_convergence(scene, converge_method_named(method), s, {16}, reference).back().error.rel_mse;
  }
  return sum / runs;
}

// Owen-scrambled Sobol numbers (engine/sobol.h) against independent ones: direct light with the tree at
// N = 16 accumulated samples, relMSE averaged over 8 seeds, against a 4096-spp reference with power
// selection (independent numbers), at pixel centres and jittered (the reference jittered too). The Sobol
// run must be at least 1.3x better (the target is 1.5x; the margin covers a smaller image than
// the study's and 8 seeds). Measured (2026-12-02) on manylights 256 lights 48x27: 1.72x at pixel centres,
// 1.57x jittered; on occluded_room 64x36: 1.63x, 1.61x. Independent numbers in both runs give 1.0x.
void expect_sobol_beats_independent(const Scene& scene, RenderSettings base, const char* scene_name) {
  for (bool jitter : {false, true}) {
    base.jitter = jitter;
    const Image reference = render_reference(scene, Transport::Direct, base, LightSamplerKind::Power, 4096, 7919);
    const double independent = rel_mse_at_16(scene, base, "direct-tree", reference, 8);
    const double sobol = rel_mse_at_16(scene, base, "direct-tree-sobol", reference, 8);
    std::printf("%s, %s: relMSE at 16 samples, direct-tree %.4e, direct-tree-sobol %.4e: %.2fx lower\n", scene_name,
                jitter ? "jittered" : "pixel centres", independent, sobol, independent / sobol);
    EXPECT_GT(independent / sobol, 1.3) << scene_name << (jitter ? ", jittered" : ", pixel centres");
  }
}

TEST_F(Convergence, SobolBeatsIndependentAt16Samples) { expect_sobol_beats_independent(*scene_, *base_, "manylights"); }

TEST(ConvergenceShared, SobolBeatsIndependentAt16Samples) {
  const std::string path = testing::shared_scene_file("occluded_room/occluded_room.gltf");
  if (path.empty()) GTEST_SKIP() << testing::shared_scenes_skip_reason();
  const RenderSettings base =
      testing::settings({{"width", 64}, {"height", 36}, {"light_sampler", "tree"}, {"seed", 3}});
  expect_sobol_beats_independent(load_scene(path), base, "occluded_room");
}

// The time-to-error summary: log-log interpolation between the points around the target, the first
// point's time when it is already below, -1 when never reached; relMSE 1 at 100 ms and 0.01 at 10,000 ms
// lie on relMSE = 100 / t, so 0.1 is reached at 1,000 ms.
TEST(ConvergeReport, TimeToErrorInterpolatesLogLog) {
  auto point = [](int samples, double ms, double rel_mse) {
    ConvergePoint p;
    p.samples = samples;
    p.time_ms = ms;
    p.error.rel_mse = rel_mse;
    return p;
  };
  const std::vector<ConvergePoint> points = {point(1, 100.0, 1.0), point(2, 10000.0, 0.01), point(4, 20000.0, 0.001)};
  EXPECT_NEAR(time_to_error(points, 0.1), 1000.0, 1e-6);
  EXPECT_NEAR(time_to_error(points, 0.01), 10000.0, 1e-6);
  EXPECT_DOUBLE_EQ(time_to_error(points, 2.0), 100.0);
  EXPECT_EQ(time_to_error(points, 1e-4), -1.0);
  // An error that rises again does not matter after the first crossing.
  const std::vector<ConvergePoint> rising = {point(1, 10.0, 0.5), point(2, 20.0, 0.05), point(4, 40.0, 0.2)};
  EXPECT_NEAR(time_to_error(rising, 0.05), 20.0, 1e-9);
}

// "METHOD+DENOISER" is the method with that denoiser on; bad names are input errors naming the part.
TEST(ConvergeReport, DenoisedMethodsByName) {
  const ConvergeMethod m = converge_method_named("restir-di-pairwise+svgf");
  EXPECT_EQ(m.name, "restir-di-pairwise+svgf");
  EXPECT_EQ(m.transport, Transport::Direct);
  RenderSettings s;
  m.configure(s);
  EXPECT_EQ(s.method, Method::RestirDi);
  EXPECT_EQ(s.denoise.kind, DenoiserKind::Svgf);
  RenderSettings t;
  converge_method_named("pt-sobol+bilateral").configure(t);
  EXPECT_EQ(t.method, Method::PathTrace);
  EXPECT_EQ(t.sampler, SampleSequence::Sobol);
  EXPECT_EQ(t.denoise.kind, DenoiserKind::Bilateral);
  RenderSettings u;
  converge_method_named("direct-tree").configure(u);
  EXPECT_EQ(u.sampler, SampleSequence::Independent);
  EXPECT_EQ(u.denoise.kind, DenoiserKind::None);
  EXPECT_THROW(converge_method_named("pt+none"), InputError);
  EXPECT_THROW(converge_method_named("pt+"), InputError);
  EXPECT_THROW(converge_method_named("nope+svgf"), InputError);
}

}  // namespace
}  // namespace candela

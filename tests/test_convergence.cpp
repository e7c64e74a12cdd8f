// Convergence of every estimator `candela converge` runs (apps/converge.h), on builtin:manylights (256
// lights) at 48x27 with primary rays through pixel centres, fixed seeds:
//  - the unbiased estimators' MSE falls as 1/N: the least-squares slope of log MSE against log N lies in
//    [-1.2, -0.8];
//  - their image mean agrees with the reference;
//  - ReSTIR DI beats the light tree's `direct` estimator at equal samples (accumulated 1-spp frames).
#include <gtest/gtest.h>

#include "apps/converge.h"
#include "engine/builtin_scenes.h"

namespace candela {
namespace {

class Convergence : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    scene_ = new Scene(make_manylights_scene(256, 7));
    base_ = new RenderSettings(base());
  }
  static void TearDownTestSuite() {
    delete full_reference_;
    delete direct_reference_;
    delete base_;
    delete scene_;
  }
  // References, rendered when first needed (ctest runs each test in its own process): 4096 samples per
  // pixel (direct, light tree; path tracer, 4 bounces); their own MSE is 1/64 of the methods' at N = 64 and
  // 1/4 at N = 1024, which flattens the fitted slopes by a few percent at most.
  static const Image& reference(Transport transport) {
    Image*& image = transport == Transport::Direct ? direct_reference_ : full_reference_;
    if (!image) image = new Image(render_reference(*scene_, transport, *base_, 4096, transport == Transport::Direct ? 7919 : 7920));
    return *image;
  }
  static RenderSettings base() {
    RenderSettings s;
    s.width = 48;
    s.height = 27;
    s.jitter = false;
    s.max_depth = 4;
    s.light_sampler = LightSamplerKind::Tree;
    s.seed = 3;
    return s;
  }
  // Method `name` at N = 1, 2, 4, ..., max_samples; `run` picks the seed.
  static std::vector<ConvergePoint> run(const std::string& name, int max_samples, int run = 0) {
    const ConvergeMethod& m = converge_method_named(name);
    RenderSettings settings = *base_;
    settings.seed += uint64_t(run);
    std::vector<int> counts;
    for (int n = 1; n <= max_samples; n *= 2) counts.push_back(n);
    return run_convergence(*scene_, m, settings, counts, reference(m.transport));
  }
  static Scene* scene_;
  static RenderSettings* base_;
  static Image *direct_reference_, *full_reference_;
};
Scene* Convergence::scene_ = nullptr;
RenderSettings* Convergence::base_ = nullptr;
Image* Convergence::direct_reference_ = nullptr;
Image* Convergence::full_reference_ = nullptr;

// Independent samples per pixel (direct with each light sampler, the path tracer): the MSE at each N is
// averaged over 16 runs (seeds), since one run's MSE is a noisy, heavy-tailed estimate (single runs measured
// slopes from -0.85 to -1.21). The slope over N = 4..64 must be in [-1.2, -0.8]; measured -0.93 (uniform),
// -0.88 (power), -1.00 (tree), -0.99 (pt). Uniform and power selection sit above -1 at every range tried
// (up to N = 256): their rare large samples (dim lights close by) are under-represented at small N, so the
// average MSE is typically below its expectation there. Pixels are independent, so the mean difference of
// the first run at N = 64 must lie within 4 standard errors (two-sided, 6e-5 chance of a false failure each).
TEST_F(Convergence, IndependentSamplesFallAsOneOverN) {
  const int runs = 16;
  for (const char* name : {"direct-uniform", "direct-power", "direct-tree", "pt"}) {
    std::vector<ConvergePoint> mean = run(name, 64, 0);
    for (int k = 1; k < runs; ++k) {
      std::vector<ConvergePoint> points = run(name, 64, k);
      for (size_t i = 0; i < mean.size(); ++i) mean[i].error.mse += points[i].error.mse;
    }
    const ImageError first = mean.back().error;
    for (ConvergePoint& p : mean) p.error.mse /= runs;
    double slope = mse_slope(mean, 4, 64);
    std::printf("%-15s MSE slope over N = 4..64: %.3f; at N = 64 relMSE %.3e, mean difference %+.2e (standard error %.2e)\n",
                name, slope, first.rel_mse, first.mean_difference, first.standard_error);
    EXPECT_GE(slope, -1.2) << name;
    EXPECT_LE(slope, -0.8) << name;
    EXPECT_LT(std::abs(first.mean_difference), 4.0 * first.standard_error) << name;
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
  double reference_mean = 0.0;
  for (const vec3& p : reference(Transport::Direct).pixels) reference_mean += (p.x + p.y + p.z) / 3.0;
  reference_mean /= double(reference(Transport::Direct).pixels.size());
  for (const char* name : {"restir-di-basic", "restir-di-pairwise"}) {
    std::vector<ConvergePoint> points = run(name, 1024);
    double early = mse_slope(points, 4, 64), late = mse_slope(points, 64, 1024);
    const ImageError& e = points.back().error;
    std::printf("%-18s MSE slope over N = 4..64: %.3f, over 64..1024: %.3f; at N = 1024 mean difference %+.2e (%.2f%% of "
                "the mean)\n", name, early, late, e.mean_difference, 100.0 * e.mean_difference / reference_mean);
    EXPECT_GE(late, -1.2) << name;
    EXPECT_LE(late, -0.8) << name;
    EXPECT_LT(std::abs(e.mean_difference), 0.01 * reference_mean) << name;
  }
}

// Equal samples, one 1-spp frame (the real-time case) and 2 accumulated frames: ReSTIR DI (pairwise) has
// lower relMSE than the light tree's direct estimator (measured 0.174 vs 0.391 and 0.132 vs 0.185). With
// more accumulated frames the tree wins (its samples are independent; ReSTIR's frames share history):
// the crossover is printed, not tested. It lies between 2 and 4 frames since the energy-preserving BSDF
// (4 frames: 0.104 vs 0.098); with the earlier BSDF, which darkened grazing diffuse light, it lay between
// 4 and 8 (4 frames: 0.076 vs 0.088).
TEST_F(Convergence, RestirDiBeatsTreeAtEqualSamples) {
  std::vector<ConvergePoint> restir = run("restir-di-pairwise", 64), tree = run("direct-tree", 64);
  for (size_t i = 0; i < restir.size(); ++i)
    std::printf("N = %2d: relMSE restir-di-pairwise %.3e, direct-tree %.3e (ratio %.2f)\n", restir[i].samples,
                restir[i].error.rel_mse, tree[i].error.rel_mse, restir[i].error.rel_mse / tree[i].error.rel_mse);
  EXPECT_LT(restir[0].error.rel_mse, 0.7 * tree[0].error.rel_mse) << "one frame";
  EXPECT_LT(restir[1].error.rel_mse, tree[1].error.rel_mse) << "two frames";
}

}  // namespace
}  // namespace candela

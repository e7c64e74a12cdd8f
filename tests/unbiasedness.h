#pragma once
// The one statistical harness of the unbiasedness tests. An estimator is run R times with independent
// seeds, and so is a reference made by a different estimator; each run's image is reduced to per-tile
// means of its pixels (a pixel's value is the mean of its three channels: pixels, not channels, are the
// units) and to its image mean. Runs are independent even where an estimator correlates the pixels of one
// run (ReSTIR's spatial reuse does), so every standard error here comes from the spread between runs.
//
// Two tests, both must pass:
//  - the image mean: Welch's t of the difference of the two means, as a normal deviate z; |z| < 4
//    (two-sided, a false failure with probability 6.3e-5);
//  - the tiles: every tile's Welch t as a normal deviate z_t, and chi^2 = sum z_t^2 over the T tiles
//    with T degrees of freedom; p > 1e-4. This one sees biases of either sign in different places, which
//    cancel in the image mean.
// Power: a bias b of the image mean is detected with 95% probability when b > (4 + 1.645) SE (the
// normal quantiles of the test and of the power), so each comparison reports that smallest detectable
// bias relative to the reference mean, and the tests demonstrate it by rejecting a known-biased mode in
// the same setting.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "apps/renderer.h"
#include "engine/image.h"
#include "tests/render_helpers.h"
#include "tests/test_util.h"

namespace candela::testing {

// Regularised incomplete beta function I_x(a, b), by its continued fraction (Abramowitz & Stegun 26.5.8)
// evaluated with the modified Lentz method, on the side of x where it converges fast (A&S 26.5.2).
inline double incomplete_beta(double a, double b, double x) {
  if (x <= 0.0) return 0.0;
  if (x >= 1.0) return 1.0;
  if (x > (a + 1.0) / (a + b + 2.0)) return 1.0 - incomplete_beta(b, a, 1.0 - x);
  const double log_front = std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) + a * std::log(x) + b * std::log1p(-x);
  auto guard = [](double v) { return std::abs(v) < 1e-300 ? 1e-300 : v; };
  double c = 1.0, d = 1.0 / guard(1.0 - (a + b) * x / (a + 1.0)), h = d;
  for (int m = 1; m < 10000; ++m) {
    const double even = m * (b - m) * x / ((a + 2 * m - 1) * (a + 2 * m));
    d = 1.0 / guard(1.0 + even * d);
    c = guard(1.0 + even / c);
    h *= d * c;
    const double odd = -(a + m) * (a + b + m) * x / ((a + 2 * m) * (a + 2 * m + 1));
    d = 1.0 / guard(1.0 + odd * d);
    c = guard(1.0 + odd / c);
    const double delta = d * c;
    h *= delta;
    if (std::abs(delta - 1.0) < 1e-15) break;
  }
  return std::exp(log_front) * h / a;
}

// Two-sided p-value of Student's t with nu degrees of freedom: I_{nu/(nu+t^2)}(nu/2, 1/2).
inline double student_t_p_value(double t, double nu) { return incomplete_beta(0.5 * nu, 0.5, nu / (nu + t * t)); }

// The normal deviate with the same two-sided p-value: z with erfc(z / sqrt 2) = p (by bisection; 40
// stands for "beyond anything a double can tell apart").
inline double normal_deviate(double p) {
  double lo = 0.0, hi = 40.0;
  for (int k = 0; k < 200; ++k) {
    const double mid = 0.5 * (lo + hi);
    (std::erfc(mid / std::sqrt(2.0)) > p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

// Mean and variance of a sample (n - 1 in the variance).
struct Moments {
  double mean = 0.0, variance = 0.0;
  int n = 0;
};
inline Moments moments(const std::vector<double>& v) {
  Moments m;
  m.n = int(v.size());
  for (double x : v) m.mean += x / m.n;
  for (double x : v) m.variance += (x - m.mean) * (x - m.mean) / (m.n - 1);
  return m;
}

// Welch's t of the difference a - b of two means, converted to a normal deviate with the sign of the
// difference. Where neither mean varies between runs (a tile of emitters or sky, seen directly), the two
// differ by float rounding alone: a floor of 1e-6 of the mean on the standard error (far below any
// noise this harness meets) keeps such tiles at z near 0 instead of dividing by zero.
inline double welch_deviate(const Moments& a, const Moments& b) {
  const double va = a.variance / a.n, vb = b.variance / b.n, diff = a.mean - b.mean;
  const double floor = 1e-6 * std::max(std::abs(a.mean), std::abs(b.mean));
  if (va + vb <= floor * floor) return floor > 0.0 ? diff / floor : 0.0;
  const double nu = (va + vb) * (va + vb) / (va * va / (a.n - 1) + vb * vb / (b.n - 1));
  return std::copysign(normal_deviate(student_t_p_value(diff / std::sqrt(va + vb), nu)), diff);
}

// Per-tile means and the image mean of each of a number of independent runs.
struct Runs {
  int tiles_x = 0, tiles_y = 0;
  std::vector<std::vector<double>> tile;  // [tile][run]
  std::vector<double> image;              // [run]
};

// Runs render(run) for run = 0..runs-1 and reduces each image to tiles_x x tiles_y tile means.
inline Runs collect_runs(int runs, int tiles_x, int tiles_y, const std::function<Image(int)>& render) {
  Runs r{tiles_x, tiles_y, std::vector<std::vector<double>>(size_t(tiles_x) * tiles_y), {}};
  for (int run = 0; run < runs; ++run) {
    const Image img = render(run);
    std::vector<double> sum(r.tile.size(), 0.0);
    std::vector<int> count(r.tile.size(), 0);
    double total = 0.0;
    for (int y = 0; y < img.height; ++y)
      for (int x = 0; x < img.width; ++x) {
        const vec3& p = img.pixels[size_t(y) * img.width + x];
        const double v = (double(p.x) + p.y + p.z) / 3.0;
        const size_t t = size_t(y * tiles_y / img.height) * tiles_x + size_t(x * tiles_x / img.width);
        sum[t] += v;
        ++count[t];
        total += v;
      }
    for (size_t t = 0; t < r.tile.size(); ++t) r.tile[t].push_back(sum[t] / count[t]);
    r.image.push_back(total / (double(img.width) * img.height));
  }
  return r;
}

// The tiles every Unbiased.* test uses.
inline constexpr int kTilesX = 8, kTilesY = 4;

// `runs` independent runs of a Renderer with `base` (seed: seed + run), `frames` frames each from the
// scene's camera, frame f at scene time f / fps (0 with fps 0: a still scene); each run's last image.
inline Runs renderer_runs(const Scene& scene, const RenderSettings& base, int runs, int frames, uint64_t seed,
                          float fps = 0.0f) {
  return collect_runs(runs, kTilesX, kTilesY, [&](int run) {
    RenderSettings s = base;
    s.seed = seed + uint64_t(run);
    Renderer renderer(scene, s);
    for (int frame = 0; frame < frames; ++frame)
      render_checked(renderer, frame, fps > 0.0f ? frame / fps : 0.0f, scene.default_camera());
    return renderer.image();
  });
}

// The verdict of comparing an estimator's runs with a reference's.
struct Verdict {
  double mean = 0.0, reference = 0.0;                  // image means, averaged over runs
  double standard_error = 0.0;                         // of the difference
  double estimate_error = 0.0, reference_error = 0.0;  // of each mean
  double z = 0.0;                                      // the image-mean test's normal deviate
  double chi_square = 0.0, p_value = 1.0;
  int dof = 0;
  double detectable = 0.0;  // smallest bias detected with 95% power, relative to the reference
  bool mean_passes() const { return std::abs(z) < 4.0; }
  bool tiles_pass() const { return p_value > 1e-4; }
  bool unbiased() const { return mean_passes() && tiles_pass(); }
};

inline Verdict compare_runs(const Runs& estimate, const Runs& reference) {
  EXPECT_EQ(estimate.tile.size(), reference.tile.size());
  Verdict v;
  const Moments a = moments(estimate.image), b = moments(reference.image);
  v.mean = a.mean;
  v.reference = b.mean;
  v.estimate_error = std::sqrt(a.variance / a.n);
  v.reference_error = std::sqrt(b.variance / b.n);
  v.standard_error = std::hypot(v.estimate_error, v.reference_error);
  v.z = welch_deviate(a, b);
  v.detectable = (4.0 + 1.645) * v.standard_error / std::abs(b.mean);
  for (size_t t = 0; t < estimate.tile.size() && t < reference.tile.size(); ++t) {
    const Moments ta = moments(estimate.tile[t]), tb = moments(reference.tile[t]);
    const double z = welch_deviate(ta, tb);
    v.chi_square += z * z;
    ++v.dof;
  }
  v.p_value = v.dof > 0 ? chi_square_p_value(v.chi_square, v.dof) : 1.0;
  return v;
}

inline void print_verdict(const std::string& name, const Verdict& v) {
  std::printf(
      "%-34s mean %.5f (SE %.2f%%) vs reference %.5f (SE %.2f%%): %+.2f%% (z %+.2f), tiles chi2 %.1f / %d dof "
      "(p %.2g); detects %.2f%% at 95%% power\n",
      name.c_str(), v.mean, 100.0 * v.estimate_error / v.reference, v.reference,
      100.0 * v.reference_error / v.reference, 100.0 * (v.mean - v.reference) / v.reference, v.z, v.chi_square, v.dof,
      v.p_value, 100.0 * v.detectable);
}

// Fails the test unless both tests pass and the setting detects a bias of `detectable` (relative).
inline void expect_unbiased(const std::string& name, const Verdict& v, double detectable) {
  print_verdict(name, v);
  EXPECT_TRUE(v.mean_passes()) << name << ": image mean off by " << v.z << " standard errors";
  EXPECT_TRUE(v.tiles_pass()) << name << ": tiles chi-square " << v.chi_square << " with " << v.dof << " dof, p "
                              << v.p_value;
  EXPECT_LE(v.detectable, detectable) << name << ": the setting is too noisy to detect the bias it claims to";
}

// Fails the test unless the harness rejects a mode known to be biased: the demonstration of its power.
inline void expect_biased(const std::string& name, const Verdict& v) {
  print_verdict(name, v);
  EXPECT_FALSE(v.unbiased()) << name << " is known to be biased, and the harness did not see it";
}

}  // namespace candela::testing

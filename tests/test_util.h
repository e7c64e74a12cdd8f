#pragma once
// Shared helpers of the tests: where the shared scenes are, and the chi-square distribution.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <cstdlib>
#include <filesystem>
#include <string>

namespace candela::testing {

// Where the shared scenes are expected: $CANDELA_SCENES if set, else ../shared/scenes beside the checkout.
inline std::string shared_scenes_location() {
  if (const char* env = std::getenv("CANDELA_SCENES"); env != nullptr && *env != '\0') return env;
  return std::string(CANDELA_SOURCE_DIR) + "/../shared/scenes";
}

// The shared scenes directory, or empty when it does not exist (a machine without ../shared).
inline std::string shared_scenes_dir() {
  std::string dir = shared_scenes_location();
  return std::filesystem::is_directory(dir) ? dir : std::string();
}

// What a test that needs the shared scenes says when it skips (make test counts and prints these).
inline std::string shared_scenes_skip_reason() {
  if (!shared_scenes_dir().empty()) return "a shared scene file is missing (the test failed above)";
  return "shared scenes not installed: " + shared_scenes_location() + " does not exist";
}

// The full path of `relative` under the shared scenes. Empty when the directory is absent: the caller
// skips (GTEST_SKIP() << shared_scenes_skip_reason()). When the directory exists, the file must too: a
// missing one fails the current test here (and the caller's skip then cannot hide it; a test that failed
// and skipped counts as failed).
inline std::string shared_scene_file(const std::string& relative) {
  const std::string dir = shared_scenes_dir();
  if (dir.empty()) return {};
  const std::string path = dir + "/" + relative;
  if (!std::filesystem::is_regular_file(path)) {
    ADD_FAILURE() << path << " is missing, but the shared scenes directory " << dir
                  << " exists (a partial copy?): tests that need it fail rather than skip";
    return {};
  }
  return path;
}

// Regularised upper incomplete gamma Q(a, x), by its series for x < a + 1 and its continued fraction
// otherwise (the standard pair of expansions, e.g. Abramowitz & Stegun 6.5.29 and 6.5.31).
inline double gamma_q(double a, double x) {
  if (x <= 0.0) return 1.0;
  double log_prefix = -x + a * std::log(x) - std::lgamma(a);
  if (x < a + 1.0) {
    double term = 1.0 / a, sum = term;
    for (int n = 1; n < 10000 && std::abs(term) > std::abs(sum) * 1e-15; ++n) {
      term *= x / (a + n);
      sum += term;
    }
    return 1.0 - sum * std::exp(log_prefix);
  }
  // Modified Lentz evaluation of the continued fraction.
  double b = x + 1.0 - a, c = 1e300, d = 1.0 / b, h = d;
  for (int i = 1; i < 10000; ++i) {
    double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < 1e-300) d = 1e-300;
    c = b + an / c;
    if (std::abs(c) < 1e-300) c = 1e-300;
    d = 1.0 / d;
    double delta = d * c;
    h *= delta;
    if (std::abs(delta - 1.0) < 1e-15) break;
  }
  return std::exp(log_prefix) * h;
}

// p-value of a chi-square statistic with `dof` degrees of freedom.
inline double chi_square_p_value(double statistic, int dof) { return gamma_q(0.5 * dof, 0.5 * statistic); }

// Exact equality, also of NaNs and signed zeros: SIMD kernels against their scalar references.
inline bool same_bits(float a, float b) { return std::memcmp(&a, &b, sizeof(float)) == 0; }

}  // namespace candela::testing

#pragma once
// Shared helpers of the tests: where the shared scenes are, and the chi-square distribution.
#include <cmath>
#include <filesystem>
#include <string>

namespace candela::testing {

// ../shared/scenes beside the checkout (CANDELA_SCENES overrides); empty if absent.
inline std::string shared_scenes_dir() {
  if (const char* env = std::getenv("CANDELA_SCENES")) return env;
  std::string dir = std::string(CANDELA_SOURCE_DIR) + "/../shared/scenes";
  return std::filesystem::is_directory(dir) ? dir : std::string();
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

}  // namespace candela::testing

// Reservoir math on 1D integrals with known answers: streaming RIS and merging are unbiased, and across
// domains with different supports the 1/M combination has exactly its predicted bias while the
// generalized balance heuristic has none. Fixed seeds; 4-sigma bounds (about 6e-5 false-failure chance each).
#include <gtest/gtest.h>

#include <cmath>
#include <functional>

#include "engine/rng.h"
#include "restir/reservoir.h"

namespace candela {
namespace {

// The integrand on [0, 1]: f(x) = 3x^2 + 1/2, whose integral over [a, b] is b^3 - a^3 + (b - a) / 2.
float f(float x) { return 3.0f * x * x + 0.5f; }
double integral_f(double a, double b) { return b * b * b - a * a * a + 0.5 * (b - a); }

struct MeanAndError {
  double mean, error;
};

MeanAndError estimate(int trials, const std::function<double(Rng&)>& one) {
  Rng rng(2024, 7);
  double sum = 0.0, sum2 = 0.0;
  for (int t = 0; t < trials; ++t) {
    double v = one(rng);
    sum += v;
    sum2 += v * v;
  }
  double mean = sum / trials;
  return {mean, std::sqrt(std::max(0.0, sum2 / trials - mean * mean) / trials)};
}

// Streaming RIS (Bitterli et al. 2020, Alg. 3): M uniform candidates, m_i = 1 / M, W_i = 1 / p = 1.
Reservoir<float> streaming_ris(const std::function<float(float)>& p_hat, int M, Rng& rng) {
  Reservoir<float> r;
  for (int i = 0; i < M; ++i) {
    float x = rng.next_float();
    r.update(x, p_hat(x) / float(M), p_hat(x), rng.next_float());
  }
  r.M = float(M);
  r.finalize();
  return r;
}

TEST(Reservoir, StreamingRisIsUnbiased) {
  auto p_hat = [](float x) { return x + 0.1f; };  // a rough target: RIS stays unbiased
  MeanAndError e = estimate(200000, [&](Rng& rng) {
    Reservoir<float> r = streaming_ris(p_hat, 8, rng);
    return double(f(r.y) * r.W);
  });
  EXPECT_NEAR(e.mean, integral_f(0, 1), 4.0 * e.error);
}

// Target equal to the integrand: the estimate is the mean of the candidates' f / p, and its variance
// falls as 1 / M.
TEST(Reservoir, RisVarianceFallsWithCandidates) {
  double variance[2];
  int k = 0;
  for (int M : {4, 16}) {
    MeanAndError e = estimate(100000, [&](Rng& rng) {
      Reservoir<float> r = streaming_ris(f, M, rng);
      return double(f(r.y) * r.W);
    });
    EXPECT_NEAR(e.mean, integral_f(0, 1), 4.0 * e.error);
    variance[k++] = e.error * e.error * 100000;
  }
  EXPECT_NEAR(variance[0] / variance[1], 4.0, 0.4);
}

// Merging four reservoirs of one domain (Bitterli et al. 2020, Alg. 4) with m_i = M_i / sum M: the same
// as one reservoir over all their candidates, unbiased, with the summed confidence.
TEST(Reservoir, MergeIsUnbiased) {
  auto p_hat = [](float x) { return x + 0.1f; };
  MeanAndError e = estimate(100000, [&](Rng& rng) {
    Reservoir<float> merged;
    for (int k = 0; k < 4; ++k) {
      Reservoir<float> r = streaming_ris(p_hat, 8, rng);
      merged.merge(r, p_hat(r.y), r.M / 32.0f, rng.next_float());
    }
    merged.finalize();
    EXPECT_EQ(merged.M, 32.0f);
    return double(f(merged.y) * merged.W);
  });
  EXPECT_NEAR(e.mean, integral_f(0, 1), 4.0 * e.error);
}

// Systematic picks after streaming RIS (systematic_picks; ReSTIR's further shaded samples): with a poor target, each
// pick j's f(y_j) w_sum / p_hat(y_j) is unbiased like the stream's own, and the mean of 3 picks has less variance than
// one (with a target proportional to f every pick would give the same estimate, and a wrong pick no bias).
TEST(Reservoir, SystematicPicksAreUnbiased) {
  auto p_hat = [](float x) { return 1.1f - x; };  // a poor target: the pick matters
  constexpr int kCandidates = 8, kPicks = 3;
  // The estimate of pick j, or with j = kPicks their mean.
  auto picked = [&](int j) {
    return estimate(200000, [&](Rng& rng) {
      float x[kCandidates], w[kCandidates];
      Reservoir<float> r;
      int chosen = -1;
      for (int i = 0; i < kCandidates; ++i) {
        x[i] = rng.next_float(), w[i] = p_hat(x[i]) / float(kCandidates);
        if (r.update(x[i], w[i], p_hat(x[i]), rng.next_float())) chosen = i;
      }
      r.finalize();
      int picks[kPicks];
      systematic_picks(w, kCandidates, chosen, rng.next_float(), kPicks, picks);
      auto value = [&](int k) { return double(f(x[picks[k]]) * r.w_sum / p_hat(x[picks[k]])); };
      if (j < kPicks) return value(j);
      double sum = 0.0;
      for (int k = 0; k < kPicks; ++k) sum += value(k);
      return sum / kPicks;
    });
  };
  for (int j = 0; j <= kPicks; ++j) {
    const MeanAndError e = picked(j);
    EXPECT_NEAR(e.mean, integral_f(0, 1), 4.0 * e.error) << "pick " << j;
  }
  std::printf("standard error of one pick %.6f, of the mean of %d %.6f\n", picked(0).error, kPicks,
              picked(kPicks).error);
  EXPECT_LT(picked(kPicks).error, 0.8 * picked(0).error);
}

// Systematic picks are stratified: of n picks, a candidate with a fraction f of the weights gets floor(n f) or
// ceil(n f) (up to rounding where n f is an integer), on random weights with zeros, and pick 0 is the kept one.
TEST(Reservoir, SystematicPicksAreStratified) {
  Rng rng(77, 3);
  for (int trial = 0; trial < 20000; ++trial) {
    const int count = 1 + int(rng.next_u32() % 6), n = 2 + int(rng.next_u32() % 7);
    float w[6], sum = 0.0f;
    for (int k = 0; k < count; ++k) {
      w[k] = rng.next_float() < 0.3f ? 0.0f : rng.next_float();
      sum += w[k];
    }
    if (!(sum > 0.0f)) continue;
    int chosen = 0;  // a candidate with weight, drawn in proportion to it
    for (float u = rng.next_float() * sum, end = 0.0f; chosen < count; ++chosen)
      if (end += w[chosen]; w[chosen] > 0.0f && u < end) break;
    while (chosen == count || !(w[chosen] > 0.0f)) --chosen;
    int picks[8], times[6] = {};
    systematic_picks(w, count, chosen, rng.next_float(), n, picks);
    ASSERT_EQ(picks[0], chosen);
    for (int j = 0; j < n; ++j) ++times[picks[j]];
    for (int k = 0; k < count; ++k) {
      const double expected = double(n) * w[k] / sum;
      EXPECT_GE(times[k], std::floor(expected - 1e-4)) << "trial " << trial << " candidate " << k;
      EXPECT_LE(times[k], std::ceil(expected + 1e-4)) << "trial " << trial << " candidate " << k;
    }
  }
}

// Two domains (think: two pixels) with different supports: domain 1 integrates f on [0, 0.7), domain 2
// on (0.3, 1]. Domain 1 combines its own reservoir with domain 2's.
//  - "none", m_i = M_i / sum M = 1/2: samples in [0, 0.3) can only come from domain 1 and count half, so
//    the expectation is integral(0.3, 0.7) + integral(0, 0.3) / 2, biased by -integral(0, 0.3) / 2.
//  - "basic", the generalized balance heuristic m_i(x) = M_i p_i(x) / sum_j M_j p_j(x) (Lin et al. 2022,
//    eq. 17 with confidence weights): unbiased.
class ReservoirBiasModes : public ::testing::Test {
 protected:
  static float target1(float x) { return x < 0.7f ? f(x) : 0.0f; }
  static float target2(float x) { return x > 0.3f ? f(x) : 0.0f; }
  MeanAndError combine(const std::function<float(int, float)>& mis_weight) {
    return estimate(200000, [&](Rng& rng) {
      Reservoir<float> own = streaming_ris(target1, 8, rng), neighbour = streaming_ris(target2, 8, rng);
      Reservoir<float> out;
      out.merge(own, target1(own.y), mis_weight(0, own.y), rng.next_float());
      out.merge(neighbour, target1(neighbour.y), mis_weight(1, neighbour.y), rng.next_float());
      out.finalize();
      return double(target1(out.y) * out.W);
    });
  }
};

TEST_F(ReservoirBiasModes, NoneHasItsPredictedBias) {
  MeanAndError e = combine([](int, float) { return 0.5f; });
  double expected = integral_f(0.3, 0.7) + 0.5 * integral_f(0.0, 0.3);
  double bias = e.mean - integral_f(0.0, 0.7);
  std::printf("none: mean %.5f, reference %.5f, bias %+.5f (predicted %+.5f), standard error %.5f\n", e.mean,
              integral_f(0.0, 0.7), bias, -0.5 * integral_f(0.0, 0.3), e.error);
  EXPECT_NEAR(e.mean, expected, 4.0 * e.error);
  EXPECT_GT(std::abs(bias), 8.0 * e.error) << "the test must be able to see this bias";
}

TEST_F(ReservoirBiasModes, BalanceHeuristicIsUnbiased) {
  MeanAndError e = combine([](int i, float x) {
    float p[2] = {8.0f * target1(x), 8.0f * target2(x)};
    return p[0] + p[1] > 0.0f ? p[i] / (p[0] + p[1]) : 0.0f;
  });
  EXPECT_NEAR(e.mean, integral_f(0.0, 0.7), 4.0 * e.error);
}

}  // namespace
}  // namespace candela

#pragma once
// The weighted reservoir of resampled importance sampling, in the generalized form of Lin et al. 2022
// ("Generalized Resampled Importance Sampling", GRIS): a candidate x_i enters with resampling weight
//   w_i = m_i(x_i) * p_hat(x_i) * W_i
// (m_i: its resampling MIS weight, p_hat: the target function of the domain that resamples, W_i: the
// candidate's unbiased contribution weight, 1 / p(x_i) for a fresh sample drawn with pdf p), one is kept
// with probability w_i / w_sum (weighted reservoir sampling, Bitterli et al. 2020, Alg. 2), and the kept
// sample y gets the contribution weight W = w_sum / p_hat(y), so that f(y) W estimates the integral of f.
// Streaming RIS over M fresh candidates is the case m_i = 1 / M (Bitterli et al. 2020, Alg. 3); combining
// reservoirs (Alg. 4) is the case where each input reservoir is one candidate carrying its own W.
#include <cmath>
#include <cstdint>

namespace candela {

template <class Sample>
struct Reservoir {
  Sample y{};            // the kept sample
  float p_hat_y = 0.0f;  // target function at y, for the domain that resampled it
  float w_sum = 0.0f;    // sum of resampling weights seen
  float M = 0.0f;        // confidence: how many candidates the reservoir stands for (capped by callers)
  float W = 0.0f;        // unbiased contribution weight of y, set by finalize()

  // Streams one candidate with resampling weight w (>= 0) and target p_hat_x; u uniform in [0, 1).
  // Returns whether it was kept.
  bool update(const Sample& x, float w, float p_hat_x, float u) {
    if (!take(w, p_hat_x, u)) return false;
    y = x;
    return true;
  }
  // update() but for the sample, which the caller writes into y in place where this returns true: a sample assembled
  // for update() and copied in was read with wide loads of its narrower stores, which stalled on store forwarding.
  bool take(float w, float p_hat_x, float u) {
    w_sum += w;
    if (w > 0.0f && u * w_sum < w) {
      p_hat_y = p_hat_x;
      return true;
    }
    return false;
  }

  // Streams another reservoir's sample as one candidate: p_hat_at_receiver is this domain's target at
  // r.y, mis_weight its resampling MIS weight m_i(r.y). Adds r's confidence M.
  bool merge(const Reservoir& r, float p_hat_at_receiver, float mis_weight, float u) {
    M += r.M;
    return update(r.y, mis_weight * p_hat_at_receiver * r.W, p_hat_at_receiver, u);
  }

  // W = w_sum / p_hat(y), or 0 when nothing with positive weight was kept (or the sum overflowed).
  void finalize() {
    W = p_hat_y > 0.0f ? w_sum / p_hat_y : 0.0f;
    if (!std::isfinite(W)) W = 0.0f;
  }
};

// Systematic resampling (Kitagawa 1996; Douc and Cappe 2005) after a stream kept candidate `chosen` (chosen >= 0)
// of the weights w[0..count): picks[j] (j < n) is the candidate whose interval of the weights' running sum holds
// point j, where point 0 lies a fraction v into the kept candidate's interval and the others follow at steps of
// sum / n, wrapping around. As the stream kept `chosen` with probability w_chosen / sum and v is uniform in [0, 1),
// point 0 is uniform in [0, sum), and so is every point: each pick is kept with probability w_k / sum, as the stream
// keeps its one, while together the picks are stratified over the weights (a candidate with a fraction f of the sum is
// picked floor(n f) or ceil(n f) times). picks[0] is `chosen`. Cost: a pass over the weights, and one per pick.
inline void systematic_picks(const float* w, int count, int chosen, float v, int n, int* picks) {
  float start = 0.0f, sum = 0.0f;  // the kept candidate's interval starts at `start`
  for (int k = 0; k < count; ++k) {
    if (k == chosen) start = sum;
    sum += w[k];
  }
  const float first = start + v * w[chosen];
  picks[0] = chosen;
  for (int j = 1; j < n; ++j) {
    float point = first + float(j) * sum / float(n);
    if (point >= sum) point -= sum;
    int k = 0;
    for (float end = 0.0f; k < count; ++k) {
      end += w[k];
      if (w[k] > 0.0f && point < end) break;
    }
    while (k == count || !(w[k] > 0.0f)) --k;  // beyond the sum by rounding: the last candidate with weight
    picks[j] = k;
  }
}

}  // namespace candela

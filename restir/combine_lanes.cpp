// The combination kernel (combine_lanes.h), compiled once per instruction set by Highway's foreach_target.h
// and dispatched at run time. It repeats restir/di_reuse.cpp's pairwise_weight and combine, and
// Reservoir::update and finalize (restir/reservoir.h), in their order.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "restir/combine_lanes.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/highway.h"
#include "restir/combine_lanes.h"
#include "engine/lanes-inl.h"

HWY_BEFORE_NAMESPACE();
namespace candela {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// pairwise_weight of the combining pixel's own sample (k = 0): (1/n) sum_i canonical / (M_i p_i(y_0) +
// canonical), summed over the inputs i = 1..n in order, where the sum is positive.
V canonical_weight(D d, const CombineLanes& c, int s, int max_count, V count, V n, V canonical) {
  const V zero = hn::Zero(d);
  V m = zero;
  for (int i = 1; i < max_count; ++i) {
    const V t = hn::Mul(hn::Load(d, c.M[i] + s), hn::Load(d, c.of[i] + s));
    const V sum = hn::Add(t, canonical);
    const M counts = hn::And(hn::Lt(hn::Set(d, float(i)), count), hn::Gt(sum, zero));
    m = hn::IfThenElse(counts, hn::Add(m, hn::Div(canonical, sum)), m);
  }
  return hn::Div(m, n);
}

// One vector of slots [s, s + lanes): combine's loop over the inputs, then Reservoir::finalize.
void combine(D d, CombineLanes& c, int s, int max_count) {
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0f);
  const V count = hn::Load(d, c.count + s), n = hn::Sub(count, one);
  const M alone = hn::Eq(n, zero);  // no other input: the weight is 1
  const V M0 = hn::Load(d, c.M[0] + s);
  V M_sum = zero, w_sum = zero, p_hat = zero, chosen = hn::Set(d, -1.0f);
  for (int k = 0; k < max_count; ++k) {
    const M has = hn::Lt(hn::Set(d, float(k)), count);
    const V W = hn::Load(d, c.W[k] + s);
    M_sum = hn::IfThenElse(has, hn::Add(M_sum, hn::Load(d, c.M[k] + s)), M_sum);
    const M sampled = hn::And(has, hn::Gt(W, zero));
    if (hn::AllFalse(d, sampled)) continue;
    // The target at the combining pixel: its own stored one for k = 0, else p_0(y_k).
    const V p_here = hn::Load(d, (k == 0 ? c.own[0] : c.at[k]) + s);
    const V canonical = hn::Mul(hn::Div(M0, n), p_here);
    V m;
    if (k == 0) {
      m = canonical_weight(d, c, s, max_count, count, n, canonical);
    } else {
      const V t = hn::Mul(hn::Load(d, c.M[k] + s), hn::Load(d, c.own[k] + s));
      const V sum = hn::Add(t, canonical);
      m = hn::IfThenElseZero(hn::Gt(sum, zero), hn::Div(hn::Div(t, sum), n));
    }
    m = hn::IfThenElse(alone, one, m);
    // Reservoir::update with w = m p_here W.
    const V w = hn::Mul(hn::Mul(m, p_here), W);
    w_sum = hn::IfThenElse(sampled, hn::Add(w_sum, w), w_sum);
    const M keep = hn::And(sampled, hn::And(hn::Gt(w, zero), hn::Lt(hn::Mul(hn::Load(d, c.u[k] + s), w_sum), w)));
    chosen = hn::IfThenElse(keep, hn::Set(d, float(k)), chosen);
    p_hat = hn::IfThenElse(keep, p_here, p_hat);
  }
  // Reservoir::finalize: W = w_sum / p_hat where p_hat > 0 and the quotient is finite, else 0.
  const V W = hn::IfThenElseZero(hn::Gt(p_hat, zero), hn::Div(w_sum, p_hat));
  hn::Store(hn::IfThenElseZero(hn::IsFinite(W), W), d, c.W_out + s);
  hn::Store(chosen, d, c.chosen + s), hn::Store(p_hat, d, c.p_hat + s);
  hn::Store(w_sum, d, c.w_sum + s), hn::Store(M_sum, d, c.M_sum + s);
}

void CombinePairwiseLanes(CombineLanes& lanes, int slots, int max_count) {
  const D d;
  for (int s = 0; s < slots; s += int(hn::Lanes(d))) combine(d, lanes, s, max_count);
}

}  // namespace HWY_NAMESPACE
}  // namespace candela
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace candela {

HWY_EXPORT(CombinePairwiseLanes);

void combine_pairwise_lanes(CombineLanes& lanes, int slots, int max_count) {
  HWY_DYNAMIC_DISPATCH(CombinePairwiseLanes)(lanes, slots, max_count);
}

}  // namespace candela
#endif  // HWY_ONCE

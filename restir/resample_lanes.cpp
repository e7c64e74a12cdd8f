// The resampling kernels (resample_lanes.h), compiled once per instruction set by Highway's foreach_target.h
// and dispatched at run time. They repeat restir/di_candidates.h's resample_candidates (its light candidates),
// restir/reuse.cpp's pairwise_weight and combine, and Reservoir::update, finalize and systematic_picks
// (restir/reservoir.h), in their order.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "restir/resample_lanes.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/highway.h"
#include "restir/resample_lanes.h"
#include "engine/lanes-inl.h"

HWY_BEFORE_NAMESPACE();
namespace candela {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// Reservoir::update of candidate k (weight w, target p, uniform u) where `sampled`: w_sum += w, and the
// candidate is kept where w > 0 and u w_sum < w.
struct Stream {
  V w_sum, p_hat, chosen;
};
void update(D d, M sampled, V w, V p, V u, int k, Stream& r) {
  r.w_sum = hn::IfThenElse(sampled, hn::Add(r.w_sum, w), r.w_sum);
  const M keep = hn::And(sampled, hn::And(hn::Gt(w, hn::Zero(d)), hn::Lt(hn::Mul(u, r.w_sum), w)));
  r.chosen = hn::IfThenElse(keep, hn::Set(d, float(k)), r.chosen);
  r.p_hat = hn::IfThenElse(keep, p, r.p_hat);
}
Stream empty_stream(D d) { return {hn::Zero(d), hn::Zero(d), hn::Set(d, -1.0f)}; }
void store(D d, const Stream& r, int s, StreamLanes& out) {
  hn::Store(r.chosen, d, out.chosen + s), hn::Store(r.p_hat, d, out.p_hat + s), hn::Store(r.w_sum, d, out.w_sum + s);
}

void ResampleLightCandidatesLanes(const CandidateLanes* planes, const float* p_light, const float* u, int count,
                                  const float* M_l, float M_b, int slots, StreamLanes& out) {
  const D d;
  const V zero = hn::Zero(d), m_b = hn::Set(d, M_b);
  for (int s = 0; s < slots; s += int(hn::Lanes(d))) {
    const V m_l = hn::Load(d, M_l + s);
    Stream r = empty_stream(d);
    for (int k = 0; k < count; ++k) {
      const size_t at = size_t(k) * kLaneSlots + size_t(s);
      const V pl = hn::LoadU(d, p_light + at), p_hat = hn::Load(d, planes[k].p_hat + s);
      const V w = hn::Div(p_hat, hn::Add(hn::Mul(m_l, pl), hn::Mul(m_b, hn::Load(d, planes[k].bsdf_area_pdf + s))));
      // The scalar code skips a candidate where p_light <= 0 or p_hat <= 0 (so a NaN is streamed, as there).
      const M sampled = hn::Not(hn::Or(hn::Le(pl, zero), hn::Le(p_hat, zero)));
      update(d, sampled, w, p_hat, hn::LoadU(d, u + at), k, r);
    }
    store(d, r, s, out);
  }
}

// pairwise_weight's term with visibility: a positive term t is 0 where the sample is not visible (visible 0).
V unless_occluded(D d, V t, V visible) {
  return hn::IfThenZeroElse(hn::AndNot(hn::Gt(visible, hn::Zero(d)), hn::Gt(t, hn::Zero(d))), t);
}

// pairwise_weight of the combining pixel's own sample (k = 0): (1/n) sum_i canonical / (M_i p_i(y_0) +
// canonical), summed over the inputs i = 1..n in order, where the sum is positive (with visibility, each
// M_i p_i(y_0) only where y_0 is visible from input i).
V canonical_weight(D d, const CombineLanes& c, int s, int max_count, bool visibility, V count, V n, V canonical) {
  const V zero = hn::Zero(d);
  V m = zero;
  for (int i = 1; i < max_count; ++i) {
    V t = hn::Mul(hn::Load(d, c.M[i] + s), hn::Load(d, c.of[i] + s));
    if (visibility) t = unless_occluded(d, t, hn::Load(d, c.of_visible[i] + s));
    const V sum = hn::Add(t, canonical);
    const M counts = hn::And(hn::Lt(hn::Set(d, float(i)), count), hn::Gt(sum, zero));
    m = hn::IfThenElse(counts, hn::Add(m, hn::Div(canonical, sum)), m);
  }
  return hn::Div(m, n);
}

// One vector of slots [s, s + lanes): combine's loop over the inputs, then Reservoir::finalize.
void combine(D d, CombineLanes& c, int s, int max_count, bool visibility) {
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0f);
  const V count = hn::Load(d, c.count + s), n = hn::Sub(count, one);
  const M alone = hn::Eq(n, zero);  // no other input: the weight is 1
  const V M0 = hn::Load(d, c.M[0] + s);
  V M_sum = zero;
  Stream r = empty_stream(d);
  for (int k = 0; k < max_count; ++k) {
    const M has = hn::Lt(hn::Set(d, float(k)), count);
    const V W = hn::Load(d, c.W[k] + s);
    M_sum = hn::IfThenElse(has, hn::Add(M_sum, hn::Load(d, c.M[k] + s)), M_sum);
    const M sampled = hn::AndNot(hn::Le(W, zero), has);  // combine skips inputs with W <= 0
    if (hn::AllFalse(d, sampled)) {
      hn::Store(zero, d, c.w[k] + s);
      continue;
    }
    // The target at the combining pixel: its own stored one for k = 0, else p_0(y_k).
    const V p_here = hn::Load(d, (k == 0 ? c.own[0] : c.at[k]) + s);
    const V canonical = hn::Mul(hn::Div(M0, n), p_here);
    V m;
    if (k == 0) {
      m = canonical_weight(d, c, s, max_count, visibility, count, n, canonical);
    } else {
      V t = hn::Mul(hn::Load(d, c.M[k] + s), hn::Load(d, c.own[k] + s));
      if (visibility) t = unless_occluded(d, t, hn::Load(d, c.own_visible[k] + s));
      const V sum = hn::Add(t, canonical);
      m = hn::IfThenElseZero(hn::Gt(sum, zero), hn::Div(hn::Div(t, sum), n));
    }
    m = hn::IfThenElse(alone, one, m);
    const V w = hn::Mul(hn::Mul(m, p_here), W);
    hn::Store(hn::IfThenElseZero(sampled, w), d, c.w[k] + s);
    update(d, sampled, w, p_here, hn::Load(d, c.u[k] + s), k, r);
  }
  // Reservoir::finalize: W = w_sum / p_hat where p_hat > 0 and the quotient is finite, else 0.
  const V W = hn::IfThenElseZero(hn::Gt(r.p_hat, zero), hn::Div(r.w_sum, r.p_hat));
  hn::Store(hn::IfThenElseZero(hn::IsFinite(W), W), d, c.W_out + s);
  store(d, r, s, c.result);
  hn::Store(M_sum, d, c.M_sum + s);
}

void CombinePairwiseLanes(CombineLanes& lanes, int slots, int max_count, bool visibility) {
  const D d;
  for (int s = 0; s < slots; s += int(hn::Lanes(d))) combine(d, lanes, s, max_count, visibility);
}

// One vector of slots [s, s + lanes) of systematic_picks: the kept input's start in the running sum and the sum, then
// per pick its point and the first input k whose interval holds it (w_k > 0 and point < end_k), else the last input
// with weight (no interval holds a NaN point, which an infinite sum of the weights gives).
void picks(D d, CombineLanes& c, const float* v, int n, int s, int max_count) {
  const V zero = hn::Zero(d);
  const V count = hn::Load(d, c.count + s), chosen = hn::Load(d, c.result.chosen + s);
  V start = zero, sum = zero, w_chosen = zero;
  for (int k = 0; k < max_count; ++k) {
    const M has = hn::Lt(hn::Set(d, float(k)), count), at_chosen = hn::And(has, hn::Eq(hn::Set(d, float(k)), chosen));
    const V w = hn::Load(d, c.w[k] + s);
    start = hn::IfThenElse(at_chosen, sum, start);
    w_chosen = hn::IfThenElse(at_chosen, w, w_chosen);
    sum = hn::IfThenElse(has, hn::Add(sum, w), sum);
  }
  const V first = hn::Add(start, hn::Mul(hn::Load(d, v + s), w_chosen));
  for (int j = 1; j < n; ++j) {
    V point = hn::Add(first, hn::Div(hn::Mul(hn::Set(d, float(j)), sum), hn::Set(d, float(n))));
    point = hn::IfThenElse(hn::Ge(point, sum), hn::Sub(point, sum), point);
    V end = zero, pick = zero, last = zero;
    M found = hn::FirstN(d, 0);
    for (int k = 0; k < max_count; ++k) {
      const V index = hn::Set(d, float(k)), w = hn::Load(d, c.w[k] + s);
      const M weighted = hn::And(hn::Lt(index, count), hn::Gt(w, zero));
      end = hn::Add(end, w);  // w is 0 for the inputs from count on
      const M here = hn::AndNot(found, hn::And(weighted, hn::Lt(point, end)));
      pick = hn::IfThenElse(here, index, pick);
      found = hn::Or(found, here);
      last = hn::IfThenElse(weighted, index, last);
    }
    hn::Store(hn::IfThenElse(found, pick, last), d, c.picks[j] + s);
  }
}

void SystematicPicksLanes(CombineLanes& lanes, const float* v, int n, int slots, int max_count) {
  const D d;
  for (int s = 0; s < slots; s += int(hn::Lanes(d))) picks(d, lanes, v, n, s, max_count);
}

}  // namespace HWY_NAMESPACE
}  // namespace candela
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace candela {

HWY_EXPORT(CombinePairwiseLanes);
HWY_EXPORT(ResampleLightCandidatesLanes);
HWY_EXPORT(SystematicPicksLanes);

void resample_light_candidates_lanes(const CandidateLanes* planes, const float* p_light, const float* u, int count,
                                     const float* M_l, float M_b, int slots, StreamLanes& out) {
  HWY_DYNAMIC_DISPATCH(ResampleLightCandidatesLanes)(planes, p_light, u, count, M_l, M_b, slots, out);
}

void combine_pairwise_lanes(CombineLanes& lanes, int slots, int max_count, bool visibility) {
  HWY_DYNAMIC_DISPATCH(CombinePairwiseLanes)(lanes, slots, max_count, visibility);
}

void systematic_picks_lanes(CombineLanes& lanes, const float* v, int n, int slots, int max_count) {
  HWY_DYNAMIC_DISPATCH(SystematicPicksLanes)(lanes, v, n, slots, max_count);
}

}  // namespace candela
#endif  // HWY_ONCE

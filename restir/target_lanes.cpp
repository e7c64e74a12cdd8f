// The candidate-lanes kernel (target_lanes.h), compiled once per instruction set by Highway's
// foreach_target.h and dispatched at run time (the BSDF arithmetic: engine/bsdf_lanes-inl.h).
// Each step names the scalar function whose arithmetic it repeats, in the same order (restir/sample.h
// sample_contribution, engine/lights.h light_sample_towards, engine/bsdf.cpp Bsdf::eval and Bsdf::pdf,
// engine/ggx_albedo.h GgxAlbedoRow::at, engine/tracer.h Tracer::spawn_ray_to and offset_point through
// engine/ray_lanes-inl.h).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "restir/target_lanes.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/highway.h"
#include "restir/target_lanes.h"
#include "engine/bsdf_lanes-inl.h"
#include "engine/ray_lanes-inl.h"

HWY_BEFORE_NAMESPACE();
namespace candela {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// One vector of slots [s, s + lanes) of one candidate plane: light_sample_towards, then sample_contribution's
// value with the BSDF planes `bsdf` of the receivers (where `valid`; its lanes hold garbage elsewhere).
struct Unshadowed {
  V3 wo, wi;
  V cos_l, dist;
  M valid;
  V value[3];
};
Unshadowed unshadowed(D d, const ReceiverLanes& r, const BsdfLanes& bsdf, const CandidateLanes& c, int s) {
  const V zero = hn::Zero(d);
  Unshadowed u;
  const V3 p = load3(d, r.px, r.py, r.pz, s), y = load3(d, c.x, c.y, c.z, s);
  const V3 delta{hn::Sub(y.x, p.x), hn::Sub(y.y, p.y), hn::Sub(y.z, p.z)};
  const V dist2 = dot(delta, delta);
  u.dist = hn::Sqrt(dist2);
  u.wi = {hn::Div(delta.x, u.dist), hn::Div(delta.y, u.dist), hn::Div(delta.z, u.dist)};
  const V3 ny = load3(d, c.nx, c.ny, c.nz, s);
  u.cos_l = dot(ny, u.wi);
  const V L[3] = {hn::Load(d, c.radiance[0] + s), hn::Load(d, c.radiance[1] + s), hn::Load(d, c.radiance[2] + s)};
  const M emits = hn::Or(hn::Gt(hn::Load(d, c.two_sided + s), zero), hn::Lt(u.cos_l, zero));
  u.valid = hn::And(hn::Gt(hn::Load(d, c.active + s), zero), hn::Gt(dist2, zero));
  u.valid = hn::And(u.valid, hn::Gt(hn::Abs(u.cos_l), hn::Set(d, 1e-7f)));
  u.valid = hn::And(u.valid, hn::And(emits, hn::Gt(hn::Max(L[0], hn::Max(L[1], L[2])), zero)));
  u.valid = hn::And(u.valid, hn::Gt(dot(u.wi, load3(d, r.gx, r.gy, r.gz, s)), zero));
  u.wo = load3(d, r.wox, r.woy, r.woz, s);
  V f[3];
  eval_bsdf<true>(d, bsdf, s, u.wo, u.wi, f);
  const V geometry = hn::Div(hn::Abs(u.cos_l), hn::Mul(u.dist, u.dist));
  for (int k = 0; k < 3; ++k) u.value[k] = hn::Mul(hn::Mul(f[k], L[k]), geometry);
  return u;
}

// One vector of one candidate plane: the value with the target BSDF and its luminance (sample_target), then
// (with_bsdf_pdf) the exact BSDF's density in area measure. A vector without an active slot gets its zeros
// unevaluated: a plane is evaluated for a whole row where only some pixels drew that many candidates (most
// pixels with history draw one), and these are the values the masks below would give it.
void evaluate(D d, const ReceiverLanes& r, CandidateLanes& c, int s, bool with_bsdf_pdf) {
  const V zero = hn::Zero(d);
  if (hn::AllFalse(d, hn::Gt(hn::Load(d, c.active + s), zero))) {
    hn::Store(zero, d, c.p_hat + s);
    hn::Store(zero, d, c.bsdf_area_pdf + s);
    return;
  }
  const Unshadowed u = unshadowed(d, r, r.target, c, s);
  const V p_hat = hn::Add(hn::Add(hn::Mul(hn::Set(d, 0.2126f), u.value[0]), hn::Mul(hn::Set(d, 0.7152f), u.value[1])),
                          hn::Mul(hn::Set(d, 0.0722f), u.value[2]));
  hn::Store(hn::IfThenElseZero(u.valid, p_hat), d, c.p_hat + s);
  const V area_pdf =
      with_bsdf_pdf ? hn::Div(hn::Mul(bsdf_pdf(d, r.exact, s, u.wo, u.wi), hn::Abs(u.cos_l)), hn::Mul(u.dist, u.dist))
                    : zero;
  hn::Store(hn::IfThenElseZero(u.valid, area_pdf), d, c.bsdf_area_pdf + s);
}

void EvaluateCandidateLanes(const ReceiverLanes& receivers, CandidateLanes* candidates, int count, int slots,
                            bool with_bsdf_pdf) {
  const D d;
  const int lanes = int(hn::Lanes(d));
  for (int k = 0; k < count; ++k)
    for (int s = 0; s < slots; s += lanes) evaluate(d, receivers, candidates[k], s, with_bsdf_pdf);
}

void EvaluateExactContributionLanes(const ReceiverLanes& receivers, const CandidateLanes& samples, int slots,
                                    ContributionLanes& out) {
  const D d;
  for (int s = 0; s < slots; s += int(hn::Lanes(d))) {
    const Unshadowed u = unshadowed(d, receivers, receivers.exact, samples, s);
    for (int c = 0; c < 3; ++c) hn::Store(hn::IfThenElseZero(u.valid, u.value[c]), d, out.value[c] + s);
  }
}

void ShadowRayLanes(const ReceiverLanes& from, const CandidateLanes& to, float epsilon, int slots, RayLanes& out) {
  const D d;
  const V eps = hn::Set(d, epsilon);
  // Tracer::spawn_ray_to from each receiver (position, geometric normal) to its sample's point and normal.
  for (int s = 0; s < slots; s += int(hn::Lanes(d))) {
    const V3 p = load3(d, from.px, from.py, from.pz, s), ng = load3(d, from.gx, from.gy, from.gz, s);
    const V3 q = load3(d, to.x, to.y, to.z, s), nq = load3(d, to.nx, to.ny, to.nz, s);
    spawn_ray_to(d, p, ng, q, nq, eps, out, s);
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace candela
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace candela {

HWY_EXPORT(EvaluateCandidateLanes);
HWY_EXPORT(EvaluateExactContributionLanes);
HWY_EXPORT(ShadowRayLanes);

void shadow_ray_lanes(const ReceiverLanes& from, const CandidateLanes& to, float epsilon, int slots, RayLanes& out) {
  HWY_DYNAMIC_DISPATCH(ShadowRayLanes)(from, to, epsilon, slots, out);
}

void evaluate_exact_contribution_lanes(const ReceiverLanes& receivers, const CandidateLanes& samples, int slots,
                                       ContributionLanes& out) {
  HWY_DYNAMIC_DISPATCH(EvaluateExactContributionLanes)(receivers, samples, slots, out);
}

static_assert(kLaneSlots % 16 == 0, "a batch is a whole number of the widest vectors");

void evaluate_candidate_lanes(const ReceiverLanes& receivers, CandidateLanes* candidates, int count, int slots,
                              bool with_bsdf_pdf) {
  HWY_DYNAMIC_DISPATCH(EvaluateCandidateLanes)(receivers, candidates, count, slots, with_bsdf_pdf);
}

void ReceiverLanes::set(int s, const vec3& p, const vec3& ng, const vec3& wo, const BsdfWoTerms& target_bsdf,
                        const BsdfWoTerms& exact_bsdf) {
  px[s] = p.x, py[s] = p.y, pz[s] = p.z;
  gx[s] = ng.x, gy[s] = ng.y, gz[s] = ng.z;
  wox[s] = wo.x, woy[s] = wo.y, woz[s] = wo.z;
  target.set(s, target_bsdf);
  exact.set(s, exact_bsdf);
}

}  // namespace candela
#endif  // HWY_ONCE

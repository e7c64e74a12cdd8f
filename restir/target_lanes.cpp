// The candidate-lanes kernel (target_lanes.h), compiled once per instruction set by Highway's
// foreach_target.h and dispatched at run time (helpers shared with the receiver kernel: lanes-inl.h).
// Each step names the scalar function whose arithmetic it repeats, in the same order (restir/di.h di_contribution,
// engine/lights.h light_sample_towards, engine/bsdf.cpp Bsdf::eval and Bsdf::pdf, engine/ggx_albedo.h
// GgxAlbedoRow::at).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "restir/target_lanes.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/highway.h"
#include "restir/target_lanes.h"
#include "engine/lanes-inl.h"

HWY_BEFORE_NAMESPACE();
namespace candela {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// ggx_d_half_vector (engine/bsdf.cpp): D(h) for the unnormalised half vector hv.
V ggx_d_half_vector(D d, const V3& n, const V3& hv, V alpha) {
  const V c = dot(n, hv);
  const V3 s{hn::Sub(hn::Mul(n.y, hv.z), hn::Mul(hv.y, n.z)), hn::Sub(hn::Mul(n.z, hv.x), hn::Mul(hv.z, n.x)),
             hn::Sub(hn::Mul(n.x, hv.y), hn::Mul(hv.x, n.y))};
  const V a2 = hn::Mul(alpha, alpha), len2 = dot(hv, hv);
  const V den = hn::Add(hn::Mul(hn::Mul(a2, c), c), dot(s, s));
  const V value = hn::Div(hn::Mul(hn::Mul(a2, len2), len2), hn::Mul(hn::Mul(hn::Set(d, kPi), den), den));
  return hn::IfThenElseZero(hn::And(hn::Gt(c, hn::Zero(d)), hn::Gt(den, hn::Zero(d))), value);
}

// Bsdf::eval(wo, wi), times |n.wi| with kTimesCosine, channel c returned in f[c], for the terms of one plane set.
template <bool kTimesCosine>
void eval_bsdf(D d, const ReceiverLanes::BsdfPlanes& t, int s, const V3& wo, const V3& wi, V f[3]) {
  const hn::RebindToSigned<D> di;
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0f);
  const V3 n = load3(d, t.nx, t.ny, t.nz, s);
  const V cos_o = hn::Load(d, t.cos_o + s), cos_i = dot(n, wi);
  const M lit = hn::And(hn::Gt(cos_o, zero), hn::Gt(cos_i, zero));
  const V cos_oi = dot(wo, wi);
  const V inv_len =
      hn::Div(one, hn::Sqrt(hn::Max(hn::Add(hn::Set(d, 2.0f), hn::Mul(hn::Set(d, 2.0f), cos_oi)), hn::Set(d, 1e-12f))));
  const V m = hn::Sub(one, hn::Min(hn::Max(hn::Mul(hn::Add(one, cos_oi), inv_len), zero), one));
  const V m2 = hn::Mul(m, m), w5 = hn::Mul(hn::Mul(m2, m2), m);
  const V alpha = hn::Load(d, t.alpha + s), a2 = hn::Mul(alpha, alpha);
  const V s_i = hn::Sqrt(hn::Add(hn::Mul(hn::Mul(cos_i, cos_i), hn::Sub(one, a2)), a2));
  const V visibility = hn::Div(hn::Set(d, 0.5f), hn::Add(hn::Mul(cos_i, hn::Load(d, t.s_o + s)), hn::Mul(cos_o, s_i)));
  const V3 hv{hn::Add(wo.x, wi.x), hn::Add(wo.y, wi.y), hn::Add(wo.z, wi.z)};
  const V dv = hn::Mul(ggx_d_half_vector(d, n, hv, alpha), visibility);
  V e_a, e_b;
  albedo_at(d, cos_i, hn::Load(di, t.albedo_row + s), hn::Load(d, t.albedo_weight + s), e_a, e_b);
  const V ms_i = hn::Mul(hn::Load(d, t.ms_o + s), hn::Max(hn::Sub(one, e_a), zero));
  const V f90 = hn::Load(d, t.f90 + s), d_f90 = hn::Load(d, t.d_f90 + s);
  const V cos_n = hn::Abs(cos_i);
  for (int c = 0; c < 3; ++c) {
    const V f0 = hn::Load(d, t.f0[c] + s);
    const V F = hn::Add(f0, hn::Mul(hn::Sub(f90, f0), w5));
    const V single = hn::Mul(F, dv);
    const V multiple = hn::Mul(hn::Load(d, t.ms[c] + s), ms_i);
    const V layer = hn::Add(hn::Add(hn::Mul(hn::Load(d, t.d_f0[c] + s), hn::Sub(e_a, e_b)), hn::Mul(d_f90, e_b)),
                            hn::Mul(hn::Load(d, t.d_ms[c] + s), hn::Sub(one, e_a)));
    const V base = hn::Mul(hn::Load(d, t.base_o[c] + s), hn::Max(hn::Sub(one, layer), zero));
    f[c] = hn::IfThenElseZero(lit, hn::Add(hn::Add(single, multiple), base));
    if (kTimesCosine) f[c] = hn::Mul(f[c], cos_n);
  }
}

// Bsdf::pdf(wo, wi): solid-angle density of BSDF sampling.
V bsdf_pdf(D d, const ReceiverLanes::BsdfPlanes& t, int s, const V3& wo, const V3& wi) {
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0f);
  const V3 n = load3(d, t.nx, t.ny, t.nz, s);
  const V cos_o = hn::Load(d, t.cos_o + s), cos_i = dot(n, wi);
  const V3 hv{hn::Add(wo.x, wi.x), hn::Add(wo.y, wi.y), hn::Add(wo.z, wi.z)};
  const V pdf_spec = hn::Div(hn::Mul(hn::Load(d, t.g1_o + s), ggx_d_half_vector(d, n, hv, hn::Load(d, t.alpha + s))),
                             hn::Mul(hn::Set(d, 4.0f), cos_o));
  const V pdf_diff = hn::Mul(cos_i, hn::Set(d, kInvPi));
  const V ps = hn::Load(d, t.p_specular + s);
  const V pdf = hn::Add(hn::Mul(ps, pdf_spec), hn::Mul(hn::Sub(one, ps), pdf_diff));
  return hn::IfThenElseZero(hn::And(hn::Gt(cos_o, zero), hn::Gt(cos_i, zero)), pdf);
}

// One vector of slots [s, s + lanes) of one candidate plane: light_sample_towards, then di_contribution's
// value with the BSDF planes `bsdf` of the receivers (where `valid`; its lanes hold garbage elsewhere).
struct Unshadowed {
  V3 wo, wi;
  V cos_l, dist;
  M valid;
  V value[3];
};
Unshadowed unshadowed(D d, const ReceiverLanes& r, const ReceiverLanes::BsdfPlanes& bsdf, const CandidateLanes& c,
                      int s) {
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

// One vector of one candidate plane: the value with the target BSDF and its luminance (di_target), then
// (with_bsdf_pdf) the exact BSDF's density in area measure.
void evaluate(D d, const ReceiverLanes& r, CandidateLanes& c, int s, bool with_bsdf_pdf) {
  const V zero = hn::Zero(d);
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

void EvaluateDirectionLanes(const ReceiverLanes& r, DirectionLanes& directions, int slots) {
  const D d;
  for (int s = 0; s < slots; s += int(hn::Lanes(d))) {
    const V3 wo = load3(d, r.wox, r.woy, r.woz, s), wi = load3(d, directions.x, directions.y, directions.z, s);
    const M active = hn::Gt(hn::Load(d, directions.active + s), hn::Zero(d));
    V f[3];
    eval_bsdf<false>(d, r.exact, s, wo, wi, f);
    for (int c = 0; c < 3; ++c) hn::Store(hn::IfThenElseZero(active, f[c]), d, directions.f[c] + s);
    hn::Store(hn::IfThenElseZero(active, bsdf_pdf(d, r.exact, s, wo, wi)), d, directions.pdf + s);
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace candela
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace candela {

HWY_EXPORT(EvaluateCandidateLanes);
HWY_EXPORT(EvaluateDirectionLanes);
HWY_EXPORT(EvaluateExactContributionLanes);

void evaluate_exact_contribution_lanes(const ReceiverLanes& receivers, const CandidateLanes& samples, int slots,
                                       ContributionLanes& out) {
  HWY_DYNAMIC_DISPATCH(EvaluateExactContributionLanes)(receivers, samples, slots, out);
}

void evaluate_direction_lanes(const ReceiverLanes& receivers, DirectionLanes& directions, int slots) {
  HWY_DYNAMIC_DISPATCH(EvaluateDirectionLanes)(receivers, directions, slots);
}

static_assert(kLaneSlots % 16 == 0, "a batch is a whole number of the widest vectors");

void evaluate_candidate_lanes(const ReceiverLanes& receivers, CandidateLanes* candidates, int count, int slots,
                              bool with_bsdf_pdf) {
  HWY_DYNAMIC_DISPATCH(EvaluateCandidateLanes)(receivers, candidates, count, slots, with_bsdf_pdf);
}

void ReceiverLanes::BsdfPlanes::set(int s, const BsdfWoTerms& t) {
  nx[s] = t.n.x, ny[s] = t.n.y, nz[s] = t.n.z;
  cos_o[s] = t.cos_o, alpha[s] = t.alpha, s_o[s] = t.s_o, f90[s] = t.f90, ms_o[s] = t.ms_o, d_f90[s] = t.d_f90;
  for (int c = 0; c < 3; ++c) {
    f0[c][s] = t.f0[c], ms[c][s] = t.ms[c], base_o[c][s] = t.base_o[c];
    d_f0[c][s] = t.d_f0[c], d_ms[c][s] = t.d_ms[c];
  }
  albedo_row[s] = int32_t(t.albedo_row), albedo_weight[s] = t.albedo_weight;
  g1_o[s] = t.g1_o, p_specular[s] = t.p_specular;
}

void ReceiverLanes::set(int s, const vec3& p, const vec3& ng, const vec3& wo, const BsdfWoTerms& target_bsdf,
                        const BsdfWoTerms& exact_bsdf) {
  px[s] = p.x, py[s] = p.y, pz[s] = p.z;
  gx[s] = ng.x, gy[s] = ng.y, gz[s] = ng.z;
  wox[s] = wo.x, woy[s] = wo.y, woz[s] = wo.z;
  target.set(s, target_bsdf);
  exact.set(s, exact_bsdf);
}

void CandidateLanes::set(int s, const LightPoint& point) {
  x[s] = point.position.x, y[s] = point.position.y, z[s] = point.position.z;
  nx[s] = point.normal.x, ny[s] = point.normal.y, nz[s] = point.normal.z;
  for (int c = 0; c < 3; ++c) radiance[c][s] = point.radiance[c];
  two_sided[s] = point.two_sided ? 1.0f : 0.0f;
  active[s] = 1.0f;
}

LightPoint CandidateLanes::point(int s) const {
  return {vec3(x[s], y[s], z[s]), vec3(nx[s], ny[s], nz[s]), vec3(radiance[0][s], radiance[1][s], radiance[2][s]),
          two_sided[s] > 0.0f};
}

void CandidateLanes::clear(int s) {
  set(s, LightPoint{vec3(0.0f), vec3(0.0f, 0.0f, 1.0f), vec3(0.0f), false});
  active[s] = 0.0f;
}

}  // namespace candela
#endif  // HWY_ONCE

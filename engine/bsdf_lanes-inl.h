// Highway kernels' pieces of engine/bsdf.cpp in lanes (engine/bsdf_lanes.h): the Bsdf constructor and
// Bsdf::wo_terms (build_bsdf), Bsdf::eval (eval_bsdf) and Bsdf::pdf (bsdf_pdf), each repeating the scalar
// operations in the same order (engine/bsdf.cpp, engine/microfacet.cpp ggx_lambda, engine/ggx_albedo.h
// GgxAlbedoRow), so that the kernels keep the scalar code's bits. Included once per instruction set by each
// kernel's foreach_target.h pass (engine/bsdf_lanes.cpp, restir/receiver_lanes.cpp, restir/target_lanes.cpp),
// hence the toggling include guard (Highway's "-inl.h" convention).
#if defined(CANDELA_ENGINE_BSDF_LANES_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef CANDELA_ENGINE_BSDF_LANES_INL_H_
#undef CANDELA_ENGINE_BSDF_LANES_INL_H_
#else
#define CANDELA_ENGINE_BSDF_LANES_INL_H_
#endif

#include "engine/bsdf_lanes.h"
#include "engine/lanes-inl.h"
#include "hwy/highway.h"

HWY_BEFORE_NAMESPACE();
namespace candela {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// multiple_scattering_fresnel (engine/bsdf.cpp): Kulla & Conty's F_ms for F0 f0, F90 f90, at a_avg.
inline V multiple_scattering_fresnel(D d, V f0, V f90, V a_avg) {
  const V one = hn::Set(d, 1.0f);
  const V f_avg = hn::Add(f0, hn::Mul(hn::Sub(f90, f0), hn::Set(d, 1.0f / 21.0f)));
  const V value = hn::Div(hn::Mul(hn::Mul(f_avg, f_avg), a_avg), hn::Sub(one, hn::Mul(f_avg, hn::Sub(one, a_avg))));
  return hn::IfThenElseZero(hn::Gt(f90, hn::Zero(d)), value);
}

// Bsdf::layer_albedo at (a, b) for the grey dielectric layer.
inline V layer_albedo(D d, V d_f0, V d_f90, V d_ms, V a, V b) {
  return hn::Add(hn::Add(hn::Mul(d_f0, hn::Sub(a, b)), hn::Mul(d_f90, b)), hn::Mul(d_ms, hn::Sub(hn::Set(d, 1.0f), a)));
}

// What the Bsdf constructor derives from the roughness: ggx_alpha, the albedo table's row (GgxAlbedoRow:
// offset and weight) and the row's average (a_avg, b_avg).
struct RoughnessTerms {
  V alpha, row_weight, avg_a, avg_b;
  VI row;
};
inline RoughnessTerms roughness_terms(D d, V roughness) {
  const DI di;
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0f);
  const V r = min_of(max_of(roughness, hn::Set(d, 0.03f)), one);
  const V x = hn::Mul(min_of(max_of(roughness, zero), one), hn::Set(d, float(kGgxAlbedoRoughnessCount - 1)));
  // Clamped below too, as albedo_at's column (a NaN roughness in a lane nobody reads).
  const VI k = hn::Max(hn::Min(hn::ConvertTo(di, x), hn::Set(di, kGgxAlbedoRoughnessCount - 2)), hn::Zero(di));
  const V row_weight = hn::Sub(x, hn::ConvertTo(d, k));
  // The row's and the next row's averages: one row for every lane (one roughness across the vector) reads them
  // once, else they are gathered.
  V avg_a0, avg_b0, avg_a1, avg_b1;
  int32_t k0;
  if (same_in_every_lane(k, k0)) {
    const float* avg = kGgxAlbedoAverages + 2 * k0;
    avg_a0 = hn::Set(d, avg[0]), avg_b0 = hn::Set(d, avg[1]), avg_a1 = hn::Set(d, avg[2]), avg_b1 = hn::Set(d, avg[3]);
  } else {
    gather_pairs(d, kGgxAlbedoAveragePairs, k, avg_a0, avg_b0);
    gather_pairs(d, kGgxAlbedoAveragePairs, hn::Add(k, hn::Set(di, 1)), avg_a1, avg_b1);
  }
  return {hn::Mul(r, r), row_weight, hn::Add(avg_a0, hn::Mul(row_weight, hn::Sub(avg_a1, avg_a0))),
          hn::Add(avg_b0, hn::Mul(row_weight, hn::Sub(avg_b1, avg_b0))),
          hn::Mul(k, hn::Set(di, kGgxAlbedoMuCount * 2))};
}

// luminance (engine/math.h): (0.2126 r + 0.7152 g) + 0.0722 b.
inline V luminance(D d, const V c[3]) {
  return hn::Add(hn::Add(hn::Mul(hn::Set(d, 0.2126f), c[0]), hn::Mul(hn::Set(d, 0.7152f), c[1])),
                 hn::Mul(hn::Set(d, 0.0722f), c[2]));
}

// std::clamp(x, lo, hi): lo below it, hi above it, else x (also NaN).
inline V clamp_to(D d, V x, float lo, float hi) {
  const V l = hn::Set(d, lo), h = hn::Set(d, hi);
  return hn::IfThenElse(hn::Lt(x, l), l, hn::IfThenElse(hn::Lt(h, x), h, x));
}

// One vector of slots [s, s + lanes) of `in` seen along wo into `t`: the Bsdf constructor with a coloured
// dielectric F0 (so the layer's terms are per channel), then Bsdf::wo_terms with ggx_lambda and
// specular_probability.
inline void build_bsdf(D d, const BsdfMaterialLanes& in, int s, const V3& wo, BsdfLanes& t) {
  const DI di;
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0f);
  const V3 n = load3(d, in.nx, in.ny, in.nz, s);
  const V base_color[3] = {hn::Load(d, in.base[0] + s), hn::Load(d, in.base[1] + s), hn::Load(d, in.base[2] + s)};
  const V roughness = hn::Load(d, in.roughness + s);
  // Bsdf::Bsdf: ggx_alpha, the albedo row of the roughness (GgxAlbedoRow) and its average.
  const RoughnessTerms rt = roughness_terms(d, roughness);
  const V alpha = rt.alpha, row_weight = rt.row_weight, avg_a = rt.avg_a, avg_b = rt.avg_b;
  const VI row = rt.row;
  // The lobes' Fresnel terms, per channel.
  const V m = clamp_to(d, hn::Load(d, in.metallic + s), 0.0f, 1.0f);
  const V sp = clamp_to(d, hn::Load(d, in.specular + s), 0.0f, 1.0f);
  const V one_minus_m = hn::Sub(one, m), d_f90 = sp, f90 = hn::Add(hn::Mul(sp, one_minus_m), m);
  const V ms_scale = hn::Div(hn::Set(d, kInvPi), max_of(hn::Sub(one, avg_a), hn::Set(d, 1e-6f)));
  V d_f0[3], f0[3], d_ms[3], f_ms[3], base[3], base_scale[3], base_d_f0[3], base_d_ms[3];
  for (int c = 0; c < 3; ++c) {
    d_f0[c] = hn::Mul(sp, hn::Load(d, in.specular_f0[c] + s));
    f0[c] = hn::Add(hn::Mul(d_f0[c], one_minus_m), hn::Mul(base_color[c], m));
    d_ms[c] = hn::IfThenElseZero(hn::Lt(m, one), multiple_scattering_fresnel(d, d_f0[c], d_f90, avg_a));
    f_ms[c] = hn::IfThenElse(
        hn::Gt(m, zero),
        hn::Add(hn::Mul(d_ms[c], one_minus_m), hn::Mul(multiple_scattering_fresnel(d, base_color[c], one, avg_a), m)),
        d_ms[c]);
    base[c] = hn::Mul(base_color[c], one_minus_m);
    const V layer_avg = layer_albedo(d, d_f0[c], d_f90, d_ms[c], avg_a, avg_b);
    base_scale[c] = hn::IfThenZeroElse(
        hn::Ge(layer_avg, hn::Set(d, 0.9999f)),
        hn::Div(hn::Mul(base[c], hn::Set(d, kInvPi)), max_of(hn::Sub(one, layer_avg), hn::Set(d, 1e-4f))));
    base_d_f0[c] = hn::Mul(base[c], d_f0[c]);
    base_d_ms[c] = hn::Mul(base[c], d_ms[c]);
  }
  const V lum_f0 = luminance(d, f0), lum_ms = luminance(d, f_ms), lum_base = luminance(d, base);
  const V lum_base_d_f0 = luminance(d, base_d_f0), lum_base_d_ms = luminance(d, base_d_ms);
  // Bsdf::wo_terms: the terms of wo (their defaults where wo is below the shading normal).
  const V cos_o = dot(n, wo);
  const M above = hn::Not(hn::Le(cos_o, zero));
  const V a2 = hn::Mul(alpha, alpha);
  const V s_o = hn::IfThenElse(above, hn::Sqrt(hn::Add(hn::Mul(hn::Mul(cos_o, cos_o), hn::Sub(one, a2)), a2)), one);
  V e_a, e_b;
  // (Looked up at 0 where the cosine is not positive, NaN included, so that no index leaves the table; the
  // scalar code returns before it looks up there.)
  albedo_at(d, hn::IfThenElseZero(hn::Gt(cos_o, zero), cos_o), row, row_weight, e_a, e_b);
  const V ms_o = hn::IfThenElseZero(above, max_of(hn::Sub(one, e_a), zero));
  // ggx_lambda and G1(wo).
  const V c2 = hn::Mul(cos_o, cos_o);
  const V tan2 = hn::Div(max_of(hn::Sub(one, c2), zero), max_of(c2, hn::Set(d, 1e-12f)));
  const V lambda = hn::Mul(hn::Set(d, 0.5f), hn::Sub(hn::Sqrt(hn::Add(one, hn::Mul(a2, tan2))), one));
  const V g1_o = hn::Div(one, hn::Add(one, lambda));
  // specular_probability(albedo at wo).
  const V a_minus_b = hn::Sub(e_a, e_b), one_minus_a = hn::Sub(one, e_a);
  const V spec = hn::Add(hn::Mul(lum_f0, a_minus_b), hn::Mul(f90, e_b));
  const V layer = hn::Add(hn::Add(hn::Mul(lum_base_d_f0, a_minus_b), hn::Mul(hn::Mul(lum_base, d_f90), e_b)),
                          hn::Mul(lum_base_d_ms, one_minus_a));
  const V rest = hn::Add(hn::Mul(lum_ms, one_minus_a), max_of(hn::Sub(lum_base, layer), zero));
  const V p_specular =
      hn::IfThenZeroElse(hn::Le(spec, zero), clamp_to(d, hn::Div(spec, hn::Add(spec, rest)), 0.1f, 0.9f));
  store3(d, n, t.nx, t.ny, t.nz, s);
  hn::Store(cos_o, d, t.cos_o + s), hn::Store(alpha, d, t.alpha + s), hn::Store(s_o, d, t.s_o + s);
  hn::Store(f90, d, t.f90 + s), hn::Store(ms_o, d, t.ms_o + s), hn::Store(d_f90, d, t.d_f90 + s);
  hn::Store(row, di, t.albedo_row + s), hn::Store(row_weight, d, t.albedo_weight + s);
  hn::Store(hn::IfThenElseZero(above, g1_o), d, t.g1_o + s);
  hn::Store(hn::IfThenElseZero(above, p_specular), d, t.p_specular + s);
  for (int c = 0; c < 3; ++c) {
    const V base_o_scale = max_of(hn::Sub(one, layer_albedo(d, d_f0[c], d_f90, d_ms[c], e_a, e_b)), zero);
    hn::Store(f0[c], d, t.f0[c] + s);
    hn::Store(hn::Mul(f_ms[c], ms_scale), d, t.ms[c] + s);
    hn::Store(hn::IfThenElseZero(above, hn::Mul(base_scale[c], base_o_scale)), d, t.base_o[c] + s);
    hn::Store(d_f0[c], d, t.d_f0[c] + s), hn::Store(d_ms[c], d, t.d_ms[c] + s);
  }
}

// ggx_d_half_vector (engine/bsdf.cpp): D(h) for the unnormalised half vector hv.
inline V ggx_d_half_vector(D d, const V3& n, const V3& hv, V alpha) {
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
inline void eval_bsdf(D d, const BsdfLanes& t, int s, const V3& wo, const V3& wi, V f[3]) {
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
inline V bsdf_pdf(D d, const BsdfLanes& t, int s, const V3& wo, const V3& wi) {
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

}  // namespace HWY_NAMESPACE
}  // namespace candela
HWY_AFTER_NAMESPACE();

#endif  // include guard

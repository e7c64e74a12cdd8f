// The receiver kernel (receiver_lanes.h), compiled once per instruction set by Highway's foreach_target.h
// and dispatched at run time. Each step names the scalar function whose arithmetic it repeats, in the same
// order (engine/octahedral.h oct_decode, restir/di.h di_receiver, engine/packed_surface.cpp PackedSurface::bsdf,
// engine/bsdf.cpp the Bsdf constructor and Bsdf::wo_terms, engine/ggx_albedo.h GgxAlbedoRow). The packed
// material's specular F0 is grey, so the dielectric layer's terms are one value for all three channels.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "restir/receiver_lanes.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/highway.h"
#include "engine/lanes-inl.h"
#include "restir/receiver_lanes.h"

HWY_BEFORE_NAMESPACE();
namespace candela {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using DU = hn::RebindToUnsigned<D>;
using VU = hn::Vec<DU>;

// oct_decode.
V3 oct_decode(D d, VU e) {
  const DI di;
  const V scale = hn::Set(d, 2.0f / 65535.0f), one = hn::Set(d, 1.0f), zero = hn::Zero(d);
  auto coordinate = [&](VU bits) { return hn::Sub(hn::Mul(hn::ConvertTo(d, hn::BitCast(di, bits)), scale), one); };
  const V x = coordinate(hn::And(e, hn::Set(DU(), 0xffffu))), y = coordinate(hn::ShiftRight<16>(e));
  const V z = hn::Sub(hn::Sub(one, hn::Abs(x)), hn::Abs(y));
  const V t = max_of(hn::Neg(z), zero);
  const V3 n{hn::Add(x, hn::IfThenElse(hn::Ge(x, zero), hn::Neg(t), t)),
             hn::Add(y, hn::IfThenElse(hn::Ge(y, zero), hn::Neg(t), t)), z};
  return normalize(d, n);
}

// PackedSurface::bsdf's from_unorm8 of the byte at `shift`.
template <int kShift>
V unorm8(D d, VU packed) {
  const VU byte = hn::And(hn::ShiftRight<kShift>(packed), hn::Set(DU(), 255u));
  return hn::Mul(hn::ConvertTo(d, hn::BitCast(DI(), byte)), hn::Set(d, 1.0f / 255.0f));
}

// multiple_scattering_fresnel (engine/bsdf.cpp): Kulla & Conty's F_ms for F0 f0, F90 f90, at a_avg.
V multiple_scattering_fresnel(D d, V f0, V f90, V a_avg) {
  const V one = hn::Set(d, 1.0f);
  const V f_avg = hn::Add(f0, hn::Mul(hn::Sub(f90, f0), hn::Set(d, 1.0f / 21.0f)));
  const V value = hn::Div(hn::Mul(hn::Mul(f_avg, f_avg), a_avg), hn::Sub(one, hn::Mul(f_avg, hn::Sub(one, a_avg))));
  return hn::IfThenElseZero(hn::Gt(f90, hn::Zero(d)), value);
}

// Bsdf::layer_albedo at (a, b) for the grey dielectric layer.
V layer_albedo(D d, V d_f0, V d_f90, V d_ms, V a, V b) {
  return hn::Add(hn::Add(hn::Mul(d_f0, hn::Sub(a, b)), hn::Mul(d_f90, b)), hn::Mul(d_ms, hn::Sub(hn::Set(d, 1.0f), a)));
}

// What the Bsdf constructor derives from the roughness: ggx_alpha, the albedo table's row (GgxAlbedoRow:
// offset and weight) and the row's average (a_avg, b_avg).
struct RoughnessTerms {
  V alpha, row_weight, avg_a, avg_b;
  VI row;
};
RoughnessTerms roughness_terms(D d, V roughness) {
  const DI di;
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0f);
  const V r = min_of(max_of(roughness, hn::Set(d, 0.03f)), one);
  const V x = hn::Mul(min_of(max_of(roughness, zero), one), hn::Set(d, float(kGgxAlbedoRoughnessCount - 1)));
  const VI k = hn::Min(hn::ConvertTo(di, x), hn::Set(di, kGgxAlbedoRoughnessCount - 2));
  const V row_weight = hn::Sub(x, hn::ConvertTo(d, k));
  auto average = [&](int j) { return hn::GatherIndex(d, kGgxAlbedoAverages, hn::Add(hn::Add(k, k), hn::Set(di, j))); };
  const V avg_a0 = average(0), avg_b0 = average(1), avg_a1 = average(2), avg_b1 = average(3);
  return {hn::Mul(r, r), row_weight, hn::Add(avg_a0, hn::Mul(row_weight, hn::Sub(avg_a1, avg_a0))),
          hn::Add(avg_b0, hn::Mul(row_weight, hn::Sub(avg_b1, avg_b0))),
          hn::Mul(k, hn::Set(di, kGgxAlbedoMuCount * 2))};
}

// One vector of slots [s, s + lanes).
void build(D d, const SurfaceLanes& in, const vec3& eye, int s, ReceiverLanes& out) {
  const DI di;
  const DU du;
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0f);
  // di_receiver: position, decoded normals, wo = normalize(eye - position).
  const V3 p = load3(d, in.px, in.py, in.pz, s);
  const V3 ng = oct_decode(d, hn::Load(du, in.geometric_normal + s));
  const V3 n = oct_decode(d, hn::Load(du, in.shading_normal + s));
  const V3 wo =
      normalize(d, {hn::Sub(hn::Set(d, eye.x), p.x), hn::Sub(hn::Set(d, eye.y), p.y), hn::Sub(hn::Set(d, eye.z), p.z)});
  store3(d, p, out.px, out.py, out.pz, s);
  store3(d, ng, out.gx, out.gy, out.gz, s);
  store3(d, wo, out.wox, out.woy, out.woz, s);
  // PackedSurface::bsdf: the packed material's parameters.
  const VU albedo = hn::Load(du, in.albedo + s), material = hn::Load(du, in.material + s);
  V base[3] = {unorm8<0>(d, albedo), unorm8<8>(d, albedo), unorm8<16>(d, albedo)};
  for (V& c : base) c = hn::Mul(c, c);
  const V roughness = unorm8<0>(d, material), metallic = unorm8<8>(d, material);
  const V specular = unorm8<16>(d, material), sqrt_f0 = unorm8<24>(d, material);
  const V specular_f0 = hn::Mul(sqrt_f0, sqrt_f0);
  // Bsdf::Bsdf: ggx_alpha, the albedo row of the roughness (GgxAlbedoRow) and its average.
  const RoughnessTerms rt = roughness_terms(d, roughness);
  const V alpha = rt.alpha, row_weight = rt.row_weight, avg_a = rt.avg_a, avg_b = rt.avg_b;
  const VI row = rt.row;
  // The lobes' Fresnel terms.
  const V m = min_of(max_of(metallic, zero), one), sp = min_of(max_of(specular, zero), one);
  const V one_minus_m = hn::Sub(one, m);
  const V d_f0 = hn::Mul(sp, specular_f0), d_f90 = sp;
  const V f90 = hn::Add(hn::Mul(sp, one_minus_m), m);
  const V d_ms = hn::IfThenElseZero(hn::Lt(m, one), multiple_scattering_fresnel(d, d_f0, d_f90, avg_a));
  const V ms_scale = hn::Div(hn::Set(d, kInvPi), max_of(hn::Sub(one, avg_a), hn::Set(d, 1e-6f)));
  const V layer_avg = layer_albedo(d, d_f0, d_f90, d_ms, avg_a, avg_b);
  const M layer_opaque = hn::Ge(layer_avg, hn::Set(d, 0.9999f));
  const V base_denominator = max_of(hn::Sub(one, layer_avg), hn::Set(d, 1e-4f));
  // Bsdf::wo_terms: the terms of wo (0 where wo is below the shading normal).
  const V cos_o = dot(n, wo);
  const M above = hn::Not(hn::Le(cos_o, zero));
  const V a2 = hn::Mul(alpha, alpha);
  const V s_o = hn::IfThenElse(above, hn::Sqrt(hn::Add(hn::Mul(hn::Mul(cos_o, cos_o), hn::Sub(one, a2)), a2)), one);
  V e_a, e_b;
  albedo_at(d, cos_o, row, row_weight, e_a, e_b);
  const V ms_o = hn::IfThenElseZero(above, max_of(hn::Sub(one, e_a), zero));
  const V base_o_scale = max_of(hn::Sub(one, layer_albedo(d, d_f0, d_f90, d_ms, e_a, e_b)), zero);
  ReceiverLanes::BsdfPlanes& t = out.target;
  store3(d, n, t.nx, t.ny, t.nz, s);
  hn::Store(cos_o, d, t.cos_o + s), hn::Store(alpha, d, t.alpha + s), hn::Store(s_o, d, t.s_o + s);
  hn::Store(f90, d, t.f90 + s), hn::Store(ms_o, d, t.ms_o + s), hn::Store(d_f90, d, t.d_f90 + s);
  hn::Store(row, di, t.albedo_row + s), hn::Store(row_weight, d, t.albedo_weight + s);
  hn::Store(zero, d, t.g1_o + s), hn::Store(zero, d, t.p_specular + s);
  for (int c = 0; c < 3; ++c) {
    const V f0 = hn::Add(hn::Mul(d_f0, one_minus_m), hn::Mul(base[c], m));
    const V f_ms = hn::IfThenElse(
        hn::Gt(m, zero),
        hn::Add(hn::Mul(d_ms, one_minus_m), hn::Mul(multiple_scattering_fresnel(d, base[c], one, avg_a), m)), d_ms);
    const V base_lobe = hn::Mul(base[c], one_minus_m);
    const V base_scale =
        hn::IfThenZeroElse(layer_opaque, hn::Div(hn::Mul(base_lobe, hn::Set(d, kInvPi)), base_denominator));
    hn::Store(f0, d, t.f0[c] + s);
    hn::Store(hn::Mul(f_ms, ms_scale), d, t.ms[c] + s);
    hn::Store(hn::IfThenElseZero(above, hn::Mul(base_scale, base_o_scale)), d, t.base_o[c] + s);
    hn::Store(d_f0, d, t.d_f0[c] + s), hn::Store(d_ms, d, t.d_ms[c] + s);
  }
}

// luminance (engine/math.h): (0.2126 r + 0.7152 g) + 0.0722 b.
V luminance(D d, const V c[3]) {
  return hn::Add(hn::Add(hn::Mul(hn::Set(d, 0.2126f), c[0]), hn::Mul(hn::Set(d, 0.7152f), c[1])),
                 hn::Mul(hn::Set(d, 0.0722f), c[2]));
}

// std::clamp(x, lo, hi): lo below it, hi above it, else x (also NaN).
V clamp_to(D d, V x, float lo, float hi) {
  const V l = hn::Set(d, lo), h = hn::Set(d, hi);
  return hn::IfThenElse(hn::Lt(x, l), l, hn::IfThenElse(hn::Lt(h, x), h, x));
}

// One vector of slots [s, s + lanes) of the exact receivers: the Bsdf constructor with a coloured dielectric
// F0 (so the layer's terms are per channel), then Bsdf::wo_terms with ggx_lambda and specular_probability;
// where `geometry` is given, also the receivers' position, geometric normal and wo into it.
void build_exact(D d, const ExactSurfaceLanes& in, const vec3& eye, int s, ReceiverLanes::BsdfPlanes& t,
                 ReceiverLanes* geometry) {
  const DI di;
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0f);
  const V3 p = load3(d, in.px, in.py, in.pz, s), n = load3(d, in.nx, in.ny, in.nz, s);
  // di_exact_receiver: wo = normalize(eye - position).
  const V3 wo =
      normalize(d, {hn::Sub(hn::Set(d, eye.x), p.x), hn::Sub(hn::Set(d, eye.y), p.y), hn::Sub(hn::Set(d, eye.z), p.z)});
  if (geometry) {
    store3(d, p, geometry->px, geometry->py, geometry->pz, s);
    store3(d, load3(d, in.gx, in.gy, in.gz, s), geometry->gx, geometry->gy, geometry->gz, s);
    store3(d, wo, geometry->wox, geometry->woy, geometry->woz, s);
  }
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

void BuildExactReceiverLanes(const ExactSurfaceLanes& surfaces, const vec3& eye, int slots,
                             ReceiverLanes::BsdfPlanes& exact) {
  const D d;
  const int lanes = int(hn::Lanes(d));
  for (int s = 0; s < slots; s += lanes) build_exact(d, surfaces, eye, s, exact, nullptr);
}

void BuildExactReceivers(const ExactSurfaceLanes& surfaces, const vec3& eye, int slots, ReceiverLanes& out) {
  const D d;
  const int lanes = int(hn::Lanes(d));
  for (int s = 0; s < slots; s += lanes) build_exact(d, surfaces, eye, s, out.exact, &out);
}

void BuildReceiverLanes(const SurfaceLanes& surfaces, const vec3& eye, int slots, ReceiverLanes& out) {
  const D d;
  const int lanes = int(hn::Lanes(d));
  for (int s = 0; s < slots; s += lanes) build(d, surfaces, eye, s, out);
}

}  // namespace HWY_NAMESPACE
}  // namespace candela
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace candela {

HWY_EXPORT(BuildReceiverLanes);
HWY_EXPORT(BuildExactReceiverLanes);
HWY_EXPORT(BuildExactReceivers);

void build_exact_receiver_lanes(const ExactSurfaceLanes& surfaces, const vec3& eye, int slots,
                                ReceiverLanes::BsdfPlanes& exact) {
  HWY_DYNAMIC_DISPATCH(BuildExactReceiverLanes)(surfaces, eye, slots, exact);
}

void build_exact_receivers(const ExactSurfaceLanes& surfaces, const vec3& eye, int slots, ReceiverLanes& out) {
  HWY_DYNAMIC_DISPATCH(BuildExactReceivers)(surfaces, eye, slots, out);
}

void build_receiver_lanes(const SurfaceLanes& surfaces, const vec3& eye, int slots, ReceiverLanes& out) {
  HWY_DYNAMIC_DISPATCH(BuildReceiverLanes)(surfaces, eye, slots, out);
}

}  // namespace candela
#endif  // HWY_ONCE

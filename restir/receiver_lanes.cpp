// The receiver kernel (receiver_lanes.h), compiled once per instruction set by Highway's foreach_target.h
// and dispatched at run time. Each step names the scalar function whose arithmetic it repeats, in the same
// order (engine/octahedral.h oct_decode, restir/sample.h reuse_receiver, engine/packed_surface.cpp PackedSurface::bsdf,
// engine/bsdf.cpp the Bsdf constructor and Bsdf::wo_terms, engine/ggx_albedo.h GgxAlbedoRow). The packed
// material's specular F0 is grey, so the dielectric layer's terms are one value for all three channels.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "restir/receiver_lanes.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/highway.h"
#include "engine/bsdf_lanes-inl.h"
#include "restir/receiver_lanes.h"

HWY_BEFORE_NAMESPACE();
namespace candela {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// PackedSurface::bsdf's from_unorm8 of the byte at `shift`.
template <int kShift>
V unorm8(D d, VU packed) {
  const VU byte = hn::And(hn::ShiftRight<kShift>(packed), hn::Set(DU(), 255u));
  return hn::Mul(hn::ConvertTo(d, hn::BitCast(DI(), byte)), hn::Set(d, 1.0f / 255.0f));
}

// One vector of slots [s, s + lanes).
void build(D d, const SurfaceLanes& in, const vec3& eye, int s, ReceiverLanes& out) {
  const DI di;
  const DU du;
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0f);
  // reuse_receiver: position, decoded normals, wo = normalize(eye - position).
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
  BsdfLanes& t = out.target;
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

// One vector of slots [s, s + lanes) of the exact receivers: exact_receiver's wo = normalize(eye - position),
// then the BSDF's terms (build_bsdf); where `geometry` is given, also the receivers' position, geometric normal
// and wo into it.
void build_exact(D d, const ExactSurfaceLanes& in, const vec3& eye, int s, BsdfLanes& t, ReceiverLanes* geometry) {
  const V3 p = load3(d, in.px, in.py, in.pz, s);
  const V3 wo =
      normalize(d, {hn::Sub(hn::Set(d, eye.x), p.x), hn::Sub(hn::Set(d, eye.y), p.y), hn::Sub(hn::Set(d, eye.z), p.z)});
  if (geometry) {
    store3(d, p, geometry->px, geometry->py, geometry->pz, s);
    store3(d, load3(d, in.gx, in.gy, in.gz, s), geometry->gx, geometry->gy, geometry->gz, s);
    store3(d, wo, geometry->wox, geometry->woy, geometry->woz, s);
  }
  build_bsdf(d, in.material, s, wo, t);
}

void BuildExactReceiverLanes(const ExactSurfaceLanes& surfaces, const vec3& eye, int slots, BsdfLanes& exact) {
  const D d;
  const int lanes = int(hn::Lanes(d));
  for (int s = 0; s < slots; s += lanes) build_exact(d, surfaces, eye, s, exact, nullptr);
}

void BuildExactReceivers(const ExactSurfaceLanes& surfaces, const vec3& eye, int slots, ReceiverLanes& out) {
  const D d;
  const int lanes = int(hn::Lanes(d));
  for (int s = 0; s < slots; s += lanes) build_exact(d, surfaces, eye, s, out.exact, &out);
}

void BuildReceiverLanes(const SurfaceLanes& surfaces, const vec3& eye, int slots, ReceiverLanes& out,
                        const float* wanted) {
  const D d;
  const int lanes = int(hn::Lanes(d));
  for (int s = 0; s < slots; s += lanes)
    if (!wanted || !hn::AllFalse(d, hn::Gt(hn::Load(d, wanted + s), hn::Zero(d)))) build(d, surfaces, eye, s, out);
}

// reuse_receiver's position and geometric normal alone.
void PackedPointsLanes(const SurfaceLanes& surfaces, int slots, ReceiverLanes& out) {
  const D d;
  const DU du;
  const int lanes = int(hn::Lanes(d));
  for (int s = 0; s < slots; s += lanes) {
    store3(d, load3(d, surfaces.px, surfaces.py, surfaces.pz, s), out.px, out.py, out.pz, s);
    store3(d, oct_decode(d, hn::Load(du, surfaces.geometric_normal + s)), out.gx, out.gy, out.gz, s);
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace candela
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace candela {

HWY_EXPORT(BuildReceiverLanes);
HWY_EXPORT(BuildExactReceiverLanes);
HWY_EXPORT(BuildExactReceivers);
HWY_EXPORT(PackedPointsLanes);

void packed_points_lanes(const SurfaceLanes& surfaces, int slots, ReceiverLanes& out) {
  HWY_DYNAMIC_DISPATCH(PackedPointsLanes)(surfaces, slots, out);
}

void build_exact_receiver_lanes(const ExactSurfaceLanes& surfaces, const vec3& eye, int slots, BsdfLanes& exact) {
  HWY_DYNAMIC_DISPATCH(BuildExactReceiverLanes)(surfaces, eye, slots, exact);
}

void build_exact_receivers(const ExactSurfaceLanes& surfaces, const vec3& eye, int slots, ReceiverLanes& out) {
  HWY_DYNAMIC_DISPATCH(BuildExactReceivers)(surfaces, eye, slots, out);
}

void build_receiver_lanes(const SurfaceLanes& surfaces, const vec3& eye, int slots, ReceiverLanes& out,
                          const float* wanted) {
  HWY_DYNAMIC_DISPATCH(BuildReceiverLanes)(surfaces, eye, slots, out, wanted);
}

}  // namespace candela
#endif  // HWY_ONCE

// The BSDF kernels (bsdf_lanes.h), compiled once per instruction set by Highway's foreach_target.h and
// dispatched at run time; their arithmetic is engine/bsdf_lanes-inl.h's, shared with ReSTIR's kernels.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "engine/bsdf_lanes.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/highway.h"
#include "engine/bsdf_lanes-inl.h"

HWY_BEFORE_NAMESPACE();
namespace candela {
namespace HWY_NAMESPACE {

void BuildBsdfLanes(const BsdfVertexLanes& vertices, int slots, BsdfLanes& out) {
  const D d;
  for (int s = 0; s < slots; s += int(hn::Lanes(d)))
    build_bsdf(d, vertices.material, s, load3(d, vertices.wox, vertices.woy, vertices.woz, s), out);
}

template <bool kTimesCosine>
void evaluate(const BsdfLanes& bsdf, const float* wox, const float* woy, const float* woz, int slots,
              DirectionLanes& directions) {
  const D d;
  for (int s = 0; s < slots; s += int(hn::Lanes(d))) {
    const V3 wo = load3(d, wox, woy, woz, s), wi = load3(d, directions.x, directions.y, directions.z, s);
    const M active = hn::Gt(hn::Load(d, directions.active + s), hn::Zero(d));
    V f[3];
    eval_bsdf<kTimesCosine>(d, bsdf, s, wo, wi, f);
    for (int c = 0; c < 3; ++c) hn::Store(hn::IfThenElseZero(active, f[c]), d, directions.f[c] + s);
    hn::Store(hn::IfThenElseZero(active, bsdf_pdf(d, bsdf, s, wo, wi)), d, directions.pdf + s);
  }
}

void EvaluateBsdfLanes(const BsdfLanes& bsdf, const float* wox, const float* woy, const float* woz, int slots,
                       bool times_cosine, DirectionLanes& directions) {
  if (times_cosine)
    evaluate<true>(bsdf, wox, woy, woz, slots, directions);
  else
    evaluate<false>(bsdf, wox, woy, woz, slots, directions);
}

// Frame::from_normal (Duff et al. 2017): the tangents t and b of unit normal n.
struct FrameLanes {
  V3 t, b, n;
  V3 to_local(const V3& v) const { return {dot(v, t), dot(v, b), dot(v, n)}; }
  // Frame::to_world: t v.x + b v.y + n v.z.
  V3 to_world(const V3& v) const {
    auto axis = [&](V tc, V bc, V nc) {
      return hn::Add(hn::Add(hn::Mul(tc, v.x), hn::Mul(bc, v.y)), hn::Mul(nc, v.z));
    };
    return {axis(t.x, b.x, n.x), axis(t.y, b.y, n.y), axis(t.z, b.z, n.z)};
  }
};
FrameLanes frame_from_normal(D d, const V3& n) {
  const V one = hn::Set(d, 1.0f), sign = hn::CopySign(one, n.z);
  const V a = hn::Div(hn::Set(d, -1.0f), hn::Add(sign, n.z));
  const V b = hn::Mul(hn::Mul(n.x, n.y), a);
  return {{hn::Add(one, hn::Mul(hn::Mul(hn::Mul(sign, n.x), n.x), a)), hn::Mul(sign, b), hn::Neg(hn::Mul(sign, n.x))},
          {b, hn::Add(sign, hn::Mul(hn::Mul(n.y, n.y), a)), hn::Neg(n.y)},
          n};
}

// ggx_sample_visible_normal (engine/microfacet.cpp, Heitz 2018) for local wo.
V3 ggx_sample_visible_normal(D d, const V3& wo, V alpha, V u0, V u1) {
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0f);
  const V3 vh = normalize(d, {hn::Mul(alpha, wo.x), hn::Mul(alpha, wo.y), wo.z});
  const V len2 = hn::Add(hn::Mul(vh.x, vh.x), hn::Mul(vh.y, vh.y));
  const M tilted = hn::Gt(len2, zero);
  const V len = hn::Sqrt(len2);
  const V3 t1{hn::IfThenElse(tilted, hn::Div(hn::Neg(vh.y), len), one), hn::IfThenElseZero(tilted, hn::Div(vh.x, len)),
              zero};
  const V3 t2 = cross(vh, t1);
  const V r = hn::Sqrt(u0);
  V sine, cosine;
  sin_cos(d, hn::Mul(hn::Set(d, 2.0f * kPi), u1), sine, cosine);
  const V p1 = hn::Mul(r, cosine);
  const V s = hn::Mul(hn::Set(d, 0.5f), hn::Add(one, vh.z));
  const V p2 = hn::Add(hn::Mul(hn::Sub(one, s), hn::Sqrt(max_of(zero, hn::Sub(one, hn::Mul(p1, p1))))),
                       hn::Mul(s, hn::Mul(r, sine)));
  const V k = hn::Sqrt(max_of(zero, hn::Sub(hn::Sub(one, hn::Mul(p1, p1)), hn::Mul(p2, p2))));
  auto axis = [&](V a, V b, V c) { return hn::Add(hn::Add(hn::Mul(p1, a), hn::Mul(p2, b)), hn::Mul(k, c)); };
  const V3 nh{axis(t1.x, t2.x, vh.x), axis(t1.y, t2.y, vh.y), axis(t1.z, t2.z, vh.z)};
  return normalize(d, {hn::Mul(alpha, nh.x), hn::Mul(alpha, nh.y), max_of(hn::Set(d, 1e-6f), nh.z)});
}

// sample_cosine_hemisphere (engine/microfacet.cpp): the concentric map of the square to the disk, lifted to the
// hemisphere.
V3 sample_cosine_hemisphere(D d, V u0, V u1) {
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0f), two = hn::Set(d, 2.0f);
  const V ox = hn::Sub(hn::Mul(two, u0), one), oy = hn::Sub(hn::Mul(two, u1), one);
  const M off_centre = hn::Or(hn::Ne(ox, zero), hn::Ne(oy, zero));
  const M wide = hn::Gt(hn::Abs(ox), hn::Abs(oy));
  const V quarter = hn::Set(d, kPi / 4.0f);
  const V r = hn::IfThenElse(wide, ox, oy);
  const V theta = hn::IfThenElse(wide, hn::Mul(quarter, hn::Div(oy, ox)),
                                 hn::Sub(hn::Set(d, kPi / 2.0f), hn::Mul(quarter, hn::Div(ox, oy))));
  V sine, cosine;
  sin_cos(d, theta, sine, cosine);
  const V dx = hn::IfThenElseZero(off_centre, hn::Mul(r, cosine)),
          dy = hn::IfThenElseZero(off_centre, hn::Mul(r, sine));
  return {dx, dy, hn::Sqrt(max_of(zero, hn::Sub(hn::Sub(one, hn::Mul(dx, dx)), hn::Mul(dy, dy))))};
}

void SampleBsdfLanes(const BsdfLanes& bsdf, const float* wox, const float* woy, const float* woz,
                     const BsdfUniformLanes& uniforms, int slots, DirectionLanes& directions) {
  const D d;
  const V zero = hn::Zero(d);
  for (int s = 0; s < slots; s += int(hn::Lanes(d))) {
    // sample_bsdf_direction: wo in the normal's frame, then sample_local_direction's two lobes, the one the lobe
    // uniform picks kept where its direction is above the surface (not <= 0: NaN passes, as in the scalar code).
    const FrameLanes frame = frame_from_normal(d, load3(d, bsdf.nx, bsdf.ny, bsdf.nz, s));
    const V3 wo = frame.to_local(load3(d, wox, woy, woz, s));
    const V u0 = hn::Load(d, uniforms.u[0] + s), u1 = hn::Load(d, uniforms.u[1] + s);
    const V3 h = ggx_sample_visible_normal(d, wo, hn::Load(d, bsdf.alpha + s), u0, u1);
    const V3 in{hn::Neg(wo.x), hn::Neg(wo.y), hn::Neg(wo.z)};  // glm::reflect(-wo, h): in - 2 (h.in) h
    const V twice = hn::Set(d, 2.0f), h_in = dot(h, in);
    const V3 specular{hn::Sub(in.x, hn::Mul(hn::Mul(h.x, h_in), twice)),
                      hn::Sub(in.y, hn::Mul(hn::Mul(h.y, h_in), twice)),
                      hn::Sub(in.z, hn::Mul(hn::Mul(h.z, h_in), twice))};
    const V3 diffuse = sample_cosine_hemisphere(d, u0, u1);
    const M specular_lobe = hn::Lt(hn::Load(d, uniforms.lobe + s), hn::Load(d, bsdf.p_specular + s));
    const V3 wi{hn::IfThenElse(specular_lobe, specular.x, diffuse.x),
                hn::IfThenElse(specular_lobe, specular.y, diffuse.y),
                hn::IfThenElse(specular_lobe, specular.z, diffuse.z)};
    M drawn = hn::And(hn::Gt(hn::Load(d, directions.active + s), zero), hn::Gt(wo.z, zero));
    drawn = hn::AndNot(hn::Le(wi.z, zero), drawn);
    const V3 world = frame.to_world(wi);
    hn::Store(hn::IfThenElseZero(drawn, world.x), d, directions.x + s);
    hn::Store(hn::IfThenElseZero(drawn, world.y), d, directions.y + s);
    hn::Store(hn::IfThenElseZero(drawn, world.z), d, directions.z + s);
    hn::Store(hn::IfThenElseZero(drawn, hn::Set(d, 1.0f)), d, directions.active + s);
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace candela
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace candela {

HWY_EXPORT(BuildBsdfLanes);
HWY_EXPORT(EvaluateBsdfLanes);
HWY_EXPORT(SampleBsdfLanes);

static_assert(kLaneSlots % 16 == 0, "a batch is a whole number of the widest vectors");

void build_bsdf_lanes(const BsdfVertexLanes& vertices, int slots, BsdfLanes& out) {
  HWY_DYNAMIC_DISPATCH(BuildBsdfLanes)(vertices, slots, out);
}

void evaluate_bsdf_lanes(const BsdfLanes& bsdf, const float* wox, const float* woy, const float* woz, int slots,
                         bool times_cosine, DirectionLanes& directions) {
  HWY_DYNAMIC_DISPATCH(EvaluateBsdfLanes)(bsdf, wox, woy, woz, slots, times_cosine, directions);
}

void sample_bsdf_lanes(const BsdfLanes& bsdf, const float* wox, const float* woy, const float* woz,
                       const BsdfUniformLanes& uniforms, int slots, DirectionLanes& directions) {
  HWY_DYNAMIC_DISPATCH(SampleBsdfLanes)(bsdf, wox, woy, woz, uniforms, slots, directions);
}

void BsdfLanes::set(int s, const BsdfWoTerms& t) {
  nx[s] = t.n.x, ny[s] = t.n.y, nz[s] = t.n.z;
  cos_o[s] = t.cos_o, alpha[s] = t.alpha, s_o[s] = t.s_o, f90[s] = t.f90, ms_o[s] = t.ms_o, d_f90[s] = t.d_f90;
  for (int c = 0; c < 3; ++c) {
    f0[c][s] = t.f0[c], ms[c][s] = t.ms[c], base_o[c][s] = t.base_o[c];
    d_f0[c][s] = t.d_f0[c], d_ms[c][s] = t.d_ms[c];
  }
  albedo_row[s] = int32_t(t.albedo_row), albedo_weight[s] = t.albedo_weight;
  g1_o[s] = t.g1_o, p_specular[s] = t.p_specular;
}

}  // namespace candela
#endif  // HWY_ONCE

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

}  // namespace HWY_NAMESPACE
}  // namespace candela
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace candela {

HWY_EXPORT(BuildBsdfLanes);
HWY_EXPORT(EvaluateBsdfLanes);

static_assert(kLaneSlots % 16 == 0, "a batch is a whole number of the widest vectors");

void build_bsdf_lanes(const BsdfVertexLanes& vertices, int slots, BsdfLanes& out) {
  HWY_DYNAMIC_DISPATCH(BuildBsdfLanes)(vertices, slots, out);
}

void evaluate_bsdf_lanes(const BsdfLanes& bsdf, const float* wox, const float* woy, const float* woz, int slots,
                         bool times_cosine, DirectionLanes& directions) {
  HWY_DYNAMIC_DISPATCH(EvaluateBsdfLanes)(bsdf, wox, woy, woz, slots, times_cosine, directions);
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

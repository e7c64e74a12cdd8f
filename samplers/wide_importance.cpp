// The wide importance kernel (wide_importance.h), compiled once per instruction set by Highway's
// foreach_target.h. Each step repeats LightBounds::importance (light_bounds.h) in the same order.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "samplers/wide_importance.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/highway.h"
#include "samplers/wide_importance.h"

HWY_BEFORE_NAMESPACE();
namespace candela {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using D = hn::CappedTag<float, kTreeWidth>;
using V = hn::Vec<D>;

// The helpers have internal linkage: engine/lanes-inl.h declares a V3 and a dot of its own (over full-width
// vectors) in this same namespace, and two external definitions of one name would be merged by the linker.
namespace {

// light_bounds_detail::safe_sqrt. (x86's max returns its second operand unless the first is greater:
// Max(x, 0) is std::max(0.0f, x) also for -0 and NaN, Max(0, x) is std::max(x, 0.0f).)
V safe_sqrt(D d, V x) { return hn::Sqrt(hn::Max(x, hn::Zero(d))); }
// light_bounds_detail::cos_sub_clamped: cos(max(0, a - b)).
V cos_sub_clamped(D d, V sin_a, V cos_a, V sin_b, V cos_b) {
  return hn::IfThenElse(hn::Gt(cos_a, cos_b), hn::Set(d, 1.0f), hn::Add(hn::Mul(cos_a, cos_b), hn::Mul(sin_a, sin_b)));
}
// light_bounds_detail::sin_sub_clamped: sin(max(0, a - b)).
V sin_sub_clamped(V sin_a, V cos_a, V sin_b, V cos_b) {
  return hn::IfThenZeroElse(hn::Gt(cos_a, cos_b), hn::Sub(hn::Mul(sin_a, cos_b), hn::Mul(cos_a, sin_b)));
}

// glm::dot and glm::cross of vec3, in their order of operations.
struct V3 {
  V x, y, z;
};
V dot(const V3& a, const V3& b) { return hn::Add(hn::Add(hn::Mul(a.x, b.x), hn::Mul(a.y, b.y)), hn::Mul(a.z, b.z)); }
V3 cross(const V3& a, const V3& b) {
  return {hn::Sub(hn::Mul(a.y, b.z), hn::Mul(b.y, a.z)), hn::Sub(hn::Mul(a.z, b.x), hn::Mul(b.z, a.x)),
          hn::Sub(hn::Mul(a.x, b.y), hn::Mul(b.x, a.y))};
}

}  // namespace

void WideImportance(const WideBounds& b, const ShadingContext& ctx, float* out) {
  const D d;
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0f);
  const vec3& p = ctx.position;
  const vec3& n = ctx.normal;
  for (int s = 0; s < kTreeWidth; s += int(hn::Lanes(d))) {
    const V signed_phi = hn::Load(d, b.phi + s);
    const V phi = hn::Abs(signed_phi), radius = hn::Add(hn::Load(d, b.radius + s), hn::Set(d, ctx.radius));
    V3 t{hn::Sub(hn::Set(d, p.x), hn::Load(d, b.cx + s)), hn::Sub(hn::Set(d, p.y), hn::Load(d, b.cy + s)),
         hn::Sub(hn::Set(d, p.z), hn::Load(d, b.cz + s))};
    const V dist2 = dot(t, t);
    const V power = hn::Div(phi, hn::Max(hn::Set(d, 1e-20f), hn::Max(radius, dist2)));  // phi / std::max({...})
    // p at the centre: the direction (0, 0, 1).
    const auto away = hn::Gt(dist2, zero);
    t = {hn::IfThenElseZero(away, t.x), hn::IfThenElseZero(away, t.y), hn::IfThenElse(away, t.z, one)};
    const V dist = hn::Sqrt(hn::IfThenElse(away, dist2, one));
    const V inv_dist = hn::Div(one, dist);
    // theta_b: the cone from p around the bounding sphere (cos -1 when p is inside it).
    const auto outside = hn::And(away, hn::Gt(dist, radius));
    const V sin_b = hn::IfThenElseZero(outside, hn::Mul(radius, inv_dist));
    const V cos_b = hn::IfThenElse(outside, hn::Mul(safe_sqrt(d, hn::Sub(dist2, hn::Mul(radius, radius))), inv_dist),
                                   hn::Set(d, -1.0f));
    // theta_w - theta_o - theta_b, then the emission cut-off theta_e.
    const V3 w{hn::Load(d, b.wx + s), hn::Load(d, b.wy + s), hn::Load(d, b.wz + s)};
    V cos_w = hn::Mul(dot(w, t), inv_dist);
    cos_w = hn::IfThenElse(hn::Lt(signed_phi, zero), hn::Abs(cos_w), cos_w);
    const V3 w_cross = cross(w, t);
    const V sin_w = hn::Mul(hn::Sqrt(dot(w_cross, w_cross)), inv_dist);
    const V cos_o = hn::Load(d, b.cos_o + s), sin_o = hn::Load(d, b.sin_o + s);
    const V cos_x = cos_sub_clamped(d, sin_w, cos_w, sin_o, cos_o);
    const V sin_x = sin_sub_clamped(sin_w, cos_w, sin_o, cos_o);
    const V cos_p = cos_sub_clamped(d, sin_x, cos_x, sin_b, cos_b);
    V value = hn::Mul(power, cos_p);
    if (n != vec3(0.0f)) {
      const V3 nv{hn::Set(d, n.x), hn::Set(d, n.y), hn::Set(d, n.z)};
      const V cos_i = hn::Mul(hn::Abs(dot(t, nv)), inv_dist);
      const V3 n_cross = cross(nv, t);
      const V sin_i = hn::Mul(hn::Sqrt(dot(n_cross, n_cross)), inv_dist);
      value = hn::Mul(value, cos_sub_clamped(d, sin_i, cos_i, sin_b, cos_b));
    }
    const auto dark = hn::Or(hn::Le(phi, zero), hn::Lt(cos_p, hn::Load(d, b.cos_e + s)));
    hn::StoreU(hn::IfThenZeroElse(dark, hn::Max(zero, value)), d, out + s);
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace candela
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace candela {

HWY_EXPORT(WideImportance);

void wide_importance(const WideBounds& bounds, const ShadingContext& ctx, float out[kTreeWidth]) {
  HWY_DYNAMIC_DISPATCH(WideImportance)(bounds, ctx, out);
}

WideBounds::WideBounds() {
  for (int s = 0; s < kTreeWidth; ++s) set(s, LightBounds{});
}

void WideBounds::set(int s, const LightBounds& b) {
  cx[s] = b.center.x, cy[s] = b.center.y, cz[s] = b.center.z, radius[s] = b.radius;
  wx[s] = b.w.x, wy[s] = b.w.y, wz[s] = b.w.z, phi[s] = b.two_sided ? -b.phi : b.phi;
  cos_o[s] = b.cos_theta_o, sin_o[s] = b.sin_theta_o, cos_e[s] = b.cos_theta_e;
}

}  // namespace candela
#endif  // HWY_ONCE

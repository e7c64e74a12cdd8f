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

void WideImportance(const WideBounds& b, const vec3& p, const vec3& n, float* out) {
  const D d;
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0f);
  for (int s = 0; s < kTreeWidth; s += int(hn::Lanes(d))) {
    const V phi = hn::Load(d, b.phi + s), radius = hn::Load(d, b.radius + s);
    const V tx = hn::Sub(hn::Set(d, p.x), hn::Load(d, b.cx + s));
    const V ty = hn::Sub(hn::Set(d, p.y), hn::Load(d, b.cy + s));
    const V tz = hn::Sub(hn::Set(d, p.z), hn::Load(d, b.cz + s));
    const V dist2 = hn::Add(hn::Add(hn::Mul(tx, tx), hn::Mul(ty, ty)), hn::Mul(tz, tz));
    const V d2 = hn::Max(hn::Set(d, 1e-20f), hn::Max(radius, dist2));  // std::max({dist2, radius, 1e-20f})
    const V dist = hn::Sqrt(dist2);
    // theta_b: the cone from p around the bounding sphere (cos -1 when p is inside it).
    const auto outside = hn::Gt(dist, radius);
    const V sin_b = hn::IfThenElseZero(outside, hn::Div(radius, dist));
    const V cos_b = hn::IfThenElse(outside, safe_sqrt(d, hn::Sub(one, hn::Mul(sin_b, sin_b))), hn::Set(d, -1.0f));
    const auto away = hn::Gt(dist, zero);
    const V dx = hn::IfThenElseZero(away, hn::Div(tx, dist)), dy = hn::IfThenElseZero(away, hn::Div(ty, dist));
    const V dz = hn::IfThenElse(away, hn::Div(tz, dist), one);
    // theta_w - theta_o - theta_b, then the emission cut-off theta_e.
    V cos_w = hn::Add(hn::Add(hn::Mul(hn::Load(d, b.wx + s), dx), hn::Mul(hn::Load(d, b.wy + s), dy)),
                      hn::Mul(hn::Load(d, b.wz + s), dz));
    cos_w = hn::IfThenElse(hn::Gt(hn::Load(d, b.two_sided + s), zero), hn::Abs(cos_w), cos_w);
    const V sin_w = safe_sqrt(d, hn::Sub(one, hn::Mul(cos_w, cos_w)));
    const V cos_o = hn::Load(d, b.cos_o + s), sin_o = hn::Load(d, b.sin_o + s);
    const V cos_x = cos_sub_clamped(d, sin_w, cos_w, sin_o, cos_o);
    const V sin_x = sin_sub_clamped(sin_w, cos_w, sin_o, cos_o);
    const V cos_p = cos_sub_clamped(d, sin_x, cos_x, sin_b, cos_b);
    V value = hn::Div(hn::Mul(phi, cos_p), d2);
    if (n != vec3(0.0f)) {
      const V cos_i = hn::Abs(hn::Add(hn::Add(hn::Mul(dx, hn::Set(d, n.x)), hn::Mul(dy, hn::Set(d, n.y))),
                                      hn::Mul(dz, hn::Set(d, n.z))));
      const V sin_i = safe_sqrt(d, hn::Sub(one, hn::Mul(cos_i, cos_i)));
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

void wide_importance(const WideBounds& bounds, const vec3& p, const vec3& n, float out[kTreeWidth]) {
  HWY_DYNAMIC_DISPATCH(WideImportance)(bounds, p, n, out);
}

WideBounds::WideBounds() {
  for (int s = 0; s < kTreeWidth; ++s) set(s, LightBounds{});
}

void WideBounds::set(int s, const LightBounds& b) {
  cx[s] = b.center.x, cy[s] = b.center.y, cz[s] = b.center.z, radius[s] = b.radius;
  wx[s] = b.w.x, wy[s] = b.w.y, wz[s] = b.w.z, phi[s] = b.phi;
  cos_o[s] = b.cos_theta_o, sin_o[s] = b.sin_theta_o, cos_e[s] = b.cos_theta_e, two_sided[s] = b.two_sided ? 1.0f : 0.0f;
}

}  // namespace candela
#endif  // HWY_ONCE

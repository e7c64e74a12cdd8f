// The wide importance kernel (wide_importance.h), compiled once per instruction set by Highway's
// foreach_target.h. Each step repeats LightBounds::importance (light_bounds.h) in the same order.
#include <bit>
#include <cmath>

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

// glm::dot and glm::cross of vec3, in their order of operations.
struct V3 {
  V x, y, z;
};
V dot(const V3& a, const V3& b) { return hn::Add(hn::Add(hn::Mul(a.x, b.x), hn::Mul(a.y, b.y)), hn::Mul(a.z, b.z)); }
V3 cross(const V3& a, const V3& b) {
  return {hn::Sub(hn::Mul(a.y, b.z), hn::Mul(b.y, a.z)), hn::Sub(hn::Mul(a.z, b.x), hn::Mul(b.z, a.x)),
          hn::Sub(hn::Mul(a.x, b.y), hn::Mul(b.x, a.y))};
}

// The quantised fields in float: 16-bit fixed point (x / 32767) and half precision times the scale.
V fixed_point(D d, const int16_t* x) {
  const hn::Rebind<int32_t, D> di32;
  const hn::Rebind<int16_t, D> di16;
  return hn::Mul(hn::ConvertTo(d, hn::PromoteTo(di32, hn::LoadU(di16, x))), hn::Set(d, kFixedPointUnit));
}
V half(D d, const uint16_t* x) {
  const hn::Rebind<hwy::float16_t, D> dh;
  return hn::PromoteTo(d, hn::LoadU(dh, reinterpret_cast<const hwy::float16_t*>(x)));
}

}  // namespace

void WideImportance(const WideBounds& b, const ShadingContext& ctx, float radius_scale, float* out) {
  const D d;
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0f);
  const vec3& p = ctx.position;
  const vec3& n = ctx.normal;
  for (int s = 0; s < kTreeWidth; s += int(hn::Lanes(d))) {
    const V signed_phi = hn::Load(d, b.phi + s);
    const V phi = hn::Abs(signed_phi);
    const V radius = hn::Add(hn::Mul(half(d, b.radius + s), hn::Set(d, radius_scale)), hn::Set(d, ctx.radius));
    V3 t{hn::Sub(hn::Set(d, p.x), hn::Load(d, b.cx + s)), hn::Sub(hn::Set(d, p.y), hn::Load(d, b.cy + s)),
         hn::Sub(hn::Set(d, p.z), hn::Load(d, b.cz + s))};
    const V dist2 = dot(t, t);
    const V power = hn::Div(phi, hn::Max(hn::Set(d, 1e-20f), hn::Max(radius, dist2)));  // phi / std::max({...})
    // p at the centre: the direction (0, 0, 1).
    const auto away = hn::Gt(dist2, zero);
    t = {hn::IfThenElseZero(away, t.x), hn::IfThenElseZero(away, t.y), hn::IfThenElse(away, t.z, one)};
    const V safe_dist2 = hn::IfThenElse(away, dist2, one);
    const V dist = hn::Sqrt(safe_dist2);
    const V inv_dist = hn::Div(one, dist);
    // theta_b: the cone from p around the bounding sphere (cos -1 when p is inside it).
    const auto outside = hn::And(away, hn::Gt(dist, radius));
    const V sin_b = hn::IfThenElseZero(outside, hn::Mul(radius, inv_dist));
    const V cos_b = hn::IfThenElse(outside, hn::Mul(safe_sqrt(d, hn::Sub(dist2, hn::Mul(radius, radius))), inv_dist),
                                   hn::Set(d, -1.0f));
    // theta_w - theta_o - theta_b, then the emission cut-off theta_e.
    const V3 w{fixed_point(d, b.wx + s), fixed_point(d, b.wy + s), fixed_point(d, b.wz + s)};
    const V w_len = hn::Sqrt(dot(w, w)), inv_w_len = hn::Div(one, w_len);
    V w_cos = hn::Mul(dot(w, t), inv_dist);
    w_cos = hn::IfThenElse(hn::Lt(signed_phi, zero), hn::Abs(w_cos), w_cos);
    const V3 w_cross = cross(w, t);
    const V w_sin = hn::Mul(hn::Sqrt(dot(w_cross, w_cross)), inv_dist);
    const V cos_o = fixed_point(d, b.cos_o + s), sin_o = hn::Sqrt(hn::Sub(one, hn::Mul(cos_o, cos_o)));
    const auto within_o = hn::Gt(w_cos, hn::Mul(cos_o, w_len));
    const V cos_x =
        hn::IfThenElse(within_o, one, hn::Mul(hn::Add(hn::Mul(w_cos, cos_o), hn::Mul(w_sin, sin_o)), inv_w_len));
    const V sin_x =
        hn::IfThenZeroElse(within_o, hn::Mul(hn::Sub(hn::Mul(w_sin, cos_o), hn::Mul(w_cos, sin_o)), inv_w_len));
    const V cos_p = cos_sub_clamped(d, sin_x, cos_x, sin_b, cos_b);
    V value = hn::Mul(power, cos_p);
    if (n != vec3(0.0f)) {
      const V3 nv{hn::Set(d, n.x), hn::Set(d, n.y), hn::Set(d, n.z)};
      const V cos_i = hn::Mul(hn::Abs(dot(t, nv)), inv_dist);
      const V3 n_cross = cross(nv, t);
      const V sin_i = hn::Mul(hn::Sqrt(dot(n_cross, n_cross)), inv_dist);
      value = hn::Mul(value, cos_sub_clamped(d, sin_i, cos_i, sin_b, cos_b));
    }
    const auto dark = hn::Or(hn::Le(phi, zero), hn::Lt(cos_p, fixed_point(d, b.cos_e + s)));
    hn::StoreU(hn::IfThenZeroElse(dark, hn::Max(zero, value)), d, out + s);
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace candela
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace candela {

HWY_EXPORT(WideImportance);

void wide_importance(const WideBounds& bounds, const ShadingContext& ctx, float radius_scale, float out[kTreeWidth]) {
  HWY_DYNAMIC_DISPATCH(WideImportance)(bounds, ctx, radius_scale, out);
}

namespace {

// Half-precision bits of non-negative finite values: exact decoding, and the smallest half at least x
// (0xffff when x exceeds the largest half, 65504).
float half_to_float(uint16_t h) {
  const uint32_t exponent = h >> 10, mantissa = h & 0x3ffu;
  if (exponent == 0) return float(mantissa) * 0x1p-24f;  // subnormal
  return std::bit_cast<float>(((exponent + 112u) << 23) | (mantissa << 13));
}
uint16_t half_at_least(float x) {
  if (!(x > 0.0f)) return 0;
  if (x < 0x1p-14f) return uint16_t(std::ceil(x * 0x1p24f));  // subnormal halves (1024 is the smallest normal)
  if (x > 65504.0f) return 0xffff;
  const uint32_t bits = std::bit_cast<uint32_t>(x);
  const uint32_t h = ((((bits >> 23) & 0xffu) - 112u) << 10) | ((bits >> 13) & 0x3ffu);
  return uint16_t(h + ((bits & 0x1fffu) != 0));  // rounding up may carry into the exponent, as it should
}

// The largest q / 32767 at most x (x in [-1, 1]).
int16_t fixed_point_at_most(float x) {
  int16_t q = int16_t(std::clamp(std::floor(x * 32767.0f), -32767.0f, 32767.0f));
  while (q > -32767 && float(q) * kFixedPointUnit > x) --q;  // the product's rounding
  return q;
}

}  // namespace

float radius_scale_for(float max_radius) {
  return max_radius > 0.0f ? std::exp2(std::ceil(std::log2(max_radius / 16.0f))) : 1.0f;
}

WideBounds::WideBounds() {
  for (int s = 0; s < kTreeWidth; ++s) (void)set(s, LightBounds{}, 1.0f);
}

bool WideBounds::set(int s, const LightBounds& b, float radius_scale) {
  const uint16_t r = half_at_least(b.radius / radius_scale);
  if (r == 0xffff) {
    (void)set(s, LightBounds{}, radius_scale);
    return false;
  }
  cx[s] = b.center.x, cy[s] = b.center.y, cz[s] = b.center.z, radius[s] = r;
  phi[s] = b.two_sided ? -b.phi : b.phi;
  // The rounded axis: each component within 0.5 / 32767 of the unit axis, so the two are at most
  // delta = asin(sqrt(3) / 2 / 32767) = 2.64e-5 radians apart (3e-5 below); the cone around the rounded axis
  // opens by delta: cos(theta_o + delta), in double, then rounded down.
  wx[s] = int16_t(std::nearbyint(b.w.x * 32767.0f));
  wy[s] = int16_t(std::nearbyint(b.w.y * 32767.0f));
  wz[s] = int16_t(std::nearbyint(b.w.z * 32767.0f));
  constexpr double kCosDelta = 0.9999999995, kSinDelta = 3e-5;  // cos(3e-5) = 0.99999999955, rounded down
  const double widened = kCosDelta <= -double(b.cos_theta_o)
                             ? -1.0
                             : double(b.cos_theta_o) * kCosDelta - double(b.sin_theta_o) * kSinDelta;
  cos_o[s] = fixed_point_at_most(float(widened) > widened ? std::nextafter(float(widened), -1.0f) : float(widened));
  cos_e[s] = fixed_point_at_most(b.cos_theta_e);
  return true;
}

LightBounds WideBounds::get(int s, float radius_scale) const {
  LightBounds b;
  b.center = vec3(cx[s], cy[s], cz[s]);
  b.radius = half_to_float(radius[s]) * radius_scale;
  b.phi = std::abs(phi[s]);
  b.two_sided = phi[s] < 0.0f;
  b.w = vec3(float(wx[s]) * kFixedPointUnit, float(wy[s]) * kFixedPointUnit, float(wz[s]) * kFixedPointUnit);
  b.set_cos_theta_o(float(cos_o[s]) * kFixedPointUnit);
  b.cos_theta_e = float(cos_e[s]) * kFixedPointUnit;
  return b;
}

}  // namespace candela
#endif  // HWY_ONCE

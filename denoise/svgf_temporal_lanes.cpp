// SVGF's temporal stage in lanes (svgf_temporal_lanes.h), compiled once per instruction set by Highway's
// foreach_target.h and dispatched at run time. It repeats denoise/svgf_temporal.cpp's Reprojector (the
// bilinear taps and their consistency tests) and svgf_temporal's blend, in their order.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "denoise/svgf_temporal_lanes.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/highway.h"
#include "denoise/svgf_temporal_lanes.h"
#include "engine/lanes-inl.h"

HWY_BEFORE_NAMESPACE();
namespace candela {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

// luminance(c): (0.2126 r + 0.7152 g) + 0.0722 b.
V luminance_of(D d, V r, V g, V b) {
  return hn::Add(hn::Add(hn::Mul(hn::Set(d, 0.2126f), r), hn::Mul(hn::Set(d, 0.7152f), g)),
                 hn::Mul(hn::Set(d, 0.0722f), b));
}
// glm::mix(x, y, a): x (1 - a) + y a.
V mix(D d, V x, V y, V a) { return hn::Add(hn::Mul(x, hn::Sub(hn::Set(d, 1.0f), a)), hn::Mul(y, a)); }

// The consistent taps' weighted sums of one vector of pixels (the scalar Gathered).
struct Sums {
  V r, g, b, m1, m2, length, weight;
};

// This frame's pixels of one vector, as the consistency tests read them.
struct Here {
  VI instance, filtered;
  V3 normal;
  V depth, slope, sx, sy;  // sx, sy: the sample's film position in the previous frame
};

// Reads of last frame's pixels q of one tap: gathers, or plain loads where the tap's pixels are
// consecutive and all taken (a still camera, or one that moved by whole pixels): 14 gathers cost ~3x as
// much as the loads.
struct TapReads {
  VI q;           // the pixels (0 where not taken)
  int64_t first;  // q's first lane where consecutive, else -1
  V at(D d, const float* plane) const {
    return first >= 0 ? hn::LoadU(d, plane + first) : hn::GatherIndex(d, plane, q);
  }
  VI at(DI di, const int32_t* plane) const {
    return first >= 0 ? hn::LoadU(di, plane + first) : hn::GatherIndex(di, plane, q);
  }
  // Component k of an interleaved plane of `stride` floats per pixel.
  void interleaved(D d, const float* plane, int stride, V* out) const {
    const DI di;
    if (first >= 0 && stride == 2) return hn::LoadInterleaved2(d, plane + 2 * first, out[0], out[1]);
    if (first >= 0) return hn::LoadInterleaved3(d, plane + 3 * first, out[0], out[1], out[2]);
    const VI base = hn::Mul(q, hn::Set(di, stride));
    for (int k = 0; k < stride; ++k) out[k] = hn::GatherIndex(d, plane, hn::Add(base, hn::Set(di, k)));
  }
};

// Reprojector::consistent and add for tap (qx, qy) of weight w where `m` (bounds, w > 0 and the pixel's
// reprojection are already in `m`): 14 reads of last frame's planes.
void add_tap(D d, const TemporalPlanes& p, const Here& h, VI qx, VI qy, V w, M m, Sums& s) {
  const DI di;
  TapReads read{hn::IfThenElseZero(hn::RebindMask(di, m), hn::Add(hn::Mul(qy, hn::Set(di, p.width)), qx)), -1};
  const int32_t q0 = hn::GetLane(read.q);
  if (hn::AllTrue(d, m) && hn::AllTrue(di, hn::Eq(read.q, hn::Add(hn::Iota(di, 0), hn::Set(di, q0))))) read.first = q0;
  m = hn::And(m, hn::RebindMask(d, hn::Eq(read.at(di, reinterpret_cast<const int32_t*>(p.prev_instance)), h.instance)));
  m = hn::And(m, hn::RebindMask(d, hn::Eq(read.at(di, p.prev_filtered), h.filtered)));
  if (hn::AllFalse(d, m)) return;
  V3 n;
  V normal[3], jitter[2];
  read.interleaved(d, p.prev_normal, 3, normal);
  n = {normal[0], normal[1], normal[2]};
  m = hn::AndNot(hn::Lt(dot(h.normal, n), hn::Set(d, p.normal_tolerance)), m);
  // apart = |(q + previous jitter) - sample|; expected = slope max(apart) + tolerance depth.
  read.interleaved(d, p.prev_jitter, 2, jitter);
  const V ax = hn::Abs(hn::Sub(hn::Add(hn::ConvertTo(d, qx), jitter[0]), h.sx));
  const V ay = hn::Abs(hn::Sub(hn::Add(hn::ConvertTo(d, qy), jitter[1]), h.sy));
  const V expected = hn::Add(hn::Mul(h.slope, hn::Max(ay, ax)), hn::Mul(hn::Set(d, p.depth_tolerance), h.depth));
  m = hn::And(m, hn::Le(hn::Abs(hn::Sub(h.depth, read.at(d, p.prev_depth))), expected));
  if (hn::AllFalse(d, m)) return;
  auto add = [&](V& sum, const float* plane) {
    sum = hn::IfThenElse(m, hn::Add(sum, hn::Mul(w, read.at(d, plane))), sum);
  };
  add(s.r, p.history_r), add(s.g, p.history_g), add(s.b, p.history_b);
  add(s.m1, p.history_m1), add(s.m2, p.history_m2), add(s.length, p.history_length);
  s.weight = hn::IfThenElse(m, hn::Add(s.weight, w), s.weight);
}

// Pixels [x, x + lanes) of row y: the bilinear taps around each reprojected pixel centre, then the blend.
// Returns the pixels whose taps kept no weight (the scalar code searches their 3x3 block).
M pixels(D d, const TemporalPlanes& p, int x, int y) {
  const DI di;
  const size_t i = size_t(y) * size_t(p.width) + size_t(x);
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0f);
  const V r = hn::LoadU(d, p.r + i), g = hn::LoadU(d, p.g + i), b = hn::LoadU(d, p.b + i);
  const V l = luminance_of(d, r, g, b);
  Here h;
  h.instance = hn::LoadU(di, reinterpret_cast<const int32_t*>(p.instance + i));
  const M hit = hn::RebindMask(d, hn::Ne(h.instance, hn::Set(di, -1)));  // kNoHit
  Sums s{zero, zero, zero, zero, zero, zero, zero};
  M left = hn::Lt(one, zero);  // none
  if (p.reproject && !hn::AllFalse(d, hit)) {
    V mx, my, jx, jy;
    hn::LoadInterleaved2(d, p.motion + 2 * i, mx, my);
    hn::LoadInterleaved2(d, p.jitter + 2 * i, jx, jy);
    const V px = hn::ConvertTo(d, hn::Add(hn::Iota(di, 0), hn::Set(di, x))), py = hn::Set(d, float(y));
    const V cx = hn::Add(px, mx), cy = hn::Add(py, my);  // the pixel centre, in pixel-centre coordinates
    h.sx = hn::Add(hn::Add(px, jx), mx), h.sy = hn::Add(hn::Add(py, jy), my);
    const V far = hn::Set(d, 1e6f);
    const M active = hn::And(hit, hn::And(hn::Lt(hn::Abs(cx), far), hn::Lt(hn::Abs(cy), far)));
    if (!hn::AllFalse(d, active)) {
      hn::LoadInterleaved3(d, p.normal + 3 * i, h.normal.x, h.normal.y, h.normal.z);
      h.depth = hn::LoadU(d, p.depth + i), h.slope = hn::LoadU(d, p.depth_slope + i);
      h.filtered = hn::PromoteTo(di, hn::LoadU(hn::Rebind<uint8_t, DI>(), p.filtered + i));
      const V fx0 = hn::Floor(hn::IfThenElseZero(active, cx)), fy0 = hn::Floor(hn::IfThenElseZero(active, cy));
      const VI x0 = hn::ConvertTo(di, fx0), y0 = hn::ConvertTo(di, fy0);
      const V fx = hn::Sub(cx, fx0), fy = hn::Sub(cy, fy0);
      for (int tb = 0; tb < 2; ++tb)
        for (int ta = 0; ta < 2; ++ta) {
          const V w = hn::Mul(ta ? fx : hn::Sub(one, fx), tb ? fy : hn::Sub(one, fy));
          const VI qx = hn::Add(x0, hn::Set(di, ta)), qy = hn::Add(y0, hn::Set(di, tb));
          const VI below = hn::Set(di, -1);  // Highway 1.0.3 has no integer >=
          const auto inside = hn::And(hn::And(hn::Gt(qx, below), hn::Gt(qy, below)),
                                      hn::And(hn::Lt(qx, hn::Set(di, p.width)), hn::Lt(qy, hn::Set(di, p.height))));
          const M m = hn::And(hn::And(active, hn::Gt(w, zero)), hn::RebindMask(d, inside));
          if (!hn::AllFalse(d, m)) add_tap(d, p, h, qx, qy, w, m, s);
        }
      left = hn::AndNot(hn::Gt(s.weight, hn::Set(d, 1e-3f)), active);
    }
  }
  // The blend: alpha = max(alpha, 1 / length) (std::max(c, x) is x86's max(x, c)).
  const M has = hn::Gt(s.weight, zero);
  const V inv = hn::Div(one, hn::IfThenElse(has, s.weight, one));
  const V length = min_of(hn::Add(hn::Mul(s.length, inv), one), hn::Set(d, p.max_history));
  const V inv_length = hn::Div(one, length);
  const V alpha_c = hn::Max(inv_length, hn::Set(d, p.alpha_color));
  const V alpha_m = hn::Max(inv_length, hn::Set(d, p.alpha_moments));
  const V br = mix(d, hn::Mul(s.r, inv), r, alpha_c), bg = mix(d, hn::Mul(s.g, inv), g, alpha_c),
          bb = mix(d, hn::Mul(s.b, inv), b, alpha_c);
  hn::StoreU(hn::IfThenElse(has, br, r), d, p.out_r + i);
  hn::StoreU(hn::IfThenElse(has, bg, g), d, p.out_g + i);
  hn::StoreU(hn::IfThenElse(has, bb, b), d, p.out_b + i);
  hn::StoreU(hn::IfThenElse(has, luminance_of(d, br, bg, bb), l), d, p.out_luminance + i);
  hn::StoreU(hn::IfThenElse(has, mix(d, hn::Mul(s.m1, inv), l, alpha_m), l), d, p.moment1 + i);
  hn::StoreU(hn::IfThenElse(has, mix(d, hn::Mul(s.m2, inv), hn::Mul(l, l), alpha_m), hn::Mul(l, l)), d, p.moment2 + i);
  hn::StoreU(hn::IfThenElseZero(hit, hn::IfThenElse(has, length, one)), d, p.length + i);
  return left;
}

int SvgfTemporalRowLanes(const TemporalPlanes& p, int y, int* left) {
  const D d;
  const int n = int(hn::Lanes(d));
  int count = 0, x = 0;
  for (; x + n <= p.width; x += n) {
    const M rest = pixels(d, p, x, y);
    if (hn::AllFalse(d, rest)) continue;
    alignas(64) float flags[HWY_MAX_BYTES / sizeof(float)];
    hn::Store(hn::IfThenElseZero(rest, hn::Set(d, 1.0f)), d, flags);
    for (int k = 0; k < n; ++k)
      if (flags[k] != 0.0f) left[count++] = x + k;
  }
  for (; x < p.width; ++x) left[count++] = x;  // short of a vector
  return count;
}

}  // namespace HWY_NAMESPACE
}  // namespace candela
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace candela {

HWY_EXPORT(SvgfTemporalRowLanes);

int svgf_temporal_row_lanes(const TemporalPlanes& planes, int y, int* left) {
  return HWY_DYNAMIC_DISPATCH(SvgfTemporalRowLanes)(planes, y, left);
}

}  // namespace candela
#endif  // HWY_ONCE

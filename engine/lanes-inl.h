// Highway helpers shared by the SIMD kernels over pixels (engine/gbuffer_lanes.cpp, engine/bsdf_lanes-inl.h and
// its users, restir/resample_lanes.cpp, engine/path_lanes.cpp): vectors of 3-vectors and the scalar code's dot and
// cross products, normalise, max_component (max_of3), octahedral decoding, sin_cos and GGX albedo lookup, each
// repeating the scalar operations in the same order so that the kernels keep the scalar code's bits. Included once per
// instruction set by each kernel's foreach_target.h pass, hence the toggling include guard (Highway's "-inl.h"
// convention).
#if defined(CANDELA_ENGINE_LANES_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef CANDELA_ENGINE_LANES_INL_H_
#undef CANDELA_ENGINE_LANES_INL_H_
#else
#define CANDELA_ENGINE_LANES_INL_H_
#endif

#include "engine/ggx_albedo.h"
#include "engine/math.h"
#include "hwy/highway.h"

HWY_BEFORE_NAMESPACE();
namespace candela {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using D = hn::ScalableTag<float>;
using DI = hn::RebindToSigned<D>;
using DU = hn::RebindToUnsigned<D>;
using V = hn::Vec<D>;
using VI = hn::Vec<DI>;
using VU = hn::Vec<DU>;
using M = hn::Mask<D>;

struct V3 {
  V x, y, z;
};

inline V3 load3(D d, const float* x, const float* y, const float* z, int s) {
  return {hn::Load(d, x + s), hn::Load(d, y + s), hn::Load(d, z + s)};
}
inline void store3(D d, const V3& v, float* x, float* y, float* z, int s) {
  hn::Store(v.x, d, x + s), hn::Store(v.y, d, y + s), hn::Store(v.z, d, z + s);
}
// glm::dot: (a.x b.x + a.y b.y) + a.z b.z.
inline V dot(const V3& a, const V3& b) {
  return hn::Add(hn::Add(hn::Mul(a.x, b.x), hn::Mul(a.y, b.y)), hn::Mul(a.z, b.z));
}
// glm::cross: (a.y b.z - b.y a.z, a.z b.x - b.z a.x, a.x b.y - b.x a.y).
inline V3 cross(const V3& a, const V3& b) {
  return {hn::Sub(hn::Mul(a.y, b.z), hn::Mul(b.y, a.z)), hn::Sub(hn::Mul(a.z, b.x), hn::Mul(b.z, a.x)),
          hn::Sub(hn::Mul(a.x, b.y), hn::Mul(b.x, a.y))};
}
// glm::normalize: v * (1 / sqrt(dot(v, v))).
inline V3 normalize(D d, const V3& v) {
  const V inv = hn::Div(hn::Set(d, 1.0f), hn::Sqrt(dot(v, v)));
  return {hn::Mul(v.x, inv), hn::Mul(v.y, inv), hn::Mul(v.z, inv)};
}
// std::max(x, c) and std::min(x, c) (x86's max and min return their second operand unless the first is
// greater, or smaller: putting c first keeps std's result also for -0 and NaN).
inline V max_of(V x, V c) { return hn::Max(c, x); }
inline V min_of(V x, V c) { return hn::Min(c, x); }
// max_component: std::max(x, std::max(y, z)).
inline V max_of3(V x, V y, V z) { return max_of(x, max_of(y, z)); }

// oct_decode (engine/octahedral.h).
inline V3 oct_decode(D d, VU e) {
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

// sin_cos (engine/math.h): the same reduction, polynomials and quadrant swaps, into s and c.
inline void sin_cos(D d, V x, V& s, V& c) {
  using namespace sin_cos_constants;
  const DI di;
  const VI q = hn::ConvertTo(di, hn::Floor(hn::Add(hn::Mul(x, hn::Set(d, kTwoOverPi)), hn::Set(d, 0.5f))));
  const V qf = hn::ConvertTo(d, q);
  const V r = hn::Sub(hn::Sub(hn::Sub(x, hn::Mul(qf, hn::Set(d, kPiOver2[0]))), hn::Mul(qf, hn::Set(d, kPiOver2[1]))),
                      hn::Mul(qf, hn::Set(d, kPiOver2[2])));
  const V z = hn::Mul(r, r);
  auto poly = [&](const float* k) {
    return hn::Add(hn::Mul(hn::Add(hn::Mul(hn::Set(d, k[0]), z), hn::Set(d, k[1])), z), hn::Set(d, k[2]));
  };
  const V sine = hn::Add(hn::Mul(hn::Mul(poly(kSin), z), r), r);
  const V cosine = hn::Add(hn::Sub(hn::Mul(hn::Mul(poly(kCos), z), z), hn::Mul(hn::Set(d, 0.5f), z)), hn::Set(d, 1.0f));
  auto bit = [&](VI v, int b) { return hn::RebindMask(d, hn::Ne(hn::And(v, hn::Set(di, b)), hn::Zero(di))); };
  const M swap = bit(q, 1);
  s = hn::IfThenElse(swap, cosine, sine);
  c = hn::IfThenElse(swap, sine, cosine);
  s = hn::IfThenElse(bit(q, 2), hn::Neg(s), s);
  c = hn::IfThenElse(bit(hn::Add(q, hn::Set(di, 1)), 2), hn::Neg(c), c);
}

// Per lane, the pair table[index] (a 64-bit word, engine/ggx_albedo_data.h) split into its low and high floats.
// One 64-bit gather fetches what two 32-bit gathers did: gathers cost per element (on this project's AMD machine a
// 16-lane 32-bit gather took ~4 ns), so the albedo lookup's eight 16-element gathers became eight of 8 elements.
inline void gather_pairs(D d, const uint64_t* table, VI index, V& low, V& high) {
  const DU du;
  const hn::Half<DI> dh;
  const hn::RepartitionToWide<DI> d64;
  const hn::RebindToUnsigned<decltype(d64)> du64;
  const VU lower = hn::BitCast(du, hn::GatherIndex(du64, table, hn::PromoteTo(d64, hn::LowerHalf(dh, index))));
  const VU upper = hn::BitCast(du, hn::GatherIndex(du64, table, hn::PromoteTo(d64, hn::UpperHalf(dh, index))));
  low = hn::BitCast(d, hn::ConcatEven(du, upper, lower));
  high = hn::BitCast(d, hn::ConcatOdd(du, upper, lower));
}

// Whether every lane of v holds lane 0's value, which goes to `first` (a vector of pixels that share one table row).
inline bool same_in_every_lane(VI v, int32_t& first) {
  const DI di;
  first = hn::GetLane(v);
  return hn::AllTrue(di, hn::Eq(v, hn::Set(di, first)));
}

// albedo_at's eight corner values (rows k and k + 1 at columns j and j + 1, a and b of each) into
// corner[2 p] (column j) and corner[2 p + 1] (column j + 1) of plane p: row k's a, row k's b, row k + 1's a, row
// k + 1's b. Where every lane reads one row (one roughness across the vector, as along a tile row of one material)
// on a 16-lane target, that row's four planes (kGgxAlbedoRowPlanes, 32 floats each) are loaded and each corner is
// an in-register lookup by j: 8 loads and 16 permutes instead of 8 gathers of 8 elements. Elsewhere the corners are
// gathered (also where the lanes read two or three rows: a pass per row and the blends cost more than the gathers,
// measured). Either way each lane gets the table's values.
inline void albedo_corners(D d, VI row, VI j, V corner[8]) {
  const DI di;
  if constexpr (hn::MaxLanes(D()) == 16 && kGgxAlbedoMuCount == 32) {
    int32_t offset;
    if (same_in_every_lane(row, offset)) {
      // Entry c (0-31) of a plane: lane c & 15 of its first or its second half.
      const VI j1 = hn::Add(j, hn::Set(di, 1)), fifteen = hn::Set(di, 15), sixteen = hn::Set(di, 16);
      const auto i0 = hn::IndicesFromVec(d, hn::And(j, fifteen)), i1 = hn::IndicesFromVec(d, hn::And(j1, fifteen));
      const M low0 = hn::RebindMask(d, hn::Lt(j, sixteen)), low1 = hn::RebindMask(d, hn::Lt(j1, sixteen));
      for (int p = 0; p < 4; ++p) {
        const float* plane = kGgxAlbedoRowPlanes + offset + p * kGgxAlbedoMuCount;
        const V first = hn::Load(d, plane), second = hn::Load(d, plane + 16);
        corner[2 * p] = hn::IfThenElse(low0, hn::TableLookupLanes(first, i0), hn::TableLookupLanes(second, i0));
        corner[2 * p + 1] = hn::IfThenElse(low1, hn::TableLookupLanes(first, i1), hn::TableLookupLanes(second, i1));
      }
      return;
    }
  }
  const VI p0 = hn::Add(hn::ShiftRight<1>(row), j), p1 = hn::Add(p0, hn::Set(di, kGgxAlbedoMuCount));
  const VI one = hn::Set(di, 1);
  gather_pairs(d, kGgxAlbedoEntryPairs, p0, corner[0], corner[2]);
  gather_pairs(d, kGgxAlbedoEntryPairs, hn::Add(p0, one), corner[1], corner[3]);
  gather_pairs(d, kGgxAlbedoEntryPairs, p1, corner[4], corner[6]);
  gather_pairs(d, kGgxAlbedoEntryPairs, hn::Add(p1, one), corner[5], corner[7]);
}

// GgxAlbedoRow::at: the (a, b) albedo pair at cos_theta, bilinear in sqrt(mu) and roughness, from the
// row offset (in floats of kGgxAlbedoEntries) and weight of the receiver's roughness.
inline void albedo_at(D d, V cos_theta, VI row, V weight, V& a, V& b) {
  const DI di;
  const V x = hn::Mul(hn::Sqrt(min_of(max_of(cos_theta, hn::Zero(d)), hn::Set(d, 1.0f))),
                      hn::Set(d, float(kGgxAlbedoMuCount - 1)));
  // Clamped below too: a NaN cosine (a lane nobody reads) converts to INT_MIN, which must stay a valid index.
  const VI j = hn::Max(hn::Min(hn::ConvertTo(di, x), hn::Set(di, kGgxAlbedoMuCount - 2)), hn::Zero(di));
  const V s = hn::Sub(x, hn::ConvertTo(d, j));
  // The four pairs around (row, j).
  V corner[8];
  albedo_corners(d, row, j, corner);
  const V a00 = corner[0], a01 = corner[1], b00 = corner[2], b01 = corner[3];
  const V a10 = corner[4], a11 = corner[5], b10 = corner[6], b11 = corner[7];
  const V a0 = hn::Add(a00, hn::Mul(s, hn::Sub(a01, a00))), b0 = hn::Add(b00, hn::Mul(s, hn::Sub(b01, b00)));
  const V a1 = hn::Add(a10, hn::Mul(s, hn::Sub(a11, a10))), b1 = hn::Add(b10, hn::Mul(s, hn::Sub(b11, b10)));
  a = hn::Add(a0, hn::Mul(weight, hn::Sub(a1, a0)));
  b = hn::Add(b0, hn::Mul(weight, hn::Sub(b1, b0)));
}

}  // namespace HWY_NAMESPACE
}  // namespace candela
HWY_AFTER_NAMESPACE();

#endif  // include guard

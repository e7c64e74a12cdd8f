// The neighbour kernel (neighbour_lanes.h), compiled once per instruction set by Highway's foreach_target.h
// and dispatched at run time. It repeats reuse.h's similar_surfaces with engine/octahedral.h's oct_decode.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "restir/neighbour_lanes.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/highway.h"
#include "engine/lanes-inl.h"
#include "restir/neighbour_lanes.h"

HWY_BEFORE_NAMESPACE();
namespace candela {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

void SimilarNeighbourLanes(NeighbourLanes& l, int count, int slots, float depth_tolerance, float normal_tolerance) {
  const D d;
  const DU du;
  const V no_surface = hn::Set(d, kInfinity), depth_tol = hn::Set(d, depth_tolerance);
  const V normal_tol = hn::Set(d, normal_tolerance);
  for (int s = 0; s < slots; s += int(hn::Lanes(d))) {
    const V depth = hn::Load(d, l.depth + s);
    const V3 n = oct_decode(d, hn::Load(du, l.normal + s));
    const V max_difference = hn::Mul(depth_tol, depth);
    for (int k = 0; k < count; ++k) {
      // similar_surfaces: a surface, close in depth (not more than the tolerance apart, NaN passing as in the scalar
      // test), then the normals' cosine.
      const V other = hn::Load(d, l.neighbour_depth[k] + s);
      const M close = hn::AndNot(hn::Gt(hn::Abs(hn::Sub(depth, other)), max_difference), hn::Lt(other, no_surface));
      const M facing = hn::Ge(dot(n, oct_decode(d, hn::Load(du, l.neighbour_normal[k] + s))), normal_tol);
      hn::Store(hn::VecFromMask(du, hn::RebindMask(du, hn::And(close, facing))), du, l.similar[k] + s);
    }
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace candela
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace candela {

HWY_EXPORT(SimilarNeighbourLanes);

void similar_neighbour_lanes(NeighbourLanes& lanes, int count, int slots, float depth_tolerance,
                             float normal_tolerance) {
  HWY_DYNAMIC_DISPATCH(SimilarNeighbourLanes)(lanes, count, slots, depth_tolerance, normal_tolerance);
}

}  // namespace candela
#endif  // HWY_ONCE

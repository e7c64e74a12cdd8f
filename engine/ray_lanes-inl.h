// Tracer::spawn_ray_to's arithmetic in SIMD lanes (its bits), shared by the kernels that build shadow rays
// (restir/target_lanes.cpp, engine/path_lanes.cpp) and kept apart from engine/lanes-inl.h so that the other kernels
// do not include the tracer. Included once per instruction set by each kernel's foreach_target.h pass, hence the
// toggling include guard (Highway's "-inl.h" convention).
#if defined(CANDELA_ENGINE_RAY_LANES_INL_H_) == defined(HWY_TARGET_TOGGLE)
#ifdef CANDELA_ENGINE_RAY_LANES_INL_H_
#undef CANDELA_ENGINE_RAY_LANES_INL_H_
#else
#define CANDELA_ENGINE_RAY_LANES_INL_H_
#endif

#include "engine/lanes-inl.h"
#include "engine/ray_lanes.h"
#include "hwy/highway.h"

HWY_BEFORE_NAMESPACE();
namespace candela {
namespace HWY_NAMESPACE {

// Tracer::offset_point: p moved along n (flipped to the side `towards` points to) by epsilon + 4e-6 max_component(|p|).
inline V3 offset_point(D d, const V3& p, const V3& n, const V3& towards, V epsilon) {
  const V magnitude = max_of3(hn::Abs(p.x), hn::Abs(p.y), hn::Abs(p.z));
  const V eps = hn::Add(epsilon, hn::Mul(hn::Set(d, 4e-6f), magnitude));
  const M front = hn::Ge(dot(n, towards), hn::Zero(d));
  auto side = [&](V c) { return hn::Mul(hn::IfThenElse(front, c, hn::Neg(c)), eps); };
  return {hn::Add(p.x, side(n.x)), hn::Add(p.y, side(n.y)), hn::Add(p.z, side(n.z))};
}

// Tracer::spawn_ray_to from p (geometric normal ng) to q (normal nq), into slots [s, s + lanes) of `out`: both ends
// offset (epsilon: Tracer::offset_epsilon()), then the direction and a tmax short of the far end.
inline void spawn_ray_to(D d, const V3& p, const V3& ng, const V3& q, const V3& nq, V epsilon, RayLanes& out, int s) {
  const V3 o = offset_point(d, p, ng, {hn::Sub(q.x, p.x), hn::Sub(q.y, p.y), hn::Sub(q.z, p.z)}, epsilon);
  const V3 e = offset_point(d, q, nq, {hn::Sub(o.x, q.x), hn::Sub(o.y, q.y), hn::Sub(o.z, q.z)}, epsilon);
  const V3 delta{hn::Sub(e.x, o.x), hn::Sub(e.y, o.y), hn::Sub(e.z, o.z)};
  const V len = hn::Sqrt(dot(delta, delta));
  const V den = max_of(len, hn::Set(d, 1e-30f));
  store3(d, o, out.ox, out.oy, out.oz, s);
  store3(d, {hn::Div(delta.x, den), hn::Div(delta.y, den), hn::Div(delta.z, den)}, out.dx, out.dy, out.dz, s);
  hn::Store(hn::Mul(len, hn::Set(d, 1.0f - 1e-4f)), d, out.tmax + s);
}

}  // namespace HWY_NAMESPACE
}  // namespace candela
HWY_AFTER_NAMESPACE();

#endif  // CANDELA_ENGINE_RAY_LANES_INL_H_

// The path vertices' kernels (path_lanes.h), compiled once per instruction set by Highway's foreach_target.h and
// dispatched at run time. Each step names the scalar function whose arithmetic it repeats, in the same order
// (engine/lights.cpp LightList::sample and triangle_point, engine/lights.h light_sample_towards, engine/path_tracer.h
// place_light_sample, weigh_light_sample, power_heuristic and continue_path, engine/tracer.h Tracer::spawn_ray_to and
// spawn_ray, through engine/ray_lanes-inl.h). Where the scalar code rejects on `x <= 0` the kernels test Not(Le) (a
// NaN passes such a test, as it does there).
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "engine/path_lanes.cpp"
#include "hwy/foreach_target.h"  // IWYU pragma: keep
#include "hwy/highway.h"
#include "engine/lanes-inl.h"
#include "engine/path_lanes.h"
#include "engine/ray_lanes-inl.h"

HWY_BEFORE_NAMESPACE();
namespace candela {
namespace HWY_NAMESPACE {

void SampleTriangleLightsLanes(const VertexLanes& v, NeeLanes& nee, int slots, DirectionLanes& light) {
  const D d;
  const V zero = hn::Zero(d), one = hn::Set(d, 1.0f);
  for (int s = 0; s < slots; s += int(hn::Lanes(d))) {
    const M active = hn::Gt(hn::Load(d, nee.active + s), zero);
    // triangle_point: a uniform point on the triangle, p0 + e1 b.x + e2 b.y.
    const V ux = hn::Load(d, nee.u[0] + s), uy = hn::Load(d, nee.u[1] + s);
    const V su = hn::Sqrt(ux), bx = hn::Mul(su, hn::Sub(one, uy)), by = hn::Mul(su, uy);
    V q[3];
    for (int c = 0; c < 3; ++c)
      q[c] = hn::Add(hn::Add(hn::Load(d, nee.corner[c] + s), hn::Mul(hn::Load(d, nee.edge1[c] + s), bx)),
                     hn::Mul(hn::Load(d, nee.edge2[c] + s), by));
    // light_sample_towards: the direction and distance from the vertex, the cosine at the light and its sidedness.
    const V3 p = load3(d, v.px, v.py, v.pz, s);
    const V3 delta{hn::Sub(q[0], p.x), hn::Sub(q[1], p.y), hn::Sub(q[2], p.z)};
    const V dist2 = dot(delta, delta), dist = hn::Sqrt(dist2);
    const V3 wi{hn::Div(delta.x, dist), hn::Div(delta.y, dist), hn::Div(delta.z, dist)};
    const V cos_l = dot(load3(d, nee.nx, nee.ny, nee.nz, s), wi), abs_cos = hn::Abs(cos_l);
    const V emitted[3] = {hn::Load(d, nee.emitted[0] + s), hn::Load(d, nee.emitted[1] + s),
                          hn::Load(d, nee.emitted[2] + s)};
    const V area = hn::Load(d, nee.area + s);
    M has = hn::And(hn::Not(hn::Le(dist2, zero)), hn::Not(hn::Le(abs_cos, hn::Set(d, 1e-7f))));
    has = hn::And(has, hn::Or(hn::Gt(hn::Load(d, nee.two_sided + s), zero), hn::Lt(cos_l, zero)));
    // LightList::sample: the density where the sample carries radiance, dist^2 / (|cos_l| area).
    has = hn::And(has, hn::And(hn::Gt(max_of3(emitted[0], emitted[1], emitted[2]), zero), hn::Gt(area, zero)));
    const V pdf = hn::Div(hn::Mul(dist, dist), hn::Mul(abs_cos, area));
    // place_light_sample: a positive density, and the light above the vertex's geometric surface.
    M valid = hn::And(active, hn::And(has, hn::Not(hn::Le(pdf, zero))));
    valid = hn::And(valid, hn::Gt(dot(wi, load3(d, v.gx, v.gy, v.gz, s)), zero));
    store3(d, {q[0], q[1], q[2]}, nee.qx, nee.qy, nee.qz, s);
    hn::Store(pdf, d, nee.pdf + s);
    auto keep = [&](const V& value, float* plane) {
      hn::Store(hn::IfThenElse(active, value, hn::Load(d, plane + s)), d, plane + s);
    };
    keep(wi.x, light.x), keep(wi.y, light.y), keep(wi.z, light.z);
    keep(hn::IfThenElseZero(valid, one), light.active);
  }
}

void WeighLightSamplesLanes(const VertexLanes& v, const DirectionLanes& light, float epsilon, int slots,
                            NeeLanes& nee) {
  const D d;
  const V zero = hn::Zero(d), eps = hn::Set(d, epsilon);
  for (int s = 0; s < slots; s += int(hn::Lanes(d))) {
    const V f[3] = {hn::Load(d, light.f[0] + s), hn::Load(d, light.f[1] + s), hn::Load(d, light.f[2] + s)};
    const M pending =
        hn::And(hn::And(hn::Gt(hn::Load(d, nee.active + s), zero), hn::Gt(hn::Load(d, light.active + s), zero)),
                hn::Not(hn::Le(max_of3(f[0], f[1], f[2]), zero)));
    hn::Store(hn::IfThenElseZero(pending, hn::Set(d, 1.0f)), d, nee.pending + s);
    // weigh_light_sample: the power heuristic between the light's density and the BSDF's, then the contribution.
    const V p_light = hn::Mul(hn::Load(d, nee.pmf + s), hn::Load(d, nee.pdf + s));
    const V bsdf_pdf = hn::Load(d, light.pdf + s);
    const V a2 = hn::Mul(p_light, p_light), sum = hn::Add(a2, hn::Mul(bsdf_pdf, bsdf_pdf));
    const V weight = hn::IfThenElseZero(hn::Gt(sum, zero), hn::Div(a2, sum));
    const V scale = hn::Div(weight, p_light);
    for (int c = 0; c < 3; ++c)
      hn::Store(hn::Mul(hn::Mul(f[c], hn::Load(d, nee.emitted[c] + s)), scale), d, nee.contribution[c] + s);
    // shadow_ray: Tracer::spawn_ray_to from the vertex to the point on the light.
    spawn_ray_to(d, load3(d, v.px, v.py, v.pz, s), load3(d, v.gx, v.gy, v.gz, s), load3(d, nee.qx, nee.qy, nee.qz, s),
                 load3(d, nee.nx, nee.ny, nee.nz, s), eps, nee.shadow, s);
  }
}

void ContinuePathsLanes(const VertexLanes& v, const float* nx, const float* ny, const float* nz,
                        const DirectionLanes& next, float epsilon, int slots, ContinueLanes& out) {
  const D d;
  const V zero = hn::Zero(d), eps = hn::Set(d, epsilon);
  for (int s = 0; s < slots; s += int(hn::Lanes(d))) {
    // continue_path: a sampled direction (positive density) above the geometric surface goes on.
    const V3 wi = load3(d, next.x, next.y, next.z, s), ng = load3(d, v.gx, v.gy, v.gz, s);
    const V pdf = hn::Load(d, next.pdf + s);
    const M drawn = hn::And(hn::Gt(hn::Load(d, next.active + s), zero), hn::Gt(pdf, zero));
    const M go = hn::And(drawn, hn::Not(hn::Le(dot(wi, ng), zero)));
    hn::Store(hn::IfThenElseZero(go, hn::Set(d, 1.0f)), d, out.go + s);
    // The throughput's factor, f (|cos| / pdf) at the shading normal.
    const V scale = hn::Div(hn::Abs(dot(wi, load3(d, nx, ny, nz, s))), pdf);
    for (int c = 0; c < 3; ++c) hn::Store(hn::Mul(hn::Load(d, next.f[c] + s), scale), d, out.factor[c] + s);
    // Tracer::spawn_ray: the origin offset to the side the direction leaves on.
    store3(d, offset_point(d, load3(d, v.px, v.py, v.pz, s), ng, wi, eps), out.ox, out.oy, out.oz, s);
  }
}

}  // namespace HWY_NAMESPACE
}  // namespace candela
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace candela {

HWY_EXPORT(SampleTriangleLightsLanes);
HWY_EXPORT(WeighLightSamplesLanes);
HWY_EXPORT(ContinuePathsLanes);

static_assert(kLaneSlots % 16 == 0, "a batch is a whole number of the widest vectors");

void sample_triangle_lights_lanes(const VertexLanes& v, NeeLanes& nee, int slots, DirectionLanes& light) {
  HWY_DYNAMIC_DISPATCH(SampleTriangleLightsLanes)(v, nee, slots, light);
}

void weigh_light_samples_lanes(const VertexLanes& v, const DirectionLanes& light, float epsilon, int slots,
                               NeeLanes& nee) {
  HWY_DYNAMIC_DISPATCH(WeighLightSamplesLanes)(v, light, epsilon, slots, nee);
}

void continue_paths_lanes(const VertexLanes& v, const float* nx, const float* ny, const float* nz,
                          const DirectionLanes& next, float epsilon, int slots, ContinueLanes& out) {
  HWY_DYNAMIC_DISPATCH(ContinuePathsLanes)(v, nx, ny, nz, next, epsilon, slots, out);
}

}  // namespace candela
#endif  // HWY_ONCE

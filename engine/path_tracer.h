#pragma once
// Reference path tracer: unidirectional, next-event estimation combined with BSDF sampling by multiple
// importance sampling (Veach 1997, power heuristic, beta = 2), Russian roulette after three bounces.
// It is the ground truth of every convergence test, so it favours clarity over speed.
// The light-selection policy is a template parameter (engine/light_sampler.h).
#include <limits>
#include <optional>

#include "engine/camera.h"
#include "engine/frame_stats.h"
#include "engine/image.h"
#include "engine/light_sampler.h"
#include "engine/lights.h"
#include "engine/rng.h"
#include "engine/sobol.h"
#include "engine/surface.h"
#include "engine/tiles.h"

namespace candela {

struct PathTracerParams {
  int spp = 1;             // paths per pixel per call
  int first_sample = 0;    // index of the first of them (progressive passes continue the sequence)
  int max_depth = 8;       // bounces; 1 = direct light only (emission seen + one reflection)
  int rr_start_depth = 3;  // Russian roulette from this bounce on (keeps deep paths unbiased)
  uint64_t seed = 0;
  bool jitter = true;  // false: every path starts through its pixel's centre (no anti-aliasing)
  SampleSequence sequence = SampleSequence::Independent;
  uint64_t epoch = 0;    // Sobol, ZSobol: the scrambles' key besides the seed (and, for Sobol, the pixel)
  int log2_samples = 0;  // ZSobol: the frame's samples per pixel, 2^this (later ones start a new sequence)
};

// Everything a frame's estimators read about the scene, fixed for the frame.
struct SceneView {
  const Scene& scene;
  const Tracer& tracer;
  const LightList& lights;
  const Camera& camera;
};

inline float power_heuristic(float a, float b) {
  float a2 = a * a, b2 = b * b;
  return a2 + b2 > 0.0f ? a2 / (a2 + b2) : 0.0f;
}

// Next-event estimation at one surface point, its draw: picks a light with the sampler and samples a point
// on it (4 random numbers, always drawn). False when the sample cannot contribute whatever the BSDF: no light,
// zero density or radiance, or below the geometric surface. `pmf` is the light's selection probability.
// In two steps, so that a caller with many points can choose every light first and overlap the cache misses of
// their records (bounce_paths): draw_light_choice (the light, and the point's uniforms), then place_light_sample.
struct LightChoice {
  SampledLight chosen;
  vec2 u;  // the point's uniforms
};
template <LightSampler S, class Stream>
LightChoice draw_light_choice(const S& sampler, const ShadingContext& ctx, const vec2& u_choice, Stream& rng) {
  const SampledLight chosen = sampler.sample(ctx, u_choice);
  return {chosen, rng.next_2d()};
}
inline bool place_light_sample(const SceneView& view, const SurfacePoint& sp, const LightChoice& choice, float& pmf,
                               LightSample& ls) {
  if (choice.chosen.pmf <= 0.0f) return false;
  pmf = choice.chosen.pmf;
  ls = view.lights.sample(view.scene, choice.chosen.index, sp.position, choice.u);
  if (ls.pdf <= 0.0f || max_component(ls.radiance) <= 0.0f) return false;
  return glm::dot(ls.wi, sp.geometric_normal) > 0.0f;
}
template <LightSampler S, class Stream>
bool draw_light_sample(const SceneView& view, const S& sampler, const SurfacePoint& sp, Stream& rng, float& pmf,
                       LightSample& ls) {
  const vec2 u_choice = rng.next_2d();
  return place_light_sample(view, sp, draw_light_choice(sampler, {sp.position, sp.shading_normal}, u_choice, rng), pmf,
                            ls);
}

// Next-event estimation's end up to its shadow ray, for a drawn light sample: with f = the BSDF times |cos| at
// the shading normal towards ls.wi and bsdf_pdf the BSDF's density there, writes the shadow ray and the
// contribution weighted by the power heuristic (without the path throughput) that counts if the ray is not
// occluded. False when there is nothing to trace.
inline bool weigh_light_sample(const Tracer& tracer, const SurfacePoint& sp, const LightSample& ls, float pmf,
                               const vec3& f, float bsdf_pdf, Ray& shadow, vec3& contribution) {
  if (max_component(f) <= 0.0f) return false;
  float p_light = pmf * ls.pdf;
  float weight = ls.is_delta ? 1.0f : power_heuristic(p_light, bsdf_pdf);
  shadow = shadow_ray(tracer, sp.position, sp.geometric_normal, ls);
  contribution = f * ls.radiance * (weight / p_light);
  return true;
}

// Where a path (or the rest of one) starts: the ray leaving its last vertex, that vertex's bounce count
// (0: the camera), the BSDF density and shading context that sampled the ray (for MIS against NEE when it
// hits an emitter), and whether emission at its first hit counts (ReSTIR GI leaves it to ReSTIR DI).
struct PathStart {
  Ray ray;
  int depth = 0;
  float bsdf_pdf = 0.0f;
  ShadingContext from;
  bool first_emission = true;
};

// A path between two bounces: the ray to trace next, the radiance gathered and the throughput, what MIS
// needs of the vertex that sampled the ray, and that vertex's next-event estimate while its shadow ray is
// not traced yet (`light_pending`; `light` holds the contribution times the throughput).
struct PathState {
  PathState() = default;  // a path that start() sets off
  explicit PathState(const PathStart& s) { start(s.ray, s.depth, s.bsdf_pdf, s.from, s.first_emission); }
  // Sets the path off from PathStart's fields, copied member by member. Where a vector of paths grows,
  // emplace_back() and start() fill the new path in place: a PathStart handed to emplace_back, or a ray or context
  // copied whole, was assembled on the stack and read back with wide loads of its narrower stores, which stalled on
  // store forwarding (gi_first_rays).
  void start(const Ray& r, int start_depth, float bsdf_pdf, const ShadingContext& from, bool first_emission) {
    // Every member of Ray and ShadingContext is copied below: one added to either must be added here.
    static_assert(sizeof(Ray) == 2 * sizeof(vec3) + 2 * sizeof(float), "start() copies Ray's members one by one");
    static_assert(sizeof(ShadingContext) == 2 * sizeof(vec3) + sizeof(float),
                  "start() copies ShadingContext's members one by one");
    ray.origin = r.origin, ray.direction = r.direction, ray.tmin = r.tmin, ray.tmax = r.tmax;
    prev_ctx.position = from.position, prev_ctx.normal = from.normal, prev_ctx.radius = from.radius;
    prev_bsdf_pdf = bsdf_pdf, depth = start_depth, emission_counts = first_emission;
  }
  Ray ray;
  vec3 L{0.0f}, beta{1.0f};
  float prev_bsdf_pdf = 0.0f;
  ShadingContext prev_ctx;
  int depth = 0;                // bounce of the vertex `ray` reaches, counted from the camera
  bool emission_counts = true;  // whether emission at that vertex counts (false only at a start that says so)
  bool first = true;            // `ray` is the start's ray
  bool alive = true;            // `ray` is still to be traced
  bool overflowed = false;
  bool light_pending = false;
  Ray shadow{vec3(0.0f), vec3(0.0f)};  // initialised: trace_paths reads it whether or not light is pending
  vec3 light{0.0f};
  // The path's radiance once it has ended: NaN when its throughput overflowed.
  vec3 radiance() const { return overflowed ? vec3(std::numeric_limits<float>::quiet_NaN()) : L; }
};

// A bounce's first step, for a path whose ray has been traced to `hit`: ends the path (alive = false) on a
// miss with the environment's light, else takes the hit's surface (`surface` if given, computed by the
// caller, else surface_at into `scratch`) and gives it to `first_hit` (for the start's ray), and adds the
// emission the ray reached (weighted by the power heuristic against NEE's chance of the same point). Returns
// the surface when the vertex scatters (below max_depth: path_bounce's next steps follow), else null.
template <LightSampler S>
const SurfacePoint* arrive_at_vertex(const SceneView& view, const S& sampler, const PathTracerParams& params,
                                     PathState& st, const Hit& hit, std::optional<SurfacePoint>* first_hit,
                                     const SurfacePoint* surface, SurfacePoint& scratch) {
  st.alive = false;
  st.light_pending = false;
  if (!hit.valid()) {
    st.L += st.beta * view.lights.environment();  // the environment is reached by BSDF sampling only
    return nullptr;
  }
  if (!surface) {
    scratch = surface_at(view.scene, hit.instance, hit.prim, hit.barycentric, -st.ray.direction);
    surface = &scratch;
  }
  const SurfacePoint& sp = *surface;
  const bool first = st.first;
  st.first = false;
  if (first && first_hit) *first_hit = sp;
  // Emission reached by a BSDF ray, weighted against the chance NEE would have sampled the same point.
  if (max_component(sp.emission) > 0.0f && (!first || st.emission_counts)) {
    float weight = 1.0f;
    int64_t light = st.depth == 0 ? -1 : view.lights.light_index(hit.instance, hit.prim);
    if (light >= 0) {
      float p_light = sampler.pmf(st.prev_ctx, uint32_t(light)) *
                      view.lights.pdf_solid_angle(size_t(light), st.prev_ctx.position, sp.position);
      weight = power_heuristic(st.prev_bsdf_pdf, p_light);
    }
    st.L += st.beta * sp.emission * weight;
  }
  return st.depth < params.max_depth ? surface : nullptr;
}

// The end of a bounce whose next ray is set (continue_path): Russian roulette (one random number, from
// rr_start_depth on), then the path goes on unless its throughput overflowed.
template <class Stream>
void survive_bounce(const PathTracerParams& params, PathState& st, Stream& rng) {
  if (st.depth + 1 >= params.rr_start_depth) {
    float survive = std::min(0.95f, max_component(st.beta));
    if (rng.next_float() >= survive) return;
    st.beta /= survive;
  }
  // A throughput that overflowed makes the whole path invalid: NaN, which the caller drops and counts.
  if (!is_finite(st.beta)) {
    st.overflowed = true;
    return;
  }
  ++st.depth;
  st.alive = true;
}

// A bounce's last step: the path goes on along the BSDF sample bs drawn at vertex sp (one that sampling
// accepted: pdf > 0) if it leaves above the geometric surface, with Russian roulette, or ends.
// engine/path_lanes.h continue_paths_lanes computes the geometry for many vertices in lanes.
template <class Stream>
void continue_path(const Tracer& tracer, const PathTracerParams& params, PathState& st, const SurfacePoint& sp,
                   const BsdfSample& bs, Stream& rng) {
  if (glm::dot(bs.wi, sp.geometric_normal) <= 0.0f) return;
  st.beta *= bs.f * (std::abs(glm::dot(bs.wi, sp.shading_normal)) / bs.pdf);
  st.prev_bsdf_pdf = bs.pdf;
  st.prev_ctx = ShadingContext{sp.position, sp.shading_normal};
  st.ray = tracer.spawn_ray(sp.position, sp.geometric_normal, bs.wi);
  survive_bounce(params, st, rng);
}

// One bounce of a path whose ray has been traced to `hit`: arrive_at_vertex, then the vertex's next-event
// estimate (its shadow ray left pending) and the next ray drawn from the BSDF (continue_path), or the path's
// end. `first_hit` and `surface` as arrive_at_vertex takes them. Reads the scene, light list and sampler;
// draws up to 8 random numbers (4 for the light sample, 3 for the BSDF sample, 1 for roulette).
// engine/path_batch.h runs the same steps for many paths with the BSDF, next-event and continuation work in lanes.
template <LightSampler S, class Stream>
void path_bounce(const SceneView& view, const S& sampler, const PathTracerParams& params, PathState& st, const Hit& hit,
                 Stream& rng, std::optional<SurfacePoint>* first_hit, const SurfacePoint* surface = nullptr) {
  SurfacePoint scratch;
  const SurfacePoint* vertex = arrive_at_vertex(view, sampler, params, st, hit, first_hit, surface, scratch);
  if (!vertex) return;
  const SurfacePoint& sp = *vertex;
  const vec3 wo = -st.ray.direction;
  Bsdf bsdf = sp.bsdf();
  const BsdfWoTerms terms = bsdf.wo_terms(wo);  // shared by the light sample's and the BSDF sample's evaluations
  float pmf;
  LightSample ls;
  if (draw_light_sample(view, sampler, sp, rng, pmf, ls)) {
    vec3 contribution;
    const vec3 f = bsdf.eval(terms, wo, ls.wi) * std::abs(glm::dot(ls.wi, sp.shading_normal));
    st.light_pending =
        weigh_light_sample(view.tracer, sp, ls, pmf, f, bsdf.pdf(terms, wo, ls.wi), st.shadow, contribution);
    if (st.light_pending) st.light = st.beta * contribution;
  }
  // Continue the path by sampling the BSDF.
  BsdfSample bs;
  vec2 u = rng.next_2d();
  if (!bsdf.sample(terms, wo, u, rng.next_float(), bs)) return;
  continue_path(view.tracer, params, st, sp, bs, rng);
}

// The answer of a pending next-event estimate's shadow ray.
inline void finish_direct_light(PathState& st, bool occluded) {
  if (!occluded) st.L += st.light;
  st.light_pending = false;
}

// Radiance arriving along start.ray: NEE with the light sampler and BSDF sampling combined by the power
// heuristic, Russian roulette, at most params.max_depth bounces counted from the camera; NaN when the
// path's throughput overflowed (callers drop and count non-finite results). `first_hit`, if given,
// receives the surface the ray hits first (stays empty on a miss). One ray at a time (engine/path_batch.h
// traces many paths in packets with the same results).
template <LightSampler S, class Stream>
vec3 trace_path(const SceneView& view, const S& sampler, const PathTracerParams& params, const PathStart& start,
                Stream& rng, uint64_t& rays, std::optional<SurfacePoint>* first_hit = nullptr) {
  PathState st(start);
  while (st.alive) {
    Hit hit = view.tracer.intersect(st.ray);
    ++rays;
    path_bounce(view, sampler, params, st, hit, rng, first_hit);
    if (st.light_pending) {
      ++rays;
      finish_direct_light(st, view.tracer.occluded(st.shadow));
    }
  }
  return st.radiance();
}

}  // namespace candela

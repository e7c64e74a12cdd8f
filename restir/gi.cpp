#include "restir/gi.h"

#include "restir/receiver_lanes.h"

namespace candela {

void gi_first_rays(const SceneView& view, const GBuffer& g, const ReuseDomain& domain, const GiParams& params,
                   int frame, int x0, int x1, int y, const std::vector<BsdfRay>* shared,
                   std::vector<ReuseReservoir>& out, std::vector<GiStart>& starts, std::vector<PathState>& paths,
                   std::vector<Rng>& rngs, std::vector<Hit>& hits) {
  struct Row {
    ExactSurfaceLanes surfaces;
    ReceiverLanes receivers;
    BsdfUniformLanes uniforms;
    DirectionLanes directions;
    RngRow<kLaneSlots> streams;
    alignas(64) float numbers[6 * kLaneSlots];
    vec2 tag[kLaneSlots];
    float u[kLaneSlots];
  };
  thread_local Row row;
  const int slots = x1 - x0;
  const size_t first = size_t(y) * size_t(g.width) + size_t(x0);
  // Per hit pixel: the uniforms of its first direction, drawn from its BSDF (the random numbers in the order the
  // scalar code drew them: the direction's two, the tag's two, the lobe's and the reservoir's uniform), every
  // slot's stream keyed and drawn in lanes (number n of slot s at numbers[n * kLaneSlots + s]).
  row.streams.key(slots, params.seed, first, uint64_t(frame), 0x61);
  row.streams.fill(6, slots, row.numbers);
  for (int s = 0; s < slots; ++s) {
    const size_t i = first + size_t(s);
    out[i] = ReuseReservoir{};
    row.directions.active[s] = 0.0f;
    if (!g.hit(i)) continue;
    // One attempt, M = 1, whatever comes of it: a ray that escapes or a path that brings no light is a
    // sample of zero contribution, and counting it keeps the reuse MIS weights consistent (with M = 0
    // there, the neighbours' samples were weighted as if this pixel could not have drawn theirs: +11%
    // indirect light with one neighbour, measured).
    out[i].M = 1.0f;
    // Each pair y before x, as the scalar vec2(rng.next_float(), rng.next_float()) took them (GCC evaluates a
    // constructor's arguments right to left), so that images stay those of earlier versions.
    auto number = [&](int n) { return row.numbers[n * kLaneSlots + s]; };
    row.tag[s] = vec2(number(3), number(2)), row.u[s] = number(5);
    row.uniforms.u[0][s] = number(1), row.uniforms.u[1][s] = number(0), row.uniforms.lobe[s] = number(4);
    row.directions.active[s] = 1.0f;
  }
  // The directions and their densities: ReSTIR DI's (`shared`; the direction's and lobe's numbers above go unused, so
  // that the tag, the reservoir's uniform and the path's stream stay those of GI's own draw), or Bsdf::sample's at
  // the exact receivers (wo, the BSDFs' terms), in lanes. Then the paths of the directions accepted that leave the
  // geometric surface.
  if (shared) {
    for (int s = 0; s < slots; ++s) {
      const BsdfRay& ray = (*shared)[first + size_t(s)];
      row.directions.x[s] = ray.wi.x, row.directions.y[s] = ray.wi.y, row.directions.z[s] = ray.wi.z;
      row.directions.pdf[s] = ray.pdf;
    }
  } else {
    row.surfaces.set_row(g, first, slots);
    build_exact_receivers(row.surfaces, domain.eye, slots, row.receivers);
    const BsdfLanes& bsdf = row.receivers.exact;
    sample_bsdf_lanes(bsdf, row.receivers.wox, row.receivers.woy, row.receivers.woz, row.uniforms, slots,
                      row.directions);
    evaluate_bsdf_lanes(bsdf, row.receivers.wox, row.receivers.woy, row.receivers.woz, slots, false, row.directions);
  }
  for (int s = 0; s < slots; ++s) {
    const size_t i = first + size_t(s);
    const float pdf = row.directions.pdf[s];
    if (row.directions.active[s] == 0.0f || !(pdf > 0.0f)) continue;
    const vec3 wi(row.directions.x[s], row.directions.y[s], row.directions.z[s]);
    if (glm::dot(wi, g.geometric_normal[i]) <= 0.0f) continue;
    // Each appended in place, from its parts (PathState::start says why).
    starts.emplace_back(i, g.position[i], pdf, row.tag[s], row.u[s]);
    paths.emplace_back().start(view.tracer.spawn_ray(g.position[i], g.geometric_normal[i], wi), 1, pdf,
                               ShadingContext{g.position[i], g.shading_normal[i]}, false);
    rngs.push_back(row.streams.stream(s));
    if (shared) hits.push_back((*shared)[i].hit);
  }
}

void gi_sample_reservoirs(const ReuseDomain& domain, const std::vector<GiStart>& starts,
                          const std::vector<PathState>& paths, const std::vector<std::optional<SurfacePoint>>& x_s,
                          std::vector<ReuseReservoir>& out, Counter& non_finite) {
  struct Group {
    SurfaceLanes surfaces;
    ReceiverLanes receivers;
    CandidateLanes samples;
    float p_area[kLaneSlots];
  };
  thread_local Group group;
  for (size_t first = 0; first < paths.size(); first += kLaneSlots) {
    const int count = int(std::min<size_t>(kLaneSlots, paths.size() - first));
    // Per path: its sample point x_s with the path's radiance, and the area density of x_s.
    for (int s = 0; s < count; ++s) {
      const size_t k = first + size_t(s);
      const GiStart& start = starts[k];
      const vec3 L = paths[k].radiance();
      if (!is_finite(L)) non_finite.add(1);
      group.samples.clear(s);
      group.surfaces.set(s, domain.surfaces[start.pixel]);
      if (!x_s[k] || !is_finite(L) || max_component(L) <= 0.0f) continue;
      const vec3 d = x_s[k]->position - start.position;
      const float d2 = glm::dot(d, d), cos_s = std::abs(glm::dot(x_s[k]->geometric_normal, d)) / std::sqrt(d2);
      group.p_area[s] = start.pdf * cos_s / d2;
      group.samples.set(s, LightPoint{x_s[k]->position, x_s[k]->geometric_normal, L, false});
    }
    // The targets at the pixels' packed receivers, in lanes; then each reservoir.
    build_receiver_lanes(group.surfaces, domain.eye, count, group.receivers);
    evaluate_candidate_lanes(group.receivers, &group.samples, 1, count, false);
    for (int s = 0; s < count; ++s) {
      const size_t k = first + size_t(s);
      const float p_hat = group.samples.p_hat[s], p_area = group.p_area[s];
      if (group.samples.active[s] == 0.0f || !(p_area > 0.0f) || p_hat <= 0.0f) continue;
      ReuseReservoir& r = out[starts[k].pixel];
      if (r.take(p_hat / p_area, p_hat, starts[k].u)) {
        r.y.light = kSurfacePointSample, r.y.uv = starts[k].tag, r.y.age = 0;
        r.y.point = group.samples.point(s);
      }
      r.finalize();
    }
  }
}

}  // namespace candela

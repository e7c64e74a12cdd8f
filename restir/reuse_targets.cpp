#include "restir/reuse_targets.h"

#include <algorithm>

#include "engine/check.h"
#include "restir/receiver_lanes.h"

namespace candela {

namespace {

// Whether set_placed places input k of slot s anew on `lights`: a triangle light's sample that `lights` does not place
// as its own frame did (placed_alike). Its light record is then read, which on `city` (104k lights) misses the
// cache: prefetch_placed starts those loads for a whole row first.
bool placed_anew(const ReuseRow& row, int k, int s, const LightList& lights) {
  const ReuseInput& in = row.inputs[k][s];
  const ReuseSample& y = in.reservoir->y;
  return (row.sampled[s] >> k & 1u) && y.light < lights.triangle_count() && !placed_alike(in.domain->lights, lights, y);
}
void prefetch_placed(const ReuseRow& row, int k, int s, const LightList& lights) {
  if (placed_anew(row, k, s, lights)) lights.prefetch(row.inputs[k][s].reservoir->y.light);
}

// Slot s of `plane`: input k's sample as receivers whose frame placed the lights as `lights` did see it
// (PlacedSample::at in reuse.cpp): the point it stores where `lights` places it alike (placed_alike), otherwise
// the point its uniforms give on its light as `lights` placed it. Inactive where the input has no sample and for
// punctual lights (left to the scalar path).
void set_placed(const Scene& scene, const ReuseRow& row, int k, int s, const LightList& lights, CandidateLanes& plane) {
  const ReuseSample& y = row.inputs[k][s].reservoir->y;
  if (placed_anew(row, k, s, lights))
    plane.set(s, lights.triangle_point(scene, y.light, y.uv));
  else if ((row.sampled[s] >> k & 1u) && (y.light == kSurfacePointSample || y.light < lights.triangle_count()))
    plane.set(s, y.point);
  else
    plane.clear(s);
}

static_assert(kLaneSlots <= 64, "a row's slots fit the bits of a uint64_t");

// The scratch planes of one thread.
struct Planes {
  SurfaceLanes surfaces;
  ReceiverLanes combiners, others;
  CandidateLanes own;
  CandidateLanes inputs[kMaxReuseInputs];
  RayLanes rays;  // with visibility: from input k's surfaces to the combining pixels' samples
};

// p_0(y_k) of every slot and input k >= 1: the combining pixels' receivers built once (slot s combines pixel
// first + s; a slot without inputs gets its pixel's receiver too, unread), every input's sample placed in plane
// k (inactive where the slot has no input k), all planes in one call.
void targets_at_combiners(const Scene& scene, const ReuseDomain& here, size_t first, int slots, int max_count,
                          ReuseRow& row, Planes& planes) {
  for (int k = 1; k < max_count; ++k)
    for (int s = 0; s < slots; ++s)
      if (k < row.count[s]) prefetch_placed(row, k, s, here.lights);
  planes.surfaces.set_row(here.surfaces.data() + first, slots);
  for (int k = 1; k < max_count; ++k)
    for (int s = 0; s < slots; ++s) {
      if (k < row.count[s])
        set_placed(scene, row, k, s, here.lights, planes.inputs[k]);
      else
        planes.inputs[k].clear(s);
    }
  build_receiver_lanes(planes.surfaces, here.eye, slots, planes.combiners);
  evaluate_candidate_lanes(planes.combiners, planes.inputs + 1, max_count - 1, slots, false);
  for (int k = 1; k < max_count; ++k)
    for (int s = 0; s < slots; ++s)
      if (k < row.count[s] && planes.inputs[k].active[s] > 0.0f) {
        row.at_combiner[k][s] = planes.inputs[k].p_hat[s];
        row.known_at[s] |= 1u << k;
      }
}

// p_k(y_0) of every slot and input k >= 1: the combining pixels' own samples at input k's receivers, one
// receiver plane per k, each sample placed as input k's frame placed the lights; with `visibility`, the
// shadow rays from input k's surface to y_0 where p_k(y_0) > 0 (answers into bit k of `visible`). A slot's own
// sample is inactive from its last input on, so that the planes of inputs few slots have (the disocclusion
// boost's, up to 10 neighbours where the rest of the row has 3) build and evaluate only the vectors holding them.
// Returns the rays traced.
uint64_t targets_of_combiners(const SceneView& view, int slots, int max_count, bool visibility, ReuseRow& row,
                              Planes& planes) {
  auto answer = [&](uint32_t tag, const RayPacket16& packet, int lane) {
    const uint32_t s = tag >> 8, k = tag & 255u;
    row.known_visible[s] |= 1u << k;
    if (!Tracer::occluded_lane(packet, lane)) row.visible[s] |= 1u << k;
  };
  auto queue = ray_queue16<uint32_t>(view.tracer, RayQuery::Occluded, answer);
  const LightList* own_placed_by = nullptr;
  for (int k = 1; k < max_count; ++k) {
    const ReuseDomain* domain = nullptr;
    for (int s = 0; s < slots; ++s) {
      const ReuseInput& in = row.inputs[k][s];
      const bool has = k < row.count[s];
      if (has) {
        CHECK(!domain || domain == in.domain);
        domain = in.domain;
      }
      planes.surfaces.set(s, has ? in.domain->surfaces[in.pixel] : PackedSurface{});
    }
    if (own_placed_by != &domain->lights) {
      for (int s = 0; s < slots; ++s)
        if (row.count[s] > 1) prefetch_placed(row, 0, s, domain->lights);
      for (int s = 0; s < slots; ++s) {
        if (row.count[s] > 1)
          set_placed(view.scene, row, 0, s, domain->lights, planes.own);
        else
          planes.own.clear(s);
      }
      own_placed_by = &domain->lights;
    }
    for (int s = 0; s < slots; ++s)
      if (k >= row.count[s]) planes.own.clear(s);  // no input k: stays so for the larger k
    build_receiver_lanes(planes.surfaces, domain->eye, slots, planes.others, planes.own.active);
    evaluate_candidate_lanes(planes.others, &planes.own, 1, slots, false);
    // The shadow rays from input k's surfaces to y_0 as placed for them (sample_shadow_ray's to a stored point).
    if (visibility) shadow_ray_lanes(planes.others, planes.own, view.tracer.offset_epsilon(), slots, planes.rays);
    for (int s = 0; s < slots; ++s)
      if (k < row.count[s] && planes.own.active[s] > 0.0f) {
        row.of_combiner[k][s] = planes.own.p_hat[s];
        row.known_of[s] |= 1u << k;
        if (visibility && planes.own.p_hat[s] > 0.0f) queue.add(planes.rays.ray(s), uint32_t(s) << 8 | uint32_t(k));
      }
  }
  queue.finish();
  return queue.traced();
}

}  // namespace

uint64_t evaluate_reuse_targets(const SceneView& view, int slots, bool of_combiner, bool visibility, ReuseRow& row) {
  thread_local Planes planes;
  int max_count = 0;
  const ReuseDomain* here = nullptr;
  size_t first = 0;  // the pixel of slot 0: the row's combining pixels are consecutive
  for (int s = 0; s < slots; ++s) {
    row.known_at[s] = row.known_of[s] = row.known_visible[s] = row.visible[s] = 0;
    max_count = std::max(max_count, row.count[s]);
    if (row.count[s] == 0) continue;
    here = row.inputs[0][s].domain;
    first = row.inputs[0][s].pixel - size_t(s);
  }
  if (max_count < 2) return 0;
  for (int s = 0; s < slots; ++s) CHECK(row.count[s] == 0 || row.inputs[0][s].pixel == first + size_t(s));
  targets_at_combiners(view.scene, *here, first, slots, max_count, row, planes);
  return of_combiner ? targets_of_combiners(view, slots, max_count, visibility, row, planes) : 0;
}

}  // namespace candela

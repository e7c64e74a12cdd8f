#include "restir/reuse_targets.h"

#include <algorithm>

#include "engine/check.h"
#include "restir/receiver_lanes.h"

namespace candela {

namespace {

// Whether input `in`'s sample evaluates in lanes at receivers whose frame placed the lights as `lights`
// did: a point it stores (a triangle light placed by the same light list, or a surface point).
bool lane_sample(const DiReuseInput& in, const LightList& lights) {
  const DiSample& y = in.reservoir->y;
  if (in.reservoir->W <= 0.0f) return false;
  return y.light == kSurfacePointSample || (&in.domain->lights == &lights && y.light < lights.triangle_count());
}

static_assert(kLaneSlots <= 64, "a row's slots fit the bits of a uint64_t");

// The scratch planes of one thread.
struct Planes {
  SurfaceLanes surfaces;
  ReceiverLanes combiners, others;
  CandidateLanes own;
  CandidateLanes inputs[kMaxReuseInputs];
};

}  // namespace

void evaluate_reuse_targets(int slots, bool of_combiner, ReuseRow& row) {
  thread_local Planes planes;
  int max_count = 0;
  const DiDomain* here = nullptr;
  for (int s = 0; s < slots; ++s) {
    row.targets[s].known_at = row.targets[s].known_of = 0;
    max_count = std::max(max_count, row.count[s]);
    if (row.count[s] > 0) here = row.inputs[s][0].domain;
  }
  if (max_count < 2) return;
  // The combining pixels' receivers; every input's sample placed in plane k (inactive where it has none,
  // or the lanes cannot evaluate it); p_0(y_k) of all of them in one call.
  for (int s = 0; s < slots; ++s) {
    const DiReuseInput* in = row.inputs[s];
    planes.surfaces.set(s, here->surfaces[row.count[s] > 0 ? in[0].pixel : 0]);
    for (int k = 1; k < max_count; ++k) {
      const bool lanes = k < row.count[s] && lane_sample(in[k], here->lights);
      if (lanes) planes.inputs[k].set(s, in[k].reservoir->y.point);
      else planes.inputs[k].clear(s);
    }
  }
  build_receiver_lanes(planes.surfaces, here->eye, slots, planes.combiners);
  evaluate_candidate_lanes(planes.combiners, planes.inputs + 1, max_count - 1, slots, false);
  for (int s = 0; s < slots; ++s)
    for (int k = 1; k < row.count[s]; ++k)
      if (planes.inputs[k].active[s] > 0.0f) {
        row.targets[s].at_combiner[k] = planes.inputs[k].p_hat[s];
        row.targets[s].known_at |= 1u << k;
      }
  if (!of_combiner) return;
  // The combining pixels' own samples at each input k's receivers, one receiver plane per k (a sample that
  // input k's frame placed elsewhere, for moving lights, is left to the scalar path).
  for (int s = 0; s < slots; ++s) {
    const bool lanes = row.count[s] > 1 && lane_sample(row.inputs[s][0], here->lights);
    if (lanes) planes.own.set(s, row.inputs[s][0].reservoir->y.point);
    else planes.own.clear(s);
  }
  for (int k = 1; k < max_count; ++k) {
    const DiDomain* domain = nullptr;
    for (int s = 0; s < slots; ++s) {
      const bool has = k < row.count[s];
      if (has) {
        CHECK(!domain || domain == row.inputs[s][k].domain);
        domain = row.inputs[s][k].domain;
      }
      planes.surfaces.set(s, has ? row.inputs[s][k].domain->surfaces[row.inputs[s][k].pixel] : DiSurface{});
    }
    uint64_t usable = 0;  // bit s: slot s reads the result
    for (int s = 0; s < slots; ++s)
      if (k < row.count[s] && planes.own.active[s] > 0.0f &&
          (&domain->lights == &here->lights || row.inputs[s][0].reservoir->y.light == kSurfacePointSample))
        usable |= uint64_t(1) << s;
    if (usable == 0) continue;
    build_receiver_lanes(planes.surfaces, domain->eye, slots, planes.others);
    evaluate_candidate_lanes(planes.others, &planes.own, 1, slots, false);
    for (int s = 0; s < slots; ++s)
      if (usable >> s & 1u) {
        row.targets[s].of_combiner[k] = planes.own.p_hat[s];
        row.targets[s].known_of |= 1u << k;
      }
  }
}

}  // namespace candela

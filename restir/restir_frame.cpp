#include "restir/restir_frame.h"

#include <algorithm>
#include <utility>

#include "engine/parallel.h"

namespace candela {

void Restir::forget_history() {
  di_.history.clear();
  gi_.history.clear();
}

ReuseDomain Restir::current_domain(const RestirFrame& frame, const GBuffer& g) const {
  return {g.packed, g.width, g.height, frame.eye, frame.lights};
}

ReuseDomain Restir::previous_domain(const RestirFrame& frame, const GBuffer& g) const {
  return {frame.prev_surfaces, g.width, g.height, frame.prev_eye, frame.prev_lights};
}

// With drop_occluded: every reservoir whose sample the shading's shadow ray (or a reused verdict) found
// occluded keeps its M and drops the sample (as the boiling filter does), before it becomes history. Where
// a pixel's strongest unshadowed sample is occluded, temporal reuse would otherwise choose it frame after
// frame and shade black. Shading integrates f V, to which an occluded sample contributes nothing, so the
// history of a still pixel stays unbiased; a neighbour that sees the sample, or this pixel once the
// occluder moved, loses its share (darkening at shadow edges). Cost: one pass over the verdicts, in parallel
// ranges of 4096 pixels (on one thread it was ~0.5% of a restir-di frame's wall time).
static void drop_occluded_samples(const std::vector<SampleVisibility>& visibility,
                                  std::vector<ReuseReservoir>& reservoirs) {
  parallel_for_ranges(size_t(0), reservoirs.size(), size_t(4096), [&](size_t begin, size_t end) {
    for (size_t i = begin; i < end; ++i)
      if (visibility[i].valid && !visibility[i].visible) reservoirs[i].W = reservoirs[i].w_sum = 0.0f;
  });
}

// Whether reuse traces the visibility of inputs' own samples from their surfaces (pairwise MIS with visibility): then
// the shading's rays start where reuse's do, and each stage takes the verdicts the other traced for the same ray
// (temporal_reuse's history_verdicts, spatial_reuse's kept_visible).
static bool reuse_traces_visibility(const ReuseParams& reuse) {
  return reuse.mis_visibility && reuse.bias == BiasCorrection::Pairwise;
}

bool Restir::reuses_history(const GBuffer& g, const ReuseParams& reuse, int pass, const ReservoirChain& chain) {
  return reuse.temporal && pass == 0 && chain.history.size() == g.size();
}

bool Restir::find_history(const GBuffer& g, const RestirFrame& frame, const std::string& prefix,
                          const ReuseParams& reuse, int key, int pass, ReservoirChain& chain, FrameStats& stats,
                          const SecondHistory* second) const {
  if (!reuses_history(g, reuse, pass, chain)) return false;
  StageTimer timer(stats, prefix + "_history");
  find_history_pixels(g, current_domain(frame, g), previous_domain(frame, g), reuse, key, chain.history_pixel, second);
  return true;
}

// Stages "<prefix>_temporal" (where find_history ran), "<prefix>_boiling_filter"
// (optional), "<prefix>_spatial" (per spatial pass) and "<prefix>_shade", or with reuse.fused (where find_history ran
// and spatial reuse is on) "<prefix>_fused" in place of the first three (the boiling filter, which needs temporal
// reuse's output, is then not run), then the further spatial passes: reuses chain.initial across
// frames and pixels and adds one estimate per pixel into the sum (plus emission seen and `unsampled`,
// when given; the shade stage also drops occluded samples, with drop_occluded); the final reservoirs and
// shadow-ray verdicts become the chain's history, by swapping buffers (every stage rewrites its output
// buffer whole, so nothing stale survives the swap).
void Restir::reuse_and_shade(const SceneView& view, const GBuffer& g, const RestirFrame& frame,
                             const std::string& prefix, const ReuseParams& reuse, int key, bool temporal,
                             const std::vector<vec3>* unsampled, ReservoirChain& chain, FrameStats& stats, Image& sum) {
  const ReuseDomain current = current_domain(frame, g), previous = previous_domain(frame, g);
  std::vector<ReuseReservoir>* result = &chain.initial;
  const int passes = reuse.spatial ? std::max(reuse.spatial_passes, 0) : 0;
  const bool fused = temporal && reuse.fused && passes > 0 && previous.surfaces.size() == g.size();
  if (temporal && !fused) {
    StageTimer timer(stats, prefix + "_temporal");
    // Last pass's verdicts (swapped out at this pass's shading) judge the history's samples where they still hold.
    const bool verdicts =
        frame.same_geometry && reuse_traces_visibility(reuse) && chain.visibility.size() == chain.history.size();
    temporal_reuse(view, g, current, previous, *result, chain.history, reuse, key, chain.temporal, chain.history_pixel,
                   timer.rays(), verdicts ? &chain.visibility : nullptr);
    result = &chain.temporal;
  }
  if (temporal && !fused && reuse.boiling_threshold > 0.0f) {
    StageTimer timer(stats, prefix + "_boiling_filter");
    boiling_filter(current, reuse.boiling_threshold, chain.temporal);
  }
  // The last spatial pass keeps shaded_samples samples of each combination (spatial_reuse's further samples):
  // each is the combination's estimator, so their mean is unbiased and averages out part of what one sample's shadow
  // ray leaves.
  const int samples = passes > 0 ? std::clamp(reuse.shaded_samples, 1, kMaxShadedSamples) : 1;
  chain.further.resize(size_t(samples - 1));
  const bool known = passes > 0 && reuse_traces_visibility(reuse) && frame.known_visibility;
  const PreviousFrame previous_frame{g, previous, chain.history};
  for (int k = 0; k < passes; ++k) {
    StageTimer timer(stats, prefix + (k == 0 && fused ? "_fused" : "_spatial"));
    const bool last = k == passes - 1;
    spatial_reuse(view, current, *result, reuse, key, k, temporal ? &chain.history_pixel : nullptr,
                  chain.spatial[k % 2], timer.rays(), last ? &chain.further : nullptr,
                  last && known ? &chain.kept_visible : nullptr, k == 0 && fused ? &previous_frame : nullptr);
    result = &chain.spatial[k % 2];
  }
  {
    StageTimer timer(stats, prefix + "_shade");
    std::swap(chain.visibility, chain.prev_visibility);
    VisibilityReuse visibility{reuse.visibility_reuse_frames, temporal ? &chain.history_pixel : nullptr,
                               &chain.prev_visibility, reuse_traces_visibility(reuse),
                               known ? &chain.kept_visible : nullptr};
    shade_reservoirs(view, g, *result, chain.further, unsampled, visibility, reuse.simd, chain.visibility, sum,
                     timer.rays(), timer.non_finite());
    if (reuse.drop_occluded) drop_occluded_samples(chain.visibility, *result);
  }
  std::swap(chain.history, *result);
}

}  // namespace candela

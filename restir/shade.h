#pragma once
// The last stage of a reuse chain: each pixel's reservoirs shaded with their shadow rays, for ReSTIR DI and ReSTIR GI
// alike, with final visibility reuse across frames.
#include <vector>

#include "engine/frame_stats.h"
#include "engine/image.h"
#include "restir/sample.h"

namespace candela {

// A pixel's final shadow-ray verdict on its sample, handed to the next frame.
struct SampleVisibility {
  uint32_t light = 0;
  vec2 uv{0.0f};
  bool valid = false;  // a verdict exists (false where nothing was traced)
  bool visible = false;
  uint8_t age = 0;  // frames this verdict has been reused
  // Whether this is a verdict on sample s (the same light and uniforms).
  bool on(const ReuseSample& s) const { return valid && light == s.light && uv == s.uv; }
};

// Final visibility reuse: a pixel whose sample is the one its temporal history pixel shaded last frame
// takes that pixel's verdict instead of tracing, for at most max_age frames in a row. Biased where
// occluders move (their shadows lag up to max_age frames) and by the sub-pixel move of the surface point.
struct VisibilityReuse {
  int max_age = 0;                                          // 0: trace every pixel every frame
  const std::vector<int32_t>* history_pixel = nullptr;      // from temporal reuse (null: no history)
  const std::vector<SampleVisibility>* previous = nullptr;  // last frame's verdicts
  // The shadow rays start from the packed surfaces (GBuffer::packed), as reuse's visibility rays do, instead of the
  // exact ones, so that reuse and shading can take each other's verdicts on the same ray (`known` below, and next
  // frame's temporal reuse: temporal_reuse's history_verdicts; where the MIS weights include visibility).
  bool from_packed = false;
  // With from_packed, or null: per pixel, the first sample's visibility where reuse traced that same ray this frame
  // (spatial_reuse's kept_visible), else -1. Taken before a verdict of last frame's.
  const std::vector<int8_t>* known = nullptr;
};

// Stages "di_shade" and "gi_shade": reads the G-buffer, reservoirs and, for ReSTIR DI, the unsampled light of its
// candidates; adds f L W of each pixel's sample (f L_e G W for a light sample, f L_o G W for a surface point), with
// the exact surface, into `sum`, plus, with `unsampled` (ReSTIR DI's), the emission seen and the unsampled light
// (ReSTIR GI passes none: the emission seen is direct light, which ReSTIR DI adds); writes
// each pixel's verdict to `visibility`; a pixel whose estimate is not finite adds nothing and is counted
// in `non_finite`. With `further` samples (ReuseParams::shaded_samples) each of the n samples' terms counts 1/n,
// and the further ones' verdicts are not kept; samples of a pixel that shade alike (same sample and W: the copies of
// a pixel without reuse, or picks of one input) are shaded once with their shares summed. One shadow ray per pixel and
// distinct sample (in packets of 16), except where the first sample's verdict is known (reuse.known) or reused; from
// the packed surface with reuse.from_packed, else from the exact one. With `simd`, the exact receivers (built once per
// pixel for all its samples) and contributions are evaluated in lanes (target_lanes.h; the scalar path, the reference,
// gives the same bits).
void shade_reservoirs(const SceneView& view, const GBuffer& g, const std::vector<ReuseReservoir>& reservoirs,
                      const std::vector<std::vector<ReuseReservoir>>& further, const std::vector<vec3>* unsampled,
                      const VisibilityReuse& reuse, bool simd, std::vector<SampleVisibility>& visibility, Image& sum,
                      RayCounter& rays, Counter& non_finite);

}  // namespace candela

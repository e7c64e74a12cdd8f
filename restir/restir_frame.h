#pragma once
// ReSTIR's part of a frame (methods restir-di and restir), and the history it keeps between frames: the
// stage chain candidates -> temporal reuse -> boiling filter -> spatial reuse -> shading, run for DI and,
// with GI on, for GI's reservoirs through the same reuse code. The renderer owns the scene, the lights
// and the G-buffer, and hands them in every pass.
#include <span>
#include <string>
#include <vector>

#include "engine/check.h"
#include "engine/frame_stats.h"
#include "engine/image.h"
#include "restir/di.h"
#include "restir/di_candidates.h"
#include "restir/reuse.h"
#include "restir/shade.h"
#include "restir/gi.h"

namespace candela {

// The buffers of one reservoir-resampling estimator (ReSTIR DI or GI): this pass's reservoirs after each
// stage, the history the next frame reuses, which previous pixel each pixel merged, and the final
// shadow-ray verdicts of this and the previous pass.
struct ReservoirChain {
  std::vector<ReuseReservoir> initial, temporal, spatial[2], history;
  std::vector<int32_t> history_pixel;
  std::vector<SampleVisibility> visibility, prev_visibility;
  std::vector<int8_t> kept_visible;  // the last spatial pass's visibility of its result's samples (-1: not traced)
  // The last spatial pass's further samples (ReuseParams::shaded_samples), shaded and then forgotten.
  std::vector<std::vector<ReuseReservoir>> further;
};

struct RestirSettings {
  DiParams di;           // initial candidates
  ReuseParams di_reuse;  // DI's temporal and spatial reuse
  ReuseParams gi_reuse;  // GI's
  GiParams gi;           // GI's samples (paths)
  bool with_gi = false;  // restir: GI too; restir-di: DI alone
  bool gi_only = false;  // with_gi: shade the indirect light alone (tests compare it with a reference)
  uint64_t seed = 1;
};

// What a pass reads besides the G-buffer (whose packed surfaces, GBufferParams::packed, its targets read):
// this frame's light placement and eye, and last frame's, as the renderer decided them (last frame's
// placement is this frame's where no light moved), and last frame's packed surfaces (empty: none).
// same_geometry: no instance moved since last frame, so a shadow ray last frame traced sees what it would see now,
// and temporal reuse takes last frame's shading verdicts instead of tracing their rays again (temporal_reuse).
// known_visibility: the shading takes the verdicts spatial reuse traced this frame for its rays (spatial_reuse's
// kept_visible); off only for a test that compares the two.
struct RestirFrame {
  const LightList& lights;
  const LightList& prev_lights;
  vec3 eye, prev_eye;
  std::span<const PackedSurface> prev_surfaces;
  bool same_geometry = false;
  bool known_visibility = true;
};

class Restir {
 public:
  explicit Restir(const RestirSettings& settings) : settings_(settings) {}

  // One pass of frame `frame_index` (pass 0 may reuse history; later passes of the same frame resample
  // anew): one estimate per pixel of direct (and indirect) light added into `sum`. Each pass of each frame
  // draws its own random streams. `g` holds packed surfaces (GBufferParams::packed).
  template <LightSampler S>
  void pass(const SceneView& view, const S& sampler, const GBuffer& g, const RestirFrame& frame, int frame_index,
            int pass, FrameStats& stats, Image& sum);

  // Forgets every reservoir of earlier frames (the next frame reuses nothing).
  void forget_history();
  // Forgets DI's history alone: its samples name lights by index, void once the light list changed.
  void forget_light_history() { di_.history.clear(); }

  // The reservoirs the last pass shaded with (empty before the first pass, or for GI without it).
  const std::vector<ReuseReservoir>& di_reservoirs() const { return di_.history; }
  const std::vector<ReuseReservoir>& gi_reservoirs() const { return gi_.history; }
  // This and last frame's packed surfaces with the frame's light placement and eye: what reuse's target
  // functions read.
  ReuseDomain current_domain(const RestirFrame& frame, const GBuffer& g) const;
  ReuseDomain previous_domain(const RestirFrame& frame, const GBuffer& g) const;

 private:
  // Whether this pass reuses the chain's history: the first pass of a frame, with temporal reuse on and a history of
  // this size.
  static bool reuses_history(const GBuffer& g, const ReuseParams& reuse, int pass, const ReservoirChain& chain);
  // Stage "<prefix>_history" where reuses_history: find_history_pixels into chain.history_pixel (and `second`'s, if
  // given). Returns whether it ran.
  bool find_history(const GBuffer& g, const RestirFrame& frame, const std::string& prefix, const ReuseParams& reuse,
                    int key, int pass, ReservoirChain& chain, FrameStats& stats,
                    const SecondHistory* second = nullptr) const;
  // `temporal`: find_history ran.
  void reuse_and_shade(const SceneView& view, const GBuffer& g, const RestirFrame& frame, const std::string& prefix,
                       const ReuseParams& reuse, int key, bool temporal, const std::vector<vec3>* unsampled,
                       ReservoirChain& chain, FrameStats& stats, Image& sum);

  RestirSettings settings_;
  ReservoirChain di_, gi_;
  std::vector<vec3> unsampled_;     // light only BSDF candidates reach (environment, unlisted emitters)
  LightTiles light_tiles_;          // presampled light tiles of this pass (with DiParams::light_tiles)
  std::vector<BsdfRay> bsdf_rays_;  // DI's first BSDF candidates, GI's first rays (shares_bsdf_ray)
  // Whether GI's paths start with DI's BSDF candidates (GiParams::share_bsdf_ray, where DI draws one per pixel with
  // certainty).
  bool shares_bsdf_ray() const {
    return settings_.with_gi && settings_.gi.share_bsdf_ray && settings_.di.bsdf_candidates >= 1 &&
           settings_.di.bsdf_probability == 1.0f;
  }
};

template <LightSampler S>
void Restir::pass(const SceneView& view, const S& sampler, const GBuffer& g, const RestirFrame& frame, int frame_index,
                  int pass, FrameStats& stats, Image& sum) {
  const int key = frame_index * 4096 + pass;
  CHECK(g.packed.size() == g.size());
  const ReuseDomain current = current_domain(frame, g);
  bool gi_history_found = false;  // GI's history found in DI's stage "di_history"
  // DI's candidates run for DI's light, and for GI's first rays where GI shares them (with gi_only too: DI's
  // candidates alone, so that the tests of GI alone run the default's rays; DI's history then stays empty).
  const bool di_shades = !settings_.with_gi || !settings_.gi_only;
  if (di_shades || shares_bsdf_ray()) {
    DiParams params = settings_.di;
    params.seed = settings_.seed;
    const LightTiles* tiles = nullptr;
    if (params.light_tiles > 0) {
      StageTimer timer(stats, "di_light_tiles");
      light_tiles_.build(view, sampler, g, params.light_tiles, params.light_tile_size, params.seed, key);
      tiles = &light_tiles_;
    }
    ReuseParams reuse = settings_.di_reuse;
    reuse.seed = settings_.seed;
    // Temporal reuse's history found first: the light candidates take fewer where it is
    // (DiParams::history_light_candidates). GI's comes with it where it follows from DI's (history_follows: by
    // default it does, less GI's smooth pixels), which saves GI's stage "gi_history".
    const bool gi_with_di = settings_.with_gi && reuses_history(g, settings_.gi_reuse, pass, gi_) &&
                            history_follows(reuse, settings_.gi_reuse);
    const SecondHistory gi_history{settings_.gi_reuse.min_roughness, &gi_.history_pixel};
    const bool temporal =
        find_history(g, frame, "di", reuse, key, pass, di_, stats, gi_with_di ? &gi_history : nullptr);
    gi_history_found = temporal && gi_with_di;
    {
      StageTimer timer(stats, "di_candidates");
      di_initial_candidates(view, sampler, g, current, params, key, di_.initial, unsampled_, timer.rays(), tiles,
                            temporal ? &di_.history_pixel : nullptr, shares_bsdf_ray() ? &bsdf_rays_ : nullptr);
    }
    if (di_shades) reuse_and_shade(view, g, frame, "di", reuse, key, temporal, &unsampled_, di_, stats, sum);
  }
  if (!settings_.with_gi) return;
  GiParams params = settings_.gi;
  params.seed = mix64(settings_.seed ^ 0x6769);
  {
    StageTimer timer(stats, "gi_samples");
    gi_initial_samples(view, sampler, g, current, params, key, gi_.initial, timer.rays(), timer.non_finite(),
                       shares_bsdf_ray() ? &bsdf_rays_ : nullptr);
  }
  ReuseParams reuse = settings_.gi_reuse;
  reuse.seed = params.seed;
  const bool temporal = gi_history_found || find_history(g, frame, "gi", reuse, key, pass, gi_, stats);
  reuse_and_shade(view, g, frame, "gi", reuse, key, temporal, nullptr, gi_, stats, sum);
}

}  // namespace candela

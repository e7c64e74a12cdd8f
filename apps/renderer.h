#pragma once
// The frame pipeline: owns the scene, tracer, lights, light samplers and frame buffers, and runs the stages
// of one frame in order (scene update, G-buffer, the chosen estimator, resolve), timing each one.
// History (last frame's camera and G-buffer) is rotated here and nowhere else.
#include <functional>
#include <memory>
#include <string>
#include <variant>

#include "engine/camera.h"
#include "engine/frame_stats.h"
#include "engine/gbuffer.h"
#include "engine/image.h"
#include "engine/lights.h"
#include "engine/scene.h"
#include "engine/path_tracer.h"
#include "engine/tracer.h"
#include "denoise/denoiser.h"
#include "restir/di.h"
#include "restir/reuse.h"
#include "restir/gi.h"
#include "restir/restir_frame.h"
#include "samplers/light_tree.h"
#include "samplers/simple_samplers.h"

namespace candela {

// pt: the reference path tracer; direct: the same estimator stopped after one bounce (emission seen
// plus light sampling and a BSDF sample combined by MIS at the first hit); restir-di: direct light by
// resampled importance sampling at the G-buffer's points, reused across pixels and frames; restir: restir-di
// plus ReSTIR GI for the indirect light (paths up to max_depth).
enum class Method { PathTrace, Direct, RestirDi, Restir };
// Auto: the sampler measured best for the method (light_sampler_for).
enum class LightSamplerKind { Auto, Uniform, Power, Tree, Exhaustive };

// ReSTIR GI's reuse defaults: ReSTIR DI's, plus no reuse on surfaces smoother than roughness 0.2 and
// samples at most 30 frames old, and visibility in the MIS weights (unbiased: the Jacobian rejection is off).
inline ReuseParams default_gi_reuse() {
  ReuseParams p;
  p.min_roughness = 0.2f;
  p.max_sample_age = 30;
  p.mis_visibility = true;   // GI samples are visible from their own pixel by construction
  p.drop_occluded = false;   // with visibility in the weights, an occluded history sample has no weight already
  p.spatial_neighbours = 2;  // chosen at equal time (docs/restir.md, "Spatial neighbours and light candidates")
  p.neighbour_block = 1;     // shared neighbour offsets are measured for DI only (docs/restir.md, "Neighbour offsets")
  p.spatial_radius = 16.0f;  // DI's 8 pixels were measured for DI only (docs/restir.md, "Spatial radius at equal time")
  return p;
}

// Switches for the tests alone, not settings (no option, script key or widget sets them; docs/testing.md):
// they isolate a stage for comparison with a reference, or break one on purpose so that a test can show
// the harness notices.
struct RenderTestSwitches {
  bool gi_only = false;              // restir: shade the indirect light alone (Unbiased.RestirGi*)
  bool stale_light_history = false;  // temporal reuse judges last frame's samples with this frame's light
                                     // placement instead of last frame's (biased where lights move;
                                     // Unbiased.MovingLights must reject it)
  // Every ray whose verdict another stage traced is traced again: temporal reuse's to its history's samples (last
  // frame's shading traced them), the shading's to samples spatial reuse kept (it traced them); the images must stay
  // the same bits (RestirDiReuse.KnownVerdictsReplaceRays).
  bool retrace_known_visibility = false;
};

struct RenderSettings {
  int width = 640, height = 360;
  int spp = 1;        // samples per pixel per frame
  int max_depth = 8;  // path tracer bounces (1 = direct light only)
  int rr_depth = 3;   // pt and ReSTIR GI's paths: Russian roulette from this bounce on
  uint64_t seed = 1;
  Method method = Method::PathTrace;
  LightSamplerKind light_sampler = LightSamplerKind::Auto;
  bool accumulate = true;                          // progressive accumulation while camera and scene stay still
  bool jitter = true;                              // G-buffer rays through jittered positions (false: pixel centres)
  SampleSequence sampler = SampleSequence::Sobol;  // direct and pt: Sobol, ZSobol or independent numbers
  double time_budget_ms = 0.0;  // > 0: instead of `spp`, as many 1-spp passes as fit in this time per frame
  DiParams di;                  // restir-di: initial candidates
  ReuseParams di_reuse;         // restir-di: temporal and spatial reuse
  ReuseParams gi_reuse = default_gi_reuse();  // restir: reuse of the GI samples
  bool gi_share_bsdf_ray = true;              // restir: GI's first rays are DI's BSDF candidates (GiParams)
  DenoiserParams denoise;                     // the denoiser that finishes each frame (none by default)
  RenderTestSwitches test;
};

using AnyLightSampler = std::variant<UniformLightSampler, PowerLightSampler, LightTreeSampler, ExhaustiveLightSampler>;

class Renderer {
 public:
  Renderer(Scene scene, const RenderSettings& settings);

  // Renders frame `frame_index` at scene time `time` seen from `camera`; returns its stats.
  // `progress`, if set, is called after each sample pass with (samples done, samples total; total 0
  // with a time budget).
  FrameStats render_frame(int frame_index, float time, const CameraDesc& camera,
                          const std::function<void(int, int)>& progress = {});
  // Forgets every frame before the next one, as if the renderer were new: no temporal reuse, no
  // denoiser history, no accumulation, zero motion on the next frame's camera.
  void reset_history();
  // Takes new settings (any of them, the size included) without rebuilding what depends on the scene
  // alone: the BVHs and the light list stay, the light sampler is rebuilt only when its kind changes, and
  // ReSTIR, the denoiser and the accumulation start over as after reset_history. On a still scene the
  // next frames equal a new Renderer's with these settings. Cost: a light sampler build at most.
  void apply_settings(const RenderSettings& settings);
  // The displayed image: accumulated radiance divided by the samples accumulated so far, denoised when
  // a denoiser is set. Valid until the next call that renders, resets or changes settings.
  const Image& image() const;
  // The same before the denoiser, computed on each call into a buffer the renderer keeps (rows in parallel;
  // a new image per frame cost its page faults, and one thread scaled it).
  const Image& noisy_image() const;
  int accumulated_spp() const { return accumulated_spp_; }
  const GBuffer& gbuffer() const { return gbuffer_; }
  // restir-di, restir: the reservoirs the last frame shaded with (empty for other methods).
  const std::vector<ReuseReservoir>& di_reservoirs() const { return restir_.di_reservoirs(); }
  const std::vector<ReuseReservoir>& gi_reservoirs() const { return restir_.gi_reservoirs(); }
  // restir-di, restir: the packed surfaces and light placement of the last frame and of the one before
  // (what reuse's target functions read; the weight tests build combinations from them).
  ReuseDomain current_domain() const;
  ReuseDomain previous_domain() const;
  const Scene& scene() const { return scene_; }
  const LightList& lights() const { return lights_; }
  const Tracer& tracer() const { return *tracer_; }
  // Records every ray query of the following frames into `log` (null: stop); see engine/ray_log.h.
  void set_ray_log(RayLog* log) { tracer_->set_ray_log(log); }
  const RenderSettings& settings() const { return settings_; }

 private:
  void update_scene(float time, const CameraDesc& camera, FrameStats& stats);
  // `done`: the frame's samples per pixel before this pass.
  void path_trace_pass(const SceneView& view, int frame_index, int done, int spp, FrameStats& stats);
  // The renderer's side of ReSTIR's pass: this and last frame's light placement and eye.
  RestirFrame restir_frame() const;

  Scene scene_;
  RenderSettings settings_;
  std::unique_ptr<Tracer> tracer_;
  LightList lights_;
  LightList prev_lights_;         // last frame's light placement (scenes with motion only)
  bool instances_moved_ = false;  // animated instances moved since last frame (and with them lights_, if they emit)
  AnyLightSampler sampler_;
  Camera camera_, prev_camera_;
  CameraDesc camera_desc_;
  bool has_frame_ = false;
  GBuffer gbuffer_, prev_gbuffer_;
  Restir restir_;
  Image sum_;
  int accumulated_spp_ = 0;
  uint64_t sample_epoch_ = 0;  // frame that began the current accumulation (keys the Sobol scrambles)
  Denoiser denoiser_;
  Image denoised_;
  mutable Image noisy_;  // noisy_image()'s buffer
};

// The sampler settings.light_sampler names, Auto resolved by the method: the light tree for restir-di (whose
// candidates then read region light tiles), power for the others. Chosen by equal-time error on still and
// moving shots (docs/restir.md, "Region light tiles"); restir's GI paths were not measured with the tree.
LightSamplerKind light_sampler_for(const RenderSettings& settings);
AnyLightSampler make_light_sampler(LightSamplerKind kind, const LightList& lights);

}  // namespace candela

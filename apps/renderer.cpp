#include "apps/renderer.h"

#include <algorithm>

#include "engine/check.h"
#include "engine/parallel.h"
#include "engine/path_batch.h"

namespace candela {

AnyLightSampler make_light_sampler(LightSamplerKind kind, const LightList& lights) {
  CHECK(kind != LightSamplerKind::Auto);  // resolved by light_sampler_for first
  switch (kind) {
    case LightSamplerKind::Uniform: return UniformLightSampler(lights);
    case LightSamplerKind::Tree: return LightTreeSampler(lights);
    case LightSamplerKind::Exhaustive: return ExhaustiveLightSampler(lights);
    case LightSamplerKind::Power:
    default: return PowerLightSampler(lights);
  }
}

LightSamplerKind light_sampler_for(const RenderSettings& settings) {
  if (settings.light_sampler != LightSamplerKind::Auto) return settings.light_sampler;
  return settings.method == Method::RestirDi ? LightSamplerKind::Tree : LightSamplerKind::Power;
}

// ReSTIR's settings from the renderer's.
static RestirSettings restir_settings(const RenderSettings& s) {
  RestirSettings r;
  r.di = s.di;
  // Auto's tree is the tree with region light tiles (one per screen block, whatever the count asked).
  if (s.light_sampler == LightSamplerKind::Auto && light_sampler_for(s) == LightSamplerKind::Tree)
    r.di.light_tiles = std::max(r.di.light_tiles, 1);
  r.di_reuse = s.di_reuse;
  r.gi_reuse = s.gi_reuse;
  r.gi.max_depth = s.max_depth;
  r.gi.rr_start_depth = s.rr_depth;
  r.gi.share_bsdf_ray = s.gi_share_bsdf_ray;
  r.with_gi = s.method == Method::Restir;
  r.gi_only = s.test.gi_only;
  r.seed = s.seed;
  return r;
}

Renderer::Renderer(Scene scene, const RenderSettings& settings)
    : scene_(std::move(scene)),
      settings_(settings),
      tracer_(std::make_unique<Tracer>(scene_)),
      lights_(scene_),
      prev_lights_(scene_.animated() ? lights_ : LightList()),
      sampler_(make_light_sampler(light_sampler_for(settings), lights_)),
      restir_(restir_settings(settings)),
      denoiser_(settings.denoise) {
  CHECK(settings.width > 0 && settings.height > 0 && settings.spp > 0);
  sum_ = Image(settings.width, settings.height);
}

static bool same_camera(const CameraDesc& a, const CameraDesc& b) {
  return a.position == b.position && a.target == b.target && a.up == b.up && a.vfov_degrees == b.vfov_degrees;
}

// Stage "scene_update": moves animated instances, re-commits the instance BVH, re-places moving lights
// (or, with animated light powers, rebuilds the light list and sampler), rotates camera history and
// decides whether accumulation continues. Cost: O(animated instances + their lights); with power
// animations a full LightList build (emission integration) and sampler build every frame.
void Renderer::update_scene(float time, const CameraDesc& camera, FrameStats& stats) {
  StageTimer timer(stats, "scene_update");
  bool moved = false;
  if (scene_.animated() && (time != scene_.time || !has_frame_)) {
    scene_.set_time(time);
    // The first frame has no last frame: zero motion, like the camera's.
    if (!has_frame_)
      for (Instance& inst : scene_.instances) inst.prev_transform = inst.transform;
    tracer_->update_instances(scene_);
    // Last frame's lights stay in prev_lights_ (temporal reuse judges history with them).
    if (has_frame_) std::swap(lights_, prev_lights_);
    if (!scene_.power_animations.empty()) {
      // Powers changed: emission averages, the power table and the tree's bounds all depend on them.
      // Rebuilt every frame, so a frame's lights depend only on its time (shards match single runs).
      lights_ = LightList(scene_);
      sampler_ = make_light_sampler(light_sampler_for(settings_), lights_);
      // An emitter scaled under the emission threshold leaves the list: light indices in history are void.
      if (lights_.size() != prev_lights_.size()) restir_.forget_light_history();
    } else {
      // The buffer swapped in is re-placed, which rewrites every light of an animated instance.
      lights_.update(scene_);
      // Rigid motion keeps every light's power, so the power table stays valid; the tree and the
      // exhaustive sampler hold light positions and are refitted / rebuilt.
      if (auto* tree = std::get_if<LightTreeSampler>(&sampler_)) tree->refit(lights_);
      if (std::holds_alternative<ExhaustiveLightSampler>(sampler_)) sampler_ = ExhaustiveLightSampler(lights_);
    }
    moved = true;
    instances_moved_ = has_frame_;
  } else if (has_frame_) {
    instances_moved_ = false;
    for (Instance& inst : scene_.instances) inst.prev_transform = inst.transform;
  }
  Camera next(camera, settings_.width, settings_.height);
  prev_camera_ = has_frame_ ? camera_ : next;
  bool camera_moved = has_frame_ && !same_camera(camera, camera_desc_);
  camera_ = next;
  camera_desc_ = camera;
  if (moved || camera_moved || !settings_.accumulate) {
    std::fill(sum_.pixels.begin(), sum_.pixels.end(), vec3(0.0f));
    accumulated_spp_ = 0;
  }
  std::swap(gbuffer_, prev_gbuffer_);
  has_frame_ = true;
}

FrameStats Renderer::render_frame(int frame_index, float time, const CameraDesc& camera,
                                  const std::function<void(int, int)>& progress) {
  FrameStats stats;
  stats.frame = frame_index;
  stats.ray_log = tracer_->ray_log();  // the stages tag the queries they record
  auto start = std::chrono::steady_clock::now();
  update_scene(time, camera, stats);
  if (accumulated_spp_ == 0) sample_epoch_ = uint64_t(frame_index);  // a new run of samples, new scrambles
  const bool restir = settings_.method == Method::RestirDi || settings_.method == Method::Restir;
  {
    StageTimer timer(stats, "gbuffer");
    GBufferParams params{settings_.seed, frame_index, settings_.jitter};
    params.packed = restir;  // ReSTIR's targets read the packed surfaces
    trace_gbuffer(scene_, *tracer_, camera_, prev_camera_, params, gbuffer_, timer.rays());
  }
  // The estimator, in sample passes of at most 4 spp (1 under a time budget, and 1 for ReSTIR DI, whose
  // passes each resample anew at the G-buffer's points), so long renders can report progress.
  SceneView view{scene_, *tracer_, lights_, camera_};
  auto stage_start = std::chrono::steady_clock::now();
  auto more = [&](int done) {
    if (settings_.time_budget_ms <= 0.0) return done < settings_.spp;
    return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - stage_start).count() <
           settings_.time_budget_ms;
  };
  int done = 0;
  while (more(done)) {
    int pass = restir || settings_.time_budget_ms > 0.0 ? 1 : std::min(4, settings_.spp - done);
    if (restir)
      std::visit(
          [&](const auto& sampler) {
            restir_.pass(view, sampler, gbuffer_, restir_frame(), frame_index, done, stats, sum_);
          },
          sampler_);
    else
      path_trace_pass(view, frame_index, done, pass, stats);
    done += pass;
    accumulated_spp_ += pass;
    if (progress) progress(done, settings_.time_budget_ms > 0.0 ? 0 : settings_.spp);
  }
  stats.spp = done;
  // Stage(s) of the denoiser (timed inside): the displayed image, filtered with this frame's G-buffer and
  // reprojected with last frame's.
  if (settings_.denoise.kind != DenoiserKind::None)
    denoiser_.denoise(gbuffer_, prev_gbuffer_, noisy_image(), stats, denoised_);
  stats.total_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return stats;
}

// Stage "path_trace": `spp` paths per pixel (max depth 1 for the direct method) added into the sum.
void Renderer::path_trace_pass(const SceneView& view, int frame_index, int done, int spp, FrameStats& stats) {
  StageTimer timer(stats, "path_trace");
  PathTracerParams params;
  params.spp = spp;
  params.first_sample = accumulated_spp_;
  params.max_depth = settings_.method == Method::Direct ? 1 : settings_.max_depth;
  params.rr_start_depth = settings_.rr_depth;
  params.seed = settings_.seed;
  params.jitter = settings_.jitter;
  params.sequence = settings_.sampler;
  params.epoch = sample_epoch_;
  if (settings_.sampler == SampleSequence::ZSobol) {  // one screen-wide sequence per frame
    params.first_sample = done;
    params.epoch = uint64_t(frame_index);
    while ((1 << params.log2_samples) < settings_.spp && params.log2_samples < 6) ++params.log2_samples;
  }
  std::visit(
      [&](const auto& sampler) {
        path_trace(view, sampler, params, frame_index, sum_, timer.rays(), timer.non_finite());
      },
      sampler_);
}

RestirFrame Renderer::restir_frame() const {
  const bool moved = instances_moved_ && !settings_.test.stale_light_history;
  const bool same_geometry = !instances_moved_ && !settings_.test.retrace_known_visibility;
  return {.lights = lights_,
          .prev_lights = moved ? prev_lights_ : lights_,
          .eye = camera_.position(),
          .prev_eye = prev_camera_.position(),
          .prev_surfaces = prev_gbuffer_.packed,
          .same_geometry = same_geometry,
          .known_visibility = !settings_.test.retrace_known_visibility};
}

ReuseDomain Renderer::current_domain() const { return restir_.current_domain(restir_frame(), gbuffer_); }

ReuseDomain Renderer::previous_domain() const { return restir_.previous_domain(restir_frame(), gbuffer_); }

void Renderer::reset_history() {
  has_frame_ = false;
  restir_.forget_history();
  std::fill(sum_.pixels.begin(), sum_.pixels.end(), vec3(0.0f));
  accumulated_spp_ = 0;
  denoiser_.reset();
}

void Renderer::apply_settings(const RenderSettings& settings) {
  CHECK(settings.width > 0 && settings.height > 0 && settings.spp > 0);
  if (light_sampler_for(settings) != light_sampler_for(settings_))
    sampler_ = make_light_sampler(light_sampler_for(settings), lights_);
  settings_ = settings;
  restir_ = Restir(restir_settings(settings));
  denoiser_ = Denoiser(settings.denoise);
  sum_ = Image(settings.width, settings.height);
  gbuffer_ = GBuffer();
  prev_gbuffer_ = GBuffer();
  denoised_ = Image();
  reset_history();
}

const Image& Renderer::image() const {
  return settings_.denoise.kind != DenoiserKind::None && denoised_.width == sum_.width ? denoised_ : noisy_image();
}

const Image& Renderer::noisy_image() const {
  if (noisy_.width != sum_.width || noisy_.height != sum_.height) noisy_ = Image(sum_.width, sum_.height);
  const float inv = accumulated_spp_ > 0 ? 1.0f / float(accumulated_spp_) : 0.0f;
  const size_t width = size_t(sum_.width);
  parallel_for_ranges(0, sum_.height, 8, [&](int y0, int y1) {
    for (size_t i = size_t(y0) * width; i < size_t(y1) * width; ++i) noisy_.pixels[i] = sum_.pixels[i] * inv;
  });
  return noisy_;
}

}  // namespace candela

#pragma once
// The convergence study (`candela converge`): each method accumulates 1-spp frames of a still camera
// and, at sample counts 1, 2, 4, ..., its image is compared with a converged reference: wall time,
// MSE, relMSE and the bias estimate (mean difference and its standard error).
//
// For every method "samples" = accumulated frames of one sample per pixel (for ReSTIR DI, frames of
// reuse; for the others, one path per pixel), so equal samples also means equal G-buffer passes.
#include <functional>
#include <string>
#include <vector>

#include "apps/renderer.h"
#include "engine/image_metrics.h"

namespace candela {

// What a method estimates, so that it is measured against the matching reference.
enum class Transport { Direct, Full };

// One row of the study.
struct ConvergeMethod {
  std::string name;
  Transport transport = Transport::Direct;
  std::function<void(RenderSettings&)> configure;  // sets method and options on top of the base settings
};

// direct-uniform, direct-power, direct-tree (light sampler + BSDF sample, MIS) and their -sobol twins
// (Owen-scrambled Sobol numbers, the others independent ones), restir-di-none,
// restir-di-basic, restir-di-pairwise (temporal and spatial reuse, candidates from the base light
// sampler), pt and pt-sobol (path tracer, base light sampler), restir (ReSTIR DI + GI, pairwise, paths of max_depth).
const std::vector<ConvergeMethod>& converge_methods();
// A method of converge_methods() by name, optionally followed by "+bilateral" or "+svgf" (its frames,
// denoised: the error of what a viewer shows); throws InputError listing the names.
ConvergeMethod converge_method_named(const std::string& name);

struct ConvergePoint {
  std::string method;
  int samples = 0;
  double time_ms = 0.0;  // wall time of all frames so far (scene update, G-buffer, estimator)
  ImageError error;
};

// Renders `method` (on top of `base`) frame by frame and measures the image at each count in `counts`
// (increasing); stops early once the frames so far took more than `max_seconds` (0 = no limit).
// `last_image`, if given, receives the image at the last count measured. Cost: max(counts) frames.
std::vector<ConvergePoint> run_convergence(const Scene& scene, const ConvergeMethod& method, const RenderSettings& base,
                                           const std::vector<int>& counts, const Image& reference,
                                           double max_seconds = 0.0, Image* last_image = nullptr);

// The light sampler of the reference `method` is measured against. References are rendered by the direct
// method or the path tracer; for those methods (direct-*, pt) the reference uses a light sampler the
// method does not, so that a reference rendered by the method's own estimator cannot hide its bias:
// power for the tree and the exhaustive sampler, the tree for uniform and power. ReSTIR methods are other
// estimators already and get the sampler they use (base's, for their candidates).
LightSamplerKind reference_light_sampler(const ConvergeMethod& method, const RenderSettings& base);

// The converged image of `transport` for `scene`: the path tracer (`max_depth` bounces for Full, the
// direct method for Direct) at `spp` samples per pixel with light sampler `sampler` and seed `seed`.
Image render_reference(const Scene& scene, Transport transport, const RenderSettings& base, LightSamplerKind sampler,
                       int spp, uint64_t seed);

// The wall time (ms) at which `points` (one method, by increasing samples) first reach relMSE `target`:
// log-log interpolation between the last point above it and the first at or below; the first point's
// time if that one is already below; -1 if none reaches it.
double time_to_error(const std::vector<ConvergePoint>& points, double target);

// Log-log least-squares slope of MSE against samples over the points with lo <= samples <= hi.
double mse_slope(const std::vector<ConvergePoint>& points, int lo, int hi);

struct ConvergeOptions {
  std::string scene;
  int lights = 1024;
  float environment = -1.0f;
  std::vector<std::string> methods;
  std::string reference, reference_direct;  // given EXRs (else rendered)
  int reference_spp = 1024;
  int max_spp = 256;
  double max_seconds = 0.0;
  double target_rel_mse = 0.01;  // the time-to-error summary's relMSE
  std::string csv, plot;
  bool quiet = false;
  RenderSettings base;
};

// Loads the scene, gets the references, runs every method, writes the CSV (and the plot). Exit status.
int run_converge(const ConvergeOptions& options);

}  // namespace candela

// `candela bench --suite soak`: a long run that must stay clean. ReSTIR (DI + GI) with SVGF renders
// builtin:city (its cars moving) from a camera orbiting the scene's target, at a small size; reports the
// non-finite pixels of the displayed frames and the NaN/Inf values the stages dropped (both should be
// 0), and the resident memory (VmRSS) after warm-up and at the end (it should stay flat).
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>

#include "apps/bench.h"
#include "apps/renderer.h"
#include "apps/scene_source.h"

namespace candela {

namespace {

// Resident memory of this process in MiB (VmRSS of /proc/self/status); 0 where it is unavailable.
double resident_mib() {
  std::ifstream status("/proc/self/status");
  for (std::string line; std::getline(status, line);)
    if (line.rfind("VmRSS:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;
  return 0.0;
}

// The camera of frame f: the scene's camera orbiting its target, one turn per 600 frames (20 s at 30 fps).
CameraDesc orbit_camera(const CameraDesc& start, int f) {
  const float angle = 2.0f * kPi * float(f % 600) / 600.0f;
  const vec3 offset = start.position - start.target;
  const float c = std::cos(angle), s = std::sin(angle);
  CameraDesc camera = start;
  camera.position = start.target + vec3(c * offset.x - s * offset.z, offset.y, s * offset.x + c * offset.z);
  return camera;
}

}  // namespace

int run_soak_bench(const BenchOptions& o) {
  RenderSettings settings;
  settings.width = o.width;
  settings.height = o.height;
  settings.method = Method::Restir;
  settings.denoise.kind = DenoiserKind::Svgf;
  settings.accumulate = false;
  Scene scene = load_scene("builtin:city");
  const CameraDesc start = scene.default_camera();
  Renderer renderer(std::move(scene), settings);
  const int warmup = std::min(100, o.soak_frames / 10);
  std::printf("soak: builtin:city, restir + svgf, %dx%d, %d frames (%d warm-up), orbiting camera\n", o.width, o.height,
              o.soak_frames, warmup);
  uint64_t bad_pixels = 0, dropped = 0;
  double rss_after_warmup = resident_mib(), total_ms = 0.0;
  for (int f = 0; f < o.soak_frames; ++f) {
    const FrameStats stats = renderer.render_frame(f, float(f) / 30.0f, orbit_camera(start, f));
    for (const vec3& p : renderer.image().pixels) bad_pixels += is_finite(p) ? 0 : 1;
    dropped += stats.non_finite();
    total_ms += stats.total_ms;
    if (f + 1 == warmup) rss_after_warmup = resident_mib();
    if ((f + 1) % 1000 == 0 || f + 1 == o.soak_frames)
      std::printf("frame %6d: VmRSS %.1f MiB, non-finite pixels %llu, dropped NaN/Inf %llu, %.2f ms/frame\n", f + 1,
                  resident_mib(), static_cast<unsigned long long>(bad_pixels), static_cast<unsigned long long>(dropped),
                  total_ms / (f + 1));
    std::fflush(stdout);  // progress shows through pipes and logs as it happens
  }
  const double rss_end = resident_mib();
  std::printf(
      "soak summary: %d frames, non-finite pixels %llu, dropped NaN/Inf %llu, VmRSS %.1f MiB after warm-up, "
      "%.1f MiB at the end (%+.1f MiB), %.2f ms/frame\n",
      o.soak_frames, static_cast<unsigned long long>(bad_pixels), static_cast<unsigned long long>(dropped),
      rss_after_warmup, rss_end, rss_end - rss_after_warmup, total_ms / o.soak_frames);
  return bad_pixels == 0 && dropped == 0 ? 0 : 1;
}

}  // namespace candela

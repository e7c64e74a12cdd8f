#include "engine/frame_stats.h"

#include "engine/ray_log.h"

namespace candela {

uint64_t FrameStats::rays() const {
  uint64_t n = 0;
  for (const StageStats& s : stages) n += s.rays;
  return n;
}

uint64_t FrameStats::non_finite() const {
  uint64_t n = 0;
  for (const StageStats& s : stages) n += s.non_finite;
  return n;
}

double FrameStats::stage_ms(const std::string& name) const {
  double ms = 0.0;
  for (const StageStats& s : stages)
    if (s.name == name) ms += s.ms;
  return ms;
}

uint64_t FrameStats::stage_rays(const std::string& name) const {
  uint64_t rays = 0;
  for (const StageStats& s : stages)
    if (s.name == name) rays += s.rays;
  return rays;
}

void FrameStats::add(const std::string& name, double ms, uint64_t rays, uint64_t non_finite) {
  for (StageStats& s : stages)
    if (s.name == name) {
      s.ms += ms;
      s.rays += rays;
      s.non_finite += non_finite;
      return;
    }
  stages.push_back({name, ms, rays, non_finite});
}

StageTimer::StageTimer(FrameStats& stats, std::string name)
    : stats_(stats), name_(std::move(name)), start_(std::chrono::steady_clock::now()) {
  if (stats_.ray_log) stats_.ray_log->begin_stage(name_);
}

StageTimer::~StageTimer() {
  if (stats_.ray_log) stats_.ray_log->end_stage();
  double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_).count();
  stats_.add(name_, ms, rays_.count.load(), non_finite_.count.load());
}

}  // namespace candela

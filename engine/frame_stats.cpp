#include "engine/frame_stats.h"

namespace candela {

uint64_t FrameStats::rays() const {
  uint64_t n = 0;
  for (const StageStats& s : stages) n += s.rays;
  return n;
}

double FrameStats::stage_ms(const std::string& name) const {
  double ms = 0.0;
  for (const StageStats& s : stages)
    if (s.name == name) ms += s.ms;
  return ms;
}

void FrameStats::add(const std::string& name, double ms, uint64_t rays) {
  for (StageStats& s : stages)
    if (s.name == name) {
      s.ms += ms;
      s.rays += rays;
      return;
    }
  stages.push_back({name, ms, rays});
}

StageTimer::StageTimer(FrameStats& stats, std::string name)
    : stats_(stats), name_(std::move(name)), start_(std::chrono::steady_clock::now()) {}

StageTimer::~StageTimer() {
  double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start_).count();
  stats_.add(name_, ms, rays_.count.load());
}

}  // namespace candela

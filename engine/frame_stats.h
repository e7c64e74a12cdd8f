#pragma once
// Per-frame, per-stage wall time, ray counts and dropped non-finite values: every stage opens a
// StageTimer, adds the rays it traced and the NaN/Inf values it dropped, and the timer records them into
// the frame's stats when it goes out of scope.
#include <atomic>
#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

namespace candela {

struct StageStats {
  std::string name;
  double ms = 0.0;
  uint64_t rays = 0;
  uint64_t non_finite = 0;  // NaN or infinite samples (or pixels) the stage dropped instead of adding
};

class RayLog;

struct FrameStats {
  RayLog* ray_log = nullptr;  // where the frame's ray queries are recorded (engine/ray_log.h): its StageTimers tag them
  int frame = 0;
  int spp = 0;  // samples per pixel the frame's estimator took
  double total_ms = 0.0;
  std::vector<StageStats> stages;
  uint64_t rays() const;
  uint64_t non_finite() const;                         // over all stages
  double stage_ms(const std::string& name) const;      // 0 if the stage did not run
  uint64_t stage_rays(const std::string& name) const;  // 0 if the stage did not run
  // Adds time, rays and dropped non-finite values to stage `name` (a stage run several times in a frame,
  // e.g. per sample pass, is one entry).
  void add(const std::string& name, double ms, uint64_t rays, uint64_t non_finite = 0);
};

// Thread-safe counter a stage's tiles add to: rays once per tile (not per ray), dropped non-finite
// values where they happen (rare, so an atomic add each costs nothing).
struct Counter {
  std::atomic<uint64_t> count{0};
  void add(uint64_t n) { count.fetch_add(n, std::memory_order_relaxed); }
};
using RayCounter = Counter;

class StageTimer {
 public:
  StageTimer(FrameStats& stats, std::string name);
  ~StageTimer();
  StageTimer(const StageTimer&) = delete;
  StageTimer& operator=(const StageTimer&) = delete;
  RayCounter& rays() { return rays_; }
  Counter& non_finite() { return non_finite_; }

 private:
  FrameStats& stats_;
  std::string name_;
  RayCounter rays_;
  Counter non_finite_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace candela

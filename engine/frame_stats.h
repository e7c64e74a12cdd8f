#pragma once
// Per-frame, per-stage wall time and ray counts: every stage opens a StageTimer, adds the rays it traced,
// and the timer records both into the frame's stats when it goes out of scope.
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
};

struct FrameStats {
  int frame = 0;
  int spp = 0;  // samples per pixel the frame's estimator took
  double total_ms = 0.0;
  std::vector<StageStats> stages;
  uint64_t rays() const;
  double stage_ms(const std::string& name) const;  // 0 if the stage did not run
  // Adds time and rays to stage `name` (a stage run several times in a frame, e.g. per sample pass, is one entry).
  void add(const std::string& name, double ms, uint64_t rays);
};

// Thread-safe ray counter a stage's tiles add to (once per tile, not per ray).
struct RayCounter {
  std::atomic<uint64_t> count{0};
  void add(uint64_t n) { count.fetch_add(n, std::memory_order_relaxed); }
};

class StageTimer {
 public:
  StageTimer(FrameStats& stats, std::string name);
  ~StageTimer();
  StageTimer(const StageTimer&) = delete;
  StageTimer& operator=(const StageTimer&) = delete;
  RayCounter& rays() { return rays_; }

 private:
  FrameStats& stats_;
  std::string name_;
  RayCounter rays_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace candela

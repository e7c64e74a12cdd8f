#include "apps/viewer/dynamic_scale.h"

#include <algorithm>
#include <cmath>

namespace candela {

// Reads the frame time and the target; writes the factor. Cost: a sort of at most 6 numbers per frame.
bool DynamicScale::update(double frame_ms, float target_fps, float min_factor) {
  if (target_fps <= 0.0f) {
    const bool moved = factor_ != 1.0f;
    factor_ = 1.0f;
    frames_at_factor_ = 0;
    measured_.clear();
    return moved;
  }
  if (++frames_at_factor_ > kSkipFrames) measured_.push_back(frame_ms);
  if (frames_at_factor_ < kSettleFrames) return false;
  // The last kSettleFrames - kSkipFrames frames (the factor may sit at a bound for longer).
  if (measured_.size() > size_t(kSettleFrames - kSkipFrames)) measured_.erase(measured_.begin());
  std::vector<double> sorted = measured_;
  std::sort(sorted.begin(), sorted.end());
  const double median = sorted[sorted.size() / 2];
  const double target_ms = 1000.0 / target_fps;
  if (median <= target_ms && median >= kGrowBelow * target_ms) return false;  // holds the target, no room to grow
  const float wanted = std::clamp(float(factor_ * std::sqrt(kAim * target_ms / std::max(median, 1e-3))),
                                  std::min(min_factor, 1.0f), 1.0f);
  if (wanted == factor_) return false;  // at a bound
  factor_ = wanted;
  frames_at_factor_ = 0;
  measured_.clear();
  return true;
}

}  // namespace candela

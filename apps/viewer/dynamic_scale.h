#pragma once
// Dynamic resolution (`candela view --target-fps`): the factor on the render scale that holds a target frame
// rate, as games do. A frame's time grows with its pixel count, that is with the square of the factor, plus
// what does not (display, HUD); the factor moves by sqrt(aim / measured) and repeats the step until the
// measured time lies in a band under the target, so the part that does not scale is found by iteration.
#include <vector>

namespace candela {

class DynamicScale {
 public:
  // The frame times are measured at a factor for kSettleFrames frames before it may move again; the first
  // kSkipFrames of them are left out (the viewer's loop times the frame before, at the old size, and a move
  // restarts the Renderer's history, whose first frame reuses nothing and resamples more), and the median of the
  // rest is the time at this factor (one slow frame moves a mean, not a median).
  static constexpr int kSettleFrames = 8, kSkipFrames = 2;
  // A move aims at kAim x the target's frame time (room for the frames' spread); the factor grows only while
  // the measured time is under kGrowBelow x the target (so that a larger one still meets it), and shrinks as
  // soon as it is over the target.
  static constexpr double kAim = 0.9, kGrowBelow = 0.75;

  // The factor on the render scale, in [min_factor, 1] (1 without a target).
  float factor() const { return factor_; }

  // Takes one frame's time (ms) with the target rate (0: off, the factor returns to 1) and the smallest factor
  // allowed. Returns whether the factor moved (the next frame renders at the new size).
  bool update(double frame_ms, float target_fps, float min_factor);

 private:
  float factor_ = 1.0f;
  int frames_at_factor_ = 0;
  std::vector<double> measured_;  // the frame times at this factor after the skipped ones
};

}  // namespace candela

#pragma once
// Renders a shot script's frames: resumes (skips frames whose files all exist), renders a shard of the
// range after unwritten warm-up frames, writes frames, AOVs and per-frame stats, shows progress.
//
// Frames are reproducible: frame f is rendered as render_frame(f, f / fps, camera(f)) with accumulation
// off, so methods without history give the same bits in any run that renders f. Methods with history
// (ReSTIR DI temporal reuse, SVGF, the motion AOV) depend on the frames before: a run renders warm-up
// frames first, and the output equals a single run's bit for bit when the warm-up reaches back to the
// sequence's first frame or to a history reset point (script key history_reset_every).
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "apps/shot_script.h"

namespace candela {

struct SequenceOptions {
  std::optional<std::pair<int, int>> range;  // --frames A:B (inclusive); default: the script's frames
  std::optional<int> warmup;                 // --warmup W; default: the script's "warmup"
  int stop_after = 0;                        // > 0: stop after writing this many frames (tests, quick looks)
  bool quiet = false;
};

struct PlannedFrame {
  int frame = 0;
  bool write = false;  // false: warm-up, rendered for its history only
  bool reset = false;  // reset the renderer's history before this frame
};

struct SequencePlan {
  std::vector<PlannedFrame> frames;  // in render order
  int finished = 0;                  // frames of the range already written (skipped)
  bool exact = true;                 // every written frame equals the single run's, bit for bit
};

// Which frames of [first, last] to render, in order: the unfinished ones, each after its warm-up
// (history methods: back to the last history reset point if the script has them, else `warmup` frames,
// never before the script's first frame). Reads only `finished(frame)`; costs O(frames).
SequencePlan plan_sequence(const ShotScript& script, int first, int last, int warmup,
                           const std::function<bool(int)>& finished);

// A frame is finished when every output file of it exists (files appear atomically).
bool frame_finished(const ShotScript& script, int frame);

// Parses --frames "A:B" (inclusive) or "A" against the script's range; throws InputError.
std::pair<int, int> parse_frame_range(const std::string& text, const ShotScript& script);

// Loads the scene, plans, renders and writes. Returns the process exit status.
int run_sequence(const ShotScript& script, const SequenceOptions& options);

}  // namespace candela

#pragma once
// The target function values that reuse reads, evaluated in SIMD lanes for a tile row of combinations at
// once (one pixel per lane) before the combinations run. A combination (reuse.cpp) resamples each input
// k's sample y_k at the combining pixel (input 0), which needs p_0(y_k), and with pairwise MIS weighs the
// combining pixel's own sample by every other input's target, p_k(y_0): 2 evaluations per input, each at
// a receiver that is used for nothing else. Scalar, every one rebuilt the receiver from its packed surface
// and evaluated it alone; here the receivers are built in lanes (receiver_lanes.h) and evaluated in lanes
// (target_lanes.h), with the scalar code's bits. Samples whose lights moved since their frame are
// re-placed here as the combination would re-place them. What the lanes cannot take (punctual lights and
// basic MIS's other pairs) is left to the combination, which evaluates it as before.
#include <cstdint>

#include "engine/scene.h"
#include "restir/reuse.h"
#include "restir/target_lanes.h"

namespace candela {

inline constexpr int kMaxReuseInputs = 32;  // a pixel and up to 31 neighbours

// One tile row of combinations as planes, input k of slot s at [k][s]: slot s combines inputs[0..count[s])[s]
// (input 0: the pixel of the slot, and the slots' pixels are consecutive, a tile row's); every slot's input k
// (k >= 1) comes from the same domain, and all inputs 0 from the same one. The targets evaluated beforehand are planes
// of the same shape: bit k of known_at[s] says at_combiner[k][s] = p_0(y_k) was evaluated, bit k of known_of[s] that
// of_combiner[k][s] = p_k(y_0) was, and bit k of known_visible[s] that bit k of visible[s] says whether y_0 is visible
// from input k's surface. (Laid out per slot, [s][k], every pass over one input of the row's slots touched a cache line
// per slot.)
struct ReuseRow {
  int count[kLaneSlots];
  ReuseInput inputs[kMaxReuseInputs][kLaneSlots];
  // Copied from the inputs' reservoirs by set_input, where the stage that gathers the inputs reads them first, so that
  // the later passes over the row (the placements, targets_known, the combination lanes) read planes instead of
  // following each input's pointer again: W[k][s] and own[k][s] are input k's W and p_hat_y (k < count[s]); bit k of
  // sampled[s]: its W > 0.
  uint32_t sampled[kLaneSlots];
  alignas(64) float W[kMaxReuseInputs][kLaneSlots];
  alignas(64) float own[kMaxReuseInputs][kLaneSlots];
  uint32_t known_at[kLaneSlots], known_of[kLaneSlots], known_visible[kLaneSlots], visible[kLaneSlots];
  alignas(64) float at_combiner[kMaxReuseInputs][kLaneSlots];
  alignas(64) float of_combiner[kMaxReuseInputs][kLaneSlots];

  // Input k of slot s, with its reservoir's planes; a slot's inputs are set in order from k = 0.
  void set_input(int k, int s, const ReuseInput& in) {
    inputs[k][s] = in;
    const ReuseReservoir& r = *in.reservoir;
    W[k][s] = r.W, own[k][s] = r.p_hat_y;
    sampled[s] = (k == 0 ? 0u : sampled[s]) | uint32_t(r.W > 0.0f) << k;
  }
};

// The targets of row's slots [0, slots) (whose inputs set_input gave): p_0(y_k) for every input k >= 1 with a sample,
// with `of_combiner` (the MIS weights read it) p_k(y_0) where the slot's own reservoir has a sample, and with
// `visibility` (MIS weights with visibility) whether y_0 is visible from input k's surface where p_k(y_0) > 0. Cost per
// slot and input: 2 receiver builds and 2 target evaluations in lanes, plus transposing surfaces and samples into
// planes (and placing a moved light's sample on it again), and with visibility one shadow ray, traced in packets of 16
// in slot order. Returns the rays traced.
uint64_t evaluate_reuse_targets(const SceneView& view, int slots, bool of_combiner, bool visibility, ReuseRow& row);

}  // namespace candela

#pragma once
// ReSTIR's streaming resampling in SIMD lanes, one tile row of pixels at a time (one pixel per lane), once
// the targets are known: the light candidates of the first stage (di_candidates.h, resample_candidates) and
// reuse's combinations with pairwise MIS (reuse.cpp, pairwise_weight and combine). Scalar, each
// candidate's keep-or-not is a coin flip, a mispredicted branch about every other time, and every kept
// candidate copies a 64-byte sample; here the weights and Reservoir::update run in lanes and only the kept
// candidate's sample is copied, once per pixel. The kernels (Google Highway, run-time dispatch) repeat the
// scalar code's operations in its order without fused multiply-adds, so they return its bits
// (tests/test_target_lanes.cpp, ReservoirsEqualTheScalarPath).
#include "restir/reuse_targets.h"

namespace candela {

// What Reservoir::update leaves per slot after a stream of candidates: the kept candidate (-1: none), its
// target and the sum of the resampling weights.
struct StreamLanes {
  alignas(64) float chosen[kLaneSlots], p_hat[kLaneSlots], w_sum[kLaneSlots];
};

// The light candidates of slots [0, slots) streamed into empty reservoirs: candidate k of slot s (plane k's
// target and BSDF area density, p_light and u at [k * kLaneSlots + s]) has the balance heuristic's weight
// w = p_hat / (M_l p_light + M_b p_bsdf) (Talbot et al. 2005; M_l[s]: the slot's count) where p_light > 0 and
// p_hat > 0, and is kept with probability w / w_sum. M_l is 64-byte aligned; p_light and u need no alignment. Cost
// per candidate: a division and 5 flops, in lanes.
void resample_light_candidates_lanes(const CandidateLanes* planes, const float* p_light, const float* u, int count,
                                     const float* M_l, float M_b, int slots, StreamLanes& out);

// One tile row of combinations as planes, input k of slot s at [k][s]; inputs at k >= count[s] are ignored.
struct CombineLanes {
  alignas(64) float count[kLaneSlots];               // inputs of the slot (input 0: the combining pixel)
  alignas(64) float M[kMaxReuseInputs][kLaneSlots];  // confidence the combination gives input k
  const float (*W)[kLaneSlots] = nullptr;            // its contribution weight (<= 0: no sample; ReuseRow's plane)
  const float (*own)[kLaneSlots] = nullptr;          // p_k(y_k): the target its reservoir stored (ReuseRow's)
  const float (*at)[kLaneSlots] = nullptr;           // p_0(y_k), k >= 1 (read where W > 0; ReuseRow's plane)
  const float (*of)[kLaneSlots] = nullptr;           // p_k(y_0), k >= 1 (read where input 0's W > 0; ReuseRow's)
  alignas(64) float u[kMaxReuseInputs][kLaneSlots];  // resampling uniform of input k
  // With visibility: 1 where y_k is visible from input k's surface, and where y_0 is (read where the
  // weights' terms are positive).
  alignas(64) float own_visible[kMaxReuseInputs][kLaneSlots];
  alignas(64) float of_visible[kMaxReuseInputs][kLaneSlots];
  // Written by the kernel: the stream's result, the total confidence and the result's contribution weight
  // (Reservoir::finalize), and each input's resampling weight (0 where it was skipped; inputs below max_count).
  StreamLanes result;
  alignas(64) float w[kMaxReuseInputs][kLaneSlots];
  alignas(64) float M_sum[kLaneSlots], W_out[kLaneSlots];
  // Written by systematic_picks_lanes: sample j's input, j = 1 .. n - 1 (sample 0 is result.chosen).
  alignas(64) float picks[kMaxShadedSamples][kLaneSlots];
};

// The combinations of slots [0, slots), each over its count inputs (count >= 1; up to max_count): the pairwise
// MIS weight m_k of every input's sample (Bitterli 2022, ch. 9; reuse.cpp), its resampling weight
// m_k p_0(y_k) W_k streamed through one reservoir with uniform u_k, then the result's contribution weight.
// With `visibility` every neighbour's term counts only where the sample is visible from its surface.
// Cost per slot: ~4 divisions and 12 flops per input, in lanes.
void combine_pairwise_lanes(CombineLanes& lanes, int slots, int max_count, bool visibility);

// systematic_picks (reservoir.h) of the combinations combine_pairwise_lanes streamed, slots [0, slots): n samples of
// each slot's weights w (its count inputs), the first the kept input result.chosen, the others into picks[1 .. n)
// (2 <= n <= kMaxShadedSamples), with v[s] the slot's uniform (v 64-byte aligned). The scalar function's operations in
// its order, so the same picks; slots that kept no input (chosen < 0) get picks nobody may read. Cost per slot: a pass
// over the weights, and one per pick, in lanes.
void systematic_picks_lanes(CombineLanes& lanes, const float* v, int n, int slots, int max_count);

}  // namespace candela

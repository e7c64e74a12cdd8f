#pragma once
// ReSTIR reuse's combinations with pairwise MIS (di_reuse.cpp, pairwise_weight and combine) in SIMD lanes:
// one tile row's combinations at once, one pixel per lane, once every target the weights read has been
// evaluated (reuse_targets.h). The scalar combination branches per input and copies a 64-byte sample per
// kept candidate; here the weights, the streaming resampling and the final weight are computed in lanes and
// only the kept input's sample is copied, once per pixel. The kernel (Google Highway, run-time dispatch)
// repeats the scalar code's operations in its order without fused multiply-adds, so it returns its bits
// (tests/test_target_lanes.cpp, ReservoirsEqualTheScalarPath).
#include "restir/reuse_targets.h"

namespace candela {

// One tile row of combinations as planes, input k of slot s at [k][s]; inputs at k >= count[s] are ignored.
struct CombineLanes {
  alignas(64) float count[kLaneSlots];                 // inputs of the slot (input 0: the combining pixel)
  alignas(64) float M[kMaxReuseInputs][kLaneSlots];    // confidence the combination gives input k
  alignas(64) float W[kMaxReuseInputs][kLaneSlots];    // its contribution weight (<= 0: no sample)
  alignas(64) float own[kMaxReuseInputs][kLaneSlots];  // p_k(y_k): the target its reservoir stored
  alignas(64) float at[kMaxReuseInputs][kLaneSlots];   // p_0(y_k), k >= 1 (read where W > 0)
  alignas(64) float of[kMaxReuseInputs][kLaneSlots];   // p_k(y_0), k >= 1 (read where input 0's W > 0)
  alignas(64) float u[kMaxReuseInputs][kLaneSlots];    // resampling uniform of input k
  // Written by the kernel: the kept input (-1: none), its target at the combining pixel, the sum of the
  // resampling weights, the total confidence and the result's contribution weight (Reservoir::finalize).
  alignas(64) float chosen[kLaneSlots], p_hat[kLaneSlots], w_sum[kLaneSlots], M_sum[kLaneSlots], W_out[kLaneSlots];
};

// The combinations of slots [0, slots), each over its count inputs (count >= 1; up to max_count): the pairwise
// MIS weight m_k of every input's sample (Bitterli 2022, ch. 9; di_reuse.cpp), its resampling weight
// m_k p_0(y_k) W_k streamed through one reservoir with uniform u_k, then the result's contribution weight.
// Cost per slot: ~4 divisions and 12 flops per input, in lanes.
void combine_pairwise_lanes(CombineLanes& lanes, int slots, int max_count);

}  // namespace candela

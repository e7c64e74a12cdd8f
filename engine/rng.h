#pragma once
// Counter-based random streams: a sample's random numbers depend only on (seed, pixel, sample index,
// stream), never on which thread or in which order tiles run, so images are identical for any thread count.
#include <cstdint>

#include "engine/math.h"

namespace candela {

// 64-bit mix (SplitMix64 finaliser, Steele et al. 2014).
inline uint64_t mix64(uint64_t z) {
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return z ^ (z >> 31);
}

// PCG32 (O'Neill 2014): 64-bit state, 32-bit output, one multiply-add per number.
class Rng {
 public:
  Rng() : Rng(0, 0) {}
  // PCG32's seeding: the increment from the stream, then two steps with the seed added between them.
  Rng(uint64_t seed, uint64_t stream) : inc_(increment(stream)) { state_ = first_state(seed, inc_); }
  // A stream keyed by several integers (seed, pixel, sample, pass...).
  static Rng for_key(uint64_t seed, uint64_t a, uint64_t b = 0, uint64_t c = 0) {
    return Rng(key_seed(seed, a, b), key_stream(a, b, c));
  }
  uint32_t next_u32() { return step(state_, inc_); }
  // Uniform float in [0, 1).
  float next_float() { return to_float(next_u32()); }
  // Two of them, for a 2D decision (the interface engine/sobol.h's streams share).
  vec2 next_2d() { return vec2(next_float(), next_float()); }

  // One PCG32 step of the stream (state, inc): advances state, returns the output.
  static uint32_t step(uint64_t& state, uint64_t inc) {
    uint64_t old = state;
    state = old * kMultiplier + inc;
    uint32_t xorshifted = uint32_t(((old >> 18u) ^ old) >> 27u);
    uint32_t rot = uint32_t(old >> 59u);
    return (xorshifted >> rot) | (xorshifted << ((~rot + 1u) & 31));
  }
  static float to_float(uint32_t x) { return float(x >> 8) * 0x1p-24f; }

  // The parts of for_key and the constructor, for RngRow::key.
  static uint64_t key_seed(uint64_t seed, uint64_t a, uint64_t b) {
    return mix64(seed ^ mix64(a + 0x9e3779b97f4a7c15ull * (b + 1)));
  }
  static uint64_t key_stream(uint64_t a, uint64_t b, uint64_t c) { return mix64(c + 0x632be59bd9b4e019ull * (a ^ b)); }
  static uint64_t increment(uint64_t stream) { return (mix64(stream) << 1u) | 1u; }
  // The state after the constructor's two steps (from 0: the first gives inc; the seed's mix is added).
  static uint64_t first_state(uint64_t seed, uint64_t inc) { return (inc + mix64(seed)) * kMultiplier + inc; }

 private:
  static constexpr uint64_t kMultiplier = 6364136223846793005ull;
  template <int>
  friend struct RngRow;
  struct Raw {};
  Rng(Raw, uint64_t state, uint64_t inc) : state_(state), inc_(inc) {}
  uint64_t state_, inc_;
};

// N streams advanced together: fill() writes the next numbers of every slot's stream, the same numbers
// next_float would give one stream at a time. One number of every slot per step, so that the slots'
// independent multiply chains overlap (and vectorise) where one stream's numbers would each wait on the
// last. Cost per number: one 64-bit multiply-add and a rotate, at throughput rather than latency.
template <int N>
struct RngRow {
  uint64_t state[N] = {}, inc[N] = {};
  Rng stream(int s) const { return Rng(Rng::Raw{}, state[s], inc[s]); }
  // The next number of slot s's stream alone (Rng::next_u32).
  uint32_t next_u32(int s) { return Rng::step(state[s], inc[s]); }
  // Slot s of [0, slots) gets Rng::for_key(seed, a + s, b, c): the same keying, in a loop over the slots that
  // the compiler vectorises (~12 64-bit multiplies per slot, at throughput rather than latency).
  void key(int slots, uint64_t seed, uint64_t a, uint64_t b, uint64_t c) {
    uint64_t* __restrict states = state;
    uint64_t* __restrict increments = inc;
    for (int s = 0; s < slots; ++s) {
      const uint64_t as = a + uint64_t(s), increment = Rng::increment(Rng::key_stream(as, b, c));
      increments[s] = increment;
      states[s] = Rng::first_state(Rng::key_seed(seed, as, b), increment);
    }
  }
  // Numbers n in [0, count) of slots [0, slots) into out[n * N + s].
  void fill(int count, int slots, float* __restrict out) {
    uint64_t* __restrict states = state;  // restrict: lets the compiler vectorise the slots' loop
    const uint64_t* __restrict increments = inc;
    for (int n = 0; n < count; ++n)
      for (int s = 0; s < slots; ++s) out[n * N + s] = Rng::to_float(Rng::step(states[s], increments[s]));
  }
};

}  // namespace candela

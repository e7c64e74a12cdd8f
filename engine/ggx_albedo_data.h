#pragma once
// The albedo table's layout, shared by its generator (ggx_albedo_gen.cpp, run at build time) and its reader
// (ggx_albedo.h). Rows per roughness r = k / (kGgxAlbedoRoughnessCount - 1), columns per
// sqrt(mu) = j / (kGgxAlbedoMuCount - 1), (a, b) per entry.
#include <cstdint>

namespace candela {

inline constexpr int kGgxAlbedoMuCount = 32;
inline constexpr int kGgxAlbedoRoughnessCount = 64;

extern const float kGgxAlbedoEntries[kGgxAlbedoRoughnessCount * kGgxAlbedoMuCount * 2];
extern const float kGgxAlbedoAverages[kGgxAlbedoRoughnessCount * 2];  // (a_avg, b_avg) per roughness
// The same two tables with each (a, b) pair's bits in one 64-bit word (a in the low half), for SIMD kernels that
// fetch a pair with one 64-bit gather instead of two 32-bit ones (engine/lanes-inl.h gather_pairs).
extern const uint64_t kGgxAlbedoEntryPairs[kGgxAlbedoRoughnessCount * kGgxAlbedoMuCount];
extern const uint64_t kGgxAlbedoAveragePairs[kGgxAlbedoRoughnessCount];
// kGgxAlbedoEntries again with each roughness row's a values first, then its b values (row k's a(mu_j) at
// [k * 2 * kGgxAlbedoMuCount + j], its b(mu_j) kGgxAlbedoMuCount later: row k starts where it starts in
// kGgxAlbedoEntries), each row starting on a 64-byte boundary, for SIMD kernels that load a whole row into registers
// (engine/lanes-inl.h albedo_corners).
alignas(64) extern const float kGgxAlbedoRowPlanes[kGgxAlbedoRoughnessCount * kGgxAlbedoMuCount * 2];

}  // namespace candela

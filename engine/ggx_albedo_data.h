#pragma once
// The albedo table's layout, shared by its generator (ggx_albedo_gen.cpp, run at build time) and its reader
// (ggx_albedo.h). Rows per roughness r = k / (kGgxAlbedoRoughnessCount - 1), columns per
// sqrt(mu) = j / (kGgxAlbedoMuCount - 1), (a, b) per entry.
namespace candela {

inline constexpr int kGgxAlbedoMuCount = 32;
inline constexpr int kGgxAlbedoRoughnessCount = 64;

extern const float kGgxAlbedoEntries[kGgxAlbedoRoughnessCount * kGgxAlbedoMuCount * 2];
extern const float kGgxAlbedoAverages[kGgxAlbedoRoughnessCount * 2];  // (a_avg, b_avg) per roughness

}  // namespace candela

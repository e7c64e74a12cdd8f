#pragma once
// Which neighbours of a tile row of pixels may share samples with them, in SIMD lanes: reuse.h's
// similar_surfaces (close in linear depth, shading normals within a cosine) for every slot and neighbour of the row at
// once. One at a time, each neighbour's octahedral normal cost a dependent square root and division
// (about 5% of a restir-di frame, measured by leaving the normal test out); in lanes they cost a
// sixteenth of that. The kernel repeats the scalar operations in order (engine/octahedral.h oct_decode,
// glm::dot), so it gives the scalar answers (tests/test_target_lanes.cpp).
#include <cstdint>

#include "engine/packed_surface.h"
#include "engine/tiles.h"
#include "restir/reuse_targets.h"

namespace candela {

inline constexpr int kMaxNeighbours = kMaxReuseInputs - 1;

// Per slot of a row: the pixel's surface (depth and shading normal) and its neighbours' (neighbour k of
// slot s at [k][s]; depth kInfinity: no surface, never similar); the kernel writes `similar`.
struct NeighbourLanes {
  alignas(64) float depth[kLaneSlots];
  alignas(64) uint32_t normal[kLaneSlots];
  alignas(64) float neighbour_depth[kMaxNeighbours][kLaneSlots];
  alignas(64) uint32_t neighbour_normal[kMaxNeighbours][kLaneSlots];
  alignas(64) uint32_t similar[kMaxNeighbours][kLaneSlots];  // nonzero where similar
  void set(int slot, const PackedSurface& s) { depth[slot] = s.depth, normal[slot] = s.shading_normal; }
  void set_neighbour(int k, int slot, const PackedSurface& s) {
    neighbour_depth[k][slot] = s.depth, neighbour_normal[k][slot] = s.shading_normal;
  }
  void clear_neighbour(int k, int slot) { neighbour_depth[k][slot] = kInfinity, neighbour_normal[k][slot] = 0; }
};

// Writes similar[k][s] for neighbours k < count of slots [0, slots): whether neighbour k of slot s has a
// surface whose depth differs from the slot's by at most depth_tolerance times the slot's depth and whose
// shading normal has a cosine of at least normal_tolerance with the slot's. Cost per pair: one octahedral
// decode (a square root and a division) and ~20 flops, in lanes.
void similar_neighbour_lanes(NeighbourLanes& lanes, int count, int slots, float depth_tolerance,
                             float normal_tolerance);

}  // namespace candela

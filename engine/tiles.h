#pragma once
// Tile-parallel loop over an image: square tiles handed to the workers of engine/parallel.h, each worker
// with flush-to-zero set. The result never depends on which thread ran which tile (stages key randomness
// on pixels).
#include "engine/frame_stats.h"
#include "engine/parallel.h"
#include "engine/tracer.h"

namespace candela {

struct Tile {
  int x0, y0, x1, y1;  // half-open pixel rectangle
};

inline constexpr int kTileWidth = 64, kTileHeight = 4;

template <class Fn>
void for_each_tile(int width, int height, Fn&& fn) {
  int tiles_x = (width + kTileWidth - 1) / kTileWidth, tiles_y = (height + kTileHeight - 1) / kTileHeight;
  parallel_for(0, tiles_x * tiles_y, [&](int t) {
    enable_ftz_daz();
    int x0 = (t % tiles_x) * kTileWidth, y0 = (t / tiles_x) * kTileHeight;
    fn(Tile{x0, y0, std::min(x0 + kTileWidth, width), std::min(y0 + kTileHeight, height)});
  });
}

// Per-pixel loop over the tiles: fn(pixel index, x, y) returns how many rays it traced; the counts are
// added to `rays` once per tile.
template <class Fn>
void for_each_pixel(int width, int height, RayCounter& rays, Fn&& fn) {
  for_each_tile(width, height, [&](const Tile& tile) {
    uint64_t traced = 0;
    for (int y = tile.y0; y < tile.y1; ++y)
      for (int x = tile.x0; x < tile.x1; ++x) traced += fn(size_t(y) * size_t(width) + size_t(x), x, y);
    rays.add(traced);
  });
}

// The same for stages that trace no rays: fn(pixel index, x, y).
template <class Fn>
void for_each_pixel(int width, int height, Fn&& fn) {
  RayCounter none;
  for_each_pixel(width, height, none, [&](size_t i, int x, int y) -> uint64_t {
    fn(i, x, y);
    return 0;
  });
}

}  // namespace candela

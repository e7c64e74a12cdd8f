#pragma once
// Tile-parallel loop over an image: square tiles handed to TBB workers, each worker with flush-to-zero
// set. The result never depends on which thread ran which tile (stages key randomness on pixels).
#include <tbb/parallel_for.h>

#include "engine/tracer.h"

namespace candela {

struct Tile {
  int x0, y0, x1, y1;  // half-open pixel rectangle
};

inline constexpr int kTileWidth = 64, kTileHeight = 4;

template <class Fn>
void for_each_tile(int width, int height, Fn&& fn) {
  int tiles_x = (width + kTileWidth - 1) / kTileWidth, tiles_y = (height + kTileHeight - 1) / kTileHeight;
  tbb::parallel_for(0, tiles_x * tiles_y, [&](int t) {
    enable_ftz_daz();
    int x0 = (t % tiles_x) * kTileWidth, y0 = (t / tiles_x) * kTileHeight;
    fn(Tile{x0, y0, std::min(x0 + kTileWidth, width), std::min(y0 + kTileHeight, height)});
  });
}

}  // namespace candela

#pragma once
// Image planes of the denoisers (structure of arrays: one contiguous float array per channel, so that a
// row of pixels is a run of floats the compiler vectorises) and the row-parallel loop every stage uses.

#include <vector>

#include "engine/math.h"
#include "engine/parallel.h"
#include "engine/tracer.h"

namespace candela {

struct ColorPlanes {
  int width = 0, height = 0;
  std::vector<float> r, g, b;

  void resize(int w, int h) {
    width = w;
    height = h;
    r.assign(size(), 0.0f);
    g.assign(size(), 0.0f);
    b.assign(size(), 0.0f);
  }
  size_t size() const { return size_t(width) * size_t(height); }
  vec3 at(size_t i) const { return vec3(r[i], g[i], b[i]); }
  void set(size_t i, const vec3& c) {
    r[i] = c.x;
    g[i] = c.y;
    b[i] = c.z;
  }
};

// Runs fn(y) for every row y in [0, height), rows split into blocks over the TBB workers (each with
// flush-to-zero set). Stages write only their own rows, so the result does not depend on the split.
template <class Fn>
void for_each_row(int height, Fn&& fn) {
  parallel_for_ranges(0, height, 4, [&](int y0, int y1) {
    enable_ftz_daz();
    for (int y = y0; y < y1; ++y) fn(y);
  });
}

}  // namespace candela

#pragma once
// Per-pixel guides of the edge-stopping functions, gathered once per frame from the G-buffer into
// contiguous float planes (the G-buffer keeps normals and albedo as vec3 arrays; the filters' inner loops
// read 8 neighbouring pixels at once).
#include <vector>

#include "denoise/planes.h"
#include "engine/gbuffer.h"

namespace candela {

struct Guides {
  int width = 0, height = 0;
  std::vector<float> depth;        // linear view depth; kInfinity where nothing was hit
  std::vector<float> depth_slope;  // |dz/dx| + |dz/dy| (per pixel) on the pixel's own surface; 0 off hits
  std::vector<float> nx, ny, nz;   // shading normal; 0 where the pixel is not filtered, so every normal
                                   // weight towards it is 0 and no filter gathers from it
  ColorPlanes albedo;              // empty unless asked for (compute_guides' with_albedo)
  // 1 where the pixel is filtered: a surface was hit and no hit pixel of its 3x3 block has a different
  // emission. At an emitter's border, demodulation cannot be trusted: the radiance's own primary samples
  // may land elsewhere in the pixel than the G-buffer's (the path tracer jitters them independently),
  // and then L - Le is off by a whole emitter's radiance; those pixels keep their input and feed no
  // filter. Inside an emitter, the reflected light L - Le is filtered like any other.
  std::vector<uint8_t> filtered;
  std::vector<float> emission_luminance;  // compute_guides' scratch: the luminance of the emission seen

  size_t size() const { return size_t(width) * size_t(height); }
};

// Stage "denoise_guides": reads the G-buffer's depth, shading normal, emission and instance planes (and
// albedo, with_albedo); writes every plane of `out` (the albedo planes only with_albedo: SVGF has no use for
// them, and they are a quarter of the pass's memory traffic). Two passes over rows, O(pixels), in loops GCC
// vectorises: the emission's luminance (the scratch plane emission_luminance), then the filtered mask from
// the 3x3 block's luminances and instances, and the slope from the 4 neighbours' depth and instance.
void compute_guides(const GBuffer& g, bool with_albedo, Guides& out);

}  // namespace candela

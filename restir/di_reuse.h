#pragma once
// ReSTIR DI reuse (Bitterli et al. 2020, sections 4.2-4.3 and Alg. 4-6): a pixel's reservoir is combined
// with the previous frame's reservoir of the same surface (temporal) and with those of nearby pixels
// (spatial). Each input reservoir is one GRIS candidate (Lin et al. 2022) whose resampling MIS weight is
//   none:  m_k = M_k / sum_z M_z                                (biased where the domains' targets differ)
//   basic: m_k = M_k p_hat_k(y_k) / sum_z M_z p_hat_z(y_k)        (generalized balance heuristic, unbiased
//          when candidates were not visibility-tested; costs k^2 target evaluations per pixel)
//   pairwise: the pixel's own reservoir paired with each neighbour (see di_reuse.cpp); unbiased under the
//          same condition, k target evaluations
#include <vector>

#include "restir/di.h"

namespace candela {

enum class DiBiasCorrection : uint8_t { None, Basic, Pairwise };

struct DiReuseParams {
  bool temporal = true;
  float history_cap = 20.0f;      // the previous reservoir counts at most this many times the current M
  bool permutation_sampling = false;  // reproject onto a neighbour of the previous pixel (x ^ a, y ^ b, a and b
                                      // fixed per frame): decorrelates frames for a temporal denoiser; unbiased
                                      // with basic/pairwise, slightly blurrier
  bool spatial = true;
  int spatial_neighbours = 5;     // per pass; each costs k + 1 target evaluations in basic mode
  float spatial_radius = 16.0f;   // pixels
  int spatial_passes = 1;
  float depth_tolerance = 0.1f;   // neighbours whose linear depth differs by more (relative) are rejected
  float normal_tolerance = 0.9f;  // ... or whose normals' cosine is below this
  DiBiasCorrection bias = DiBiasCorrection::Pairwise;
  uint64_t seed = 0;
};

// Stage "di_temporal": reads this frame's G-buffer (motion), this and the previous frame's surfaces and
// reservoirs, writes `out` (one combined reservoir per pixel). Reprojects with the motion vectors. No rays.
void di_temporal_reuse(const SceneView& view, const GBuffer& g, const DiDomain& current, const DiDomain& previous,
                       const std::vector<DiReservoir>& reservoirs, const std::vector<DiReservoir>& history,
                       const DiReuseParams& params, int frame, std::vector<DiReservoir>& out);

// Stage "di_spatial": reads the surfaces and `in`, writes `out` combining each pixel with up to k
// similar neighbours within the radius. No rays. `pass` selects its own random stream.
void di_spatial_reuse(const SceneView& view, const DiDomain& current, const std::vector<DiReservoir>& in,
                      const DiReuseParams& params, int frame, int pass, std::vector<DiReservoir>& out);

}  // namespace candela

#pragma once
// Reuse of reservoirs, ReSTIR DI's and ReSTIR GI's alike (Bitterli et al. 2020, sections 4.2-4.3 and Alg. 4-6;
// Ouyang et al. 2021): a pixel's reservoir is combined with the previous frame's reservoir of the same
// surface (temporal) and with those of nearby pixels (spatial). Each input reservoir is one GRIS candidate (Lin et al.
// 2022) whose resampling MIS weight is
//   none:  m_k = M_k / sum_z M_z                                (biased where the domains' targets differ)
//   basic: m_k = M_k p_hat_k(y_k) / sum_z M_z p_hat_z(y_k)        (generalized balance heuristic, unbiased
//          when candidates were not visibility-tested, or with mis_visibility; k^2 target evaluations)
//   pairwise: the pixel's own reservoir paired with each neighbour (see reuse.cpp); unbiased under the
//          same condition, k target evaluations
#include <vector>

#include "restir/sample.h"
#include "restir/shade.h"

namespace candela {

enum class BiasCorrection : uint8_t { None, Basic, Pairwise };

inline constexpr int kMaxShadedSamples = 8;  // ReuseParams::shaded_samples's bound

struct ReuseParams {
  bool temporal = true;
  float history_cap = 20.0f;          // the previous reservoir counts at most this many times the current M
  bool permutation_sampling = false;  // reproject onto a neighbour of the previous pixel (x ^ a, y ^ b, a and b
                                      // fixed per frame): decorrelates frames for a temporal denoiser; unbiased
                                      // with basic/pairwise, slightly blurrier
  bool spatial = true;
  int spatial_neighbours = 3;        // per pass; each costs k + 1 target evaluations in basic mode; 3 beat 5 at
                                     // equal time on manylights, city and occluded_room with the radius of 8
                                     // (docs/restir.md, "Spatial radius at equal time")
  int disocclusion_neighbours = 10;  // first pass, pixels where temporal reuse found no history: more
                                     // neighbours make up for the lost history (a disocclusion boost); on moving
                                     // shots 3, 6 and 10 were within noise except city, where 10 won
                                     // (docs/restir.md, "Disocclusion neighbours in motion")
  float spatial_radius = 8.0f;       // pixels; 8 beat 16 and 32 at equal time on city and occluded_room and lost
                                     // 1-2% on manylights (docs/restir.md, "Spatial radius at equal time")
  int neighbour_block = 4;           // > 1: the pixels of each block this many pixels on a side take the same
                                     // neighbour offsets (cheaper: neighbouring pixels read neighbouring data;
                                     // unbiased, the choice ignores the samples); 4 chosen at equal time
                                     // (docs/restir.md, "Neighbour offsets")
  bool fused = false;  // with temporal and spatial reuse: one fused spatiotemporal pass (RTXDI's fused spatiotemporal
                       // resampling) instead of the temporal pass and the first spatial pass: the neighbours are last
                       // frame's reservoirs around the pixel's reprojection, with the reprojected pixel itself as the
                       // temporal input (see spatial_reuse's `previous`); one pass over the frame instead of two
  int spatial_passes = 1;
  int shaded_samples = 2;        // samples the last spatial pass keeps of each pixel's combination (stratified over its
                                 // weights), each shaded with weight 1/n; the first becomes history. Unbiased (each is
                                 // the one-sample estimator); with spatial reuse only. 2 chosen at equal time for DI
                                 // and GI (docs/restir.md, "Shaded samples at equal time")
  float depth_tolerance = 0.1f;  // neighbours whose linear depth differs by more (relative) are rejected
  float normal_tolerance = 0.9f;  // ... or whose normals' cosine is below this
  BiasCorrection bias = BiasCorrection::Pairwise;
  bool mis_visibility = false;      // the MIS weights include visibility of the sample from the other inputs'
                                    // surfaces: needed to stay unbiased when every input's samples are visible
                                    // from it (candidate_visibility; ReSTIR GI's samples, always). Shadow rays per
                                    // pixel: basic (k+1)^2, pairwise 2k; temporal inputs are tested against this
                                    // frame's geometry
  float boiling_threshold = 0.0f;   // > 0: after temporal reuse, drop reservoirs whose estimated contribution
                                    // exceeds this many times their 16x16 block's mean (biased: darkens; see
                                    // boiling_filter)
  int visibility_reuse_frames = 0;  // > 0: final visibility reuse for up to this many frames (see VisibilityReuse)
  bool drop_occluded = true;        // a reservoir whose sample the shading found occluded keeps its M but loses the
                                    // sample before it becomes history, so that reuse stops choosing it (see
                                    // Restir::reuse_and_shade; biased where visibility differs between frames or
                                    // neighbours, about -1.5% on manylights; frame error 0.45-0.67x:
                                    // docs/restir.md, "Occluded samples")
  int max_sample_age = 0;           // > 0: temporal reuse drops history whose sample is older (frames); 0: no limit
  float min_roughness = 0.0f;       // pixels smoother than this keep their own reservoir (no reuse): where the BSDF
                                    // is sharp, neighbours' samples rarely fit and their weights explode
  float max_jacobian = 0.0f;        // > 0, surface-point samples (ReSTIR GI): a reused sample whose reconnection
                                    // Jacobian (Ouyang et al. 2021, eq. 11: the ratio of its solid angle per area
                                    // seen from this pixel to that from its own) exceeds this is rejected. Biased
                                    // (drops the samples that would be fireflies); 0: unbiased
  bool simd = true;                 // evaluate the combinations' targets in SIMD lanes (reuse_targets.h); false: the
                                    // scalar reference, which gives the same bits
  uint64_t seed = 0;
};

// One input of a combination: a reservoir and the domain/pixel whose target function produced it.
struct ReuseInput {
  const ReuseReservoir* reservoir;
  const ReuseDomain* domain;
  size_t pixel;
  float M;                  // confidence used for this input (capped for history)
  int8_t own_visible = -1;  // 1 or 0: whether the reservoir's sample is visible from its own surface, when
                            // known already; -1: a ray finds out if a weight needs it
  uint8_t age_step = 0;     // frames its sample ages by entering the combination (1 for last frame's history)
};

// Whether surface b may share samples with surface a (shading normal a_n, decoded by the caller once for
// all of a's neighbours): b has a surface within params.depth_tolerance of a's depth (relative) and a shading
// normal whose cosine with a_n is at least params.normal_tolerance. The scalar reference of
// similar_neighbour_lanes (neighbour_lanes.h), which the stages use with params.simd.
bool similar_surfaces(const PackedSurface& a, const vec3& a_n, const PackedSurface& b, const ReuseParams& params);

// Stage "di_history", temporal reuse's first half: for every pixel, last frame's pixel under its surface point
// (reprojected with the motion vectors; with params.permutation_sampling moved to a neighbour by the frame's
// pattern; none where it has no hit, is smoother than params.min_roughness or leaves the screen), where that
// holds a similar surface last frame (similar_surfaces; in lanes with params.simd), else -1 (everywhere
// without last frame's surfaces), into `history_pixel`, sized here. It runs before the light candidates, which take
// fewer where history is found (DiParams::history_light_candidates). Cost per pixel: a reprojection and one packed
// surface of last frame read. With `second` (ReSTIR GI's history found in DI's pass, see history_follows), also
// second->history_pixel: the same pixels, -1 where the surface is smoother than second->min_roughness; one more
// store per pixel.
struct SecondHistory {
  float min_roughness;
  std::vector<int32_t>* history_pixel;
};
void find_history_pixels(const GBuffer& g, const ReuseDomain& current, const ReuseDomain& previous,
                         const ReuseParams& params, int frame, std::vector<int32_t>& history_pixel,
                         const SecondHistory* second = nullptr);

// Whether find_history_pixels with `second` gives what the pass with `first` gives less the pixels smoother than
// second.min_roughness (SecondHistory): both reuse temporally with the same tolerances and the same evaluation
// (simd), neither permutes (its pattern is keyed on the chain's seed), and `first` rejects no pixel `second` keeps.
bool history_follows(const ReuseParams& first, const ReuseParams& second);

// The resampling MIS weights m_z(y), z = 0..count-1, that params.bias gives every input of a combination
// for the sample y of input `source` (input 0: the pixel that combines, whose frame y is placed in), into
// `weights`. The reuse stages compute the same function for z = source only; tests call this to check
// that the weights of one sample sum to one over the inputs (tests/test_reuse.cpp, MisWeights).
void reuse_mis_weights(const SceneView& view, const ReuseInput* inputs, int count, int source,
                       const ReuseParams& params, float* weights);

// Stage "di_temporal": reads this and the previous frame's surfaces and reservoirs and `history_pixel`
// (find_history_pixels's), writes `out` (one combined reservoir per pixel) and turns `history_pixel` into the
// previous frame's pixel whose reservoir was merged, or -1 where the history was lost (also where its sample
// grew older than params.max_sample_age). One tile row at a time: the rows' pairs of inputs, their targets in
// lanes (with params.simd; reuse_targets.h), then the combinations. No rays, except with mis_visibility: then two per
// pixel with history, from the history's surface to the history's sample and to the pixel's own sample.
// `history_verdicts` (or null): last frame's shading verdicts on the history's samples (shade_reservoirs), given
// where no geometry moved since. A verdict traced for the same sample from the same pixel answers the first of
// those rays: the shading's shadow ray starts from the packed surface as reuse's rays do, so it is the same ray
// against the same geometry, and the image stays the same bits (RestirDiReuse.KnownVerdictsReplaceRays).
void temporal_reuse(const SceneView& view, const GBuffer& g, const ReuseDomain& current, const ReuseDomain& previous,
                    const std::vector<ReuseReservoir>& reservoirs, const std::vector<ReuseReservoir>& history,
                    const ReuseParams& params, int frame, std::vector<ReuseReservoir>& out,
                    std::vector<int32_t>& history_pixel, RayCounter& rays,
                    const std::vector<SampleVisibility>* history_verdicts = nullptr);

// The random streams of spatial pass `pass` (Rng::for_key's last key): the pixels' (kPixelStreams), the neighbour
// blocks' starts (kBlockStarts) and the further samples' points (kFurtherPoints). Pass 0 keeps the names and each later
// pass adds 256, so no two (name, pass) pairs of the 8 passes share a stream (name + pass gave pass 2's pixels the
// streams of pass 0's block starts).
enum SpatialStream : uint64_t { kPixelStreams = 0xd3, kBlockStarts = 0xd5, kFurtherPoints = 0xe1 };
constexpr uint64_t spatial_stream(SpatialStream name, int pass) { return uint64_t(name) + (uint64_t(pass) << 8); }

// Fused spatiotemporal reuse's neighbours (ReuseParams::fused): last frame's final reservoirs (the history), its
// domain, and this frame's G-buffer, whose motion vectors reproject each pixel.
struct PreviousFrame {
  const GBuffer& g;
  const ReuseDomain& domain;
  const std::vector<ReuseReservoir>& reservoirs;
};

// Stage "di_spatial": reads the surfaces and `in`, writes `out` combining each pixel with up to k
// similar neighbours within the radius, one tile row at a time as temporal reuse does (2 target
// evaluations per neighbour, in lanes). No rays, except with mis_visibility. `pass` selects its own random
// stream. With `previous` (stage "di_fused", pass 0 only), the neighbours are last frame's reservoirs instead of
// `in`'s: the pixel's reprojection (reprojected_pixel's, as find_history_pixels finds it) and up to k more around it
// within the radius, each taken where its surface is similar to the pixel's and its sample no older than
// params.max_sample_age, with temporal reuse's confidence cap and aging; where the pixel has no reprojection it keeps
// `in`'s reservoir alone. With mis_visibility, whether each of last frame's samples is visible from its own surface
// is traced against this frame's geometry, as temporal reuse does, and kept_visible gets -1 (`in`'s own samples
// were not traced). With `history_pixel` (temporal reuse ran), the first pass gives pixels without history
// disocclusion_neighbours instead. With `further` (ReuseParams::shaded_samples), each of its n - 1 vectors
// receives one more sample of every pixel's combination, and the n samples are stratified over the combination's
// weights (systematic resampling; in lanes with params.simd: systematic_picks_lanes); each is the combination's
// estimator. Cost: a pass over the pixel's inputs' weights per further sample. With `kept_visible`, it receives per
// pixel whether out's sample is visible from the pixel's packed surface where the pass traced that ray (the pixel
// kept its own sample, whose visibility pairwise MIS with visibility asks), else -1: the shading's first ray there
// is the same ray (VisibilityReuse::known).
void spatial_reuse(const SceneView& view, const ReuseDomain& current, const std::vector<ReuseReservoir>& in,
                   const ReuseParams& params, int frame, int pass, const std::vector<int32_t>* history_pixel,
                   std::vector<ReuseReservoir>& out, RayCounter& rays,
                   std::vector<std::vector<ReuseReservoir>>* further = nullptr,
                   std::vector<int8_t>* kept_visible = nullptr, const PreviousFrame* previous = nullptr);

// Stage "boiling_filter": reads and rewrites the reservoirs. Temporal reuse can make a rare sample with
// a huge contribution weight spread to its neighbours frame after frame ("boiling"); this drops every
// reservoir's sample whose estimated contribution p_hat(y) W exceeds `threshold` times the mean over its
// 16x16 block (the idea of RTXDI's boiling filter; the statistic here is our own); the reservoir keeps its
// M, as if none of its candidates had counted (dropping M too would overweight its neighbours' samples
// wherever it is reused). Biased: it removes energy. Cost: two passes over the reservoirs.
void boiling_filter(const ReuseDomain& current, float threshold, std::vector<ReuseReservoir>& reservoirs);

}  // namespace candela

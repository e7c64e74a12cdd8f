#pragma once
// ReSTIR DI's light candidates evaluated in SIMD lanes: the target function p_hat (sample_target of
// sample_contribution) and the BSDF's area density at each candidate, for one tile row of pixels at a time,
// laid out as structure-of-arrays planes so that one vector holds the same term of 8 (AVX2) or 16
// (AVX-512) pixels. The kernel is written with Google Highway and picks the widest instruction set of the
// running CPU (runtime dispatch). It performs the scalar code's operations in the scalar code's order,
// without fused multiply-adds, so it returns the scalar code's bits (tests/test_target_lanes.cpp); the
// scalar code (evaluate_candidates_scalar) stays as the reference.
#include <cstdint>
#include <functional>
#include <vector>

#include "engine/bsdf_lanes.h"
#include "engine/lights.h"
#include "engine/ray_lanes.h"
#include "engine/tracer.h"
#include "engine/tiles.h"

namespace candela {

// Per pixel of a batch, what the target function and the BSDF density need of the receiver: the packed
// surface's point, normals, direction to the eye and BSDF terms (the target; build_receiver_lanes in
// receiver_lanes.h fills them), and the exact G-buffer BSDF's terms (the density of BSDF sampling).
struct ReceiverLanes {
  alignas(64) float px[kLaneSlots], py[kLaneSlots], pz[kLaneSlots];
  alignas(64) float gx[kLaneSlots], gy[kLaneSlots], gz[kLaneSlots];  // geometric normal
  alignas(64) float wox[kLaneSlots], woy[kLaneSlots], woz[kLaneSlots];
  BsdfLanes target, exact;
  // Slot `slot`: the receiver at p (geometric normal ng) seen along wo, with the two BSDFs' terms, one
  // scalar at a time (the tests' reference for the kernels).
  void set(int slot, const vec3& p, const vec3& ng, const vec3& wo, const BsdfWoTerms& target_bsdf,
           const BsdfWoTerms& exact_bsdf);
};

// Candidate k of every pixel of a batch: a point on a triangle light (position, normal, radiance and
// whether both sides emit) where `active` is 1; the kernel writes p_hat and the BSDF's area density there.
struct CandidateLanes {
  alignas(64) float x[kLaneSlots], y[kLaneSlots], z[kLaneSlots];
  alignas(64) float nx[kLaneSlots], ny[kLaneSlots], nz[kLaneSlots];
  alignas(64) float radiance[3][kLaneSlots];
  alignas(64) float two_sided[kLaneSlots], active[kLaneSlots];
  alignas(64) float p_hat[kLaneSlots], bsdf_area_pdf[kLaneSlots];
  void set(int slot, const LightPoint& point) {
    x[slot] = point.position.x, y[slot] = point.position.y, z[slot] = point.position.z;
    nx[slot] = point.normal.x, ny[slot] = point.normal.y, nz[slot] = point.normal.z;
    for (int c = 0; c < 3; ++c) radiance[c][slot] = point.radiance[c];
    two_sided[slot] = point.two_sided ? 1.0f : 0.0f;
    active[slot] = 1.0f;
  }
  // Not a triangle-light point: the kernel gives the slot 0 (p_hat and density are the caller's to find); its
  // point is left as it was (the kernel computes on it, masked, and nobody reads it).
  void clear(int slot) { active[slot] = 0.0f; }
  // The point set() stored.
  LightPoint point(int slot) const {
    return {vec3(x[slot], y[slot], z[slot]), vec3(nx[slot], ny[slot], nz[slot]),
            vec3(radiance[0][slot], radiance[1][slot], radiance[2][slot]), two_sided[slot] > 0.0f};
  }
};

// The unshadowed contribution of one sample per pixel of a batch (sample_contribution's value), per channel.
struct ContributionLanes {
  alignas(64) float value[3][kLaneSlots];
};

// The kernel: p_hat and (with_bsdf_pdf) the BSDF area density of every active candidate of slots
// [0, slots) of each of `count` candidate planes; inactive slots get 0. Cost per candidate: ~100 flops
// and 8 table gathers, in lanes.
void evaluate_candidate_lanes(const ReceiverLanes& receivers, CandidateLanes* candidates, int count, int slots,
                              bool with_bsdf_pdf);
// sample_contribution's value at the receivers' exact BSDFs (their position, geometric normal, wo and exact planes)
// of the active points of slots [0, slots) of `samples`; inactive slots get 0. The final shading. Cost per
// sample: ~80 flops and 4 table gathers, in lanes.
void evaluate_exact_contribution_lanes(const ReceiverLanes& receivers, const CandidateLanes& samples, int slots,
                                       ContributionLanes& out);
// Tracer::spawn_ray_to's rays (its bits) from the receivers' points (position, geometric normal) to the points of
// `to` (position, normal), slots [0, slots); `epsilon` is the Tracer's offset_epsilon(). Slots whose point is
// inactive get rays nobody may trace. Cost per ray: ~50 flops, a square root and 3 divisions, in lanes.
void shadow_ray_lanes(const ReceiverLanes& from, const CandidateLanes& to, float epsilon, int slots, RayLanes& out);
// (engine/simd_targets.h names the instruction set it runs with and lets tests run every one.)

}  // namespace candela

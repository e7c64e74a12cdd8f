#pragma once
// Directional albedo of the single-scattering GGX lobe, tabulated once per process, for the energy
// bookkeeping of the BSDF (Kulla & Conty 2017, "Revisiting Physically Based Shading at Imageworks",
// SIGGRAPH course: albedo scaling of the base layer and the multiple-scattering lobe).
//
// For a Schlick Fresnel F(c) = F0 + (F90 - F0) (1 - c)^5 the albedo of the lobe is linear in F0 and F90:
//   E(mu) = F0 (a(mu) - b(mu)) + F90 b(mu),  a = int f1 cos dwi,  b = int (1 - wo.h)^5 f1 cos dwi,
// where f1 = D G2 / (4 |n.wo| |n.wi|) is the lobe with F = 1 and mu = n.wo. The table stores (a, b) on a
// regular grid of sqrt(mu) (dense at grazing angles, where smooth lobes change fast) and perceptual
// roughness r (alpha = r^2), read with bilinear interpolation; the cosine-weighted averages
// a_avg = 2 int a(mu) mu dmu (and b_avg) are integrals of that interpolant, exact up to float rounding, so
// a lobe (1 - E(mu_o)) (1 - E(mu_i)) / (pi (1 - E_avg)) integrates to exactly 1 - E(mu_o).
// The table is computed at build time (ggx_albedo_gen.cpp) into ggx_albedo_table.cpp; a lookup is four
// 8-byte loads and a sqrt, inline here.
#include "engine/ggx_albedo_data.h"
#include "engine/math.h"

namespace candela {

struct GgxAlbedo {
  float a = 0.0f;  // albedo with F = 1
  float b = 0.0f;  // the (1 - wo.h)^5 share of it
};

// Lookups along one roughness: the two table rows that bracket it and their weight. Cheap to build;
// Bsdf keeps one per surface.
class GgxAlbedoRow {
 public:
  GgxAlbedoRow() : GgxAlbedoRow(1.0f) {}
  explicit GgxAlbedoRow(float roughness) {
    float x = std::clamp(roughness, 0.0f, 1.0f) * float(kGgxAlbedoRoughnessCount - 1);
    int k = std::min(int(x), kGgxAlbedoRoughnessCount - 2);
    t_ = x - float(k);
    row0_ = &kGgxAlbedoEntries[size_t(k) * kGgxAlbedoMuCount * 2];
    row1_ = row0_ + kGgxAlbedoMuCount * 2;
    const float* avg = &kGgxAlbedoAverages[2 * size_t(k)];
    avg_ = {avg[0] + t_ * (avg[2] - avg[0]), avg[1] + t_ * (avg[3] - avg[1])};
  }
  // Directional albedo for mu = cos_theta in [0, 1] (inline: the BSDF calls it twice per evaluation).
  GgxAlbedo at(float cos_theta) const {
    float x = std::sqrt(std::clamp(cos_theta, 0.0f, 1.0f)) * float(kGgxAlbedoMuCount - 1);
    int j = std::min(int(x), kGgxAlbedoMuCount - 2);
    float s = x - float(j);
    const float* p0 = row0_ + 2 * j;
    const float* p1 = row1_ + 2 * j;
    float a0 = p0[0] + s * (p0[2] - p0[0]), b0 = p0[1] + s * (p0[3] - p0[1]);
    float a1 = p1[0] + s * (p1[2] - p1[0]), b1 = p1[1] + s * (p1[3] - p1[1]);
    return {a0 + t_ * (a1 - a0), b0 + t_ * (b1 - b0)};
  }
  GgxAlbedo average() const { return avg_; }  // cosine-weighted hemispherical average (a_avg, b_avg)
  // Where at() reads: the offset of the lower roughness row in kGgxAlbedoEntries (the upper row follows it)
  // and the upper row's weight, for kernels that look up many cosines at once (restir/target_lanes.cpp).
  size_t row_offset() const { return size_t(row0_ - kGgxAlbedoEntries); }
  float row_weight() const { return t_; }

 private:
  const float* row0_ = nullptr;  // (a, b) pairs of the table row of the lower roughness
  const float* row1_ = nullptr;  // of the upper roughness
  float t_ = 0.0f;               // weight of row1_
  GgxAlbedo avg_;
};

}  // namespace candela

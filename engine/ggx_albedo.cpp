#include "engine/ggx_albedo.h"

#include "engine/ggx_albedo_data.h"

namespace candela {

GgxAlbedoRow::GgxAlbedoRow(float roughness) {
  constexpr int kMu = kGgxAlbedoMuCount, kRough = kGgxAlbedoRoughnessCount;
  float x = std::clamp(roughness, 0.0f, 1.0f) * (kRough - 1);
  int k = std::min(int(x), kRough - 2);
  t_ = x - float(k);
  row0_ = &kGgxAlbedoEntries[size_t(k) * kMu * 2];
  row1_ = row0_ + kMu * 2;
  const float* lo = &kGgxAlbedoAverages[2 * size_t(k)];
  avg_ = {lo[0] + t_ * (lo[2] - lo[0]), lo[1] + t_ * (lo[3] - lo[1])};
}

GgxAlbedo GgxAlbedoRow::at(float cos_theta) const {
  constexpr int kMu = kGgxAlbedoMuCount;
  float x = std::sqrt(std::clamp(cos_theta, 0.0f, 1.0f)) * (kMu - 1);
  int j = std::min(int(x), kMu - 2);
  float s = x - float(j);
  const float* p0 = row0_ + 2 * j;
  const float* p1 = row1_ + 2 * j;
  float a0 = p0[0] + s * (p0[2] - p0[0]), b0 = p0[1] + s * (p0[3] - p0[1]);
  float a1 = p1[0] + s * (p1[2] - p1[0]), b1 = p1[1] + s * (p1[3] - p1[1]);
  return {a0 + t_ * (a1 - a0), b0 + t_ * (b1 - b0)};
}

GgxAlbedo GgxAlbedoRow::average() const { return avg_; }

}  // namespace candela

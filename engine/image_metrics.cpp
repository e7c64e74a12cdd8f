#include "engine/image_metrics.h"

#include "engine/check.h"

namespace candela {

double image_mean(const Image& image) {
  double sum = 0.0;
  for (const vec3& p : image.pixels) sum += (double(p.x) + p.y + p.z) / 3.0;
  return image.pixels.empty() ? 0.0 : sum / double(image.pixels.size());
}

ImageError compare_images(const Image& estimate, const Image& reference) {
  if (estimate.width != reference.width || estimate.height != reference.height)
    throw InputError("image sizes differ: " + std::to_string(estimate.width) + "x" + std::to_string(estimate.height) +
                     " vs " + std::to_string(reference.width) + "x" + std::to_string(reference.height));
  double sum = 0.0, sum2 = 0.0, rel = 0.0;
  size_t n = 0;
  for (size_t i = 0; i < estimate.pixels.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      double r = reference.pixels[i][c], d = double(estimate.pixels[i][c]) - r;
      sum += d;
      sum2 += d * d;
      rel += d * d / (r * r + 0.01);
      ++n;
    }
  ImageError e;
  if (n == 0) return e;
  e.mean_difference = sum / double(n);
  e.mse = sum2 / double(n);
  e.rel_mse = rel / double(n);
  e.standard_error = std::sqrt(std::max(0.0, e.mse - e.mean_difference * e.mean_difference) / double(n));
  return e;
}

}  // namespace candela

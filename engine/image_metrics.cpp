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
  // MSE and relMSE over channels; the mean difference and its standard error over pixels, each pixel's
  // difference the mean of its channels' (a pixel's channels come from the same paths, so they are not
  // independent estimates).
  double sum2 = 0.0, rel = 0.0, pixel_sum = 0.0, pixel_sum2 = 0.0;
  const size_t pixels = estimate.pixels.size();
  for (size_t i = 0; i < pixels; ++i) {
    double pixel = 0.0;
    for (int c = 0; c < 3; ++c) {
      double r = reference.pixels[i][c], d = double(estimate.pixels[i][c]) - r;
      pixel += d / 3.0;
      sum2 += d * d;
      rel += d * d / (r * r + 0.01);
    }
    pixel_sum += pixel;
    pixel_sum2 += pixel * pixel;
  }
  ImageError e;
  if (pixels == 0) return e;
  e.mean_difference = pixel_sum / double(pixels);
  e.mse = sum2 / double(3 * pixels);
  e.rel_mse = rel / double(3 * pixels);
  e.standard_error =
      std::sqrt(std::max(0.0, pixel_sum2 / double(pixels) - e.mean_difference * e.mean_difference) / double(pixels));
  return e;
}

}  // namespace candela

#pragma once
// Error of an image against a reference, over pixels and channels.
#include "engine/image.h"

namespace candela {

struct ImageError {
  double mean_difference = 0.0;  // mean of (x - r) over pixels and channels
  double standard_error = 0.0;   // of that mean, treating pixels (not channels) as independent estimates
  double mse = 0.0;              // mean of (x - r)^2
  double rel_mse = 0.0;          // mean of (x - r)^2 / (r^2 + 0.01)
};

// Mean over pixels and channels (0 for an empty image).
double image_mean(const Image& image);

// Throws InputError when the sizes differ.
ImageError compare_images(const Image& estimate, const Image& reference);

}  // namespace candela

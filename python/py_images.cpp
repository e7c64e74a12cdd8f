// Images between Candela and NumPy, candela.read_image and the candela.metrics submodule (the error
// measures of `candela compare`, engine/image_metrics.h).
#include <cstring>

#include "engine/image_metrics.h"
#include "python/bindings.h"

namespace candela::python {

py::array_t<float> image_array(const Image& image, py::object owner) {
  static_assert(sizeof(vec3) == 3 * sizeof(float), "pixels are 3 packed floats");
  const py::ssize_t w = image.width, h = image.height, pixel = sizeof(vec3), channel = sizeof(float);
  return py::array_t<float>({h, w, py::ssize_t(3)}, {w * pixel, pixel, channel},
                            reinterpret_cast<const float*>(image.pixels.data()), std::move(owner));
}

Image array_image(const py::array& array, const char* what) {
  const auto a = py::array_t<float, py::array::c_style | py::array::forcecast>::ensure(array);
  if (!a || a.ndim() != 3 || a.shape(2) != 3 || a.shape(0) < 1 || a.shape(1) < 1)
    throw py::value_error(std::string(what) + ": expected an H x W x 3 array of numbers");
  Image image(int(a.shape(1)), int(a.shape(0)));
  std::memcpy(image.pixels.data(), a.data(), image.pixels.size() * sizeof(vec3));
  return image;
}

void bind_images(py::module_& m) {
  m.def(
      "read_image",
      [](const std::string& path) {
        auto image = std::make_unique<Image>(read_image(path));
        const Image& ref = *image;
        py::capsule owner(image.release(), [](void* p) { delete static_cast<Image*>(p); });
        return image_array(ref, owner);
      },
      py::arg("path"), "Reads an EXR or PNG file as an H x W x 3 float32 array (PNG: sRGB values in 0..1).");
  m.def(
      "write_image",
      [](const std::string& path, const py::array& image, float exposure) {
        write_image(path, array_image(image, "image"), exposure);
      },
      py::arg("path"), py::arg("image"), py::arg("exposure") = 1.0f,
      "Writes an H x W x 3 array as EXR (linear values) or PNG (tonemapped sRGB), atomically, as `candela render`.");

  py::module_ metrics =
      m.def_submodule("metrics", "Error of an image against a reference, as `candela compare` measures it.");
  auto measure = [&](const char* name, double ImageError::*member, const char* doc) {
    metrics.def(
        name,
        [member](const py::array& image, const py::array& reference) {
          return compare_images(array_image(image, "image"), array_image(reference, "reference")).*member;
        },
        py::arg("image"), py::arg("reference"), doc);
  };
  measure("mse", &ImageError::mse, "Mean of (x - r)^2 over pixels and channels.");
  measure("rel_mse", &ImageError::rel_mse, "Mean of (x - r)^2 / (r^2 + 0.01) over pixels and channels.");
  measure("mean_difference", &ImageError::mean_difference, "Mean of x - r over pixels and channels.");
  measure("standard_error", &ImageError::standard_error,
          "Standard error of mean_difference, pixels taken as independent estimates.");
}

}  // namespace candela::python

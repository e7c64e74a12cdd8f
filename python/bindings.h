#pragma once
// The `candela` Python module (pybind11), in three parts: scenes and cameras (py_scene.cpp), the renderer
// and its frames (py_renderer.cpp), images and error metrics (py_images.cpp). Images cross as H x W x 3
// float32 NumPy arrays, row 0 at the top (engine/image.h's layout).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "engine/image.h"

namespace candela::python {

namespace py = pybind11;

void bind_scene(py::module_& m);
void bind_renderer(py::module_& m);
void bind_images(py::module_& m);

// An H x W x 3 float32 array over `image`'s pixels, without a copy; `owner` keeps them alive.
py::array_t<float> image_array(const Image& image, py::object owner);
// A copy of a H x W x 3 array (any real dtype) as an Image; `what` names it in the ValueError of a bad shape.
Image array_image(const py::array& array, const char* what);

}  // namespace candela::python

// PYBIND11_MODULE: the `candela` module's docstring, its exception and its three parts (bindings.h).
#include "engine/check.h"
#include "python/bindings.h"

PYBIND11_MODULE(candela, m) {
  using namespace candela::python;
  m.doc() =
      "Candela, a CPU many-light renderer: load a scene, render frames with any method and setting of "
      "`candela render`, and get them as NumPy arrays (docs/python.md).";
  // Bad input (files, settings) raises candela.InputError, a ValueError, with the command line's message.
  py::register_exception<candela::InputError>(m, "InputError", PyExc_ValueError);
  bind_scene(m);
  bind_renderer(m);
  bind_images(m);
}

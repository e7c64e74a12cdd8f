// candela.load_scene, candela.Scene and candela.Camera.
#include <pybind11/stl.h>

#include <cmath>

#include "apps/scene_source.h"
#include "engine/check.h"
#include "engine/input_limits.h"
#include "engine/lights.h"
#include "python/bindings.h"

namespace candela::python {

namespace {

// Three finite numbers within the coordinate limit (engine/input_limits.h), else ValueError naming `what`.
vec3 to_vec3(const py::handle& value, const char* what) {
  if (!py::isinstance<py::sequence>(value) || py::isinstance<py::str>(value) || py::len(value) != 3)
    throw py::value_error(std::string(what) + ": expected 3 numbers");
  const auto s = py::reinterpret_borrow<py::sequence>(value);
  vec3 v;
  for (int k = 0; k < 3; ++k) {
    if (!py::isinstance<py::float_>(s[k]) && !py::isinstance<py::int_>(s[k]))
      throw py::value_error(std::string(what) + ": expected 3 numbers");
    v[k] = s[k].cast<float>();
  }
  if (!is_finite(v) || max_component(glm::abs(v)) > kMaxCoordinate)
    throw py::value_error(std::string(what) + ": not finite or beyond the coordinate limit");
  return v;
}

py::tuple to_tuple(const vec3& v) { return py::make_tuple(v.x, v.y, v.z); }

CameraDesc make_camera(const py::handle& position, const py::handle& target, const py::handle& up, float fov) {
  CameraDesc c{to_vec3(position, "position"), to_vec3(target, "target"), to_vec3(up, "up"), fov};
  if (!(fov >= 1.0f && fov <= 179.0f)) throw py::value_error("fov: must be in 1..179 degrees");
  if (glm::length(c.target - c.position) <= 0.0f)
    throw py::value_error("target: equals the position (no view direction)");
  if (glm::length(glm::cross(c.target - c.position, c.up)) <= 0.0f)
    throw py::value_error("up: parallel to the view direction");
  return c;
}

}  // namespace

void bind_scene(py::module_& m) {
  py::class_<CameraDesc>(
      m, "Camera", "A pinhole camera: where it stands, what it looks at, which way is up, vertical field of view.")
      .def(py::init([](const py::object& position, const py::object& target, const py::object& up, float fov) {
             return make_camera(position, target, up, fov);
           }),
           py::arg("position"), py::arg("target"), py::arg("up") = py::make_tuple(0.0f, 1.0f, 0.0f),
           py::arg("fov") = 45.0f)
      .def_property_readonly("position", [](const CameraDesc& c) { return to_tuple(c.position); })
      .def_property_readonly("target", [](const CameraDesc& c) { return to_tuple(c.target); })
      .def_property_readonly("up", [](const CameraDesc& c) { return to_tuple(c.up); })
      .def_property_readonly("fov", [](const CameraDesc& c) { return c.vfov_degrees; })
      .def_static(
          "lerp",
          [](const CameraDesc& a, const CameraDesc& b, float t) {
            const vec3 up = glm::mix(a.up, b.up, t);
            return make_camera(to_tuple(glm::mix(a.position, b.position, t)), to_tuple(glm::mix(a.target, b.target, t)),
                               to_tuple(glm::length(up) > 0.0f ? up : a.up),
                               a.vfov_degrees + (b.vfov_degrees - a.vfov_degrees) * t);
          },
          py::arg("a"), py::arg("b"), py::arg("t"),
          "The camera a fraction t of the way from a to b (position, target, up and fov linearly).")
      .def("__repr__", [](const CameraDesc& c) {
        return py::str("Camera(position={}, target={}, up={}, fov={})")
            .format(to_tuple(c.position), to_tuple(c.target), to_tuple(c.up), c.vfov_degrees);
      });

  py::class_<Scene>(m, "Scene", "A loaded scene: geometry, materials, lights and the camera it brings.")
      .def_property_readonly("name", [](const Scene& s) { return s.name; })
      .def_property_readonly("triangle_count", &Scene::triangle_count)
      .def_property_readonly("instance_names",
                             [](const Scene& s) {
                               std::vector<std::string> names;
                               for (const Instance& i : s.instances) names.push_back(i.name);
                               return names;
                             })
      .def_property_readonly("camera", &Scene::default_camera, "The scene's own camera (or the default view).")
      .def_property_readonly(
          "light_count", [](const Scene& s) { return LightList(s).size(); },
          "Lights the renderer samples: emissive triangles and punctual lights (builds the light list).")
      .def_property_readonly("emissive_triangle_count", [](const Scene& s) { return LightList(s).triangle_count(); })
      .def("__repr__",
           [](const Scene& s) { return py::str("Scene('{}', {} triangles)").format(s.name, s.triangle_count()); });

  m.def(
      "load_scene",
      [](const std::string& source, int lights, std::optional<float> environment) {
        if (lights < 1 || lights > 4000000) throw py::value_error("lights: must be in 1..4000000");
        if (environment && !(*environment >= 0.0f && *environment <= 1e6f))
          throw py::value_error("environment: must be in 0..1e6");
        BuiltinOptions options;
        options.light_count = lights;
        py::gil_scoped_release release;
        return load_scene(source, options, environment.value_or(-1.0f));
      },
      py::arg("source"), py::arg("lights") = 1024, py::arg("environment") = py::none(),
      "Loads builtin:cornell|manylights|city or a .gltf/.glb file. `lights`: builtin:manylights' light count; "
      "`environment`: a uniform background radiance (None: the scene's own rule, as `candela render`). Raises "
      "candela.InputError with the command line's message when the scene cannot be loaded.");
}

}  // namespace candela::python

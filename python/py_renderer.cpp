// candela.Renderer (every render setting a keyword argument, from the settings schema), candela.Frame,
// candela.settings_schema() and candela.set_threads().
#include <pybind11/stl.h>
#include <tbb/global_control.h>

#include <cmath>
#include <memory>

#include "apps/aovs.h"
#include "apps/renderer.h"
#include "apps/settings_schema.h"
#include "python/bindings.h"

namespace candela::python {

namespace {

// The Renderer and what Python's calls count: frames rendered (render_frame's default frame index and
// time), the camera of the next frame, and the generation of its state (set and reset_history start a new
// one: earlier frames' AOVs are gone). `busy` while a call runs without the GIL: another Python thread's
// call on the same renderer then raises instead of racing it.
struct PyRenderer {
  std::unique_ptr<Renderer> renderer;
  int frames = 0;
  int generation = 0;
  CameraDesc camera;
  bool busy = false;
};

// Marks `r` busy for a call that releases the GIL (taken and released with the GIL held).
class BusyScope {
 public:
  explicit BusyScope(PyRenderer& r) : r_(r) {
    if (r_.busy) throw std::runtime_error("the Renderer is busy in another thread (one call at a time)");
    r_.busy = true;
  }
  ~BusyScope() { r_.busy = false; }
  BusyScope(const BusyScope&) = delete;
  BusyScope& operator=(const BusyScope&) = delete;

 private:
  PyRenderer& r_;
};

// `r` when no other thread is inside one of its calls, else RuntimeError.
PyRenderer& idle(PyRenderer& r) {
  if (r.busy) throw std::runtime_error("the Renderer is busy in another thread (one call at a time)");
  return r;
}

// One rendered frame: its radiance (the Renderer's image after the frame) and stats; its AOVs are read
// from the renderer while it is still the renderer's last frame.
struct Frame {
  Image radiance;
  FrameStats stats;
  int index = 0;
  int generation = 0;   // the renderer's generation when it was rendered
  py::object renderer;  // the PyRenderer that rendered it
};

std::string known_settings() {
  std::string out;
  for (const Setting& row : settings_schema())
    if (row.scope & kCommandLine) out += (out.empty() ? "" : ", ") + row.key;
  return out;
}

// The Python value of keyword `row.key` as the row's number, or TypeError (wrong type) / ValueError (outside
// the row's range, with the range).
double setting_value(const Setting& row, const py::handle& v) {
  const std::string key = row.key;
  // Python and NumPy integers (anything with __index__) count as ints, bools as bools only.
  const bool is_bool = py::isinstance<py::bool_>(v), is_int = !is_bool && PyIndex_Check(v.ptr());
  auto out_of_range = [&](const std::string& got) {
    return py::value_error(key + ": must be " +
                           (row.type == SettingType::Choice ? "one of "
                            : row.values.empty()            ? "in "
                                                            : "") +
                           row.range_text() + ", got " + got);
  };
  switch (row.type) {
    case SettingType::Choice: {
      if (!py::isinstance<py::str>(v)) throw py::type_error(key + ": expected a str (" + row.range_text() + ")");
      const std::string name = v.cast<std::string>();
      const int index = row.name_index(name);
      if (index < 0) throw out_of_range("'" + name + "'");
      return double(index);
    }
    case SettingType::Flag:
      if (!is_bool) throw py::type_error(key + ": expected a bool");
      return v.cast<bool>() ? 1.0 : 0.0;
    case SettingType::Int: {
      if (!is_int) throw py::type_error(key + ": expected an int");
      long long x = 0;
      try {
        x = py::int_(py::reinterpret_borrow<py::object>(v)).cast<long long>();
      } catch (const py::cast_error&) {
        throw out_of_range(py::str(v).cast<std::string>());
      }
      if (!row.accepts(double(x))) throw out_of_range(std::to_string(x));
      return double(x);
    }
    case SettingType::Float: {
      if (!is_int && !py::isinstance<py::float_>(v)) throw py::type_error(key + ": expected a number");
      const double x = v.cast<double>();
      if (!row.accepts(x)) throw out_of_range(py::str(v).cast<std::string>());
      return x;
    }
  }
  return 0.0;
}

// `base` with every keyword set through its schema row; TypeError for an unknown keyword, naming the known
// ones.
RenderSettings settings_from(const py::kwargs& kwargs, RenderSettings base) {
  for (const auto& [name, value] : kwargs) {
    const std::string key = name.cast<std::string>();
    const Setting* row = find_setting(key);
    if (!row || !(row->scope & kCommandLine))
      throw py::type_error("unknown setting '" + key + "' (known: " + known_settings() + ")");
    row->set(base, setting_value(*row, value));
  }
  if (int64_t(base.width) * base.height > (int64_t(1) << 26))
    throw py::value_error("width x height: at most 67108864 pixels (8192 x 8192)");
  return base;
}

// The settings as keyword arguments would give them.
py::dict settings_dict(const RenderSettings& s) {
  py::dict out;
  for (const Setting& row : settings_schema()) {
    if (!(row.scope & kCommandLine)) continue;
    const double v = row.get(s);
    switch (row.type) {
      case SettingType::Choice: out[row.key.c_str()] = row.names.at(size_t(v)); break;
      case SettingType::Flag: out[row.key.c_str()] = v != 0.0; break;
      case SettingType::Int: out[row.key.c_str()] = int64_t(v); break;
      case SettingType::Float: out[row.key.c_str()] = v; break;
    }
  }
  return out;
}

py::dict stats_dict(const FrameStats& stats) {
  py::dict stages;
  for (const StageStats& s : stats.stages)
    stages[s.name.c_str()] =
        py::dict(py::arg("ms") = s.ms, py::arg("rays") = s.rays, py::arg("non_finite") = s.non_finite);
  return py::dict(py::arg("frame") = stats.frame, py::arg("spp") = stats.spp, py::arg("total_ms") = stats.total_ms,
                  py::arg("rays") = stats.rays(), py::arg("non_finite") = stats.non_finite(),
                  py::arg("stages") = stages);
}

const char* kType[] = {"int", "float", "bool", "str"};

py::list schema_list() {
  const py::dict defaults = settings_dict(RenderSettings{});
  py::list out;
  for (const Setting& row : settings_schema()) {
    if (!(row.scope & kCommandLine)) continue;
    py::dict r;
    r["key"] = row.key;
    r["type"] = kType[int(row.type)];
    r["group"] = setting_group_name(row.group);
    r["default"] = defaults[row.key.c_str()];
    r["range"] = row.range_text();
    if (row.type == SettingType::Int || row.type == SettingType::Float) {
      r["min"] = row.min;
      r["max"] = row.max;
    }
    if (!row.values.empty()) r["values"] = row.values;
    if (!row.names.empty()) r["names"] = row.names;
    r["methods"] = method_list(row.methods);
    r["doc"] = row.doc;
    out.append(r);
  }
  return out;
}

std::unique_ptr<tbb::global_control> thread_limit;

}  // namespace

void bind_renderer(py::module_& m) {
  py::class_<Frame>(m, "Frame", "One rendered frame: radiance, debug images (AOVs) and stage timings.")
      .def_property_readonly(
          "radiance", [](py::object self) { return image_array(self.cast<Frame&>().radiance, self); },
          "H x W x 3 float32 array of linear radiance (denoised when a denoiser is set), without a copy.")
      .def_property_readonly("index", [](const Frame& f) { return f.index; })
      .def_property_readonly(
          "stats", [](const Frame& f) { return stats_dict(f.stats); },
          "frame, spp, total_ms, rays, non_finite and per stage: ms, rays, non_finite.")
      .def(
          "aov",
          [](const Frame& f, const std::string& name) {
            const AovInfo* aov = find_aov(name);
            if (!aov) {
              std::string names;
              for (const std::string& n : aov_names()) names += (names.empty() ? "" : ", ") + n;
              throw py::value_error("aov: '" + name + "' is not one of " + names);
            }
            PyRenderer& r = idle(f.renderer.cast<PyRenderer&>());
            if (r.frames != f.index + 1 || r.generation != f.generation)
              throw py::value_error(
                  "aov: frame " + std::to_string(f.index) +
                  " is no longer the renderer's last frame (read AOVs before the next render_frame, set or "
                  "reset_history)");
            if (!aov_available(aov->aov, *r.renderer))
              throw py::value_error("aov: " + name + " needs method restir-di or restir");
            auto image = std::make_unique<Image>(aov_image(*r.renderer, aov->aov));
            const Image& ref = *image;
            return image_array(ref, py::capsule(image.release(), [](void* p) { delete static_cast<Image*>(p); }));
          },
          py::arg("name"),
          "The frame's debug image `name` (docs/settings.md, \"Debug images\": albedo, normal, depth, motion, "
          "reservoir-m, ...) as an H x W x 3 float32 array of its values; only while it is the renderer's last frame.");

  py::class_<PyRenderer>(m, "Renderer",
                         "The frame pipeline on one scene. Every render setting of `candela render` is a keyword "
                         "argument, named by its shot-script key (docs/settings.md): Renderer(scene, "
                         "method='restir-di', di_candidates=8, denoise='svgf').")
      .def(py::init([](const Scene& scene, const py::kwargs& kwargs) {
             const RenderSettings settings = settings_from(kwargs, RenderSettings{});
             auto r = std::make_unique<PyRenderer>();
             r->camera = scene.default_camera();
             py::gil_scoped_release release;
             r->renderer = std::make_unique<Renderer>(scene, settings);
             return r;
           }),
           py::arg("scene"))
      .def(
          "render_frame",
          [](py::object self, std::optional<CameraDesc> camera, std::optional<float> time) {
            PyRenderer& r = self.cast<PyRenderer&>();
            BusyScope busy(r);
            if (camera) r.camera = *camera;
            const float t = time.value_or(float(r.frames) / 30.0f);
            if (!std::isfinite(t)) throw py::value_error("time: not finite");
            Frame frame;
            frame.index = r.frames;
            frame.renderer = self;
            frame.generation = r.generation;
            {
              py::gil_scoped_release release;
              frame.stats = r.renderer->render_frame(r.frames, t, r.camera);
              frame.radiance = r.renderer->image();
            }
            ++r.frames;
            if (PyErr_CheckSignals() != 0) throw py::error_already_set();  // Ctrl-C during the frame
            return frame;
          },
          py::arg("camera") = py::none(), py::arg("time") = py::none(),
          "Renders the next frame (index: frames rendered so far) at scene time `time` (default index / 30 s, as "
          "`candela render`'s --fps 30) from `camera` (default: the last one given, at first the scene's). A still "
          "camera and scene accumulate unless accumulate=False. The GIL is released while it renders.")
      .def(
          "reset_history",
          [](PyRenderer& r) {
            idle(r).renderer->reset_history();
            ++r.generation;
          },
          "Forgets every frame so far: no temporal reuse, denoiser history or accumulation.")
      .def(
          "set",
          [](PyRenderer& r, const py::kwargs& kwargs) {
            const RenderSettings settings = settings_from(kwargs, idle(r).renderer->settings());
            BusyScope busy(r);
            ++r.generation;
            py::gil_scoped_release release;
            r.renderer->apply_settings(settings);
          },
          "Changes settings (keyword arguments, as the constructor's) without rebuilding BVHs and light list; "
          "history starts over.")
      .def_property_readonly("settings", [](PyRenderer& r) { return settings_dict(idle(r).renderer->settings()); })
      .def_property_readonly("frames_rendered", [](const PyRenderer& r) { return r.frames; })
      .def_property_readonly("accumulated_spp", [](PyRenderer& r) { return idle(r).renderer->accumulated_spp(); });

  m.def("settings_schema", &schema_list,
        "Every render setting as a dict: key, type, group, default, range (min/max, values or names), methods, doc.");
  m.def(
      "set_threads",
      [](int threads) {
        if (threads < 0 || threads > 1024) throw py::value_error("threads: must be in 0..1024");
        thread_limit.reset();
        if (threads > 0)
          thread_limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, threads);
      },
      py::arg("threads"),
      "Worker threads for everything rendered from now on; 0 = all cores. Images do not depend on it.");
}

}  // namespace candela::python

#include "apps/shot_script.h"

#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

#include <glm/gtc/matrix_transform.hpp>
#include <nlohmann/json.hpp>

#include "apps/aovs.h"
#include "apps/settings_names.h"
#include "apps/settings_schema.h"
#include "engine/check.h"
#include "engine/input_limits.h"

namespace candela {

namespace {

using nlohmann::json;

// Reads the members of one JSON object, remembering which keys were read so that finish() can reject
// the rest; every message names the file and the key path ("camera.keys[2].fov").
class ObjectReader {
 public:
  ObjectReader(const std::string& file, const json& object, std::string where)
      : file_(file), object_(object), where_(std::move(where)) {
    if (!object_.is_object()) fail_at(where_.empty() ? "the script" : where_, "expected an object");
  }
  [[noreturn]] void fail_at(const std::string& place, const std::string& what) const {
    throw InputError(file_ + ": " + place + ": " + what);
  }
  [[noreturn]] void fail(const std::string& key, const std::string& what) const { fail_at(path(key), what); }
  std::string path(const std::string& key) const { return where_.empty() ? key : where_ + "." + key; }
  const json* get(const std::string& key) {
    seen_.insert(key);
    auto it = object_.find(key);
    return it == object_.end() ? nullptr : &*it;
  }
  bool has(const std::string& key) const { return object_.contains(key); }
  const std::string& file() const { return file_; }

  double number(const std::string& key, double lo, double hi, double fallback) {
    const json* v = get(key);
    if (!v) return fallback;
    if (!v->is_number()) fail(key, "expected a number, got " + v->dump());
    double x = v->get<double>();
    if (!(x >= lo && x <= hi)) fail(key, "must be in " + format(lo) + ".." + format(hi) + ", got " + v->dump());
    return x;
  }
  int64_t integer(const std::string& key, int64_t lo, int64_t hi, int64_t fallback) {
    const json* v = get(key);
    if (!v) return fallback;
    if (!v->is_number_integer()) fail(key, "expected an integer, got " + v->dump());
    if (v->is_number_unsigned() && v->get<uint64_t>() > uint64_t(std::numeric_limits<int64_t>::max()))
      fail(key, "must be in " + std::to_string(lo) + ".." + std::to_string(hi) + ", got " + v->dump());
    int64_t x = v->get<int64_t>();
    if (x < lo || x > hi)
      fail(key, "must be in " + std::to_string(lo) + ".." + std::to_string(hi) + ", got " + v->dump());
    return x;
  }
  bool flag(const std::string& key, bool fallback) {
    const json* v = get(key);
    if (!v) return fallback;
    if (!v->is_boolean()) fail(key, "expected true or false, got " + v->dump());
    return v->get<bool>();
  }
  std::string text(const std::string& key, const std::string& fallback) {
    const json* v = get(key);
    if (!v) return fallback;
    if (!v->is_string()) fail(key, "expected a string, got " + v->dump());
    return v->get<std::string>();
  }
  std::string choice(const std::string& key, const std::vector<std::string>& names, const std::string& fallback) {
    std::string s = text(key, fallback);
    if (std::find(names.begin(), names.end(), s) == names.end()) fail(key, "'" + s + "' is not one of " + join(names));
    return s;
  }
  template <class T>
  T named(const std::string& key, const std::map<std::string, T>& names, T fallback) {
    return names.at(choice(key, keys_of(names), name_of(names, fallback)));
  }
  vec3 vector3(const json& v, const std::string& place) const {
    if (!v.is_array() || v.size() != 3 || !v[0].is_number() || !v[1].is_number() || !v[2].is_number())
      fail_at(place, "expected an array of 3 numbers, got " + v.dump());
    const vec3 out(v[0].get<float>(), v[1].get<float>(), v[2].get<float>());
    if (!is_finite(out)) fail_at(place, "not finite");
    // Positions, targets and translations: the coordinate limit where ray arithmetic stays finite.
    if (max_component(glm::abs(out)) > kMaxCoordinate)
      fail_at(place, v.dump() + " is beyond the limit of " + format(kMaxCoordinate) + " (see engine/input_limits.h)");
    return out;
  }
  // Rejects keys nobody read (typos would otherwise be silently ignored).
  void finish() const {
    for (auto it = object_.begin(); it != object_.end(); ++it)
      if (!seen_.count(it.key()))
        fail(it.key(), "unknown key (known here: " + join({seen_.begin(), seen_.end()}) + ")");
  }
  static std::string join(const std::vector<std::string>& names) {
    std::string out;
    for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
    return out;
  }
  static std::string format(double x) {
    std::ostringstream s;
    s << x;
    return s.str();
  }

 private:
  const std::string& file_;
  const json& object_;
  std::string where_;
  std::set<std::string> seen_;
};

const std::map<std::string, Interpolation>& interpolation_names() {
  static const std::map<std::string, Interpolation> names = {
      {"step", Interpolation::Step}, {"linear", Interpolation::Linear}, {"smooth", Interpolation::Smooth}};
  return names;
}

// Line and column of byte `offset` in `text` (both from 1), for JSON syntax errors.
std::string line_and_column(const std::string& text, size_t offset) {
  size_t line = 1, column = 1;
  for (size_t i = 0; i < offset && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else
      ++column;
  }
  return "line " + std::to_string(line) + ", column " + std::to_string(column);
}

json parse_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open the script");
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string text = buffer.str();
  check_json_nesting(text, path);
  try {
    return json::parse(text);
  } catch (const json::parse_error& e) {
    std::string what = e.what();
    what = what.substr(what.find(':') + 2);  // drop nlohmann's "[json.exception.parse_error.101] parse error at ..."
    throw InputError(path + ": " + line_and_column(text, e.byte > 0 ? e.byte - 1 : 0) + ": invalid JSON: " + what);
  } catch (const json::out_of_range& e) {
    // A number beyond double's range ("1e999"): nlohmann's error 406, which carries no position.
    std::string what = e.what();
    throw InputError(path + ": invalid JSON: " + what.substr(what.find("] ") + 2));  // drop "[json.exception...] "
  }
}

// A "keys" array of objects, each with "frame" (increasing) and the members `read_key` takes.
template <class ReadKey>
void read_keys(ObjectReader& parent, std::vector<float>& frames, ReadKey read_key) {
  const json* keys = parent.get("keys");
  if (!keys) parent.fail("keys", "missing (an array of keyframes)");
  if (!keys->is_array() || keys->empty()) parent.fail("keys", "expected a non-empty array of keyframes");
  for (size_t i = 0; i < keys->size(); ++i) {
    ObjectReader k(parent.file(), (*keys)[i], parent.path("keys") + "[" + std::to_string(i) + "]");
    if (!k.has("frame")) k.fail("frame", "missing");
    float frame = float(k.number("frame", -1e7, 1e7, 0.0));
    if (!frames.empty() && frame <= frames.back())
      k.fail("frame", "keyframes must be in increasing frame order (" + ObjectReader::format(frame) + " after " +
                          ObjectReader::format(frames.back()) + ")");
    frames.push_back(frame);
    read_key(k);
    k.finish();
  }
}

// "%d" or "%0Nd", exactly once, and no other '%'.
void check_pattern(const ObjectReader& r, const std::string& key, const std::string& pattern, bool exr_only) {
  static const std::regex one(R"(^[^%]*%(0[1-9])?d[^%]*$)");
  if (!std::regex_match(pattern, one))
    r.fail(key, "'" + pattern + "' needs exactly one %d or %0Nd for the frame number");
  std::string ext = std::filesystem::path(pattern).extension().string();
  for (char& c : ext) c = char(std::tolower(c));
  if (ext != ".exr" && (exr_only || ext != ".png"))
    r.fail(key, "'" + pattern + "' must end in " + (exr_only ? ".exr" : ".exr or .png"));
}

// Every schema row a script may give (apps/settings_schema.h), as its key; the rows it may not give are
// refused with their reason. Then what one key alone cannot check: the image size.
void read_render_settings(ObjectReader& r, ShotScript& s) {
  RenderSettings& st = s.settings;
  st.accumulate = false;
  for (const Setting& row : settings_schema()) {
    if (!(row.scope & kScript)) {
      if (r.has(row.key)) r.fail(row.key, "not allowed in scripts: " + row.refusal);
      continue;
    }
    const double fallback = row.get(st);
    switch (row.type) {
      case SettingType::Int: {
        const int64_t v = r.integer(row.key, int64_t(row.min), int64_t(row.max), int64_t(fallback));
        if (!row.accepts(double(v))) r.fail(row.key, "must be " + row.range_text() + ", got " + std::to_string(v));
        row.set(st, double(v));
        break;
      }
      case SettingType::Float: row.set(st, r.number(row.key, row.min, row.max, fallback)); break;
      case SettingType::Flag: row.set(st, r.flag(row.key, fallback != 0.0)); break;
      case SettingType::Choice: {
        const std::string name = r.choice(row.key, row.names, row.names.at(size_t(fallback)));
        row.set(st, double(row.name_index(name)));
        break;
      }
    }
  }
  if (int64_t(st.width) * st.height > (int64_t(1) << 26)) r.fail("width", "width x height: at most 67108864 pixels");
}

void read_camera(ObjectReader& parent, ShotScript& s) {
  const json* camera = parent.get("camera");
  if (!camera) return;
  ObjectReader r(parent.file(), *camera, "camera");
  s.camera_interpolation = r.named("interpolation", interpolation_names(), Interpolation::Smooth);
  read_keys(r, s.camera_frames, [&](ObjectReader& k) {
    for (const char* key : {"position", "target", "fov"})
      if (!k.has(key)) k.fail(key, "missing");
    s.camera_position.push_back(k.vector3(*k.get("position"), k.path("position")));
    s.camera_target.push_back(k.vector3(*k.get("target"), k.path("target")));
    s.camera_fov.push_back(float(k.number("fov", 1.0, 179.0, 45.0)));
    if (glm::length(s.camera_target.back() - s.camera_position.back()) <= 0.0f)
      k.fail("target", "equals the position (no view direction)");
  });
  r.finish();
}

// Calls read(entry, where) for each object of the array `key` ("instances[2]"); absent: nothing.
template <class Read>
void read_objects(ObjectReader& parent, const std::string& key, Read read) {
  const json* list = parent.get(key);
  if (!list) return;
  if (!list->is_array()) parent.fail(key, "expected an array");
  for (size_t i = 0; i < list->size(); ++i) {
    const std::string where = key + "[" + std::to_string(i) + "]";
    ObjectReader r(parent.file(), (*list)[i], where);
    read(r, where);
    r.finish();
  }
}

void read_instances(ObjectReader& parent, ShotScript& s) {
  read_objects(parent, "instances", [&](ObjectReader& r, const std::string& where) {
    InstanceKeys keys;
    keys.where = where;
    if (r.has("instance") == r.has("name")) r.fail_at(where, "give exactly one of \"instance\" (index) or \"name\"");
    keys.index = r.integer("instance", 0, std::numeric_limits<int>::max(), -1);
    keys.name = r.text("name", "");
    keys.interpolation = r.named("interpolation", interpolation_names(), Interpolation::Linear);
    bool translation = false, rotation = false;
    read_keys(r, keys.frames, [&](ObjectReader& k) {
      if (keys.frames.size() == 1) {
        translation = k.has("translation");
        rotation = k.has("rotation_degrees");
        if (!translation && !rotation)
          k.fail_at(k.path("translation"), "a key needs \"translation\" and/or \"rotation_degrees\"");
      }
      if (k.has("translation") != translation || k.has("rotation_degrees") != rotation)
        k.fail_at(k.path("translation"), "every key must give the same channels as the first one");
      if (translation) keys.translation.push_back(k.vector3(*k.get("translation"), k.path("translation")));
      if (rotation) keys.rotation_degrees.push_back(k.vector3(*k.get("rotation_degrees"), k.path("rotation_degrees")));
    });
    s.instances.push_back(std::move(keys));
  });
}

void read_light_power(ObjectReader& parent, ShotScript& s) {
  read_objects(parent, "light_power", [&](ObjectReader& r, const std::string& where) {
    PowerKeys keys;
    keys.where = where;
    if (int(r.has("punctual")) + int(r.has("material")) + int(r.has("material_name")) != 1)
      r.fail_at(where, "give exactly one of \"punctual\", \"material\" (indices) or \"material_name\"");
    keys.punctual = r.integer("punctual", 0, std::numeric_limits<int>::max(), -1);
    keys.material = r.integer("material", 0, std::numeric_limits<int>::max(), -1);
    keys.material_name = r.text("material_name", "");
    keys.interpolation = r.named("interpolation", interpolation_names(), Interpolation::Linear);
    read_keys(r, keys.frames, [&](ObjectReader& k) {
      if (!k.has("scale")) k.fail("scale", "missing");
      keys.scale.push_back(float(k.number("scale", 1.0 / kMaxPowerScale, kMaxPowerScale, 1.0)));
    });
    s.light_power.push_back(std::move(keys));
  });
}

void read_output(ObjectReader& parent, ShotScript& s) {
  const json* out = parent.get("output");
  if (!out) parent.fail("output", "missing (where the frames go)");
  ObjectReader r(parent.file(), *out, "output");
  const json* images = r.get("images");
  if (images) {
    if (images->is_string())
      s.output.images.push_back(images->get<std::string>());
    else if (images->is_array() &&
             std::all_of(images->begin(), images->end(), [](const json& x) { return x.is_string(); }))
      s.output.images = images->get<std::vector<std::string>>();
    else
      r.fail("images", "expected a path pattern or an array of them");
    for (const std::string& p : s.output.images) check_pattern(r, "images", p, false);
  }
  for (const AovInfo& aov : aov_table()) {
    if (aov.aov == Aov::Radiance) continue;  // "images"
    std::string pattern = r.text(aov.name, "");
    if (pattern.empty()) continue;
    check_pattern(r, aov.name, pattern, true);
    const bool restir = s.settings.method == Method::RestirDi || s.settings.method == Method::Restir;
    if (aov.restir && !restir) r.fail(aov.name, "needs method restir-di or restir");
    s.output.aovs[aov.name] = pattern;
  }
  if (s.output.images.empty() && s.output.aovs.empty()) r.fail_at("output", "names no images or AOVs to write");
  s.output.stats = r.text("stats", "");
  s.output.exposure = float(r.number("exposure", 1e-6, 1e6, 1.0));
  r.finish();
}

}  // namespace

bool ShotScript::keeps_history() const {
  bool restir = settings.method == Method::RestirDi || settings.method == Method::Restir;
  return (restir && (settings.di_reuse.temporal || settings.gi_reuse.temporal)) ||
         settings.denoise.kind == DenoiserKind::Svgf || output.aovs.count("motion");
}

ShotScript read_shot_script(const std::string& path) {
  const json root = parse_file(path);
  ShotScript s;
  s.file = path;
  ObjectReader r(path, root, "");
  if (!r.has("scene")) r.fail("scene", "missing (builtin:NAME or a .gltf/.glb file)");
  s.scene = r.text("scene", "");
  s.lights = r.integer("lights", 1, 4000000, s.lights);
  s.environment = float(r.number("environment", 0.0, 1e6, s.environment));
  read_render_settings(r, s);
  s.first_frame = r.integer("first_frame", 0, 10000000, s.first_frame);
  s.frames = r.integer("frames", 1, 10000000, s.frames);
  s.fps = float(r.number("fps", 0.001, 10000.0, s.fps));
  s.warmup = r.integer("warmup", 0, 10000, s.warmup);
  s.history_reset_every = r.integer("history_reset_every", 0, 10000000, s.history_reset_every);
  s.gltf_animations = r.flag("gltf_animations", s.gltf_animations);
  read_camera(r, s);
  read_instances(r, s);
  read_light_power(r, s);
  read_output(r, s);
  r.finish();
  return s;
}

// Instances: world(t) = T(centre) * T(translation(t)) * R(t) * T(-centre) * loaded transform, with the
// centre of the instance's world bounds as loaded. Powers: base = the loaded intensity or emission.
void apply_shot_animation(const ShotScript& script, Scene& scene) {
  if (!script.gltf_animations) scene.instance_animations.clear();
  for (const InstanceKeys& keys : script.instances) {
    std::vector<int> targets;
    if (keys.index >= 0) {
      if (size_t(keys.index) >= scene.instances.size())
        throw InputError(script.file + ": " + keys.where + ".instance: " + std::to_string(keys.index) +
                         " does not exist (" + script.scene + " has " + std::to_string(scene.instances.size()) +
                         " instances)");
      targets.push_back(keys.index);
    } else {
      for (size_t i = 0; i < scene.instances.size(); ++i)
        if (scene.instances[i].name == keys.name) targets.push_back(int(i));
      if (targets.empty())
        throw InputError(script.file + ": " + keys.where + ".name: no instance of " + script.scene + " is named '" +
                         keys.name + "'");
    }
    for (int target : targets) {
      Instance& inst = scene.instances[size_t(target)];
      Bounds3 local = scene.meshes[size_t(inst.mesh)].bounds();
      vec3 centre = transform_point(inst.transform, local.empty() ? vec3(0.0f) : local.center());
      InstanceAnimation a;
      a.instance = target;
      a.after = glm::translate(mat4(1.0f), centre);
      a.before = glm::translate(mat4(1.0f), -centre) * inst.transform;
      auto track = [&](const std::vector<vec3>& values) {
        Track<vec3> t;
        for (float f : keys.frames) t.times.push_back(f / script.fps);
        t.values = values;
        t.interpolation = keys.interpolation;
        return t;
      };
      if (!keys.translation.empty()) a.translation = track(keys.translation);
      if (!keys.rotation_degrees.empty()) a.euler_degrees = track(keys.rotation_degrees);
      std::erase_if(scene.instance_animations,
                    [&](const InstanceAnimation& other) { return other.instance == target; });
      scene.instance_animations.push_back(a);
      inst.animated = true;
    }
  }
  for (const PowerKeys& keys : script.light_power) {
    auto add = [&](PowerAnimation::Target target, int index, vec3 base) {
      PowerAnimation a;
      a.target = target;
      a.index = index;
      a.base = base;
      for (float f : keys.frames) a.scale.times.push_back(f / script.fps);
      a.scale.values = keys.scale;
      a.scale.interpolation = keys.interpolation;
      scene.power_animations.push_back(a);
    };
    auto missing = [&](const std::string& key, const std::string& what) {
      throw InputError(script.file + ": " + keys.where + "." + key + ": " + what);
    };
    if (keys.punctual >= 0) {
      if (size_t(keys.punctual) >= scene.punctual_lights.size())
        missing("punctual", std::to_string(keys.punctual) + " does not exist (" + script.scene + " has " +
                                std::to_string(scene.punctual_lights.size()) + " punctual lights)");
      add(PowerAnimation::Target::Punctual, keys.punctual, scene.punctual_lights[size_t(keys.punctual)].intensity);
      continue;
    }
    std::vector<int> materials;
    if (keys.material >= 0) {
      if (size_t(keys.material) >= scene.materials.size())
        missing("material", std::to_string(keys.material) + " does not exist (" + script.scene + " has " +
                                std::to_string(scene.materials.size()) + " materials)");
      materials.push_back(keys.material);
    } else {
      for (size_t i = 0; i < scene.materials.size(); ++i)
        if (scene.materials[i].name == keys.material_name) materials.push_back(int(i));
      if (materials.empty())
        missing("material_name", "no material of " + script.scene + " is named '" + keys.material_name + "'");
    }
    for (int m : materials) {
      if (!scene.materials[size_t(m)].emissive())
        missing(keys.material >= 0 ? "material" : "material_name", "material " + std::to_string(m) + " does not emit");
      add(PowerAnimation::Target::Material, m, scene.materials[size_t(m)].emission);
    }
  }
}

CameraDesc shot_camera(const ShotScript& script, const Scene& scene, int frame) {
  CameraDesc camera = scene.default_camera();
  if (script.camera_frames.empty()) return camera;
  auto at = [&](const auto& values) {
    Track<typename std::decay_t<decltype(values)>::value_type> t;
    t.times = script.camera_frames;
    t.values = values;
    t.interpolation = script.camera_interpolation;
    return t.at(float(frame));
  };
  camera.position = at(script.camera_position);
  camera.target = at(script.camera_target);
  camera.vfov_degrees = std::clamp(at(script.camera_fov), 1.0f, 179.0f);
  camera.up = vec3(0.0f, 1.0f, 0.0f);
  return camera;
}

std::string frame_path(const std::string& pattern, int frame) {
  size_t at = pattern.find('%');
  size_t end = pattern.find('d', at);
  int width = end > at + 1 ? std::stoi(pattern.substr(at + 1, end - at - 1)) : 0;
  std::string number = std::to_string(frame);
  if (int(number.size()) < width) number.insert(0, size_t(width) - number.size(), '0');
  return pattern.substr(0, at) + number + pattern.substr(end + 1);
}

}  // namespace candela

#include "apps/scene_source.h"

#include <cstdio>

#include "engine/gltf_loader.h"

namespace candela {

static bool brings_light(const Scene& scene) {
  if (!scene.punctual_lights.empty()) return true;
  for (const Instance& inst : scene.instances)
    if (scene.materials[scene.meshes[inst.mesh].material].emissive()) return true;
  return false;
}

void apply_default_environment(Scene& scene, const std::string& source) {
  if (source.rfind("builtin:", 0) == 0) return;
  scene.environment = vec3(0.0f);
  if (brings_light(scene)) return;
  scene.environment = vec3(kFallbackEnvironment);
  std::fprintf(stderr,
               "warning: %s: no emissive material and no punctual light; lit by a uniform grey environment "
               "of %g (--environment sets another)\n",
               source.c_str(), double(kFallbackEnvironment));
}

// The scene as its source defines it (no environment rule), with the loader's warnings printed.
static Scene load_scene_file(const std::string& source, const BuiltinOptions& options) {
  const std::string prefix = "builtin:";
  if (source.rfind(prefix, 0) == 0) return make_builtin_scene(source.substr(prefix.size()), options);
  LoadReport report;
  Scene scene = load_gltf(source, &report);
  size_t shown = 0;
  for (const std::string& w : report.warnings)
    if (shown++ < 10) std::fprintf(stderr, "warning: %s\n", w.c_str());
  if (report.warnings.size() > 10) std::fprintf(stderr, "warning: ... and %zu more\n", report.warnings.size() - 10);
  if (report.degenerate_triangles_skipped)
    std::fprintf(stderr, "warning: %s: skipped %zu degenerate triangles\n", source.c_str(),
                 report.degenerate_triangles_skipped);
  return scene;
}

Scene load_scene(const std::string& source, const BuiltinOptions& options, float environment) {
  Scene scene = load_scene_file(source, options);
  if (environment >= 0.0f)
    scene.environment = vec3(environment);
  else
    apply_default_environment(scene, source);
  return scene;
}

}  // namespace candela

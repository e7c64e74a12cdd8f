#include "apps/scene_source.h"

#include <cstdio>

#include "engine/gltf_loader.h"

namespace candela {

Scene load_scene(const std::string& source, const BuiltinOptions& options) {
  const std::string prefix = "builtin:";
  if (source.rfind(prefix, 0) == 0) return make_builtin_scene(source.substr(prefix.size()), options);
  LoadReport report;
  Scene scene = load_gltf(source, &report);
  size_t shown = 0;
  for (const std::string& w : report.warnings)
    if (shown++ < 10) std::fprintf(stderr, "warning: %s\n", w.c_str());
  if (report.warnings.size() > 10) std::fprintf(stderr, "warning: ... and %zu more\n", report.warnings.size() - 10);
  if (report.degenerate_triangles_skipped)
    std::fprintf(stderr, "warning: %s: skipped %zu degenerate triangles\n", source.c_str(), report.degenerate_triangles_skipped);
  return scene;
}

}  // namespace candela

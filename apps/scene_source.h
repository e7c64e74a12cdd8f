#pragma once
// Resolves a scene argument: "builtin:NAME" (procedural) or a path to a .gltf/.glb file.
#include <string>

#include "engine/builtin_scenes.h"
#include "engine/scene.h"

namespace candela {

// Throws InputError naming the argument or file when it cannot be loaded. Prints load warnings to stderr.
// `environment` >= 0 sets a uniform environment of that radiance; < 0 applies the default rule (below).
Scene load_scene(const std::string& source, const BuiltinOptions& options = {}, float environment = -1.0f);

// The default environment, the one rule every command and script uses: built-in scenes keep their own; a
// file that brings light (emissive materials or punctual lights) gets none, so that only its own light
// shines; a file with no light at all gets a uniform grey of kFallbackEnvironment and a warning.
inline constexpr float kFallbackEnvironment = 0.3f;
void apply_default_environment(Scene& scene, const std::string& source);

}  // namespace candela

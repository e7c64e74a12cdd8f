#pragma once
// Resolves a scene argument: "builtin:NAME" (procedural) or a path to a .gltf/.glb file.
#include <string>

#include "engine/builtin_scenes.h"
#include "engine/scene.h"

namespace candela {

// Throws InputError naming the argument or file when it cannot be loaded. Prints load warnings to stderr.
Scene load_scene(const std::string& source, const BuiltinOptions& options = {});

}  // namespace candela

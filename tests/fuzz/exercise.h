#pragma once
// What each fuzz target does with one input file, shared with the regression test of the findings
// (tests/test_fuzz_findings.cpp). Both throw InputError on bad input; anything else is a bug.
#include <string>

#include "apps/shot_script.h"
#include "engine/builtin_scenes.h"
#include "engine/gltf_loader.h"

namespace candela::fuzz {

// The glTF/GLB loader.
inline void exercise_gltf(const std::string& path) {
  LoadReport report;
  load_gltf(path, &report);
}

// The shot-script reader, then what a render does with the script before its first frame: keyframes
// applied to a built-in scene, the first and last frames' cameras, the output paths.
inline void exercise_shot_script(const std::string& path) {
  static const Scene cornell = make_cornell_scene();
  ShotScript script = read_shot_script(path);
  Scene scene = cornell;
  apply_shot_animation(script, scene);
  shot_camera(script, scene, script.first_frame);
  shot_camera(script, scene, script.last_frame());
  for (const std::string& pattern : script.output.images) frame_path(pattern, script.last_frame());
}

}  // namespace candela::fuzz

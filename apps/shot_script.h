#pragma once
// A shot script (`candela render --script SHOT.json`): the scene, the render settings (keys named as the
// `render` options, "--di-candidates" -> "di_candidates"), the frame range and rate, camera keyframes,
// keyframed instance transforms, light power keyframes and where frames, AOVs and stats go. docs/sequences.md
// documents the format; docs/shots/ holds examples. Every error names the script file and the key.
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "apps/renderer.h"
#include "engine/animation.h"
#include "engine/scene.h"

namespace candela {

// Keyed by frame number (may be fractional); keys in increasing frame order.
struct InstanceKeys {
  std::string where;  // "instances[2]", for messages
  int index = -1;     // "instance": index into Scene::instances, or
  std::string name;   // "name": the instances whose Instance::name equals it
  Interpolation interpolation = Interpolation::Linear;
  std::vector<float> frames;
  std::vector<vec3> translation;       // offsets added to the instance's position (empty: not animated)
  std::vector<vec3> rotation_degrees;  // Euler X, Y, Z about the instance's bounds centre (empty: not animated)
};

struct PowerKeys {
  std::string where;          // "light_power[0]"
  int punctual = -1;          // "punctual": index into Scene::punctual_lights, or
  int material = -1;          // "material": index into Scene::materials, or
  std::string material_name;  // "material_name": the materials whose name equals it
  Interpolation interpolation = Interpolation::Linear;
  std::vector<float> frames;
  std::vector<float> scale;  // power scale factors, > 0
};

// Image outputs: patterns with one %d or %0Nd for the frame number.
struct ShotOutput {
  std::vector<std::string> images;          // .exr (linear) and/or .png (tonemapped)
  std::map<std::string, std::string> aovs;  // AOV name (apps/aovs.h: "albedo", "reservoir-m", ...) -> .exr pattern
  std::string stats;                        // base path: writes STATS.csv and STATS.json ("" = none)
  float exposure = 1.0f;                    // PNG only
};

struct ShotScript {
  std::string file;           // the script's path, as given
  std::string scene;          // builtin:NAME or a .gltf/.glb path (relative to the current directory)
  int lights = 1024;          // builtin:manylights
  float environment = -1.0f;  // < 0: the default rule (apply_default_environment), as `render`
  RenderSettings settings;    // accumulate is always off: every frame stands alone
  int first_frame = 0, frames = 1;
  float fps = 30.0f;            // scene time of frame f is f / fps seconds
  int warmup = 8;               // frames rendered unwritten before a shard or a resumed run (history methods)
  int history_reset_every = 0;  // > 0: history restarts at first_frame + k * N (makes shards exact)
  bool gltf_animations = true;  // play the glTF file's own animations
  Interpolation camera_interpolation = Interpolation::Smooth;
  std::vector<float> camera_frames;  // empty: the scene's camera, still
  std::vector<vec3> camera_position, camera_target;
  std::vector<float> camera_fov;
  std::vector<InstanceKeys> instances;
  std::vector<PowerKeys> light_power;
  ShotOutput output;

  int last_frame() const { return first_frame + frames - 1; }
  float time_of(int frame) const { return float(frame) / fps; }
  // The method keeps state from frame to frame (temporal reuse, SVGF, and motion vectors for the motion AOV).
  bool keeps_history() const;
};

// Reads and validates a script (syntax, keys, types, ranges, keyframe order, output patterns). Throws
// InputError("FILE: line L, column C: ..." for bad JSON, "FILE: KEY: ..." otherwise).
ShotScript read_shot_script(const std::string& path);

// Adds the script's instance and light power keyframes to `scene` as InstanceAnimation/PowerAnimation
// (and drops the scene's glTF animations if "gltf_animations" is false). Throws InputError naming the
// script and key when an index or name does not exist in the scene.
void apply_shot_animation(const ShotScript& script, Scene& scene);

// The camera of frame `frame`: the keyframed camera or, without keys, the scene's default camera.
CameraDesc shot_camera(const ShotScript& script, const Scene& scene, int frame);

// `pattern` with its %d / %0Nd replaced by `frame`.
std::string frame_path(const std::string& pattern, int frame);

}  // namespace candela

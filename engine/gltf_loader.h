#pragma once
// glTF 2.0 loader (.gltf and .glb, through tinygltf): turns a file into a candela::Scene.
//
// What it reads: the default scene's node hierarchy (all root nodes when no scene is given), triangle
// primitives (one candela Mesh per glTF (mesh, primitive) pair, instanced by every node that uses it),
// metallic-roughness materials with KHR_materials_emissive_strength and KHR_texture_transform, textures
// (as 8-bit RGBA), KHR_lights_punctual lights and the first perspective camera.
//
// Choices worth knowing:
// - A primitive without NORMAL keeps Mesh::normals empty: the renderer uses geometric normals.
// - A texture used both as colour (base colour, emission: sRGB) and as data (normal, metallic-roughness:
//   linear) is duplicated; the linear copy is appended after the glTF textures.
// - A texture whose image is missing or cannot be decoded stays in Scene::textures as a 1x1 white
//   placeholder (indices keep matching the glTF file) and every material slot naming it becomes -1.
// - The camera is the first perspective one met depth-first; its up vector is the node's +Y axis.
// - Out-of-range material factors are clamped with a warning; emissiveFactor above 1 is kept silently.
// - Degenerate triangles (a repeated index or exactly zero area) are dropped and counted once per mesh.
// - Skins and morph targets are ignored (the static pose is loaded) with a warning.
// - Animations: every animation's translation/rotation/scale channels play at once (time in seconds) on
//   the instances of the nodes they target (Scene::instance_animations), LINEAR (rotations by slerp) and
//   STEP; CUBICSPLINE is read as LINEAR through its key values with a warning. Animated nodes without a
//   mesh, nodes moved only by an animated ancestor, and lights/cameras on animated nodes stay static
//   (with a warning).
// - Instances carry their node's name (Instance::name).
//
// Hostile input (limits and their reasons in engine/input_limits.h): the JSON (of a .gltf, or a .glb's
// JSON chunk) is refused before parsing when nested deeper than kMaxJsonDepth (512) levels. After the
// node transforms, every vertex (the corners of each instance's bounds, for animated instances at every
// key time), light position and the camera must lie within +-kMaxCoordinate (1e8) in every coordinate:
// ray arithmetic multiplies up to three coordinate differences, (2e8)^3 = 8e24 stays far below FLT_MAX,
// while 1e38 vertices or a node scale of 1e25 overflowed to inf/NaN inside Embree. Emission
// (emissiveFactor x strength) and punctual intensities must be at most kMaxEmission (1e10) per channel,
// so that light powers (radiance x area x 2 pi, in float) stay finite. Each refusal is an InputError
// naming the accessor, node, light or material.
#include <cstddef>
#include <string>
#include <vector>

#include "engine/scene.h"

namespace candela {

// What a load noticed without failing.
struct LoadReport {
  size_t degenerate_triangles_skipped = 0;  // over unique meshes, not instances
  std::vector<std::string> warnings;        // each starts with the file path
};

// Loads a .gltf/.glb file into a Scene. Throws InputError("<file>: <what is wrong and where>") on bad
// input; no other exception escapes for a bad file. `report`, if given, is cleared and then filled.
Scene load_gltf(const std::string& path, LoadReport* report = nullptr);

}  // namespace candela

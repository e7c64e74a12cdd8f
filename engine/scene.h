#pragma once
// The scene model every loader produces and every stage reads: meshes (one material each), instances
// of meshes with transforms (animated ones keep last frame's transform for motion vectors), materials,
// textures, punctual lights, an optional camera and a uniform environment colour.
#include <optional>
#include <string>
#include <vector>

#include "engine/animation.h"
#include "engine/math.h"
#include "engine/texture.h"

namespace candela {

enum class AlphaMode : uint8_t { Opaque, Mask, Blend };

// glTF 2.0 metallic-roughness material.
struct Material {
  std::string name;
  vec4 base_color{1.0f};
  TextureRef base_color_tex;
  float metallic = 0.0f, roughness = 1.0f;
  TextureRef metallic_roughness_tex;  // G = roughness, B = metallic
  float specular = 1.0f;              // KHR_materials_specular factor (0 = pure Lambert diffuse)
  TextureRef specular_tex;            // A = specular factor multiplier
  vec3 specular_color{1.0f};          // KHR_materials_specular colour factor (scales the dielectric F0)
  TextureRef specular_color_tex;      // RGB (sRGB) multiplies it
  float ior = 1.5f;                   // KHR_materials_ior: dielectric F0 = ((ior - 1) / (ior + 1))^2
  TextureRef normal_tex;
  float normal_scale = 1.0f;
  vec3 emission{0.0f};  // emissiveFactor * KHR_materials_emissive_strength
  TextureRef emissive_tex;
  AlphaMode alpha_mode = AlphaMode::Opaque;
  float alpha_cutoff = 0.5f;
  bool double_sided = false;  // also makes emission two-sided
  bool emissive() const { return max_component(emission) > 0.0f; }
};

// An indexed triangle mesh in object space with one material. Optional attributes are empty or full.
struct Mesh {
  std::string name;
  std::vector<vec3> positions;
  std::vector<vec3> normals;
  std::vector<vec4> tangents;  // xyz tangent, w handedness
  std::vector<vec2> uv0, uv1;
  std::vector<uvec3> triangles;
  int material = 0;
  Bounds3 bounds() const;
};

struct Instance {
  int mesh = 0;
  mat4 transform{1.0f};
  mat4 prev_transform{1.0f};  // last frame's transform, for motion vectors
  bool animated = false;      // its transform may change between frames
  std::string name;           // glTF node name (may be empty)
};

enum class PunctualType : uint8_t { Point, Spot, Directional };

// KHR_lights_punctual in world space: intensity in candela (point/spot) or lux (directional).
struct PunctualLight {
  PunctualType type = PunctualType::Point;
  vec3 position{0.0f};
  vec3 direction{0.0f, 0.0f, -1.0f};  // where the light points (spot, directional)
  vec3 intensity{1.0f};               // colour * intensity
  float inner_cone = 0.0f, outer_cone = kPi / 4.0f;
  int instance = -1;  // attached to an instance: position/direction are in its object space
};

struct CameraDesc {
  vec3 position{0.0f, 0.0f, 5.0f};
  vec3 target{0.0f};
  vec3 up{0.0f, 1.0f, 0.0f};
  float vfov_degrees = 45.0f;
};

// Straight-line motion of an animated instance, wrapping around after `wrap_distance`.
struct InstanceMotion {
  int instance = 0;
  mat4 start{1.0f};
  vec3 velocity{0.0f};  // scene units per second
  float wrap_distance = 1.0f;
  float phase = 0.0f;  // distance already travelled at t = 0
};

struct Scene {
  std::string name;
  std::vector<Mesh> meshes;
  std::vector<Material> materials;
  std::vector<Texture> textures;
  std::vector<Instance> instances;
  std::vector<PunctualLight> punctual_lights;
  std::vector<InstanceMotion> motions;
  std::vector<InstanceAnimation> instance_animations;  // keyframed (glTF animations, shot scripts)
  std::vector<PowerAnimation> power_animations;        // light power over time
  std::optional<CameraDesc> camera;
  vec3 environment{0.0f};  // uniform radiance of the background
  float time = 0.0f;

  Bounds3 bounds() const;
  size_t triangle_count() const;  // over instances
  const Material& material_of(uint32_t instance) const { return materials[meshes[instances[instance].mesh].material]; }
  // Moves animated instances to time t (seconds); their previous transform becomes prev_transform.
  // Then scales animated light powers (punctual intensities, material emission).
  void set_time(float t);
  // Anything changes with time (motions, keyframed instances or light powers).
  bool animated() const { return !motions.empty() || !instance_animations.empty() || !power_animations.empty(); }
  // Camera to use: the scene's own, or one framing the scene bounds.
  CameraDesc default_camera() const;
};

}  // namespace candela

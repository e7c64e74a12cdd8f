#pragma once
// The G-buffer's surfaces evaluated in SIMD lanes, one tile row of primary hits at a time. The kernel repeats
// surface_at's arithmetic in its order (world_triangle, the face and interpolated normals, the flips towards
// the viewer) and the G-buffer's own (view depth, motion vector through the previous camera), so its planes
// hold surface_at's bits (tests/test_gbuffer.cpp). Materials with textures are left to surface_at: the kernel
// covers the geometry and constant material parameters only.
#include <cstdint>
#include <vector>

#include "engine/camera.h"
#include "engine/gbuffer.h"
#include "engine/tiles.h"

namespace candela {

// What shading a primary hit reads of its instance, gathered once per frame: per instance, one record of
// kFields floats that the kernel gathers by instance index, and the transforms the scalar path reads.
struct GBufferInstances {
  enum Field : int {
    kTransform = 0,         // mat4 columns 0..3, rows 0..2
    kNormalMatrix = 12,     // cofactor matrix of the linear part, columns 0..2
    kPrevFromCurrent = 21,  // this frame's world position -> last frame's (animated instances)
    kBaseColor = 33,        // rgb
    kMetallic = 36,
    kRoughness = 37,
    kSpecular = 38,
    kSpecularF0 = 39,   // rgb, dielectric_f0 of the material
    kEmission = 42,     // rgb; 0 unless the material emits
    kMirrored = 45,     // 1: the transform flips handedness
    kAnimated = 46,     // 1: motion vectors go through kPrevFromCurrent
    kDoubleSided = 47,  // 1: emits on both sides
    kHasNormals = 48,   // 1: the mesh has vertex normals
    kFields = 49,
  };
  // Reads the scene's instances, meshes and materials. O(instances).
  explicit GBufferInstances(const Scene& scene);
  std::vector<float> records;           // kFields per instance (one zero record when there are none)
  std::vector<mat4> prev_from_current;  // identity for static instances
  std::vector<uint8_t> plain;           // 1: the material has no textures, the kernel's values are final
};

// Primary hits of one tile row in pixel order (slot s is pixel x0 + s) with the object-space corners and
// vertex normals of each hit triangle (fetched from the meshes by the caller, 0 where there is no hit or
// no vertex normal).
struct PrimaryHitLanes {
  alignas(64) uint32_t instance[kTileWidth];  // kNoHit where the ray missed
  alignas(64) uint32_t prim[kTileWidth];
  alignas(64) float u[kTileWidth], v[kTileWidth];  // Embree's barycentrics
  alignas(64) float dir[3][kTileWidth];            // unit ray direction
  alignas(64) float film[2][kTileWidth];           // film position of the ray (pixels)
  alignas(64) float corner[3][3][kTileWidth];      // [corner][axis], object space
  alignas(64) float normal[3][3][kTileWidth];      // [corner][axis], object space
};

// Slots [0, count) of row.dir: the camera's unit direction through each film position (Camera::direction's
// bits). ~20 flops per pixel, in lanes.
void camera_directions_lanes(const Camera& camera, int count, PrimaryHitLanes& row);

// Writes pixels [first_pixel, first_pixel + count) of every G-buffer plane except `jitter` from slots
// [0, count) of `hits` (count <= kTileWidth): surface_at's values for hits on plain materials (the caller
// overwrites the others with surface_at), the environment for misses; `still` (camera == prev_camera): only
// animated instances' hits get a motion vector. ~250 flops and 40 gathers per pixel, in lanes.
void shade_gbuffer_lanes(const GBufferInstances& instances, const Camera& camera, const Camera& prev_camera, bool still,
                         const vec3& environment, const PrimaryHitLanes& hits, int count, size_t first_pixel,
                         GBuffer& out);

}  // namespace candela

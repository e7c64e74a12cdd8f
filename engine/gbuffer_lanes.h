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
#include "engine/surface.h"
#include "engine/tiles.h"

namespace candela {

// What shading a primary hit reads of its instance, gathered once per frame: per instance, one record of
// kFields floats that the kernel gathers by instance index, the arrays of its mesh, and the transforms the
// scalar path reads.
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
  // An instance's mesh as flat arrays: 3 vertex indices per triangle, 3 floats per vertex.
  struct MeshArrays {
    const uint32_t* triangles = nullptr;
    const float* positions = nullptr;
    const float* normals = nullptr;  // null: the mesh has no vertex normals
  };
  // Reads the scene's instances, meshes and materials. O(instances).
  explicit GBufferInstances(const Scene& scene);
  std::vector<float> records;           // kFields per instance (one zero record when there are none)
  std::vector<MeshArrays> meshes;       // per instance
  std::vector<mat4> prev_from_current;  // identity for static instances
  std::vector<uint8_t> plain;           // 1: the material has no textures, the kernel's values are final
  bool all_plain = true;                // every instance's material is plain: no hit needs surface_at
  // Whether the kernels' surface of a hit on `instance` is final (a hit on a plain material), or surface_at's
  // is needed (a textured one; kNoHit: no surface).
  bool in_lanes(uint32_t instance) const { return instance != kNoHit && plain[instance]; }
  // The two dependent loads of a hit's corners (surface_points_lanes' triangle_corners), started ahead for hits far
  // apart, whose triangles are cache misses: first the line of the triangle's vertex indices, then, once that line
  // has arrived, the lines of its three corners and their normals (which read the indices).
  void prefetch_triangle(uint32_t instance, uint32_t prim) const {
    if (instance != kNoHit) __builtin_prefetch(meshes[instance].triangles + size_t(prim) * 3);
  }
  void prefetch_corners(uint32_t instance, uint32_t prim) const {
    if (instance == kNoHit) return;
    const MeshArrays& a = meshes[instance];
    const uint32_t* tri = a.triangles + size_t(prim) * 3;
    for (int k = 0; k < 3; ++k) {
      __builtin_prefetch(a.positions + size_t(tri[k]) * 3);
      if (a.normals) __builtin_prefetch(a.normals + size_t(tri[k]) * 3);
    }
  }
};

// Primary rays and hits of one tile row in pixel order (slot s is pixel x0 + s).
struct PrimaryHitLanes {
  alignas(64) uint32_t instance[kTileWidth];  // kNoHit where the ray missed
  alignas(64) uint32_t prim[kTileWidth];
  alignas(64) float u[kTileWidth], v[kTileWidth];  // Embree's barycentrics
  alignas(64) float dir[3][kTileWidth];            // unit ray direction
  alignas(64) float film[2][kTileWidth];           // film position of the ray (pixels)
};

// Slots [0, count) of the row of pixels (x0 + s, y): row.film = the pixel plus its jitter (jitter_x[s],
// jitter_y[s]; the pixel centre where jitter_x is null), row.dir = Camera::direction's bits through it, and
// jitter[s] = the jitter. ~20 flops per pixel, in lanes.
void primary_rays_lanes(const Camera& camera, int x0, int y, int count, const float* jitter_x, const float* jitter_y,
                        PrimaryHitLanes& row, vec2* jitter);

// surface_at(scene, instance, prim, (u, v), -dir) for the hits of slots [0, count) of `hits` (count <= kTileWidth;
// film is not read) whose material is plain (GBufferInstances::plain), into out[slot]; other slots are left
// alone. The same bits as surface_at (tests/test_path_tracer.cpp), ~250 flops per hit in lanes.
void surface_points_lanes(const GBufferInstances& instances, const PrimaryHitLanes& hits, int count, SurfacePoint* out);

// Writes pixels [first_pixel, first_pixel + count) of every G-buffer plane except `jitter` (and `packed` where it is
// sized) from slots [0, count) of `hits` (count <= kTileWidth): surface_at's values for hits on plain materials
// (the caller overwrites the others with surface_at), the environment for misses; `still` (camera ==
// prev_camera): only animated instances' hits get a motion vector. ~250 flops per pixel in lanes (~60 more for
// the packed surface), and ~20 scalar loads per distinct triangle of each vector.
void shade_gbuffer_lanes(const GBufferInstances& instances, const Camera& camera, const Camera& prev_camera, bool still,
                         const vec3& environment, const PrimaryHitLanes& hits, int count, size_t first_pixel,
                         GBuffer& out);

}  // namespace candela

#pragma once
// The G-buffer: one plane per attribute (structure of arrays) of the surface seen through each pixel,
// and the stage that fills it with jittered primary rays traced in 4x4 packets.
#include <vector>

#include "engine/bsdf.h"
#include "engine/camera.h"
#include "engine/frame_stats.h"
#include "engine/packed_surface.h"
#include "engine/scene.h"
#include "engine/tracer.h"

namespace candela {

// Allocates on 64-byte boundaries, so that a whole vector of 16 pixels' values is one or more whole cache lines.
template <class T>
struct CacheLineAllocator {
  using value_type = T;
  CacheLineAllocator() = default;
  template <class U>
  CacheLineAllocator(const CacheLineAllocator<U>&) {}
  T* allocate(size_t n) { return static_cast<T*>(::operator new(n * sizeof(T), std::align_val_t(64))); }
  void deallocate(T* p, size_t) { ::operator delete(p, std::align_val_t(64)); }
  friend bool operator==(const CacheLineAllocator&, const CacheLineAllocator&) { return true; }
};
template <class T>
using Plane = std::vector<T, CacheLineAllocator<T>>;

struct GBuffer {
  int width = 0, height = 0;
  Plane<vec3> position;
  Plane<vec3> shading_normal;
  Plane<vec3> geometric_normal;
  Plane<float> depth;       // linear view depth; kInfinity where nothing was hit
  Plane<vec3> albedo;       // base colour
  Plane<vec3> material;     // roughness, metallic, specular factor
  Plane<vec3> specular_f0;  // the dielectric's F0
  Plane<vec3> emission;
  Plane<uint32_t> instance;  // kNoHit where nothing was hit
  Plane<vec2> motion;        // pixels from this frame's film position to last frame's
  Plane<vec2> jitter;        // film position of the primary ray within its pixel, in [0,1)^2
  // The same surfaces packed (PackedSurface{} where nothing was hit), written where GBufferParams::packed asks
  // for them; empty otherwise.
  Plane<PackedSurface> packed;

  void resize(int w, int h);
  size_t size() const { return size_t(width) * height; }
  bool hit(size_t i) const { return instance[i] != kNoHit; }
  Bsdf bsdf(size_t i) const {
    return Bsdf(shading_normal[i], albedo[i], material[i].y, material[i].x, material[i].z, specular_f0[i]);
  }
};

struct GBufferParams {
  uint64_t seed = 0;
  int frame = 0;
  bool jitter = true;   // false: rays through pixel centres
  bool simd = true;     // false: every pixel through surface_at (the reference the SIMD kernel is tested against)
  bool packed = false;  // also write GBuffer::packed (ReSTIR's targets read it)
};

// Reads scene, tracer and both cameras; writes every plane of `out` (`packed` only with params.packed). Traces one ray
// per pixel (rtcIntersect16 on 4x4 pixel blocks, coherent flag); shades a tile row at a time in SIMD lanes
// (gbuffer_lanes.h), hits on textured materials with surface_at.
void trace_gbuffer(const Scene& scene, const Tracer& tracer, const Camera& camera, const Camera& prev_camera,
                   const GBufferParams& params, GBuffer& out, RayCounter& rays);

}  // namespace candela

#include "engine/gbuffer.h"

#include "engine/gbuffer_lanes.h"
#include "engine/rng.h"
#include "engine/surface.h"
#include "engine/tiles.h"

namespace candela {

void GBuffer::resize(int w, int h) {
  width = w;
  height = h;
  size_t n = size();
  position.assign(n, vec3(0.0f));
  shading_normal.assign(n, vec3(0.0f));
  geometric_normal.assign(n, vec3(0.0f));
  depth.assign(n, kInfinity);
  albedo.assign(n, vec3(0.0f));
  material.assign(n, vec3(0.0f));
  specular_f0.assign(n, vec3(0.0f));
  emission.assign(n, vec3(0.0f));
  instance.assign(n, kNoHit);
  motion.assign(n, vec2(0.0f));
  jitter.assign(n, vec2(0.5f));
}

// Writes pixel i from a primary hit: surface attributes and the motion vector, which follows the hit
// point through its instance's previous transform into the previous camera. Where neither the camera nor
// the point moved, the motion is exactly 0 (projecting would give rounding noise of ~1e-4 pixels, of
// either sign, which moves the reprojected pixel centres off the pixels: SVGF then blends 2-4 taps).
// `still`: camera == prev_camera.
static void write_pixel(const Scene& scene, const std::vector<mat4>& prev_from_current, const Camera& camera,
                        const Camera& prev_camera, bool still, const Hit& hit, const vec3& dir, vec2 film, size_t i,
                        GBuffer& g) {
  if (!hit.valid()) {
    g.position[i] = g.shading_normal[i] = g.geometric_normal[i] = g.albedo[i] = vec3(0.0f);
    g.material[i] = g.specular_f0[i] = vec3(0.0f);
    g.instance[i] = kNoHit;
    g.depth[i] = kInfinity;
    g.emission[i] = scene.environment;
    g.motion[i] = vec2(0.0f);
    if (!g.packed.empty()) g.packed[i] = PackedSurface{};
    vec2 prev_film;
    // The background is infinitely far: it moves with the camera's rotation only.
    if (!still && prev_camera.project(prev_camera.position() + dir, prev_film)) g.motion[i] = prev_film - film;
    return;
  }
  SurfacePoint sp = surface_at(scene, hit.instance, hit.prim, hit.barycentric, -dir);
  g.position[i] = sp.position;
  g.shading_normal[i] = sp.shading_normal;
  g.geometric_normal[i] = sp.geometric_normal;
  g.depth[i] = camera.view_depth(sp.position);
  g.albedo[i] = sp.base_color;
  g.material[i] = vec3(sp.roughness, sp.metallic, sp.specular);
  g.specular_f0[i] = sp.specular_f0;
  g.emission[i] = sp.emission;
  g.instance[i] = hit.instance;
  if (!g.packed.empty())
    g.packed[i] = pack_surface(sp.position, g.depth[i], sp.shading_normal, sp.geometric_normal, sp.base_color,
                               g.material[i], sp.specular_f0);
  const bool animated = scene.instances[hit.instance].animated;
  vec3 prev_position = animated ? transform_point(prev_from_current[hit.instance], sp.position) : sp.position;
  // The hit lies on the ray through `film`, so `film` is its projection in this frame.
  vec2 prev_film;
  g.motion[i] = (animated || !still) && prev_camera.project(prev_position, prev_film) ? prev_film - film : vec2(0.0f);
}

// Stage "rays" of a tile: one jittered primary ray per pixel (jitter from the pixel's Rng stream, keyed
// and drawn a tile row at a time; directions in lanes), traced as 4x4 packets (rtcIntersect16, coherent);
// writes the jitter plane and, per tile row, each pixel's film position, direction and hit.
static void trace_tile(const Tracer& tracer, const Camera& camera, const GBufferParams& params, const Tile& tile,
                       GBuffer& out, PrimaryHitLanes* rows) {
  const int w = out.width, count = tile.x1 - tile.x0;
  RngRow<kTileWidth> streams;
  alignas(64) float uniforms[2 * kTileWidth];
  for (int y = tile.y0; y < tile.y1; ++y) {
    PrimaryHitLanes& row = rows[y - tile.y0];
    const size_t first = size_t(y) * size_t(w) + size_t(tile.x0);
    if (params.jitter) {
      streams.key(count, params.seed, first, uint64_t(params.frame), 0x6b);
      streams.fill(2, count, uniforms);
    }
    // The stream's first number is y, its second x (the order the jitter had as vec2(next, next) in GCC).
    if (params.simd) {
      primary_rays_lanes(camera, tile.x0, y, count, params.jitter ? uniforms + kTileWidth : nullptr,
                         params.jitter ? uniforms : nullptr, row, out.jitter.data() + first);
      continue;
    }
    for (int x = tile.x0; x < tile.x1; ++x) {
      const int s = x - tile.x0;
      const vec2 j = params.jitter ? vec2(uniforms[kTileWidth + s], uniforms[s]) : vec2(0.5f);
      out.jitter[first + size_t(s)] = j;
      row.film[0][s] = float(x) + j.x;
      row.film[1][s] = float(y) + j.y;
      const vec3 dir = camera.direction(row.film[0][s], row.film[1][s]);
      row.dir[0][s] = dir.x, row.dir[1][s] = dir.y, row.dir[2][s] = dir.z;
    }
  }
  RayPacket16 packet;
  for (int by = tile.y0; by < tile.y1; by += 4) {
    for (int bx = tile.x0; bx < tile.x1; bx += 4) {
      // One 4x4 packet, row r of it from tile row by + r; lanes outside the image stay inactive.
      const int s = bx - tile.x0, n = std::min(4, tile.x1 - bx);
      for (int r = 0; r < 4; ++r) {
        const PrimaryHitLanes& row = rows[std::min(by + r, tile.y1 - 1) - tile.y0];
        packet.set_row4(r, camera.position(), row.dir[0] + s, row.dir[1] + s, row.dir[2] + s, by + r < tile.y1 ? n : 0);
      }
      tracer.intersect16(packet, true);
      for (int r = 0; r < 4 && by + r < tile.y1; ++r) {
        PrimaryHitLanes& row = rows[by + r - tile.y0];
        tracer.packet_hits_row4(packet, r, row.instance + s, row.prim + s, row.u + s, row.v + s);
      }
    }
  }
}

void trace_gbuffer(const Scene& scene, const Tracer& tracer, const Camera& camera, const Camera& prev_camera,
                   const GBufferParams& params, GBuffer& out, RayCounter& rays) {
  if (out.width != camera.width() || out.height != camera.height()) out.resize(camera.width(), camera.height());
  if (!params.packed)
    out.packed.clear();
  else if (out.packed.size() != out.size())
    out.packed.resize(out.size());  // every pixel is written below
  const GBufferInstances instances(scene);
  const bool still = camera == prev_camera;  // then only animated instances have motion
  for_each_tile(out.width, out.height, [&](const Tile& tile) {
    // Trace every packet of the tile first, then shade: alternating Embree's traversal code with
    // shading code every 16 rays costs instruction-cache misses.
    PrimaryHitLanes rows[kTileHeight];
    trace_tile(tracer, camera, params, tile, out, rows);
    // Stage "shade", per tile row: the kernel writes every pixel, then surface_at rewrites the hits on
    // textured materials (every pixel for the scalar reference).
    const int count = tile.x1 - tile.x0;
    for (int y = tile.y0; y < tile.y1; ++y) {
      PrimaryHitLanes& row = rows[y - tile.y0];
      const size_t first = size_t(y) * size_t(out.width) + size_t(tile.x0);
      if (params.simd)
        shade_gbuffer_lanes(instances, camera, prev_camera, still, scene.environment, row, count, first, out);
      if (params.simd && instances.all_plain) continue;  // a branch per pixel of the check below: ~2% of the pass
      for (int s = 0; s < count; ++s) {
        if (params.simd && (row.instance[s] == kNoHit || instances.in_lanes(row.instance[s]))) continue;
        const Hit hit{0.0f, row.instance[s], row.prim[s], vec2(row.u[s], row.v[s])};
        write_pixel(scene, instances.prev_from_current, camera, prev_camera, still, hit,
                    vec3(row.dir[0][s], row.dir[1][s], row.dir[2][s]), vec2(row.film[0][s], row.film[1][s]),
                    first + size_t(s), out);
      }
    }
  });
  // One primary ray per pixel, counted once: an atomic add per tile waited there for the tile's streaming stores to
  // drain (a locked instruction is a full fence), where they can overlap the next tile's traversal.
  rays.add(uint64_t(out.size()));
}

}  // namespace candela

#include "engine/gbuffer.h"

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
  prim.assign(n, kNoHit);
  motion.assign(n, vec2(0.0f));
  jitter.assign(n, vec2(0.5f));
}

// Writes pixel i from a primary hit: surface attributes and the motion vector, which follows the hit
// point through its instance's previous transform into the previous camera.
static void write_pixel(const Scene& scene, const std::vector<mat4>& prev_from_current, const Camera& camera,
                        const Camera& prev_camera, const Hit& hit, const vec3& dir, vec2 film, size_t i, GBuffer& g) {
  if (!hit.valid()) {
    g.position[i] = g.shading_normal[i] = g.geometric_normal[i] = g.albedo[i] = vec3(0.0f);
    g.material[i] = g.specular_f0[i] = vec3(0.0f);
    g.instance[i] = g.prim[i] = kNoHit;
    g.depth[i] = kInfinity;
    g.emission[i] = scene.environment;
    g.motion[i] = vec2(0.0f);
    vec2 prev_film;
    // The background is infinitely far: it moves with the camera's rotation only.
    if (prev_camera.project(prev_camera.position() + dir, prev_film)) g.motion[i] = prev_film - film;
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
  g.prim[i] = hit.prim;
  vec3 prev_position = scene.instances[hit.instance].animated
                           ? transform_point(prev_from_current[hit.instance], sp.position)
                           : sp.position;
  // The hit lies on the ray through `film`, so `film` is its projection in this frame.
  vec2 prev_film;
  g.motion[i] = prev_camera.project(prev_position, prev_film) ? prev_film - film : vec2(0.0f);
}

void trace_gbuffer(const Scene& scene, const Tracer& tracer, const Camera& camera, const Camera& prev_camera,
                   const GBufferParams& params, GBuffer& out, RayCounter& rays) {
  if (out.width != camera.width() || out.height != camera.height()) out.resize(camera.width(), camera.height());
  const int w = out.width;
  // Per animated instance, the map from this frame's world position to last frame's (identity otherwise).
  std::vector<mat4> prev_from_current(scene.instances.size(), mat4(1.0f));
  for (size_t k = 0; k < scene.instances.size(); ++k)
    if (scene.instances[k].animated)
      prev_from_current[k] = scene.instances[k].prev_transform * glm::inverse(scene.instances[k].transform);
  for_each_tile(out.width, out.height, [&](const Tile& tile) {
    // Trace every packet of the tile first, then shade: alternating Embree's traversal code with
    // shading code every 16 rays costs instruction-cache misses.
    constexpr int kMaxPixels = kTileWidth * kTileHeight;
    Hit hits[kMaxPixels];
    vec3 dirs[kMaxPixels];
    vec2 film[kMaxPixels];
    uint32_t pixel[kMaxPixels];
    int count = 0;
    RayPacket16 packet;
    for (int by = tile.y0; by < tile.y1; by += 4) {
      for (int bx = tile.x0; bx < tile.x1; bx += 4) {
        // One 4x4 packet; lanes outside the image stay inactive.
        int first = count;
        for (int lane = 0; lane < 16; ++lane) {
          int x = bx + (lane & 3), y = by + (lane >> 2);
          if (x >= tile.x1 || y >= tile.y1) {
            packet.set_inactive(lane);
            continue;
          }
          uint32_t i = uint32_t(y) * uint32_t(w) + uint32_t(x);
          vec2 j(0.5f);
          if (params.jitter) {
            Rng rng = Rng::for_key(params.seed, i, uint64_t(params.frame), 0x6b);
            j = vec2(rng.next_float(), rng.next_float());
          }
          film[count] = vec2(x, y) + j;
          out.jitter[i] = j;
          dirs[count] = camera.direction(film[count].x, film[count].y);
          pixel[count] = i;
          packet.set(lane, Ray{camera.position(), dirs[count], 0.0f, kInfinity});
          ++count;
        }
        tracer.intersect16(packet, true);
        for (int lane = 0, k = first; lane < 16; ++lane)
          if (packet.valid[lane]) hits[k++] = tracer.packet_hit(packet, lane);
      }
    }
    for (int k = 0; k < count; ++k)
      write_pixel(scene, prev_from_current, camera, prev_camera, hits[k], dirs[k], film[k], pixel[k], out);
    uint64_t traced = uint64_t(count);
    rays.add(traced);
  });
}

}  // namespace candela

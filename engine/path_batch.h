#pragma once
// Many paths traced together, bounce by bounce ("wavefront" order): each bounce traces the closest hits of
// every live path in packets of 16, runs path_bounce's steps on groups of paths (bounce_paths), then traces
// the bounce's shadow rays in packets. Each path keeps its own random stream, and the steps are trace_path's
// own with the BSDF's arithmetic and the triangle lights' samples in SIMD lanes that repeat the scalar code's, so
// every path gets trace_path's bits (test PathBatch.GivesTracePathBits); what changes is the cost: packets instead of
// single rays, the BSDF and next-event work in lanes, and one path's memory waits overlapping the next path's
// arithmetic.
#include <vector>

#include "engine/bsdf_lanes.h"
#include "engine/check.h"
#include "engine/gbuffer_lanes.h"
#include "engine/path_lanes.h"
#include "engine/path_tracer.h"

namespace candela {

// A group of up to kLaneSlots paths in one bounce: their vertices, and the work of path_bounce in lanes (the BSDFs'
// terms, the light samples of plain triangle lights with their weights and shadow rays, the light samples' and the
// BSDF samples' values and densities).
struct PathVertexBatch {
  SurfacePoint scratch[kLaneSlots];         // the surfaces arrive_at_vertex computes
  const SurfacePoint* sp[kLaneSlots] = {};  // the scattering vertices' surfaces (arrive_at_vertex's answer)
  ShadingContext ctx[kLaneSlots];           // what the light choice is for
  vec2 u_choice[kLaneSlots];                // the light choice's uniforms
  LightChoice choice[kLaneSlots];           // the chosen light and the point's uniforms
  float pmf[kLaneSlots] = {};               // the selection probability of a light sample the scalar code places
  LightSample light_sample[kLaneSlots];     // the samples of the lights path_lanes leaves to the scalar code
  VertexLanes at;                           // the vertices' positions and geometric normals
  NeeLanes nee;                             // the samples of plain triangle lights
  ContinueLanes go_on;                      // the continuation's geometry
  BsdfVertexLanes vertices;
  BsdfLanes bsdf;
  BsdfUniformLanes uniforms;   // the BSDF samples' uniforms
  DirectionLanes light, next;  // the light samples' directions, the BSDF samples' directions
};

// path_bounce for the paths group[0, count) whose rays reached hits[group[j]], in its steps, each over the
// group: arrive_at_vertex (the surface surfaces[j] where `instances` says the lanes computed it), the BSDFs'
// terms in lanes, the light samples (plain triangle lights' in lanes) and the BSDF directions' uniforms (each path's
// random numbers in path_bounce's order), the BSDF directions in lanes, their BSDF values and densities in lanes, then
// the light samples' weights and shadow rays (left pending; in lanes where the sample was), and continue_path's
// geometry in lanes (continue_paths_lanes) with its Russian roulette per path (survive_bounce). Each path gets
// path_bounce's bits. Cost per path: path_bounce's, with the BSDF's constructor, wo terms, direction sampling, two
// evaluations and densities, the triangle light's sample, weight and shadow ray and the next ray's geometry in lanes
// instead of scalar code.
template <LightSampler S, class Stream>
void bounce_paths(const SceneView& view, const S& sampler, const PathTracerParams& params, const uint32_t* group,
                  int count, const std::vector<Hit>& hits, const SurfacePoint* surfaces,
                  const GBufferInstances* instances, std::vector<PathState>& paths, std::vector<Stream>& rngs,
                  std::vector<std::optional<SurfacePoint>>* first_hits, PathVertexBatch& b) {
  // Arrive: emission, and each scattering vertex's BSDF parameters and wo into the lanes (the other slots keep
  // stale ones, whose results nobody reads).
  for (int j = 0; j < count; ++j) {
    const uint32_t k = group[j];
    const SurfacePoint* surface = instances && instances->in_lanes(hits[k].instance) ? &surfaces[j] : nullptr;
    const vec3 wo = -paths[k].ray.direction;
    b.sp[j] = arrive_at_vertex(view, sampler, params, paths[k], hits[k], first_hits ? &(*first_hits)[k] : nullptr,
                               surface, b.scratch[j]);
    if (!b.sp[j]) continue;
    const SurfacePoint& sp = *b.sp[j];
    b.vertices.material.set(j, sp.shading_normal, sp.base_color, sp.metallic, sp.roughness, sp.specular,
                            sp.specular_f0);
    b.vertices.wox[j] = wo.x, b.vertices.woy[j] = wo.y, b.vertices.woz[j] = wo.z;
    b.at.set(j, sp.position, sp.geometric_normal);
  }
  build_bsdf_lanes(b.vertices, count, b.bsdf);
  // Draw: each scattering vertex's light sample, then its BSDF direction from the lanes' terms. In three passes
  // over the group (each path's random numbers still in path_bounce's order), so that the cache misses of the
  // sampler's tables and of the chosen lights' records overlap across paths: the choices' uniforms (and the
  // sampler's prefetch), the choices with the other uniforms (and the lights' records prefetched), the points (a plain
  // triangle light's record copied into the lanes, the other lights' samples placed by the scalar code).
  for (int j = 0; j < count; ++j) {
    if (!b.sp[j]) continue;
    b.ctx[j] = {b.sp[j]->position, b.sp[j]->shading_normal};
    b.u_choice[j] = rngs[group[j]].next_2d();
    prefetch_lights(sampler, b.ctx[j], &b.u_choice[j], 1);
  }
  for (int j = 0; j < count; ++j) {
    b.light.active[j] = b.next.active[j] = b.nee.active[j] = 0.0f;
    if (!b.sp[j]) continue;
    Stream& rng = rngs[group[j]];
    b.choice[j] = draw_light_choice(sampler, b.ctx[j], b.u_choice[j], rng);
    view.lights.prefetch(b.choice[j].chosen.index);
    const vec2 u = rng.next_2d();
    b.uniforms.u[0][j] = u.x, b.uniforms.u[1][j] = u.y, b.uniforms.lobe[j] = rng.next_float();
    b.next.active[j] = 1.0f;
  }
  const std::vector<TriangleLight>& triangles = view.lights.triangles();
  for (int j = 0; j < count; ++j) {
    if (!b.sp[j]) continue;
    const SampledLight& chosen = b.choice[j].chosen;
    if (chosen.pmf > 0.0f && chosen.index < triangles.size() && !triangles[chosen.index].textured) {
      b.nee.set_light(j, triangles[chosen.index], b.choice[j].u, chosen.pmf);  // placed in lanes below
      continue;
    }
    if (!place_light_sample(view, *b.sp[j], b.choice[j], b.pmf[j], b.light_sample[j])) continue;
    const vec3& wi = b.light_sample[j].wi;
    b.light.x[j] = wi.x, b.light.y[j] = wi.y, b.light.z[j] = wi.z, b.light.active[j] = 1.0f;
  }
  // The plain triangle lights' samples in lanes (LightList::sample and place_light_sample's tests).
  sample_triangle_lights_lanes(b.at, b.nee, count, b.light);
  sample_bsdf_lanes(b.bsdf, b.vertices.wox, b.vertices.woy, b.vertices.woz, b.uniforms, count, b.next);
  evaluate_bsdf_lanes(b.bsdf, b.vertices.wox, b.vertices.woy, b.vertices.woz, count, true, b.light);
  evaluate_bsdf_lanes(b.bsdf, b.vertices.wox, b.vertices.woy, b.vertices.woz, count, false, b.next);
  // Finish: the light samples' weights and shadow rays (those of plain triangle lights in lanes), then the paths
  // that go on.
  const float epsilon = view.tracer.offset_epsilon();
  weigh_light_samples_lanes(b.at, b.light, epsilon, count, b.nee);
  const BsdfMaterialLanes& material = b.vertices.material;
  continue_paths_lanes(b.at, material.nx, material.ny, material.nz, b.next, epsilon, count, b.go_on);
  for (int j = 0; j < count; ++j) {
    if (!b.sp[j]) continue;
    PathState& st = paths[group[j]];
    if (b.nee.active[j] > 0.0f) {
      st.light_pending = b.nee.pending[j] > 0.0f;
      if (st.light_pending) {
        st.shadow = b.nee.shadow.ray(j);
        st.light = st.beta * vec3(b.nee.contribution[0][j], b.nee.contribution[1][j], b.nee.contribution[2][j]);
      }
    } else if (b.light.active[j] > 0.0f) {
      vec3 contribution;
      const vec3 f(b.light.f[0][j], b.light.f[1][j], b.light.f[2][j]);
      st.light_pending = weigh_light_sample(view.tracer, *b.sp[j], b.light_sample[j], b.pmf[j], f, b.light.pdf[j],
                                            st.shadow, contribution);
      if (st.light_pending) st.light = st.beta * contribution;
    }
    // continue_path, its geometry from the lanes.
    if (b.go_on.go[j] > 0.0f) {
      const vec3 wi(b.next.x[j], b.next.y[j], b.next.z[j]);
      st.beta *= vec3(b.go_on.factor[0][j], b.go_on.factor[1][j], b.go_on.factor[2][j]);
      st.prev_bsdf_pdf = b.next.pdf[j];
      st.prev_ctx = b.ctx[j];
      st.ray = Ray{vec3(b.go_on.ox[j], b.go_on.oy[j], b.go_on.oz[j]), wi, 0.0f, kInfinity};
      survive_bounce(params, st, rngs[group[j]]);
    }
  }
}

// Traces paths[k] with stream rngs[k] to its end (paths[k].radiance() is then trace_path's result);
// first_hits, if not null, receives per path the surface its start's ray hits. With `instances` (the scene's,
// GBufferInstances), each bounce's hits on plain materials get their surfaces in SIMD lanes
// (surface_points_lanes), the others surface_at. With `start_hits` the start rays were traced already:
// (*start_hits)[k] is what paths[k].ray hit. Returns the rays traced.
// Cost: trace_path's per path, less the BSDF, next-event and continuation work bounce_paths does in lanes; rays in
// packets of 16 in slot order (slots of neighbouring pixels keep the first bounces' packets coherent).
template <LightSampler S, class Stream>
uint64_t trace_paths(const SceneView& view, const S& sampler, const PathTracerParams& params,
                     std::vector<PathState>& paths, std::vector<Stream>& rngs,
                     std::vector<std::optional<SurfacePoint>>* first_hits, const GBufferInstances* instances = nullptr,
                     const std::vector<Hit>* start_hits = nullptr) {
  CHECK(!start_hits || start_hits->size() == paths.size());
  const Tracer& tracer = view.tracer;
  std::vector<uint32_t> live(paths.size());
  for (uint32_t k = 0; k < live.size(); ++k) live[k] = k;
  std::vector<Hit> hits = start_hits ? *start_hits : std::vector<Hit>(paths.size());
  thread_local PathVertexBatch batch;
  thread_local SurfacePoint surfaces[kLaneSlots];
  uint64_t traced = 0;
  for (bool first_bounce = true; !live.empty(); first_bounce = false) {
    // Closest hits of the live paths' rays.
    auto bounce = ray_queue16<uint32_t>(tracer, RayQuery::Intersect, [&](uint32_t k, const RayPacket16& p, int lane) {
      hits[k] = tracer.packet_hit(p, lane);
      if (instances) instances->prefetch_triangle(hits[k].instance, hits[k].prim);
    });
    if (start_hits && first_bounce) {  // the start rays' hits are given
      if (instances)
        for (uint32_t k : live) instances->prefetch_triangle(hits[k].instance, hits[k].prim);
    } else {
      for (uint32_t k : live) bounce.add(paths[k].ray, k);
      bounce.finish();
    }
    // The bounce of each path (emission, its next-event estimate's shadow ray, its next ray), a group of live
    // paths at a time, with the surfaces of the group's hits on plain materials in lanes first. The next group's
    // corners are prefetched a group ahead (their vertex indices were prefetched as the hits came back): later
    // bounces' hits are scattered, and the corners' loads were the largest line of triangle_corners.
    auto prefetch_group = [&](size_t first) {
      if (!instances) return;
      for (size_t j = first, end = std::min(live.size(), first + size_t(kLaneSlots)); j < end; ++j)
        instances->prefetch_corners(hits[live[j]].instance, hits[live[j]].prim);
    };
    prefetch_group(0);
    for (size_t first = 0; first < live.size(); first += kLaneSlots) {
      const int count = int(std::min<size_t>(kLaneSlots, live.size() - first));
      prefetch_group(first + size_t(kLaneSlots));
      if (instances) {
        PrimaryHitLanes row;
        for (int j = 0; j < count; ++j) {
          const Hit& hit = hits[live[first + size_t(j)]];
          const vec3& dir = paths[live[first + size_t(j)]].ray.direction;
          row.instance[j] = hit.instance, row.prim[j] = hit.prim;
          row.u[j] = hit.barycentric.x, row.v[j] = hit.barycentric.y;
          row.dir[0][j] = dir.x, row.dir[1][j] = dir.y, row.dir[2][j] = dir.z;
        }
        surface_points_lanes(*instances, row, count, surfaces);
      }
      bounce_paths(view, sampler, params, &live[first], count, hits, surfaces, instances, paths, rngs, first_hits,
                   batch);
    }
    // The shadow rays, then the paths that go on.
    auto shadows = ray_queue16<uint32_t>(tracer, RayQuery::Occluded, [&](uint32_t k, const RayPacket16& p, int lane) {
      finish_direct_light(paths[k], Tracer::occluded_lane(p, lane));
    });
    size_t kept = 0;
    for (uint32_t k : live) {
      shadows.add_if(paths[k].light_pending, paths[k].shadow, k);
      live[kept] = k, kept += paths[k].alive ? 1 : 0;  // without a branch: which paths go on is unpredictable
    }
    shadows.finish();
    live.resize(kept);
    traced += bounce.traced() + shadows.traced();
  }
  return traced;
}

// Stage: adds params.spp path samples per pixel into `sum` (running sum of radiance; divide by the total
// sample count to display); a non-finite sample is dropped and counted in `non_finite`. Reads the scene
// view; traces about spp * (1 + 2 * depth) rays per pixel, a tile's paths of one sample number together
// (trace_paths: rays in packets, surfaces, BSDFs and light samples in lanes; trace_path's bits for every path).
// Randomness is keyed on (seed, pixel, frame, sample) (Sobol: (seed, pixel, epoch) and the sample as the
// sequence index; ZSobol: (seed, epoch) and the pixel's Morton index with the sample), so the result does
// not depend on thread count.
template <LightSampler S>
void path_trace(const SceneView& view, const S& sampler, const PathTracerParams& params, int frame, Image& sum,
                RayCounter& rays, Counter& non_finite) {
  const GBufferInstances instances(view.scene);
  for_each_tile(view.camera.width(), view.camera.height(), [&](const Tile& tile) {
    const int tile_width = tile.x1 - tile.x0;
    std::vector<vec3> acc(size_t(tile_width) * size_t(tile.y1 - tile.y0), vec3(0.0f));
    uint64_t traced = 0;
    // One sample of every pixel of the tile, each path with the stream stream_of(pixel, x, y) gives.
    auto trace_sample = [&](auto&& stream_of) {
      using Stream = decltype(stream_of(size_t(0), 0, 0));
      std::vector<PathState> paths;
      std::vector<Stream> streams;
      for (int y = tile.y0; y < tile.y1; ++y)
        for (int x = tile.x0; x < tile.x1; ++x) {
          Stream stream = stream_of(size_t(y) * size_t(view.camera.width()) + size_t(x), x, y);
          vec2 offset = stream.next_2d();
          vec2 film = vec2(x, y) + (params.jitter ? offset : vec2(0.5f));
          paths.emplace_back(
              PathStart{Ray{view.camera.position(), view.camera.direction(film.x, film.y), 0.0f, kInfinity}});
          streams.push_back(stream);
        }
      traced += trace_paths(view, sampler, params, paths, streams, nullptr, &instances);
      for (size_t k = 0; k < paths.size(); ++k) {
        const vec3 L = paths[k].radiance();
        if (is_finite(L))
          acc[k] += L;
        else
          non_finite.add(1);
      }
    };
    for (int s = 0; s < params.spp; ++s) {
      const uint64_t sample = uint64_t(params.first_sample + s);
      if (params.sequence == SampleSequence::Sobol) {
        trace_sample([&](size_t pixel, int, int) {
          return SobolStream::for_pixel(params.seed, pixel, params.epoch, uint32_t(sample));
        });
      } else if (params.sequence == SampleSequence::ZSobol) {
        const uint32_t low = uint32_t(sample) & ((1u << params.log2_samples) - 1u);
        const uint64_t run = sample >> params.log2_samples;
        trace_sample([&](size_t, int x, int y) {
          return SobolStream::for_screen(params.seed, mix64(params.epoch) ^ run,
                                         zsobol_index(uint32_t(x), uint32_t(y), params.log2_samples, low));
        });
      } else {
        trace_sample([&](size_t pixel, int, int) { return Rng::for_key(params.seed, pixel, sample, uint64_t(frame)); });
      }
    }
    for (int y = tile.y0; y < tile.y1; ++y)
      for (int x = tile.x0; x < tile.x1; ++x)
        sum.pixels[size_t(y) * size_t(view.camera.width()) + size_t(x)] +=
            acc[size_t(y - tile.y0) * size_t(tile_width) + size_t(x - tile.x0)];
    rays.add(traced);
  });
}

}  // namespace candela

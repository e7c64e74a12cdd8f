#include "restir/shade.h"

#include "engine/check.h"
#include "engine/prefetch.h"
#include "restir/receiver_lanes.h"
#include "restir/reuse.h"

namespace candela {

// Whether two reservoirs shade alike: the same sample (light, uv and stored point) with the same W.
static bool shade_alike(const ReuseReservoir& a, const ReuseReservoir& b) {
  const LightPoint &p = a.y.point, &q = b.y.point;
  return a.W == b.W && a.y.light == b.y.light && a.y.uv == b.y.uv && p.position == q.position && p.normal == q.normal &&
         p.radiance == q.radiance && p.two_sided == q.two_sided;
}

void shade_reservoirs(const SceneView& view, const GBuffer& g, const std::vector<ReuseReservoir>& reservoirs,
                      const std::vector<std::vector<ReuseReservoir>>& further, const std::vector<vec3>* unsampled,
                      const VisibilityReuse& reuse, bool simd, std::vector<SampleVisibility>& visibility, Image& sum,
                      RayCounter& rays, Counter& non_finite) {
  const bool reusing = reuse.max_age > 0 && reuse.history_pixel && reuse.previous &&
                       reuse.history_pixel->size() == g.size() && reuse.previous->size() == g.size();
  const int samples = 1 + int(further.size());
  CHECK(samples <= kMaxShadedSamples);
  CHECK(!reuse.from_packed || g.packed.size() == g.size());
  CHECK(!reuse.known || (reuse.from_packed && reuse.known->size() == g.size()));
  const float weight = 1.0f / float(samples);  // each sample's share of the pixel's estimate
  auto sampled = [&](int k) -> const std::vector<ReuseReservoir>& {
    return k == 0 ? reservoirs : further[size_t(k - 1)];
  };
  // Pixel i's samples that shade alike (a pixel without reuse repeats its reservoir in every further plane; two picks
  // of one combination may land on the same input) are shaded once, by the first of them: alike[k] gets the number of
  // the pixel's samples alike to sample k where k is the first of them, else 0 (also without a surface or weight).
  // Each sample is compared with the earlier ones that stand for their kind: one comparison for 2 samples.
  auto count_alike = [&](size_t i, int* alike, size_t stride) {
    for (int k = 0; k < samples; ++k) {
      const ReuseReservoir& r = sampled(k)[i];
      int& here = alike[size_t(k) * stride];
      here = g.hit(i) && r.W > 0.0f ? 1 : 0;
      for (int j = 0; here > 0 && j < k; ++j)
        if (alike[size_t(j) * stride] > 0 && shade_alike(sampled(j)[i], r)) ++alike[size_t(j) * stride], here = 0;
    }
  };
  // Pixel i's shadow ray to sample y built one pixel at a time, from the surface the lanes' rays start from.
  auto scalar_shadow_ray = [&](size_t i, const ReuseSample& y) {
    return reuse.from_packed ? sample_shadow_ray(view.tracer, g.packed[i], view.lights, y)
                             : sample_shadow_ray(view.tracer, g.position[i], g.geometric_normal[i], view.lights, y);
  };
  visibility.resize(
      g.size());  // every pixel's verdict is written below (in parallel, where a fill here ran on one thread)
  auto finish = [&](size_t i, const vec3& L) {
    if (is_finite(L))
      sum.pixels[i] += L;
    else
      non_finite.add(1);
  };
  // Per tile row: the exact receivers (in lanes with simd), then for each sample in turn its unshadowed contribution
  // and shadow ray, in lanes where the sample stores its point (with simd; else, and for punctual lights,
  // sample_contribution and sample_shadow_ray one pixel at a time), and each pixel's estimate. The shadow rays go out
  // 16 at a time in pixel order (rtcOccluded16), the row's first samples' before its further samples': neighbouring
  // pixels' rays towards nearby lights share much of their traversal. With reuse.from_packed they start from the
  // packed surfaces (the octahedral geometric normal offsets the origin; 32 more bytes per pixel read).
  for_each_tile(g.width, g.height, [&](const Tile& tile) {
    struct Lanes {
      ExactSurfaceLanes surfaces;
      ReceiverLanes receivers;
      SurfaceLanes packed;    // reuse.from_packed: the row's packed surfaces
      ReceiverLanes origins;  // and their points and geometric normals (the rest unused)
      CandidateLanes samples;
      ContributionLanes contributions;
      RayLanes rays;  // to the stored points (sample_shadow_ray's)
    };
    thread_local Lanes lanes;
    struct Pending {
      size_t pixel;
      vec3 L, lit;   // the pixel's light without the sample, and what the sample adds if visible
      bool verdict;  // the pixel's first sample: its verdict is kept
    };
    auto answer = [&](const Pending& p, const RayPacket16& packet, int lane) {
      const bool visible = !Tracer::occluded_lane(packet, lane);
      if (p.verdict) visibility[p.pixel].visible = visible;
      finish(p.pixel, visible ? p.L + p.lit : p.L);
    };
    auto queue = ray_queue16<Pending>(view.tracer, RayQuery::Occluded, answer);
    const int slots = tile.x1 - tile.x0;
    for (int y = tile.y0; y < tile.y1; ++y) {
      const size_t first = size_t(y) * size_t(g.width) + size_t(tile.x0);
      if (simd) {
        lanes.surfaces.set_row(g, first, slots);
        build_exact_receivers(lanes.surfaces, view.camera.position(), slots, lanes.receivers);
        if (reuse.from_packed) {
          lanes.packed.set_row(g.packed.data() + first, slots);
          packed_points_lanes(lanes.packed, slots, lanes.origins);
        }
      }
      int alike_row[kMaxShadedSamples][kTileWidth];  // count_alike's, per sample and slot
      for (int s = 0; s < slots; ++s) {
        const size_t i = first + size_t(s);
        for (int k = 0; y + 1 < tile.y1 && k < samples; ++k)
          prefetch_object(sampled(k)[i + size_t(g.width)]);  // the tile's next row
        count_alike(i, &alike_row[0][s], kTileWidth);
      }
      for (int k = 0; k < samples; ++k) {
        const std::vector<ReuseReservoir>& sample = sampled(k);
        const int* alike = alike_row[k];
        if (simd) {
          for (int s = 0; s < slots; ++s) {
            const ReuseReservoir& r = sample[first + size_t(s)];
            if (alike[s] > 0 && stored_point(view.lights, r.y))
              lanes.samples.set(s, r.y.point);
            else
              lanes.samples.clear(s);
          }
          evaluate_exact_contribution_lanes(lanes.receivers, lanes.samples, slots, lanes.contributions);
          shadow_ray_lanes(reuse.from_packed ? lanes.origins : lanes.receivers, lanes.samples,
                           view.tracer.offset_epsilon(), slots, lanes.rays);
        }
        for (int s = 0; s < slots; ++s) {
          const size_t i = first + size_t(s);
          // The first sample adds the pixel's light without a sample too; the further ones add their term alone.
          vec3 L = k == 0 && unsampled ? g.emission[i] + (*unsampled)[i] : vec3(0.0f);
          const ReuseReservoir& r = sample[i];
          SampleVisibility& v = visibility[i];
          if (k == 0) v = SampleVisibility{};
          if (alike[s] > 0) {
            const float share = float(alike[s]) * weight;  // weight itself where the sample is alone (same bits)
            const bool in_lanes = simd && lanes.samples.active[s] > 0.0f;
            const vec3 value =
                in_lanes ? vec3(lanes.contributions.value[0][s], lanes.contributions.value[1][s],
                                lanes.contributions.value[2][s])
                         : sample_contribution(exact_receiver(g, view.camera.position(), view.lights, i), r.y).value;
            if (max_component(value) > 0.0f) {
              // The first sample's verdict (k == 0 only): the one reuse traced this frame for the same ray
              // (reuse.known; its age stays 0), else one reused from last frame where it may be. Field by field
              // (visible and age stay the reset's): a whole SampleVisibility assembled on the stack was copied in
              // through an overlapping reload that stalled on store forwarding (15% of this stage's samples).
              const SampleVisibility* old = nullptr;
              const int8_t known = k == 0 && reuse.known ? (*reuse.known)[i] : int8_t(-1);
              if (k == 0) {
                v.light = r.y.light, v.uv = r.y.uv, v.valid = true;
                const int32_t j = reusing && known < 0 ? (*reuse.history_pixel)[i] : -1;
                old = j >= 0 ? &(*reuse.previous)[size_t(j)] : nullptr;
                if (old && !(old->on(r.y) && old->age < reuse.max_age)) old = nullptr;
              }
              if (!old && known < 0) {
                queue.add(in_lanes ? lanes.rays.ray(s) : scalar_shadow_ray(i, r.y),
                          {i, L, value * (r.W * share), k == 0});
                continue;
              }
              v.visible = old ? old->visible : known == 1;
              if (old) v.age = uint8_t(old->age + 1);
              if (v.visible) L += value * (r.W * share);
            }
          }
          if (k == 0) finish(i, L);
        }
      }
    }
    queue.finish();
    rays.add(queue.traced());
  });
}

}  // namespace candela

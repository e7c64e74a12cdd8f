#pragma once
// A frame's ray queries, recorded as the Tracer received them, to be traced again alone: what the rays of a
// frame cost without the work around them (`candela bench --suite restir` compares a frame's time with its
// replay). Packets are recorded as packets (with their active lanes and coherence hint) and single rays as
// single rays, so the replay asks Embree exactly what the frame asked, in the same groupings. Memory: about
// 900 bytes per packet and 36 per single ray (a 640x360 `restir` frame's 3 million rays: about 170 MB).
//
//   RayLog log;
//   renderer.set_ray_log(&log);  // every query of the next frames is recorded
//   renderer.render_frame(...);
//   renderer.set_ray_log(nullptr);
//   log.replay(renderer.tracer());  // the same queries again, in parallel; returns the rays traced
#include <tbb/enumerable_thread_specific.h>

#include <cstdint>
#include <vector>

#include "engine/tracer.h"

namespace candela {

class RayLog {
 public:
  // Called by the Tracer before it traces (thread-safe: each thread appends to its own buffers).
  void record(const Ray& ray, RayQuery query);
  void record(const RayPacket16& packet, RayQuery query, bool coherent);
  // Rays recorded: single rays plus the active lanes of packets.
  uint64_t rays() const;
  // Traces every recorded query again with `tracer` (which must not record into this log), packets with
  // rtcIntersect16 / rtcOccluded16 and single rays with rtcIntersect1 / rtcOccluded1, spread over the TBB
  // workers. Returns the rays traced. Cost: the recorded queries' traversal, plus copying each packet.
  uint64_t replay(const Tracer& tracer) const;

 private:
  struct Single {
    Ray ray;
    RayQuery query;
  };
  struct alignas(64) Packet {
    RTCRay16 ray;  // the rays as given to the Tracer (before tracing changed tfar)
    alignas(64) int valid[16];
    RayQuery query;
    bool coherent;
    uint64_t active() const {  // rays: the active lanes
      uint64_t n = 0;
      for (int lane : valid) n += lane != 0;
      return n;
    }
  };
  struct Buffers {
    std::vector<Single> singles;
    std::vector<Packet> packets;
  };
  tbb::enumerable_thread_specific<Buffers> buffers_;
};

}  // namespace candela

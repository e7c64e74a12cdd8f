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
//
// Each query is also tagged with the frame stage that asked it (StageTimer opens and closes the stages of a frame
// whose FrameStats carries the log), so that one stage's queries replay alone: what its rays cost, against its time.
#include <tbb/enumerable_thread_specific.h>

#include <cstdint>
#include <string>
#include <vector>

#include "engine/tracer.h"

namespace candela {

class RayLog {
 public:
  // Called by the Tracer before it traces (thread-safe: each thread appends to its own buffers).
  void record(const Ray& ray, RayQuery query);
  void record(const RayPacket16& packet, RayQuery query, bool coherent);
  // The stage whose queries follow (StageTimer; called between stages, while no query runs). Stages nest: end_stage
  // returns to the enclosing one. Queries outside every stage belong to stage "".
  void begin_stage(const std::string& name);
  void end_stage();
  // The stages that recorded queries or began, in the order they first began ("" first).
  const std::vector<std::string>& stages() const { return stage_names_; }
  // Rays recorded (single rays plus the active lanes of packets), of every stage or of stages()[stage].
  uint64_t rays(int stage = kAllStages) const;
  // Traces every recorded query (of every stage, or of stages()[stage] alone) again with `tracer` (which must not
  // record into this log), packets with rtcIntersect16 / rtcOccluded16 and single rays with rtcIntersect1 /
  // rtcOccluded1, spread over the TBB workers. Returns the rays traced. Cost: the recorded queries' traversal, plus
  // copying each packet.
  uint64_t replay(const Tracer& tracer, int stage = kAllStages) const;
  static constexpr int kAllStages = -1;

 private:
  // Whether a query tagged `tagged` belongs to `stage` (an index of stages(), or kAllStages).
  static bool selects(int stage, int tagged) { return stage == kAllStages || tagged == stage; }
  struct Single {
    Ray ray;
    RayQuery query;
    int stage;
  };
  struct alignas(64) Packet {
    RTCRay16 ray;  // the rays as given to the Tracer (before tracing changed tfar)
    alignas(64) int valid[16];
    RayQuery query;
    bool coherent;
    int stage;
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
  std::vector<std::string> stage_names_{""};
  std::vector<int> open_stages_{0};  // innermost last; the queries' stage is the last
};

}  // namespace candela

#include "engine/ray_log.h"

#include <algorithm>
#include <atomic>
#include <cstring>

#include "engine/check.h"
#include "engine/parallel.h"

namespace candela {

void RayLog::record(const Ray& ray, RayQuery query) {
  buffers_.local().singles.push_back({ray, query, open_stages_.back()});
}

void RayLog::record(const RayPacket16& packet, RayQuery query, bool coherent) {
  Packet& p = buffers_.local().packets.emplace_back();
  p.ray = packet.rayhit.ray;
  std::memcpy(p.valid, packet.valid, sizeof(p.valid));
  p.query = query;
  p.coherent = coherent;
  p.stage = open_stages_.back();
}

void RayLog::begin_stage(const std::string& name) {
  auto known = std::find(stage_names_.begin(), stage_names_.end(), name);
  if (known == stage_names_.end()) known = stage_names_.insert(stage_names_.end(), name);
  open_stages_.push_back(int(known - stage_names_.begin()));
}

void RayLog::end_stage() {
  CHECK(open_stages_.size() > 1);  // the outermost, stage "", never ends
  open_stages_.pop_back();
}

uint64_t RayLog::rays(int stage) const {
  uint64_t n = 0;
  for (const Buffers& b : buffers_) {
    for (const Single& s : b.singles) n += selects(stage, s.stage);
    for (const Packet& p : b.packets)
      if (selects(stage, p.stage)) n += p.active();
  }
  return n;
}

// Reads the recorded queries; per packet, a copy into a packet with no hit yet and one rtcIntersect16 /
// rtcOccluded16; per single ray, one rtcIntersect1 / rtcOccluded1.
uint64_t RayLog::replay(const Tracer& tracer, int stage) const {
  std::vector<const Packet*> packets;
  std::vector<const Single*> singles;
  for (const Buffers& b : buffers_) {
    for (const Packet& p : b.packets)
      if (selects(stage, p.stage)) packets.push_back(&p);
    for (const Single& s : b.singles)
      if (selects(stage, s.stage)) singles.push_back(&s);
  }
  std::atomic<uint64_t> traced{0};
  parallel_for_ranges(size_t(0), packets.size(), size_t(64), [&](size_t first, size_t end) {
    enable_ftz_daz();
    RayPacket16 packet;
    uint64_t rays = 0;
    for (size_t k = first; k < end; ++k) {
      const Packet& p = *packets[k];
      packet.rayhit.ray = p.ray;
      std::memcpy(packet.valid, p.valid, sizeof(packet.valid));
      for (int lane = 0; lane < 16; ++lane) packet.rayhit.hit.geomID[lane] = RTC_INVALID_GEOMETRY_ID;
      rays += p.active();
      if (p.query == RayQuery::Occluded)
        tracer.occluded16(packet);
      else
        tracer.intersect16(packet, p.coherent);
    }
    traced += rays;
  });
  parallel_for_ranges(size_t(0), singles.size(), size_t(1024), [&](size_t first, size_t end) {
    enable_ftz_daz();
    for (size_t k = first; k < end; ++k) {
      const Single& s = *singles[k];
      if (s.query == RayQuery::Occluded)
        (void)tracer.occluded(s.ray);
      else
        (void)tracer.intersect(s.ray);
    }
  });
  return traced + singles.size();
}

}  // namespace candela

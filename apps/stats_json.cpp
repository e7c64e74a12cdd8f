#include "apps/stats_json.h"

#include "engine/atomic_files.h"

namespace candela {

nlohmann::json stats_to_json(const std::vector<FrameStats>& frames) {
  nlohmann::json out = nlohmann::json::array();
  for (const FrameStats& f : frames) {
    nlohmann::json stages = nlohmann::json::array();
    for (const StageStats& s : f.stages)
      stages.push_back({{"name", s.name}, {"ms", s.ms}, {"rays", s.rays}, {"non_finite", s.non_finite}});
    out.push_back({{"frame", f.frame},
                   {"spp", f.spp},
                   {"total_ms", f.total_ms},
                   {"rays", f.rays()},
                   {"non_finite", f.non_finite()},
                   {"stages", stages}});
  }
  return out;
}

void write_json_file(const std::string& path, const nlohmann::json& json) {
  write_text_atomically(path, [&](std::ostream& f) { f << json.dump(2) << "\n"; });
}

}  // namespace candela

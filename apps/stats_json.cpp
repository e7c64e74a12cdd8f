#include "apps/stats_json.h"

#include <filesystem>
#include <fstream>

#include "engine/check.h"
#include "engine/file_names.h"

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
  std::filesystem::path target(path);
  std::filesystem::path tmp = hidden_beside(target, target.filename().string() + ".tmp");
  {
    std::ofstream f(tmp);
    if (!f) throw InputError(path + ": cannot open for writing");
    f << json.dump(2) << "\n";
    if (!f) throw InputError(path + ": write failed");
  }
  std::error_code ec;
  std::filesystem::rename(tmp, target, ec);
  if (ec) {
    std::filesystem::remove(tmp, ec);
    throw InputError(path + ": cannot write: " + ec.message());
  }
}

}  // namespace candela

#pragma once
// Frame statistics as JSON (per frame: total and per-stage milliseconds, ray counts and dropped non-finite
// values).
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/frame_stats.h"

namespace candela {

nlohmann::json stats_to_json(const std::vector<FrameStats>& frames);
// Writes JSON atomically (temporary file, then rename); throws InputError naming the path on failure.
void write_json_file(const std::string& path, const nlohmann::json& json);

}  // namespace candela

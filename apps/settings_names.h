#pragma once
// The names the command line and shot scripts give to RenderSettings' choices (one table each, so that
// `render --method` and a script's "method" accept exactly the same words).
#include <map>
#include <string>
#include <vector>

#include "apps/renderer.h"

namespace candela {

const std::map<std::string, Method>& method_names();
const std::map<std::string, LightSamplerKind>& light_sampler_names();
const std::map<std::string, SampleSequence>& sampler_names();
const std::map<std::string, DenoiserKind>& denoiser_names();
const std::map<std::string, DiBiasCorrection>& di_bias_names();
// "none", "temporal", "spatial", "both": which reuse stages of a reservoir chain (ReSTIR DI's or GI's) run.
const std::vector<std::string>& di_reuse_names();
// Sets the stages `reuse` names and the bias correction `bias` names (one of di_bias_names()).
void set_reuse(const std::string& reuse, const std::string& bias, DiReuseParams& params);
// The name `value` has in `names` (the inverse lookup, for messages and CSV columns).
template <class T>
std::string name_of(const std::map<std::string, T>& names, T value) {
  for (const auto& [name, v] : names)
    if (v == value) return name;
  return "?";
}
template <class T>
std::vector<std::string> keys_of(const std::map<std::string, T>& names) {
  std::vector<std::string> out;
  for (const auto& entry : names) out.push_back(entry.first);
  return out;
}

}  // namespace candela

#pragma once
// The names RenderSettings' choices have everywhere (the settings schema's choice rows, converge's method
// names, messages): one table each.
#include <map>
#include <string>
#include <vector>

#include "apps/renderer.h"

namespace candela {

const std::map<std::string, Method>& method_names();
const std::map<std::string, LightSamplerKind>& light_sampler_names();
const std::map<std::string, SampleSequence>& sampler_names();
const std::map<std::string, DenoiserKind>& denoiser_names();
const std::map<std::string, BiasCorrection>& bias_names();
// "none", "temporal", "spatial", "both" (index: temporal + 2 spatial): which reuse stages of a reservoir chain
// (ReSTIR DI's or GI's) run.
const std::vector<std::string>& reuse_names();
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

#include "apps/settings_names.h"

namespace candela {

const std::map<std::string, Method>& method_names() {
  static const std::map<std::string, Method> names = {{"pt", Method::PathTrace},
                                                      {"direct", Method::Direct},
                                                      {"restir-di", Method::RestirDi},
                                                      {"restir", Method::Restir}};
  return names;
}

const std::map<std::string, LightSamplerKind>& light_sampler_names() {
  static const std::map<std::string, LightSamplerKind> names = {{"auto", LightSamplerKind::Auto},
                                                                {"uniform", LightSamplerKind::Uniform},
                                                                {"power", LightSamplerKind::Power},
                                                                {"tree", LightSamplerKind::Tree},
                                                                {"exhaustive", LightSamplerKind::Exhaustive}};
  return names;
}

const std::map<std::string, SampleSequence>& sampler_names() {
  static const std::map<std::string, SampleSequence> names = {{"independent", SampleSequence::Independent},
                                                              {"sobol", SampleSequence::Sobol},
                                                              {"zsobol", SampleSequence::ZSobol}};
  return names;
}

const std::map<std::string, DenoiserKind>& denoiser_names() {
  static const std::map<std::string, DenoiserKind> names = {
      {"none", DenoiserKind::None}, {"bilateral", DenoiserKind::Bilateral}, {"svgf", DenoiserKind::Svgf}};
  return names;
}

const std::map<std::string, BiasCorrection>& bias_names() {
  static const std::map<std::string, BiasCorrection> names = {
      {"none", BiasCorrection::None}, {"basic", BiasCorrection::Basic}, {"pairwise", BiasCorrection::Pairwise}};
  return names;
}

const std::vector<std::string>& reuse_names() {
  static const std::vector<std::string> names = {"none", "temporal", "spatial", "both"};
  return names;
}

}  // namespace candela

#include "apps/settings_schema.h"

#include <cmath>
#include <sstream>
#include <type_traits>

#include "apps/settings_names.h"
#include "engine/check.h"

namespace candela {

namespace {

// Rows are built from a `member` function, a generic lambda returning a reference to the member in a const
// or non-const RenderSettings.
template <class Member>
Setting number_row(std::string key, SettingGroup group, SettingType type, double min, double max, Member member,
                   std::string doc, unsigned methods) {
  Setting row;
  row.key = std::move(key);
  row.group = group;
  row.type = type;
  row.doc = std::move(doc);
  row.methods = methods;
  row.min = min;
  row.max = max;
  row.get = [member](const RenderSettings& s) { return double(member(s)); };
  row.set = [member](RenderSettings& s, double v) {
    using T = std::remove_reference_t<decltype(member(s))>;
    member(s) = T(v);
  };
  return row;
}

template <class Member>
Setting flag_row(std::string key, SettingGroup group, Member member, std::string doc, unsigned methods,
                 std::string off_option = "") {
  Setting row = number_row(key, group, SettingType::Flag, 0.0, 1.0, member, std::move(doc), methods);
  row.set = [member](RenderSettings& s, double v) { member(s) = v != 0.0; };
  row.off_option = off_option.empty() ? "no-" + row.option().substr(2) : std::move(off_option);
  return row;
}

template <class T, class Member>
Setting choice_row(std::string key, SettingGroup group, const std::map<std::string, T>& names, Member member,
                   std::string doc, unsigned methods) {
  Setting row;
  row.key = std::move(key);
  row.group = group;
  row.type = SettingType::Choice;
  row.doc = std::move(doc);
  row.methods = methods;
  row.names = keys_of(names);
  row.get = [&names, member, list = row.names](const RenderSettings& s) {
    const std::string name = name_of(names, T(member(s)));
    return double(std::find(list.begin(), list.end(), name) - list.begin());
  };
  row.set = [&names, member, list = row.names](RenderSettings& s, double i) {
    CHECK(i >= 0.0 && size_t(i) < list.size());
    member(s) = names.at(list[size_t(i)]);
  };
  return row;
}

// The reuse rows ReSTIR DI and GI share, under `prefix` ("di" or "gi"), on the ReuseParams `params` reaches.
template <class Params>
void append_reuse_rows(std::vector<Setting>& rows, const std::string& prefix, SettingGroup group, unsigned methods,
                       Params params) {
  auto key = [&](const char* name) { return prefix + "_" + name; };
  auto field = [params](auto pointer) {
    return [ params, pointer ](auto& s) -> auto& { return params(s).*pointer; };
  };
  const bool gi = group == SettingGroup::RestirGi;
  Setting reuse;
  reuse.key = key("reuse");
  reuse.group = group;
  reuse.type = SettingType::Choice;
  reuse.doc = "Reuse stages: none, temporal, spatial or both";
  reuse.methods = methods;
  reuse.scope = kEverywhere & ~kConverge;
  reuse.names = reuse_names();  // index = temporal + 2 spatial
  reuse.get = [params](const RenderSettings& s) {
    return double(int(params(s).temporal) + 2 * int(params(s).spatial));
  };
  reuse.set = [params](RenderSettings& s, double v) {
    params(s).temporal = (int(v) & 1) != 0;
    params(s).spatial = (int(v) & 2) != 0;
  };
  rows.push_back(reuse);
  rows.push_back(choice_row(key("bias"), group, bias_names(), field(&ReuseParams::bias),
                            "Bias correction of reuse: none (1/M), basic (generalized balance heuristic, k^2 target "
                            "evaluations) or pairwise (pairwise MIS, k evaluations)",
                            methods));
  rows.back().scope = kEverywhere & ~kConverge;
  rows.push_back(number_row(key("neighbours"), group, SettingType::Int, 0, 31, field(&ReuseParams::spatial_neighbours),
                            "Spatial neighbours per pass", methods));
  rows.push_back(number_row(key("radius"), group, SettingType::Float, 1, 1000, field(&ReuseParams::spatial_radius),
                            "Spatial reuse radius in pixels", methods));
  rows.back().widget_max = 64;
  rows.push_back(number_row(key("neighbour_block"), group, SettingType::Int, 1, 64,
                            field(&ReuseParams::neighbour_block),
                            "Pixels of each block this many pixels on a side share their spatial neighbours' offsets "
                            "(1 = each pixel draws its own; larger is faster and correlates the block)",
                            methods));
  rows.back().widget_max = 16;
  rows.push_back(flag_row(key("fused"), group, field(&ReuseParams::fused),
                          "One fused spatiotemporal pass instead of the temporal and first spatial passes: the "
                          "neighbours are last frame's reservoirs around the pixel's reprojection (needs temporal and "
                          "spatial reuse; no boiling filter)",
                          methods));
  rows.push_back(number_row(key("spatial_passes"), group, SettingType::Int, 1, 8, field(&ReuseParams::spatial_passes),
                            "Spatial reuse passes", methods));
  rows.push_back(number_row(key("shaded_samples"), group, SettingType::Int, 1, kMaxShadedSamples,
                            field(&ReuseParams::shaded_samples),
                            "Samples the last spatial pass keeps of each pixel's combination (stratified over its "
                            "weights), each weighted 1/n and shaded with its own shadow ray, once for repeats of one "
                            "sample (the first becomes history; needs spatial reuse)",
                            methods));
  rows.push_back(number_row(key("disocclusion_neighbours"), group, SettingType::Int, 0, 31,
                            field(&ReuseParams::disocclusion_neighbours),
                            "Spatial neighbours (first pass) for pixels whose temporal history was lost", methods));
  rows.push_back(number_row(key("boiling_filter"), group, SettingType::Float, 0, 1e6,
                            field(&ReuseParams::boiling_threshold),
                            "Drop reservoirs whose estimated contribution exceeds this many times their 16x16 block's "
                            "mean, after temporal reuse (0 = off; biased: removes energy)",
                            methods));
  rows.back().widget_max = 100;
  rows.push_back(number_row(key("visibility_reuse"), group, SettingType::Int, 0, 255,
                            field(&ReuseParams::visibility_reuse_frames),
                            "Reuse last frame's final shadow-ray verdict where a pixel keeps its temporal history's "
                            "sample, for at most this many frames in a row (0 = off; biased where occluders move)",
                            methods));
  rows.back().widget_max = 16;
  rows.push_back(flag_row(key("drop_occluded"), group, field(&ReuseParams::drop_occluded),
                          "A reservoir whose sample the shading found occluded drops it before it becomes history "
                          "(biased at shadow edges and where occluders move)",
                          methods, prefix + "-keep-occluded"));
  rows.push_back(flag_row(key("permutation"), group, field(&ReuseParams::permutation_sampling),
                          "Permutation sampling of the previous frame (decorrelates frames for a denoiser)", methods));
  rows.push_back(number_row(key("history_cap"), group, SettingType::Float, 0, 1000, field(&ReuseParams::history_cap),
                            "The previous frame's reservoir counts at most this many times the current M", methods));
  rows.back().widget_max = 100;
  if (!gi) return;
  rows.push_back(
      number_row("gi_max_jacobian", group, SettingType::Float, 0, 1e6, field(&ReuseParams::max_jacobian),
                 "Reject a reused GI sample whose reconnection Jacobian exceeds this (0 = off, unbiased; > 0 "
                 "removes fireflies at the price of bias)",
                 methods));
  rows.back().widget_max = 100;
  rows.push_back(number_row("gi_min_roughness", group, SettingType::Float, 0, 1, field(&ReuseParams::min_roughness),
                            "Pixels smoother than this keep their own GI sample (no reuse on glossy surfaces)",
                            methods));
  rows.push_back(number_row("gi_max_age", group, SettingType::Int, 0, 65535, field(&ReuseParams::max_sample_age),
                            "Temporal reuse drops GI samples older than this many frames (0 = no limit)", methods));
  rows.back().widget_max = 255;
}

// The rows of the Frame group: size, samples, estimator, light selection, random numbers.
void append_frame_rows(std::vector<Setting>& rows) {
  const SettingGroup g = SettingGroup::Frame;
  rows.push_back(number_row(
      "width", g, SettingType::Int, 1, 16384, [](auto& s) -> auto& { return s.width; },
      "Image width in pixels (view: the window's)", kAllMethods));
  rows.back().scope = kCommandLine | kScript | kConverge;
  rows.push_back(number_row(
      "height", g, SettingType::Int, 1, 16384, [](auto& s) -> auto& { return s.height; },
      "Image height in pixels (view: the window's)", kAllMethods));
  rows.back().scope = kCommandLine | kScript | kConverge;
  rows.push_back(number_row(
      "spp", g, SettingType::Int, 1, 1 << 20, [](auto& s) -> auto& { return s.spp; }, "Samples per pixel per frame",
      kAllMethods));
  rows.back().scope = kEverywhere & ~kConverge;
  rows.back().widget_max = 16;
  rows.push_back(number_row(
      "seed", g, SettingType::Int, 0, 9007199254740991.0 /* 2^53 - 1, exact in a double */,
      [](auto& s) -> auto& { return s.seed; }, "Random seed; same seed, same image, whatever the thread count",
      kAllMethods));
  rows.back().scope = kCommandLine | kScript | kConverge;
  rows.push_back(number_row(
      "max_depth", g, SettingType::Int, 1, 1024, [](auto& s) -> auto& { return s.max_depth; },
      "Path bounces; 1 = direct light only", kPt | kRestir));
  rows.back().widget_max = 16;
  rows.push_back(number_row(
      "rr_depth", g, SettingType::Int, 1, 1024, [](auto& s) -> auto& { return s.rr_depth; },
      "Russian roulette ends paths at random from this bounce on (unbiased; smaller is faster and noisier)",
      kPt | kRestir));
  rows.back().widget_max = 8;
  rows.push_back(choice_row(
      "method", g, method_names(), [](auto& s) -> auto& { return s.method; },
      "Estimator: pt (reference path tracer), direct (direct light only: light samples and a BSDF "
      "sample combined by MIS), restir-di (direct light by spatiotemporal reservoir resampling), "
      "restir (restir-di plus ReSTIR GI for indirect light, paths up to max_depth)",
      kAllMethods));
  rows.back().scope = kEverywhere & ~kConverge;
  rows.push_back(choice_row(
      "light_sampler", g, light_sampler_names(), [](auto& s) -> auto& { return s.light_sampler; },
      "Light selection: auto (restir-di: tree with region light tiles, as --light-sampler tree "
      "--di-light-tiles 1; the other methods: power), uniform, power (alias table), tree (light BVH), "
      "exhaustive (every light's importance; slow oracle)",
      kAllMethods));
  rows.push_back(choice_row(
      "sampler", g, sampler_names(), [](auto& s) -> auto& { return s.sampler; },
      "Where paths' random numbers come from: independent (PCG32), sobol (Owen-scrambled Sobol "
      "points, stratified within each pixel's samples) or zsobol (one screen-wide Sobol sequence "
      "per frame in Morton order)",
      kPt | kDirect));
  rows.back().scope = kEverywhere & ~kConverge;
  rows.push_back(flag_row(
      "jitter", g, [](auto& s) -> auto& { return s.jitter; },
      "Primary rays through jittered positions (off: pixel centres, no anti-aliasing; isolates the "
      "light transport estimator in comparisons)",
      kAllMethods));
  rows.push_back(flag_row(
      "accumulate", g, [](auto& s) -> auto& { return s.accumulate; },
      "Accumulate frames while camera and scene stay still (off: each frame alone)", kAllMethods));
  rows.back().scope = kCommandLine | kViewer;
  rows.back().refusal = "each frame of a script is rendered alone";
  rows.push_back(number_row(
      "time_budget_ms", g, SettingType::Float, 0, 1e9, [](auto& s) -> auto& { return s.time_budget_ms; },
      "Equal-time mode: per frame, as many samples per pixel as fit in this many milliseconds "
      "(0 = off; overrides spp)",
      kAllMethods));
  rows.back().scope = kCommandLine;
  rows.back().refusal = "a frame's samples must not depend on the clock";
}

// The rows of ReSTIR DI's initial candidates.
void append_di_candidate_rows(std::vector<Setting>& rows) {
  const SettingGroup g = SettingGroup::RestirDi;
  rows.push_back(number_row(
      "di_candidates", g, SettingType::Int, 0, 1024, [](auto& s) -> auto& { return s.di.light_candidates; },
      "Light candidates per pixel (M_l)", kRestirMethods));
  rows.back().widget_max = 64;
  rows.push_back(number_row(
      "di_history_candidates", g, SettingType::Int, 0, 1024,
      [](auto& s) -> auto& { return s.di.history_light_candidates; },
      "Light candidates for pixels whose temporal history is found (at most di_candidates)", kRestirMethods));
  rows.back().widget_max = 64;
  rows.push_back(number_row(
      "di_bsdf_candidates", g, SettingType::Int, 0, 64, [](auto& s) -> auto& { return s.di.bsdf_candidates; },
      "BSDF-sampled candidates per pixel (M_b; one ray each)", kRestirMethods));
  rows.back().widget_max = 8;
  rows.push_back(number_row(
      "di_bsdf_probability", g, SettingType::Float, 0, 1, [](auto& s) -> auto& { return s.di.bsdf_probability; },
      "Probability with which each BSDF candidate is drawn and its ray traced; the MIS weights count it as that "
      "fraction of a candidate (unbiased)",
      kRestirMethods));
  rows.push_back(number_row(
      "di_light_tiles", g, SettingType::Int, 0, 4096, [](auto& s) -> auto& { return s.di.light_tiles; },
      "Draw light candidates from presampled light tiles: with the power and uniform light samplers "
      "this many per frame, shared by 16x16-pixel blocks; with tree and exhaustive each block draws "
      "its own for the region its points occupy (0 = off)",
      kRestirMethods));
  rows.back().widget_max = 256;
  rows.push_back(number_row(
      "di_light_tile_size", g, SettingType::Int, 0, 1 << 16, [](auto& s) -> auto& { return s.di.light_tile_size; },
      "Light samples per light tile (0 = 1024 per shared tile, 128 per region tile)", kRestirMethods));
  rows.back().widget_max = 4096;
  rows.push_back(flag_row(
      "di_visibility", g, [](auto& s) -> auto& { return s.di.candidate_visibility; },
      "Trace a shadow ray to the chosen candidate before reuse (drops occluded choices; the basic bias "
      "correction is then no longer exactly unbiased)",
      kRestirMethods));
  rows.push_back(flag_row(
      "di_mis_visibility", g, [](auto& s) -> auto& { return s.di_reuse.mis_visibility; },
      "Include visibility in the reuse MIS weights (unbiased also with di_visibility; basic: (k+1)^2 "
      "shadow rays per pixel, pairwise: 2k)",
      kRestirMethods));
}

// The rows of ReSTIR GI's samples.
void append_gi_sample_rows(std::vector<Setting>& rows) {
  rows.push_back(flag_row(
      "gi_share_bsdf_ray", SettingGroup::RestirGi, [](auto& s) -> auto& { return s.gi_share_bsdf_ray; },
      "GI paths start with ReSTIR DI's BSDF candidate rays (one BSDF sample and ray per pixel for both; needs "
      "di_bsdf_candidates >= 1 and di_bsdf_probability 1, else GI draws its own)",
      kRestir));
}

void append_denoiser_rows(std::vector<Setting>& rows) {
  const SettingGroup g = SettingGroup::Denoiser;
  rows.push_back(choice_row(
      "denoise", g, denoiser_names(), [](auto& s) -> auto& { return s.denoise.kind; },
      "Denoiser that finishes each frame: none, bilateral (cross-bilateral, one frame) or svgf "
      "(spatiotemporal variance-guided filtering); both demodulate by albedo",
      kAllMethods));
  rows.back().scope = kEverywhere & ~kConverge;
  Setting kernel = number_row(
      "svgf_kernel", g, SettingType::Int, 3, 5, [](auto& s) -> auto& { return s.denoise.svgf.atrous_radius; },
      "SVGF's a-trous kernel: 3 (3x3 binomial) or 5 (the paper's 5x5 B3 spline, wider and slower)", kAllMethods);
  kernel.values = {3, 5};
  kernel.get = [](const RenderSettings& s) { return double(2 * s.denoise.svgf.atrous_radius + 1); };
  kernel.set = [](RenderSettings& s, double v) { s.denoise.svgf.atrous_radius = int(v) / 2; };
  kernel.relevant = [](const RenderSettings& s) { return s.denoise.kind == DenoiserKind::Svgf; };
  rows.push_back(kernel);
}

// Whole numbers in full ("1048576"), others in the shortest of 6 significant digits ("0.1").
std::string format_number(double x) {
  if (x == std::floor(x) && std::abs(x) < 1e16) return std::to_string(int64_t(x));
  std::ostringstream out;
  out << x;
  return out.str();
}

}  // namespace

std::string Setting::option() const {
  std::string out = "--" + key;
  for (char& c : out)
    if (c == '_') c = '-';
  return out;
}

std::string Setting::format(const RenderSettings& s) const {
  const double v = get(s);
  switch (type) {
    case SettingType::Int: return std::to_string(int64_t(v));
    case SettingType::Float: return format_number(v);
    case SettingType::Flag: return v != 0.0 ? "true" : "false";
    case SettingType::Choice: return names.at(size_t(v));
  }
  return "?";
}

std::string Setting::range_text() const {
  std::string out;
  switch (type) {
    case SettingType::Int:
      if (values.empty()) return format_number(min) + ".." + format_number(max);
      for (size_t i = 0; i < values.size(); ++i)
        out += (i == 0 ? "" : i + 1 == values.size() ? " or " : ", ") + std::to_string(values[i]);
      return out;
    case SettingType::Float: return format_number(min) + ".." + format_number(max);
    case SettingType::Flag: return "true, false";
    case SettingType::Choice:
      for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
      return out;
  }
  return out;
}

bool Setting::applies(const RenderSettings& s) const {
  const unsigned bit = 1u << unsigned(s.method);
  return (methods & bit) != 0 && (!relevant || relevant(s));
}

int Setting::name_index(const std::string& name) const {
  const auto it = std::find(names.begin(), names.end(), name);
  return it == names.end() ? -1 : int(it - names.begin());
}

bool Setting::accepts(double v) const {
  switch (type) {
    case SettingType::Int:
      return v >= min && v <= max && v == std::floor(v) &&
             (values.empty() || std::find(values.begin(), values.end(), int(v)) != values.end());
    case SettingType::Float: return v >= min && v <= max;
    case SettingType::Flag: return v == 0.0 || v == 1.0;
    case SettingType::Choice: return v >= 0.0 && v < double(names.size()) && v == std::floor(v);
  }
  return false;
}

const std::vector<Setting>& settings_schema() {
  static const std::vector<Setting> rows = [] {
    std::vector<Setting> r;
    append_frame_rows(r);
    append_di_candidate_rows(r);
    append_reuse_rows(
        r, "di", SettingGroup::RestirDi, kRestirMethods, [](auto& s) -> auto& { return s.di_reuse; });
    append_reuse_rows(
        r, "gi", SettingGroup::RestirGi, kRestir, [](auto& s) -> auto& { return s.gi_reuse; });
    append_gi_sample_rows(r);
    append_denoiser_rows(r);
    return r;
  }();
  return rows;
}

const Setting* find_setting(const std::string& key) {
  for (const Setting& row : settings_schema())
    if (row.key == key) return &row;
  return nullptr;
}

const char* setting_group_name(SettingGroup group) {
  switch (group) {
    case SettingGroup::Frame: return "Frame";
    case SettingGroup::RestirDi: return "ReSTIR DI";
    case SettingGroup::RestirGi: return "ReSTIR GI";
    case SettingGroup::Denoiser: return "Denoiser";
  }
  return "?";
}

std::string method_list(unsigned methods) {
  if (methods == kAllMethods) return "all";
  std::string out;
  for (Method m : {Method::PathTrace, Method::Direct, Method::RestirDi, Method::Restir})
    if (methods & (1u << unsigned(m))) out += (out.empty() ? "" : ", ") + name_of(method_names(), m);
  return out;
}

std::string settings_markdown() {
  const RenderSettings defaults;
  std::string out;
  for (SettingGroup group :
       {SettingGroup::Frame, SettingGroup::RestirDi, SettingGroup::RestirGi, SettingGroup::Denoiser}) {
    out += std::string(out.empty() ? "" : "\n") + "### " + setting_group_name(group) + "\n\n";
    out += "| option | script key | values | default | methods | description |\n";
    out += "|---|---|---|---|---|---|\n";
    for (const Setting& row : settings_schema()) {
      if (row.group != group) continue;
      std::string option = "`" + row.option() + "`";
      if (row.type == SettingType::Flag) option += ", `--" + row.off_option + "`";
      std::string where;
      if (!(row.scope & kScript)) where += " Not in shot scripts: " + row.refusal + ".";
      if ((row.scope & kCommandLine) && !(row.scope & kConverge)) where += " `converge`: set by its `--methods`.";
      if (!(row.scope & kViewer)) where += " No viewer widget.";
      out += "| " + option + " | " + ((row.scope & kScript) ? "`" + row.key + "`" : "-") + " | " + row.range_text() +
             " | " + row.format(defaults) + " | " + method_list(row.methods) + " | " + row.doc + "." + where + " |\n";
    }
  }
  return out;
}

}  // namespace candela

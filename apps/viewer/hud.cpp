#include "apps/viewer/hud.h"

#include <imgui.h>

#include <algorithm>
#include <cmath>

#include "apps/settings_schema.h"

namespace candela {

void FrameHistory::push(double frame_ms, FrameStats stats) {
  if (frames_.size() == kCapacity) frames_.pop_front();
  frames_.push_back({frame_ms, std::move(stats)});
}

namespace {

constexpr float kHudWidth = 360.0f;

// A colour per stage, fixed by the stage's order of first appearance: hues a golden-ratio turn apart, so
// neighbours in the legend differ and no two of the first dozen look alike.
ImU32 stage_colour(int index) {
  float r, g, b;
  ImGui::ColorConvertHSVtoRGB(std::fmod(0.1f + 0.618034f * float(index), 1.0f), 0.65f, 0.95f, r, g, b);
  return ImGui::ColorConvertFloat4ToU32(ImVec4(r, g, b, 1.0f));
}

// Stacked bars of per-stage milliseconds, one column per recorded frame (oldest left), then a legend with
// each stage's last and mean milliseconds, rays and dropped non-finite values. Cost: O(frames x stages)
// rectangles.
void draw_stage_graph(const FrameHistory& history) {
  std::vector<std::string> names;  // stages in order of first appearance
  for (size_t f = 0; f < history.size(); ++f)
    for (const StageStats& s : history.stats(f).stages)
      if (std::find(names.begin(), names.end(), s.name) == names.end()) names.push_back(s.name);
  double max_ms = 1.0;
  for (size_t f = 0; f < history.size(); ++f) max_ms = std::max(max_ms, history.stats(f).total_ms);
  const ImVec2 size(ImGui::GetContentRegionAvail().x, 80.0f);
  const ImVec2 origin = ImGui::GetCursorScreenPos();
  ImDrawList* draw = ImGui::GetWindowDrawList();
  draw->AddRectFilled(origin, ImVec2(origin.x + size.x, origin.y + size.y), IM_COL32(30, 30, 30, 200));
  const float column = size.x / float(FrameHistory::kCapacity);
  for (size_t f = 0; f < history.size(); ++f) {
    float x0 = origin.x + size.x - float(history.size() - f) * column, y = origin.y + size.y;
    for (const StageStats& s : history.stats(f).stages) {
      int index = int(std::find(names.begin(), names.end(), s.name) - names.begin());
      float h = float(s.ms / max_ms) * size.y;
      draw->AddRectFilled(ImVec2(x0, y - h), ImVec2(x0 + std::max(column, 1.0f), y), stage_colour(index));
      y -= h;
    }
  }
  draw->AddText(ImVec2(origin.x + 4, origin.y + 2), IM_COL32(255, 255, 255, 255),
                (std::to_string(int(max_ms + 0.5)) + " ms").c_str());
  ImGui::Dummy(size);
  if (!ImGui::BeginTable("stages", 5, ImGuiTableFlags_SizingStretchProp)) return;
  ImGui::TableSetupColumn("stage");
  ImGui::TableSetupColumn("ms");
  ImGui::TableSetupColumn("mean");
  ImGui::TableSetupColumn("Mrays");
  ImGui::TableSetupColumn("NaN/Inf");
  ImGui::TableHeadersRow();
  const FrameStats& last = history.stats(history.size() - 1);
  for (size_t k = 0; k < names.size(); ++k) {
    double mean = 0.0;
    for (size_t f = 0; f < history.size(); ++f) mean += history.stats(f).stage_ms(names[k]);
    mean /= double(history.size());
    uint64_t rays = 0, non_finite = 0;
    for (const StageStats& s : last.stages)
      if (s.name == names[k]) rays = s.rays, non_finite = s.non_finite;
    ImGui::TableNextRow();
    ImGui::TableNextColumn();
    ImVec2 p = ImGui::GetCursorScreenPos();
    float line = ImGui::GetTextLineHeight();
    ImGui::GetWindowDrawList()->AddRectFilled(p, ImVec2(p.x + line * 0.8f, p.y + line * 0.8f), stage_colour(int(k)));
    ImGui::SetCursorScreenPos(ImVec2(p.x + line, p.y));
    ImGui::TextUnformatted(names[k].c_str());
    ImGui::TableNextColumn();
    ImGui::Text("%.2f", last.stage_ms(names[k]));
    ImGui::TableNextColumn();
    ImGui::Text("%.2f", mean);
    ImGui::TableNextColumn();
    ImGui::Text("%.3f", double(rays) * 1e-6);
    ImGui::TableNextColumn();
    ImGui::Text("%llu", static_cast<unsigned long long>(non_finite));
  }
  ImGui::EndTable();
}

// The label of a row's widget: its key without the group's prefix, words apart ("di_bsdf_candidates" ->
// "bsdf candidates").
std::string widget_label(const Setting& row) {
  std::string label = row.key;
  if (row.group == SettingGroup::RestirDi || row.group == SettingGroup::RestirGi) label = label.substr(3);
  std::replace(label.begin(), label.end(), '_', ' ');
  return label;
}

// A combo box over `names`; true when the choice changed.
bool combo(const char* label, int& index, const std::vector<std::string>& names) {
  bool changed = false;
  if (ImGui::BeginCombo(label, names.at(size_t(index)).c_str())) {
    for (int i = 0; i < int(names.size()); ++i)
      if (ImGui::Selectable(names[size_t(i)].c_str(), i == index) && i != index) index = i, changed = true;
    ImGui::EndCombo();
  }
  return changed;
}

// The widget of one schema row (apps/settings_schema.h), greyed out where the row does not apply to the
// settings' method: a combo for names, a slider over [min, widget_max] for numbers (ctrl+click types any
// value, clamped to the row's range), a checkbox for flags. The settings follow the widget as it moves;
// true when a change is complete (a slider released), so dragging reconfigures the Renderer once.
bool setting_widget(const Setting& row, RenderSettings& s) {
  const std::string label = widget_label(row);
  const double value = row.get(s);
  const double top = row.widget_max > 0.0 ? row.widget_max : row.max;
  bool done = false;
  ImGui::BeginDisabled(!row.applies(s));
  if (row.type == SettingType::Choice) {
    int index = int(value);
    if ((done = combo(label.c_str(), index, row.names))) row.set(s, double(index));
  } else if (row.type == SettingType::Int && !row.values.empty()) {
    std::vector<std::string> names;
    for (int v : row.values) names.push_back(std::to_string(v));
    int index = int(std::find(row.values.begin(), row.values.end(), int(value)) - row.values.begin());
    if ((done = combo(label.c_str(), index, names))) row.set(s, double(row.values[size_t(index)]));
  } else if (row.type == SettingType::Int) {
    int v = int(value);
    if (ImGui::SliderInt(label.c_str(), &v, int(row.min), int(top)))
      row.set(s, std::clamp(double(v), row.min, row.max));
    done = ImGui::IsItemDeactivatedAfterEdit();
  } else if (row.type == SettingType::Float) {
    float v = float(value);
    if (ImGui::SliderFloat(label.c_str(), &v, float(row.min), float(top), top <= 1.0 ? "%.2f" : "%.1f"))
      row.set(s, std::clamp(double(v), row.min, row.max));
    done = ImGui::IsItemDeactivatedAfterEdit();
  } else {
    bool v = value != 0.0;
    if ((done = ImGui::Checkbox(label.c_str(), &v))) row.set(s, v ? 1.0 : 0.0);
  }
  ImGui::EndDisabled();
  return done;
}

// The widgets of every row of `group` the viewer shows; true when one changed.
bool draw_group(SettingGroup group, RenderSettings& s) {
  bool changed = false;
  for (const Setting& row : settings_schema())
    if (row.group == group && (row.scope & kViewer)) changed |= setting_widget(row, s);
  return changed;
}

// The frame's and the denoiser's settings, then the viewer's own (render scale, target frame rate, paused
// scene time); true when one that reconfigures the Renderer changed.
bool draw_renderer_settings(HudState& state) {
  bool changed = draw_group(SettingGroup::Frame, state.settings);
  changed |= draw_group(SettingGroup::Denoiser, state.settings);
  ImGui::SliderFloat("resolution scale", &state.scale, 0.125f, 1.0f, "%.3f");
  changed |= ImGui::IsItemDeactivatedAfterEdit();
  ImGui::SliderFloat("target FPS", &state.target_fps, 0.0f, 120.0f, state.target_fps > 0.0f ? "%.0f" : "off");
  if (state.target_fps > 0.0f) ImGui::Text("dynamic resolution: x%.2f of the scale", state.dynamic_scale);
  ImGui::Checkbox("pause time", &state.pause_time);
  return changed;
}

}  // namespace

HudActions draw_hud(HudState& state, const FrameHistory& history, const Renderer& renderer, const CameraDesc& camera,
                    HudRect& rect) {
  HudActions actions;
  const ImGuiIO& io = ImGui::GetIO();
  ImGui::SetNextWindowPos(ImVec2(8.0f, 8.0f), ImGuiCond_Always);
  const float width = std::max(std::min(kHudWidth, io.DisplaySize.x - 16.0f), 64.0f);
  ImGui::SetNextWindowSizeConstraints(ImVec2(width, 0.0f), ImVec2(width, std::max(io.DisplaySize.y - 16.0f, 32.0f)));
  ImGui::SetNextWindowBgAlpha(0.8f);
  if (ImGui::Begin("candela", nullptr, ImGuiWindowFlags_AlwaysAutoResize | ImGuiWindowFlags_NoMove)) {
    if (history.size() > 0) {
      const double frame_ms = history.frame_ms(history.size() - 1);
      const FrameStats& last = history.stats(history.size() - 1);
      ImGui::Text("%dx%d  frame %d  %d spp accumulated", renderer.settings().width, renderer.settings().height,
                  last.frame, renderer.accumulated_spp());
      ImGui::Text("frame %.1f ms (%.1f FPS), render %.1f ms", frame_ms, 1000.0 / std::max(frame_ms, 1e-3),
                  last.total_ms);
      // NaN/Inf values the stages dropped (they should never occur): red as soon as one did in the graph's frames.
      uint64_t recent_non_finite = 0;
      for (size_t f = 0; f < history.size(); ++f) recent_non_finite += history.stats(f).non_finite();
      ImGui::TextColored(recent_non_finite ? ImVec4(1.0f, 0.3f, 0.3f, 1.0f) : ImGui::GetStyleColorVec4(ImGuiCol_Text),
                         "non-finite dropped: %llu last frame, %llu in the last %zu",
                         static_cast<unsigned long long>(last.non_finite()),
                         static_cast<unsigned long long>(recent_non_finite), history.size());
      float frame_times[FrameHistory::kCapacity], mrays[FrameHistory::kCapacity];
      for (size_t f = 0; f < history.size(); ++f) {
        frame_times[f] = float(history.frame_ms(f));
        mrays[f] = float(double(history.stats(f).rays()) * 1e-6);
      }
      char overlay[64];
      std::snprintf(overlay, sizeof(overlay), "frame ms (last %zu)", history.size());
      ImGui::PlotLines("##frame_ms", frame_times, int(history.size()), 0, overlay, 0.0f, FLT_MAX,
                       ImVec2(ImGui::GetContentRegionAvail().x, 40.0f));
      std::snprintf(overlay, sizeof(overlay), "rays per frame: %.3f M (%.1f Mrays/s)", mrays[history.size() - 1],
                    mrays[history.size() - 1] / std::max(last.total_ms * 1e-3, 1e-6));
      ImGui::PlotLines("##rays", mrays, int(history.size()), 0, overlay, 0.0f, FLT_MAX,
                       ImVec2(ImGui::GetContentRegionAvail().x, 40.0f));
      draw_stage_graph(history);
    }
    ImGui::PushItemWidth(ImGui::GetContentRegionAvail().x * 0.55f);  // leaves room for the labels
    if (ImGui::CollapsingHeader("Renderer", ImGuiTreeNodeFlags_DefaultOpen))
      actions.settings_changed |= draw_renderer_settings(state);
    for (SettingGroup group : {SettingGroup::RestirDi, SettingGroup::RestirGi}) {
      if (!ImGui::CollapsingHeader(setting_group_name(group))) continue;
      ImGui::PushID(int(group));  // the DI and GI widgets share their labels
      actions.settings_changed |= draw_group(group, state.settings);
      ImGui::PopID();
    }
    if (ImGui::CollapsingHeader("View")) {
      for (const AovInfo& aov : aov_table()) {  // three per line
        ImGui::BeginDisabled(!aov_available(aov.aov, renderer));
        if (ImGui::RadioButton(aov.name, state.view == aov.aov)) state.view = aov.aov;
        ImGui::EndDisabled();
        if ((&aov - aov_table().data()) % 3 != 2) ImGui::SameLine();
      }
      ImGui::NewLine();
      ImGui::SliderFloat("exposure", &state.exposure, 0.01f, 16.0f, "%.2f", ImGuiSliderFlags_Logarithmic);
      ImGui::Text("camera (%.1f, %.1f, %.1f) -> (%.1f, %.1f, %.1f)", camera.position.x, camera.position.y,
                  camera.position.z, camera.target.x, camera.target.y, camera.target.z);
      ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyleColorVec4(ImGuiCol_TextDisabled));
      ImGui::TextWrapped("orbit: left drag, wheel; fly: right drag + WASD QE (shift: faster)");
      ImGui::PopStyleColor();
    }
    ImGui::PopItemWidth();
    actions.reset = ImGui::Button("reset");
    ImGui::SameLine();
    actions.save_png = ImGui::Button("save PNG");
    ImGui::SameLine();
    actions.save_exr = ImGui::Button("save EXR");
    ImGui::SameLine();
    ImGui::SetNextItemWidth(-1.0f);
    ImGui::InputText("##screenshot", state.screenshot_base, sizeof(state.screenshot_base));
    if (!state.status.empty()) ImGui::TextWrapped("%s", state.status.c_str());
  }
  rect = {ImGui::GetWindowPos().x, ImGui::GetWindowPos().y, ImGui::GetWindowSize().x, ImGui::GetWindowSize().y};
  ImGui::End();
  return actions;
}

}  // namespace candela

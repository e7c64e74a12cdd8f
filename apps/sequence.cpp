#include "apps/sequence.h"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>

#include "apps/aovs.h"
#include "apps/scene_source.h"
#include "apps/stats_json.h"
#include "engine/check.h"

namespace candela {

namespace {

std::vector<std::string> output_patterns(const ShotScript& script) {
  std::vector<std::string> out = script.output.images;
  for (const auto& [name, pattern] : script.output.aovs) out.push_back(pattern);
  return out;
}

// Stage "write": every image and AOV of `frame`, each file atomically. Cost: one image encode per file.
void write_frame(const ShotScript& script, const Renderer& renderer, int frame) {
  Image image = renderer.image();
  for (const std::string& pattern : script.output.images)
    write_image(frame_path(pattern, frame), image, script.output.exposure);
  for (const auto& [name, pattern] : script.output.aovs)
    write_aov(frame_path(pattern, frame), renderer, find_aov(name)->aov, script.output.exposure);
}

// Per-frame stats of this run: STATS.csv gets one row per stage and frame as each frame ends (long
// format: frame, written, scene time, spp, stage, ms, rays, non_finite; stage "total" for the frame), STATS.json
// is rewritten atomically after each frame (stats_to_json plus "written" and "time").
class StatsFiles {
 public:
  explicit StatsFiles(const std::string& base) : base_(base) {
    if (base_.empty()) return;
    csv_.open(base_ + ".csv", std::ios::trunc);
    if (!csv_) throw InputError(base_ + ".csv: cannot open for writing");
    csv_ << "frame,written,time_s,spp,stage,ms,rays,non_finite\n";
  }
  void add(const FrameStats& stats, bool written, float time) {
    if (base_.empty()) return;
    auto row = [&](const std::string& stage, double ms, uint64_t rays, uint64_t non_finite) {
      csv_ << stats.frame << ',' << int(written) << ',' << time << ',' << stats.spp << ',' << stage << ',' << ms << ','
           << rays << ',' << non_finite << '\n';
    };
    for (const StageStats& s : stats.stages) row(s.name, s.ms, s.rays, s.non_finite);
    row("total", stats.total_ms, stats.rays(), stats.non_finite());
    csv_.flush();
    nlohmann::json entry = stats_to_json({stats})[0];
    entry["written"] = written;
    entry["time"] = time;
    json_.push_back(entry);
    write_json_file(base_ + ".json", json_);
  }

 private:
  std::string base_;
  std::ofstream csv_;
  nlohmann::json json_ = nlohmann::json::array();
};

// One line on stderr, redrawn after each frame: a bar, frames written of those planned, warm-up frames,
// seconds per frame and the time left at that rate.
void show_progress(int done, int total, double elapsed_s, int rendered, int warmup_left) {
  const int width = 30;
  int filled = total > 0 ? done * width / total : width;
  double per_frame = rendered > 0 ? elapsed_s / rendered : 0.0;
  int eta = int(per_frame * (total - done + warmup_left) + 0.5);
  std::fprintf(stderr, "\r[%s%s] %d/%d frames, %.2f s/frame, ETA %d:%02d:%02d ",
               std::string(size_t(filled), '#').c_str(), std::string(size_t(width - filled), '.').c_str(), done, total,
               per_frame, eta / 3600, eta / 60 % 60, eta % 60);
}

}  // namespace

bool frame_finished(const ShotScript& script, int frame) {
  std::error_code ec;
  for (const std::string& pattern : output_patterns(script))
    if (!std::filesystem::exists(frame_path(pattern, frame), ec)) return false;
  return true;
}

SequencePlan plan_sequence(const ShotScript& script, int first, int last, int warmup,
                           const std::function<bool(int)>& finished) {
  SequencePlan plan;
  const int start = script.first_frame, every = script.history_reset_every;
  auto reset_point = [&](int f) { return f == start || (every > 0 && (f - start) % every == 0); };
  std::set<int> render, write;
  for (int g = first; g <= last; ++g) {
    if (finished(g)) {
      ++plan.finished;
      continue;
    }
    write.insert(g);
    int w = 0;
    if (script.keeps_history()) w = every > 0 ? (g - start) % every : std::min(warmup, g - start);
    for (int f = g - w; f <= g; ++f) render.insert(f);
  }
  int previous = -2;
  for (int f : render) {
    bool run_start = f != previous + 1;
    if (run_start && script.keeps_history() && !reset_point(f)) plan.exact = false;
    plan.frames.push_back({f, write.count(f) > 0, run_start || reset_point(f)});
    previous = f;
  }
  return plan;
}

std::pair<int, int> parse_frame_range(const std::string& text, const ShotScript& script) {
  size_t colon = text.find(':');
  int a = 0, b = 0;
  try {
    size_t used = 0;
    a = std::stoi(text.substr(0, colon), &used);
    if (used != (colon == std::string::npos ? text.size() : colon)) throw std::invalid_argument(text);
    b = a;
    if (colon != std::string::npos) {
      b = std::stoi(text.substr(colon + 1), &used);
      if (used != text.size() - colon - 1) throw std::invalid_argument(text);
    }
  } catch (const std::logic_error&) {
    throw InputError("--frames " + text + ": expected FIRST:LAST (inclusive) or one frame number");
  }
  if (a > b) throw InputError("--frames " + text + ": first frame after last");
  if (a < script.first_frame || b > script.last_frame())
    throw InputError("--frames " + text + ": outside " + script.file + "'s frames " +
                     std::to_string(script.first_frame) + ":" + std::to_string(script.last_frame()));
  return {a, b};
}

int run_sequence(const ShotScript& script, const SequenceOptions& options) {
  auto [first, last] = options.range.value_or(std::make_pair(script.first_frame, script.last_frame()));
  SequencePlan plan = plan_sequence(script, first, last, options.warmup.value_or(script.warmup),
                                    [&](int f) { return frame_finished(script, f); });
  int to_write = 0;
  for (const PlannedFrame& p : plan.frames) to_write += p.write;
  if (!options.quiet) {
    std::fprintf(stderr, "%s: frames %d:%d, %d already written, %d to render (+%zu warm-up)\n", script.file.c_str(),
                 first, last, plan.finished, to_write, plan.frames.size() - size_t(to_write));
    if (!plan.exact)
      std::fprintf(stderr,
                   "note: the warm-up does not reach a history reset point: frames are statistically like a single "
                   "run's but not bit-identical (set history_reset_every for exact shards)\n");
  }
  if (plan.frames.empty()) return 0;

  // Scene setup (load, script animation), then output directories: all before the first frame.
  BuiltinOptions builtin;
  builtin.light_count = script.lights;
  Scene scene;
  try {
    scene = load_scene(script.scene, builtin, script.environment);
  } catch (const InputError& e) {
    throw InputError(script.file + ": scene: " + e.what());
  }
  apply_shot_animation(script, scene);
  std::vector<std::string> files = output_patterns(script);
  files.push_back(script.output.stats);
  for (const std::string& pattern : files) {
    std::filesystem::path dir =
        std::filesystem::path(pattern == script.output.stats ? pattern : frame_path(pattern, 0)).parent_path();
    if (!dir.empty()) std::filesystem::create_directories(dir);
  }
  std::string stats_base = script.output.stats;
  if (!stats_base.empty() && options.range) stats_base += "_" + std::to_string(first) + "-" + std::to_string(last);
  StatsFiles stats_files(stats_base);
  Renderer renderer(std::move(scene), script.settings);

  auto start = std::chrono::steady_clock::now();
  int written = 0, rendered = 0, warmup_left = int(plan.frames.size()) - to_write;
  for (const PlannedFrame& p : plan.frames) {
    if (p.reset) renderer.reset_history();
    CameraDesc camera = shot_camera(script, renderer.scene(), p.frame);
    FrameStats stats = renderer.render_frame(p.frame, script.time_of(p.frame), camera);
    if (p.write) write_frame(script, renderer, p.frame);
    stats_files.add(stats, p.write, script.time_of(p.frame));
    ++rendered;
    written += p.write;
    warmup_left -= !p.write;
    double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (!options.quiet) show_progress(written, to_write, elapsed, rendered, warmup_left);
    if (options.stop_after > 0 && written >= options.stop_after) {
      if (!options.quiet) std::fprintf(stderr, "\nstopped after %d written frames (--stop-after)\n", written);
      return 0;
    }
  }
  if (!options.quiet) std::fprintf(stderr, "\nwrote %d frames\n", written);
  return 0;
}

}  // namespace candela

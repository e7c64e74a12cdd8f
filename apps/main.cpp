// `candela`: one binary, subcommands `render`, `view`, `converge`, `compare` and `bench`. Bad command lines and bad
// input files print one `error:` line naming the option or file and exit with kBadInputExit (2).
#include <CLI/CLI.hpp>
#include <tbb/global_control.h>

#include <cstdio>
#include <filesystem>
#include <map>
#include <optional>
#include <set>

#include "apps/aovs.h"
#include "apps/bench.h"
#include "apps/converge.h"
#include "apps/renderer.h"
#include "apps/scene_source.h"
#include "apps/sequence.h"
#include "apps/shot_script.h"
#include "apps/settings_names.h"
#include "apps/settings_options.h"
#include "apps/stats_json.h"
#include "apps/viewer/viewer.h"
#include "engine/check.h"
#include "engine/image_metrics.h"

using namespace candela;

namespace {

struct RenderOptions {
  std::string scene;
  std::string out;
  std::string stats;
  std::string script;        // --script: a shot script instead of scene and options
  std::string frames = "1";  // a count, or with --script a range FIRST:LAST
  std::optional<int> warmup;
  int stop_after = 0;
  float fps = 30.0f;
  float exposure = 1.0f;
  int threads = 0;
  int lights = 1024;
  float environment = -1.0f;  // < 0: the default rule (apply_default_environment)
  bool quiet = false;
  std::string aov = "radiance";   // render: what --out holds (apps/aovs.h)
  std::string show = "radiance";  // view: what is displayed first
  RenderSettings settings;
};

void check_output_path(const std::string& path, const std::vector<std::string>& extensions, const char* option) {
  std::filesystem::path p(path);
  std::string ext = p.extension().string();
  for (char& c : ext) c = char(std::tolower(c));
  if (std::find(extensions.begin(), extensions.end(), ext) == extensions.end()) {
    std::string list;
    for (const std::string& e : extensions) list += (list.empty() ? "" : " or ") + e;
    throw InputError(std::string(option) + " " + path + ": must end in " + list);
  }
  std::filesystem::path dir = p.parent_path();
  std::error_code ec;
  if (!dir.empty() && !std::filesystem::is_directory(dir, ec))
    throw InputError(std::string(option) + " " + path + ": directory " + dir.string() + " does not exist");
}

// Checks what one option alone cannot: the image size.
void check_settings(const RenderOptions& o) {
  if (int64_t(o.settings.width) * o.settings.height > (int64_t(1) << 26))
    throw InputError("--width x --height: at most 67108864 pixels (8192 x 8192)");
}

// Loads the scene argument with the options that shape it (light count, environment).
Scene load_frame_scene(const RenderOptions& o) {
  BuiltinOptions builtin;
  builtin.light_count = o.lights;
  return load_scene(o.scene, builtin, o.environment);
}

// Renders `frames` frames (scene time advances by 1/fps per frame), prints progress and per-frame
// timings, writes the last frame's image and optionally the stats of every frame.
int run_render(RenderOptions& o) {
  if (o.scene.empty()) throw InputError("render: give a SCENE (or --script SHOT.json)");
  if (o.out.empty()) throw InputError("--out is required");
  int frames = 0;
  try {
    size_t used = 0;
    frames = std::stoi(o.frames, &used);
    if (used != o.frames.size() || frames < 1) throw std::invalid_argument(o.frames);
  } catch (const std::logic_error&) {
    throw InputError("--frames " + o.frames + ": expected a positive number of frames (FIRST:LAST needs --script)");
  }
  check_output_path(o.out, {".exr", ".png"}, "--out");
  const bool restir = o.settings.method == Method::RestirDi || o.settings.method == Method::Restir;
  const AovInfo& aov = *find_aov(o.aov);  // the option checked the name
  if (aov.restir && !restir) throw InputError("--aov " + o.aov + ": needs --method restir-di or restir");
  if (!o.stats.empty()) check_output_path(o.stats, {".json"}, "--stats");
  check_settings(o);
  auto t0 = std::chrono::steady_clock::now();
  Scene scene = load_frame_scene(o);
  size_t triangles = scene.triangle_count();
  Renderer renderer(std::move(scene), o.settings);
  double setup_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  if (!o.quiet)
    std::fprintf(stderr, "%s: %zu triangles, %zu lights (%zu emissive triangles), setup %.0f ms\n", o.scene.c_str(),
                 triangles, renderer.lights().size(), renderer.lights().triangle_count(), setup_ms);
  std::vector<FrameStats> all;
  CameraDesc camera = renderer.scene().default_camera();
  for (int f = 0; f < frames; ++f) {
    auto progress = [&](int done, int total) {
      if (o.quiet || (total > 0 && total <= 4)) return;
      if (total > 0)
        std::fprintf(stderr, "\r  frame %d/%d: %d/%d spp", f + 1, frames, done, total);
      else
        std::fprintf(stderr, "\r  frame %d/%d: %d spp", f + 1, frames, done);
    };
    FrameStats stats = renderer.render_frame(f, float(f) / o.fps, camera, progress);
    if (!o.quiet) {
      std::fprintf(stderr, "\rframe %d/%d: %d spp, %.1f ms, %.2f Mrays/s |", f + 1, frames, stats.spp, stats.total_ms,
                   stats.rays() / (stats.total_ms * 1e3));
      for (const StageStats& s : stats.stages) std::fprintf(stderr, " %s %.1f ms", s.name.c_str(), s.ms);
      std::fprintf(stderr, "\n");
    }
    all.push_back(std::move(stats));
  }
  write_aov(o.out, renderer, aov.aov, o.exposure);
  if (!o.stats.empty()) write_json_file(o.stats, stats_to_json(all));
  if (!o.quiet) std::fprintf(stderr, "wrote %s (%d spp accumulated)\n", o.out.c_str(), renderer.accumulated_spp());
  return 0;
}

// The interactive viewer (or its headless run): the same scene and settings as `render`, shown live.
int run_view(RenderOptions& o, ViewerOptions& v) {
  if (o.scene.empty()) throw InputError("view: give a SCENE (builtin:NAME or a .gltf/.glb file)");
  if (!v.screenshot.empty()) check_output_path(v.screenshot, {".png"}, "--screenshot");
  if (v.headless && v.frames == 0) throw InputError("--headless needs --frames N");
  const bool restir = o.settings.method == Method::RestirDi || o.settings.method == Method::Restir;
  v.view = find_aov(o.show)->aov;  // the option checked the name
  if (aov_info(v.view).restir && !restir) throw InputError("--show " + o.show + ": needs --method restir-di or restir");
  check_settings(o);
  v.width = o.settings.width;
  v.height = o.settings.height;
  v.fps = o.fps;
  v.exposure = o.exposure;
  v.quiet = o.quiet;
  return run_viewer(load_frame_scene(o), o.settings, v);
}

// The options that shape a loaded scene (render, view, converge): the built-in manylights' light count and
// the environment (apply_default_environment's rule unless given).
void add_scene_options(CLI::App& cmd, int& lights, float& environment) {
  cmd.add_option("--lights", lights, "builtin:manylights: number of ceiling lights")
      ->check(CLI::Range(1, 4000000))
      ->capture_default_str();
  char fallback[32];
  std::snprintf(fallback, sizeof(fallback), "%g", double(kFallbackEnvironment));
  cmd.add_option("--environment", environment,
                 std::string("Uniform background radiance (grey); default: a built-in scene's own; for a glTF file "
                             "none if it has lights, else ") +
                     fallback + " with a warning")
      ->check(CLI::Range(0.0f, 1e6f));
}

// Options `render` and `view` share: the scene, every render setting (apps/settings_schema.h) and the
// options that shape the scene and its output.
void add_frame_options(CLI::App* cmd, RenderOptions& r) {
  cmd->add_option("scene", r.scene,
                  "builtin:cornell|manylights|city, or a .gltf/.glb file (render: not with --script)");
  add_setting_options(*cmd, r.settings, kCommandLine);
  cmd->add_option("--fps", r.fps, "Scene time step between frames is 1/fps seconds (animated scenes)")
      ->check(CLI::Range(0.001f, 10000.0f))
      ->capture_default_str();
  cmd->add_option("--exposure", r.exposure, "Exposure multiplier applied before tonemapping (PNG only)")
      ->check(CLI::Range(1e-6f, 1e6f))
      ->capture_default_str();
  cmd->add_option("--threads", r.threads, "Worker threads; 0 = all cores")
      ->check(CLI::Range(0, 1024))
      ->capture_default_str();
  add_scene_options(*cmd, r.lights, r.environment);
  cmd->add_flag("--quiet,-q", r.quiet, "No progress output");
}

// `render --script`: the script holds scene and settings; only the run's own options may be given.
int run_script(const CLI::App& render, const RenderOptions& o) {
  for (const CLI::Option* opt : render.get_options()) {
    static const std::set<std::string> allowed = {"--script",  "--frames", "--warmup", "--stop-after",
                                                  "--threads", "--quiet",  "--help"};
    if (opt->count() > 0 && !allowed.count(opt->get_name()) && !opt->get_name().empty())
      throw InputError(opt->get_name() + ": not allowed with --script (set it in " + o.script + ")");
  }
  ShotScript script = read_shot_script(o.script);
  SequenceOptions options;
  if (render.get_option("--frames")->count() > 0) options.range = parse_frame_range(o.frames, script);
  options.warmup = o.warmup;
  options.stop_after = o.stop_after;
  options.quiet = o.quiet;
  return run_sequence(script, options);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Candela: a CPU many-light renderer"};
  app.require_subcommand(1);

  RenderOptions r;
  CLI::App* render = app.add_subcommand("render", "Render a scene to an image file");
  add_frame_options(render, r);
  render->add_option("--out,-o", r.out,
                     "Output image: .exr (linear radiance) or .png (tonemapped sRGB) (not with --script)");
  render
      ->add_option("--frames", r.frames,
                   "Frames to render; a still scene and camera accumulate across frames. With --script: the frames "
                   "FIRST:LAST (inclusive) of the script to render (a shard)")
      ->capture_default_str();
  render->add_option("--script", r.script,
                     "Render the frame sequence a shot script describes (JSON; see docs/sequences.md)");
  render
      ->add_option("--warmup", r.warmup,
                   "--script: frames rendered but not written before the first frame to render, so temporal history is "
                   "warm (default: the script's \"warmup\"; unused with history_reset_every)")
      ->check(CLI::Range(0, 100000));
  render->add_option("--stop-after", r.stop_after, "--script: stop after writing this many frames")
      ->check(CLI::Range(0, 1 << 30));
  render
      ->add_option("--aov", r.aov,
                   "What --out holds: radiance or a debug image of the G-buffer (albedo, normal, depth, motion) or of "
                   "ReSTIR DI's reservoirs (reservoir-m, reservoir-w, reservoir-light; restir-di and restir); EXR "
                   "holds its values, PNG shows it as the viewer does (docs/settings.md, \"Debug images\")")
      ->check(CLI::IsMember(aov_names()))
      ->capture_default_str();
  render->add_option("--stats", r.stats, "Write per-frame stage timings and ray counts as JSON");
  bool help_markdown = false;
  render->add_flag("--help-markdown", help_markdown,
                   "Print every render setting as Markdown tables (docs/settings.md's generated part) and exit");

  RenderOptions view_frame;
  ViewerOptions viewer;
  CLI::App* view = app.add_subcommand(
      "view", "Interactive viewer with per-frame timing (or --headless: off-screen frames to a PNG)");
  add_frame_options(view, view_frame);
  view->add_option("--scale", viewer.scale, "Render resolution = window resolution x scale")
      ->check(CLI::Range(0.01f, 1.0f))
      ->capture_default_str();
  view->add_option("--target-fps", viewer.target_fps,
                   "Dynamic resolution: adapt the render scale (up to --scale) frame by frame to hold this frame rate "
                   "(0 = off)")
      ->check(CLI::Range(0.0f, 1000.0f))
      ->capture_default_str();
  view->add_flag("--headless", viewer.headless, "No window: draw frames and HUD off screen (OSMesa); needs --frames");
  view->add_option("--frames", viewer.frames, "Stop after this many frames (0 = when the window is closed)")
      ->check(CLI::Range(0, 1 << 24))
      ->capture_default_str();
  view->add_option("--screenshot", viewer.screenshot,
                   "After the last frame, write the window's content (frame + HUD) as PNG");
  view->add_option("--camera-orbit", viewer.orbit_degrees_per_frame,
                   "The camera orbits its target by this many degrees per frame")
      ->check(CLI::Range(-360.0f, 360.0f));
  view->add_option("--show", view_frame.show, "What is displayed first: radiance or a debug image (the names of --aov)")
      ->check(CLI::IsMember(aov_names()))
      ->capture_default_str();
  view->add_flag(
      "--no-hud", [&viewer](int64_t) { viewer.hud = false; },
      "Show the frame alone, without the HUD (screenshots then equal `render` over the whole frame)");
  // Hidden from --help: a test hook (cli.view_window_minimised), documented in docs/viewer.md.
  view->add_option("--test-minimise", viewer.test_minimise_frame,
                   "Test hook: minimise the window for 3 frames from this frame on")
      ->check(CLI::Range(0, 1 << 24))
      ->group("");

  std::string compare_image, compare_reference;
  CLI::App* compare = app.add_subcommand("compare", "Error of an image against a reference (EXR): MSE and relMSE");
  compare->add_option("image", compare_image, "Image to measure (.exr)")->required()->check(CLI::ExistingFile);
  compare->add_option("reference", compare_reference, "Reference image (.exr), e.g. a converged render")
      ->required()
      ->check(CLI::ExistingFile);

  ConvergeOptions c;
  c.base.width = 160;
  c.base.height = 90;
  c.base.light_sampler = LightSamplerKind::Tree;
  c.base.jitter = false;
  c.methods = {"direct-uniform",
               "direct-power",
               "direct-tree",
               "direct-tree-sobol",
               "restir-di-none",
               "restir-di-basic",
               "restir-di-pairwise",
               "restir-di-pairwise+svgf",
               "pt",
               "pt-sobol",
               "restir"};
  CLI::App* converge =
      app.add_subcommand("converge", "Error against samples and time of each method: CSV and a log-log plot");
  converge->add_option("scene", c.scene, "builtin:cornell|manylights|city, or a .gltf/.glb file")->required();
  converge
      ->add_option(
          "--csv", c.csv,
          "Output CSV: method, samples, time_ms, mse, rel_mse, mean_difference, standard_error, time_to_target_ms")
      ->required();
  converge->add_option("--plot", c.plot,
                       "Output PNG: relMSE against time, log-log, one line per method (needs gnuplot)");
  converge
      ->add_option("--methods", c.methods,
                   "Methods to run (direct-uniform, direct-power, direct-tree, their -sobol "
                   "twins, restir-di-none, restir-di-basic, restir-di-pairwise, pt, pt-sobol, "
                   "restir; any followed by +bilateral or +svgf: denoised)")
      ->delimiter(',')
      ->capture_default_str();
  converge
      ->add_option("--reference", c.reference,
                   "Converged full-transport EXR for pt and restir (any renderer's, same size; default: rendered)")
      ->check(CLI::ExistingFile);
  converge
      ->add_option("--reference-direct", c.reference_direct,
                   "Converged direct-light EXR for direct-* and restir-di-* (default: rendered with --method direct)")
      ->check(CLI::ExistingFile);
  converge->add_option("--reference-spp", c.reference_spp, "Samples per pixel of rendered references")
      ->check(CLI::Range(1, 1 << 20))
      ->capture_default_str();
  converge->add_option("--max-spp", c.max_spp, "Largest sample count; counts are 1, 2, 4, ... up to it")
      ->check(CLI::Range(1, 1 << 20))
      ->capture_default_str();
  converge
      ->add_option("--target-rel-mse", c.target_rel_mse,
                   "The time-to-error summary: each method's wall time to this relMSE (log-log interpolated)")
      ->check(CLI::Range(1e-12, 1e12))
      ->capture_default_str();
  converge
      ->add_option("--max-seconds", c.max_seconds,
                   "Stop a method after the count at which it passed this time (0 = off)")
      ->check(CLI::Range(0.0, 1e9))
      ->capture_default_str();
  add_scene_options(*converge, c.lights, c.environment);
  converge->add_option("--threads", r.threads, "Worker threads; 0 = all cores")->check(CLI::Range(0, 1024));
  add_setting_options(*converge, c.base, kConverge);
  converge->footer(
      "Every render setting not chosen by --methods applies to every method (docs/settings.md). "
      "Rendered references use --seed + 7919, independent random numbers and, for direct and pt "
      "methods, another light sampler than the method's own (power for tree, else tree).");
  converge->add_flag("--quiet,-q", c.quiet, "No progress output");

  BenchOptions b;
  CLI::App* bench = app.add_subcommand("bench", "Ray throughput benchmarks (Google Benchmark)");
  add_bench_options(*bench, b);

  // --help prints the usage and exits 0; any other parse error is bad input: one `error:` line naming
  // the option (CLI11's message), exit kBadInputExit.
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help
    std::fprintf(stderr, "error: %s (see candela --help)\n", e.what());
    return kBadInputExit;
  }
  int threads = render->parsed() || converge->parsed() ? r.threads : view->parsed() ? view_frame.threads : b.threads;
  std::unique_ptr<tbb::global_control> limit;
  if (threads > 0) limit = std::make_unique<tbb::global_control>(tbb::global_control::max_allowed_parallelism, threads);
  try {
    if (help_markdown) {
      std::printf("%s\n### Debug images\n\n%s", settings_markdown().c_str(), aovs_markdown().c_str());
      return 0;
    }
    if (render->parsed()) return r.script.empty() ? run_render(r) : run_script(*render, r);
    if (view->parsed()) return run_view(view_frame, viewer);
    if (converge->parsed()) return run_converge(c);
    if (compare->parsed()) {
      ImageError e = compare_images(read_image(compare_image), read_image(compare_reference));
      std::printf("mse %.6e rel_mse %.6e mean_difference %+.6e standard_error %.6e\n", e.mse, e.rel_mse,
                  e.mean_difference, e.standard_error);
      return 0;
    }
    return run_bench(b);
  } catch (const InputError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return kBadInputExit;
  } catch (const std::bad_alloc&) {
    std::fprintf(stderr, "error: out of memory (try a smaller --width/--height or scene)\n");
    return 1;
  } catch (const std::exception& e) {  // e.g. std::filesystem errors on odd output paths
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
}

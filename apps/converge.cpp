#include "apps/converge.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <utility>

#include "apps/plot.h"
#include "apps/scene_source.h"
#include "apps/settings_names.h"
#include "engine/atomic_files.h"
#include "engine/check.h"

namespace candela {

const std::vector<ConvergeMethod>& converge_methods() {
  static const std::vector<ConvergeMethod> methods = [] {
    std::vector<ConvergeMethod> m;
    for (SampleSequence sequence : {SampleSequence::Independent, SampleSequence::Sobol}) {
      const std::string suffix = sequence == SampleSequence::Sobol ? "-sobol" : "";
      for (const char* sampler : {"uniform", "power", "tree"})
        m.push_back({std::string("direct-") + sampler + suffix, Transport::Direct,
                     [kind = light_sampler_names().at(sampler), sequence](RenderSettings& s) {
                       s.method = Method::Direct;
                       s.light_sampler = kind;
                       s.sampler = sequence;
                     }});
    }
    for (const char* bias : {"none", "basic", "pairwise"})
      m.push_back(
          {std::string("restir-di-") + bias, Transport::Direct, [mode = bias_names().at(bias)](RenderSettings& s) {
             s.method = Method::RestirDi;
             s.di_reuse.temporal = s.di_reuse.spatial = true;
             s.di_reuse.bias = mode;
           }});
    m.push_back({"pt", Transport::Full, [](RenderSettings& s) {
                   s.method = Method::PathTrace;
                   s.sampler = SampleSequence::Independent;
                 }});
    m.push_back({"pt-sobol", Transport::Full, [](RenderSettings& s) {
                   s.method = Method::PathTrace;
                   s.sampler = SampleSequence::Sobol;
                 }});
    m.push_back({"restir", Transport::Full, [](RenderSettings& s) {
                   s.method = Method::Restir;
                   s.di_reuse.temporal = s.di_reuse.spatial = s.gi_reuse.temporal = s.gi_reuse.spatial = true;
                   s.di_reuse.bias = s.gi_reuse.bias = BiasCorrection::Pairwise;
                 }});
    return m;
  }();
  return methods;
}

ConvergeMethod converge_method_named(const std::string& name) {
  // "METHOD+DENOISER": the method's frames, finished by the denoiser (what a viewer shows).
  const size_t plus = name.find('+');
  const std::string base = name.substr(0, plus);
  std::string names;
  for (const ConvergeMethod& m : converge_methods()) {
    names += (names.empty() ? "" : ", ") + m.name;
    if (m.name != base) continue;
    if (plus == std::string::npos) return m;
    const std::string denoiser = name.substr(plus + 1);
    auto kind = denoiser_names().find(denoiser);
    if (kind == denoiser_names().end() || kind->second == DenoiserKind::None)
      throw InputError("--methods: unknown denoiser '" + denoiser + "' in '" + name + "' (known: bilateral, svgf)");
    return {name, m.transport, [configure = m.configure, kind = kind->second](RenderSettings& s) {
              configure(s);
              s.denoise.kind = kind;
            }};
  }
  throw InputError("--methods: unknown method '" + base + "' (known: " + names +
                   ", each optionally followed by "
                   "+bilateral or +svgf)");
}

double time_to_error(const std::vector<ConvergePoint>& points, double target) {
  for (size_t i = 0; i < points.size(); ++i) {
    const ConvergePoint& p = points[i];
    if (p.error.rel_mse > target) continue;
    if (i == 0) return p.time_ms;
    const ConvergePoint& q = points[i - 1];
    // log relMSE is linear in log time between the two points around the target.
    const double t = std::log(target / q.error.rel_mse) / std::log(p.error.rel_mse / q.error.rel_mse);
    return std::exp(std::log(q.time_ms) + t * (std::log(p.time_ms) - std::log(q.time_ms)));
  }
  return -1.0;
}

std::vector<ConvergePoint> run_convergence(const Scene& scene, const ConvergeMethod& method, const RenderSettings& base,
                                           const std::vector<int>& counts, const Image& reference, double max_seconds,
                                           Image* last_image) {
  RenderSettings settings = base;
  settings.spp = 1;
  settings.accumulate = true;
  settings.time_budget_ms = 0.0;
  method.configure(settings);
  Renderer renderer(scene, settings);
  const CameraDesc camera = scene.default_camera();
  std::vector<ConvergePoint> points;
  double time_ms = 0.0;
  int frames = 0;
  for (int count : counts) {
    while (frames < count) time_ms += renderer.render_frame(frames++, 0.0f, camera).total_ms;
    points.push_back({method.name, count, time_ms, compare_images(renderer.image(), reference)});
    if (max_seconds > 0.0 && time_ms > 1e3 * max_seconds) break;
  }
  if (last_image) *last_image = renderer.image();
  return points;
}

LightSamplerKind reference_light_sampler(const ConvergeMethod& method, const RenderSettings& base) {
  RenderSettings settings = base;
  method.configure(settings);
  const LightSamplerKind kind = light_sampler_for(settings);
  if (settings.method != Method::Direct && settings.method != Method::PathTrace) return kind;
  const bool tree_like = kind == LightSamplerKind::Tree || kind == LightSamplerKind::Exhaustive;
  return tree_like ? LightSamplerKind::Power : LightSamplerKind::Tree;
}

Image render_reference(const Scene& scene, Transport transport, const RenderSettings& base, LightSamplerKind sampler,
                       int spp, uint64_t seed) {
  RenderSettings settings = base;
  settings.method = transport == Transport::Direct ? Method::Direct : Method::PathTrace;
  settings.light_sampler = sampler;
  settings.spp = spp;
  settings.seed = seed;
  settings.sampler = SampleSequence::Independent;  // another estimator than a Sobol method's own
  settings.time_budget_ms = 0.0;
  Renderer renderer(scene, settings);
  renderer.render_frame(0, 0.0f, scene.default_camera());
  return renderer.image();
}

double mse_slope(const std::vector<ConvergePoint>& points, int lo, int hi) {
  double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (const ConvergePoint& p : points) {
    if (p.samples < lo || p.samples > hi) continue;
    double x = std::log(double(p.samples)), y = std::log(p.error.mse);
    n += 1;
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
  }
  CHECK(n >= 2);
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

namespace {

// Stage "references": the given EXR (checked for size) or a rendered one, per transport and reference
// light sampler the methods need (reference_light_sampler). Cost: reference_spp samples per pixel (Full:
// whole paths) unless given.
Image reference_for(const ConvergeOptions& o, const Scene& scene, Transport transport, LightSamplerKind sampler) {
  const std::string& given = transport == Transport::Direct ? o.reference_direct : o.reference;
  if (!given.empty()) {
    Image image = read_image(given);
    if (image.width != o.base.width || image.height != o.base.height)
      throw InputError(given + ": reference is " + std::to_string(image.width) + "x" + std::to_string(image.height) +
                       ", the study renders " + std::to_string(o.base.width) + "x" + std::to_string(o.base.height));
    return image;
  }
  auto start = std::chrono::steady_clock::now();
  Image image = render_reference(scene, transport, o.base, sampler, o.reference_spp, o.base.seed + 7919);
  if (!o.quiet)
    std::fprintf(stderr, "reference (%s, %s light sampler, %d spp): %.1f s\n",
                 transport == Transport::Direct ? "direct" : "path traced",
                 name_of(light_sampler_names(), sampler).c_str(), o.reference_spp,
                 std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  return image;
}

// Each method's time to the target relMSE (time_to_error), by method name.
std::map<std::string, double> times_to_target(const std::vector<ConvergePoint>& points, double target) {
  std::map<std::string, std::vector<ConvergePoint>> by_method;
  for (const ConvergePoint& p : points) by_method[p.method].push_back(p);
  std::map<std::string, double> out;
  for (const auto& [method, run] : by_method) out[method] = time_to_error(run, target);
  return out;
}

// The time-to-error table on stderr: per method the time to the target and how many times longer that is
// than the fastest method's.
void print_time_to_target(const std::vector<ConvergePoint>& points, const std::map<std::string, double>& times,
                          double target) {
  double fastest = -1.0;
  for (const auto& [method, t] : times)
    if (t >= 0.0 && (fastest < 0.0 || t < fastest)) fastest = t;
  std::fprintf(stderr, "time to relMSE %.3g:\n", target);
  std::string last;
  for (const ConvergePoint& p : points) {
    if (p.method == last) continue;
    last = p.method;
    const double t = times.at(p.method);
    if (t < 0.0)
      std::fprintf(stderr, "  %-26s not reached\n", p.method.c_str());
    else
      std::fprintf(stderr, "  %-26s %10.1f ms  %6.2fx the fastest\n", p.method.c_str(), t, t / fastest);
  }
}

void write_csv(const std::string& path, const std::vector<ConvergePoint>& points,
               const std::map<std::string, double>& times) {
  write_text_atomically(path, [&](std::ostream& f) {
    f.precision(8);
    f << "method,samples,time_ms,mse,rel_mse,mean_difference,standard_error,time_to_target_ms\n";
    for (const ConvergePoint& p : points) {
      f << p.method << ',' << p.samples << ',' << p.time_ms << ',' << p.error.mse << ',' << p.error.rel_mse << ','
        << p.error.mean_difference << ',' << p.error.standard_error << ',';
      if (times.at(p.method) >= 0.0) f << times.at(p.method);
      f << '\n';
    }
  });
}

// relMSE against seconds, one line per method.
LogLogPlot error_plot(const ConvergeOptions& o, const std::vector<ConvergePoint>& points) {
  LogLogPlot plot;
  plot.title =
      o.scene + ", " + std::to_string(o.base.width) + "x" + std::to_string(o.base.height) + ", error against time";
  plot.x_label = "render time (s)";
  plot.y_label = "relMSE";
  for (const ConvergePoint& p : points) {
    if (plot.series.empty() || plot.series.back().title != p.method) plot.series.push_back({p.method, {}, {}});
    if (p.error.rel_mse > 0.0) {
      plot.series.back().x.push_back(p.time_ms * 1e-3);
      plot.series.back().y.push_back(p.error.rel_mse);
    }
  }
  return plot;
}

}  // namespace

int run_converge(const ConvergeOptions& o) {
  // Everything that can fail on input fails before the first render.
  std::vector<ConvergeMethod> methods;
  for (const std::string& name : o.methods) methods.push_back(converge_method_named(name));
  if (!o.plot.empty() && find_gnuplot().empty())
    throw InputError("--plot " + o.plot + ": gnuplot is not on PATH (Debian: apt-get install gnuplot-nox)");
  for (const std::string& path : {o.csv, o.plot}) {
    std::filesystem::path dir = std::filesystem::path(path).parent_path();
    std::error_code ec;
    if (!path.empty() && !dir.empty() && !std::filesystem::is_directory(dir, ec))
      throw InputError(path + ": directory " + dir.string() + " does not exist");
  }
  BuiltinOptions builtin;
  builtin.light_count = o.lights;
  Scene scene = load_scene(o.scene, builtin, o.environment);

  std::vector<int> counts;
  for (int n = 1; n <= o.max_spp; n *= 2) counts.push_back(n);
  std::vector<ConvergePoint> points;
  // References rendered once per (transport, light sampler); a given EXR serves every method of its transport.
  std::map<std::pair<Transport, LightSamplerKind>, Image> references;
  for (Transport transport : {Transport::Direct, Transport::Full}) {
    for (const ConvergeMethod& m : methods) {
      if (m.transport != transport) continue;
      const std::string& given = transport == Transport::Direct ? o.reference_direct : o.reference;
      const LightSamplerKind sampler = given.empty() ? reference_light_sampler(m, o.base) : LightSamplerKind::Power;
      auto key = std::make_pair(transport, sampler);
      if (!references.count(key)) references.emplace(key, reference_for(o, scene, transport, sampler));
      const Image& reference = references.at(key);
      std::vector<ConvergePoint> run = run_convergence(scene, m, o.base, counts, reference, o.max_seconds);
      if (!o.quiet)
        for (const ConvergePoint& p : run)
          std::fprintf(stderr, "%-20s %5d spp %9.1f ms  MSE %.3e  relMSE %.3e  bias %+.2e +- %.2e\n", p.method.c_str(),
                       p.samples, p.time_ms, p.error.mse, p.error.rel_mse, p.error.mean_difference,
                       p.error.standard_error);
      points.insert(points.end(), run.begin(), run.end());
    }
  }
  const std::map<std::string, double> times = times_to_target(points, o.target_rel_mse);
  if (!o.quiet) print_time_to_target(points, times, o.target_rel_mse);
  write_csv(o.csv, points, times);
  if (!o.plot.empty()) draw_log_log_plot(error_plot(o, points), o.plot);
  if (!o.quiet) std::fprintf(stderr, "wrote %s%s%s\n", o.csv.c_str(), o.plot.empty() ? "" : " and ", o.plot.c_str());
  return 0;
}

}  // namespace candela

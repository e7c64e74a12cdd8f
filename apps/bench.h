#pragma once
// `candela bench`: ray throughput of the G-buffer pass and of shadow rays, next to raw Embree packet
// throughput on the same scene and rays, measured with Google Benchmark.
#include <CLI/CLI.hpp>
#include <string>
#include <vector>

namespace candela {

struct BenchOptions {
  std::vector<std::string> scenes;  // empty: the built-in scenes plus StainedGlassLamp when ../shared exists
  int width = 1280, height = 720;
  int threads = 0;
  double min_time = 0.5;
  int repetitions = 3;
  std::string filter = ".";
};

void add_bench_options(CLI::App& app, BenchOptions& options);
int run_bench(const BenchOptions& options);

}  // namespace candela

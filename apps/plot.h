#pragma once
// Log-log line plots drawn by gnuplot (Debian package gnuplot-nox), run as a subprocess on a generated
// script: one line per series, labelled axes, a legend, written as PNG.
#include <string>
#include <vector>

namespace candela {

struct PlotSeries {
  std::string title;
  std::vector<double> x, y;  // positive values (log axes)
};

struct LogLogPlot {
  std::string title, x_label, y_label;
  std::vector<PlotSeries> series;
};

// Path of the gnuplot executable on PATH, or "" if there is none.
std::string find_gnuplot();

// Throws InputError when gnuplot is missing (naming the package) or fails; `png` appears atomically.
void draw_log_log_plot(const LogLogPlot& plot, const std::string& png);

}  // namespace candela

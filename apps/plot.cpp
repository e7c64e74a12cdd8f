#include "apps/plot.h"

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "engine/atomic_files.h"
#include "engine/check.h"

namespace candela {

std::string find_gnuplot() {
  const char* path = std::getenv("PATH");
  std::stringstream dirs(path ? path : "");
  std::string dir;
  while (std::getline(dirs, dir, ':')) {
    std::filesystem::path candidate = std::filesystem::path(dir.empty() ? "." : dir) / "gnuplot";
    if (access(candidate.c_str(), X_OK) == 0) return candidate.string();
  }
  return "";
}

namespace {

// Quotes text for a gnuplot string literal.
std::string quoted(const std::string& text) {
  std::string out = "\"";
  for (char c : text) {
    if (c == '"' || c == '\\') out += '\\';
    out += c;
  }
  return out + "\"";
}

// The gnuplot script: data inline as named blocks ($s0, $s1, ...), then one plot command.
std::string gnuplot_script(const LogLogPlot& plot, const std::string& png) {
  std::ostringstream s;
  s.precision(9);
  for (size_t k = 0; k < plot.series.size(); ++k) {
    s << "$s" << k << " << EOD\n";
    for (size_t i = 0; i < plot.series[k].x.size(); ++i) s << plot.series[k].x[i] << ' ' << plot.series[k].y[i] << '\n';
    s << "EOD\n";
  }
  s << "set terminal pngcairo size 960,640 font 'sans,11'\n"
    << "set output " << quoted(png) << "\n"
    << "set title " << quoted(plot.title) << "\n"
    << "set xlabel " << quoted(plot.x_label) << "\n"
    << "set ylabel " << quoted(plot.y_label) << "\n"
    << "set logscale xy\nset format xy '10^{%L}'\nset grid xtics ytics mxtics mytics lc rgb '#dddddd'\n"
    << "set key outside right top\n"
    << "plot ";
  for (size_t k = 0; k < plot.series.size(); ++k)
    s << (k ? ", " : "") << "$s" << k << " using 1:2 with linespoints lw 2 pt 7 ps 0.8 title "
      << quoted(plot.series[k].title);
  s << "\n";
  return s.str();
}

}  // namespace

void draw_log_log_plot(const LogLogPlot& plot, const std::string& png) {
  const std::string gnuplot = find_gnuplot();
  if (gnuplot.empty())
    throw InputError(png + ": cannot draw the plot: gnuplot is not on PATH (Debian: apt-get install gnuplot-nox)");
  std::filesystem::path target(png);
  std::filesystem::path tmp = hidden_beside(target, target.stem().string() + ".tmp.png");
  std::filesystem::path script = hidden_beside(target, target.stem().string() + ".gnuplot");
  {
    std::ofstream f(script);
    if (!f) throw InputError(script.string() + ": cannot write the gnuplot script");
    f << gnuplot_script(plot, tmp.string());
  }
  // gnuplot SCRIPT, without a shell; its stderr goes to ours.
  pid_t pid = fork();
  if (pid == 0) {
    execl(gnuplot.c_str(), "gnuplot", script.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  int status = 0;
  bool ok = pid > 0 && waitpid(pid, &status, 0) == pid && WIFEXITED(status) && WEXITSTATUS(status) == 0;
  std::error_code ec;
  std::filesystem::remove(script, ec);
  if (ok) std::filesystem::rename(tmp, target, ec);
  if (!ok || ec) {
    std::filesystem::remove(tmp, ec);
    throw InputError(png + ": gnuplot failed (" + gnuplot + ", exit status " + std::to_string(WEXITSTATUS(status)) +
                     ")");
  }
}

}  // namespace candela

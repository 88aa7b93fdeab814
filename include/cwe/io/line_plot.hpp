#pragma once
// Lines of (x, y) points as a figure (PNG or SVG): `cwe compare`'s differences along the path
// and its convergence figures. Each axis linear or logarithmic (decades); a series per colour,
// named in a legend. The functions return the file's bytes.
//
// Points whose x or y is not finite, or not positive on a logarithmic axis, are left out (a
// series' line breaks there). No point at all: empty axes with the note "no data".

#include <string>
#include <vector>

namespace cwe {

struct PlotSeries {
  std::string label;
  std::vector<double> x, y;  // the same length
  bool markers = false;      // a dot at every point besides the line
};

struct LinePlot {
  std::string title, x_label, y_label;
  bool log_x = false, log_y = false;
  std::vector<PlotSeries> series;
};

inline constexpr int kLinePlotWidth = 1000;
inline constexpr int kLinePlotHeight = 520;

std::string line_plot_png(const LinePlot& plot);
std::string line_plot_svg(const LinePlot& plot);

}  // namespace cwe

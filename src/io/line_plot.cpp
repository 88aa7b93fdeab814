#include "cwe/io/line_plot.hpp"

#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "cwe/geometry/vec.hpp"
#include "plot_common.hpp"

namespace cwe {
namespace {

using namespace io_detail;

constexpr unsigned kColors[] = {0x1f77b4, 0xff7f0e, 0x2ca02c, 0xd62728,
                                0x9467bd, 0x8c564b, 0xe377c2, 0x7f7f7f};
constexpr double kLeft = 100, kTop = 70, kWidth = 840, kHeight = 360;

bool usable(double v, bool log) { return std::isfinite(v) && (!log || v > 0.0); }

// An axis: the data's range made nice, and where a value goes on it (0 to 1).
struct Axis {
  bool log = false;
  double lo = 0.0, hi = 1.0;  // log: decades' exponents
  double step = 1.0;          // linear: tick step
  static Axis of(double lo, double hi, bool log) {
    Axis a;
    a.log = log;
    if (!(lo <= hi)) {  // no data
      lo = log ? 1.0 : 0.0;
      hi = log ? 10.0 : 1.0;
    }
    if (log) {
      a.lo = std::floor(std::log10(lo) + kTickSlack);
      a.hi = std::ceil(std::log10(hi) - kTickSlack);
      if (a.hi <= a.lo) a.hi = a.lo + 1.0;
      return a;
    }
    if (lo > 0.0) lo = 0.0;  // linear axes from zero, or below it
    if (hi == lo) hi = lo + 1.0;
    a.step = nice_step(hi - lo, 6);
    a.lo = std::floor(lo / a.step + kTickSlack) * a.step;
    a.hi = std::ceil(hi / a.step - kTickSlack) * a.step;
    return a;
  }
  double at(double v) const {
    const double t = log ? std::log10(v) : v;
    return (t - lo) / (hi - lo);
  }
  std::vector<double> ticks() const {
    std::vector<double> t;
    if (log) {
      for (double e = lo; e <= hi + kTickSlack; e += 1.0) t.push_back(std::pow(10.0, e));
    } else {
      for (double v = lo; v <= hi + kTickSlack * std::abs(hi); v += step) {
        t.push_back(std::abs(v) < 1e-12 * step ? 0.0 : v);
      }
    }
    return t;
  }
};

void draw(cairo_t* cr, const LinePlot& plot) {
  double x_lo = std::numeric_limits<double>::infinity(), x_hi = -x_lo, y_lo = x_lo, y_hi = -x_lo;
  for (const PlotSeries& s : plot.series) {
    for (std::size_t k = 0; k < std::min(s.x.size(), s.y.size()); ++k) {
      if (!usable(s.x[k], plot.log_x) || !usable(s.y[k], plot.log_y)) continue;
      x_lo = std::min(x_lo, s.x[k]);
      x_hi = std::max(x_hi, s.x[k]);
      y_lo = std::min(y_lo, s.y[k]);
      y_hi = std::max(y_hi, s.y[k]);
    }
  }
  const bool any = x_lo <= x_hi;
  const Axis ax = Axis::of(x_lo, x_hi, plot.log_x), ay = Axis::of(y_lo, y_hi, plot.log_y);
  const auto X = [&](double v) { return kLeft + ax.at(v) * kWidth; };
  const auto Y = [&](double v) { return kTop + kHeight - ay.at(v) * kHeight; };
  const double right = kLeft + kWidth, bottom = kTop + kHeight;

  white_background(cr, kLinePlotWidth, kLinePlotHeight);
  set_color(cr, kBlack);
  text(cr, kLeft, 32, plot.title, Anchor::kStart, 17, true);
  set_color(cr, kGridColor);
  cairo_set_line_width(cr, 1);
  for (const double t : ax.ticks()) line(cr, X(t), kTop, X(t), bottom);
  for (const double t : ay.ticks()) line(cr, kLeft, Y(t), right, Y(t));
  cairo_stroke(cr);
  set_color(cr, kBlack);
  cairo_rectangle(cr, kLeft, kTop, kWidth, kHeight);
  cairo_stroke(cr);
  for (const double t : ax.ticks()) {
    line(cr, X(t), bottom, X(t), bottom + 4);
    text(cr, X(t), bottom + 18, number(t), Anchor::kMiddle);
  }
  for (const double t : ay.ticks()) {
    line(cr, kLeft - 4, Y(t), kLeft, Y(t));
    text(cr, kLeft - 7, Y(t) + 4, number(t), Anchor::kEnd);
  }
  cairo_stroke(cr);
  text(cr, kLeft + 0.5 * kWidth, bottom + 44, plot.x_label, Anchor::kMiddle, 13);
  text(cr, 30, kTop + 0.5 * kHeight, plot.y_label, Anchor::kMiddle, 13, false, -0.5 * kPi);

  // The series, clipped to the plot; a line breaks at a point left out.
  cairo_save(cr);
  cairo_rectangle(cr, kLeft, kTop, kWidth, kHeight);
  cairo_clip(cr);
  cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
  cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
  for (std::size_t s = 0; s < plot.series.size(); ++s) {
    const PlotSeries& series = plot.series[s];
    const std::size_t n = std::min(series.x.size(), series.y.size());
    set_color(cr, kColors[s % std::size(kColors)]);
    cairo_set_line_width(cr, 1.5);
    bool drawing = false;
    for (std::size_t k = 0; k < n; ++k) {
      if (!usable(series.x[k], plot.log_x) || !usable(series.y[k], plot.log_y)) {
        drawing = false;
        continue;
      }
      const double x = X(series.x[k]), y = Y(series.y[k]);
      if (drawing) {
        cairo_line_to(cr, x, y);
      } else {
        cairo_move_to(cr, x, y);
        cairo_line_to(cr, x, y);  // a lone point shows as a dot (round caps)
      }
      drawing = true;
    }
    cairo_stroke(cr);
    if (series.markers) {
      for (std::size_t k = 0; k < n; ++k) {
        if (!usable(series.x[k], plot.log_x) || !usable(series.y[k], plot.log_y)) continue;
        cairo_new_sub_path(cr);
        cairo_arc(cr, X(series.x[k]), Y(series.y[k]), 4, 0, kTwoPi);
      }
      cairo_fill(cr);
    }
  }
  cairo_restore(cr);

  // Legend, right-aligned above the plot.
  double width = 0.0;
  for (const PlotSeries& s : plot.series) width += 22 + text_width(cr, s.label) + 18;
  double x = right - width + 18;
  for (std::size_t s = 0; s < plot.series.size(); ++s) {
    set_color(cr, kColors[s % std::size(kColors)]);
    cairo_set_line_width(cr, 2);
    line(cr, x, kTop - 17, x + 16, kTop - 17);
    cairo_stroke(cr);
    set_color(cr, kBlack);
    text(cr, x + 22, kTop - 13, plot.series[s].label);
    x += 22 + text_width(cr, plot.series[s].label) + 18;
  }
  cairo_set_line_width(cr, 1);
  if (!any) note(cr, kLeft + 0.5 * kWidth, kTop + 0.5 * kHeight, "no data");
}

}  // namespace

std::string line_plot_png(const LinePlot& plot) {
  return render_png(kLinePlotWidth, kLinePlotHeight, [&](cairo_t* cr) { draw(cr, plot); });
}

std::string line_plot_svg(const LinePlot& plot) {
  return with_svg_text(
      render_svg(kLinePlotWidth, kLinePlotHeight, [&](cairo_t* cr) { draw(cr, plot); }), plot.title,
      fmt::format("{} against {}", plot.y_label, plot.x_label));
}

}  // namespace cwe

#include "cwe/io/force_plot.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <iterator>
#include <string>
#include <vector>

#include <cairo.h>
#include <fmt/format.h>

#include "cwe/core/error.hpp"
#include "cwe/geometry/vec.hpp"
#include "plot_common.hpp"

namespace cwe {
namespace {

namespace layout = plot_layout;
// The figures' plumbing and helpers, private to io (plot_common.hpp).
using namespace io_detail;

// Throws InputError for a value that cannot be written or drawn.
void validate(const std::vector<ForceSample>& curve, const char* what) {
  for (std::size_t k = 0; k < curve.size(); ++k) {
    const ForceSample& s = curve[k];
    // Component by component: Eigen's allFinite() subtracts, and ∞ − ∞ raises FE_INVALID.
    if (!std::isfinite(s.angle) || !std::isfinite(s.force.x()) || !std::isfinite(s.force.y()) ||
        !std::isfinite(s.force.z()) || !std::isfinite(s.torque)) {
      throw InputError(
          fmt::format("{}: sample {} has a non-finite angle, force component or torque", what, k));
    }
    // Finite components whose squares overflow: |F| cannot be drawn or written.
    if (!std::isfinite(s.force.norm())) {
      throw InputError(fmt::format("{}: sample {} has a force too large to measure", what, k));
    }
  }
}

// The series of the figure: legend label, colour, line width (px), value of a sample.
struct Series {
  const char* label;
  unsigned color;
  double line_width;
  double (*value)(const ForceSample&);
};
// Drawn in this order, the resultant on top; the torque (last) is drawn first, under them.
const Series kForceSeries[] = {
    {"Fx (N)", layout::kForceXColor, 2.0, [](const ForceSample& s) { return s.force.x(); }},
    {"Fy (N)", layout::kForceYColor, 2.0, [](const ForceSample& s) { return s.force.y(); }},
    {"Fz (N)", layout::kForceZColor, 2.0, [](const ForceSample& s) { return s.force.z(); }},
    {"|F| (N)", layout::kResultantColor, 2.5, [](const ForceSample& s) { return s.force.norm(); }},
};
const Series kTorqueSeries{"torque (N·m)", layout::kTorqueColor, 2.0,
                           [](const ForceSample& s) { return s.torque; }};
constexpr double kTorqueDashes[] = {7.0, 4.0};

// An axis ends at least this fraction of its largest magnitude above it, so that the peak of a
// line stays clear of the frame.
constexpr double kHeadroom = 0.02;

layout::ForceAxes axes_of(const std::vector<ForceSample>& curve) {
  double force_low = 0.0, force_high = 0.0, torque_low = 0.0, torque_high = 0.0;
  for (const ForceSample& s : curve) {
    force_low = std::min(force_low, s.force.minCoeff());
    force_high = std::max(force_high, s.force.norm());  // |F| bounds every component from above
    torque_low = std::min(torque_low, s.torque);
    torque_high = std::max(torque_high, s.torque);
  }
  // One shape for both axes, so that their zeros sit at the same height.
  const bool symmetric = force_low < 0.0 || torque_low < 0.0;
  const auto axis = [&](double low, double high, double& bottom, double& top, double& step) {
    const double extent = symmetric ? std::max(-low, high) : high;
    if (extent > 0.0) {
      step = nice_step(extent, symmetric ? 4 : 5);
      top = round_up(extent * (1.0 + kHeadroom), step);
    } else {  // all zero: a unit axis
      step = nice_step(1.0, 5);
      top = 1.0;
    }
    bottom = symmetric ? -top : 0.0;
  };
  layout::ForceAxes axes;
  axis(force_low, force_high, axes.force_bottom, axes.force_top, axes.force_step);
  axis(torque_low, torque_high, axes.torque_bottom, axes.torque_top, axes.torque_step);
  return axes;
}

struct ForceFigure {
  std::string title;
  layout::ForceAxes axes;
  std::vector<ForceSample> samples;  // angles wrapped into [0, 2π), sorted by them
  bool no_force = true;              // every force component and torque is zero
};

ForceFigure prepare_force(const std::vector<ForceSample>& curve, const ForcePlotInfo& info) {
  if (curve.empty()) throw InputError("force plot: the curve has no samples");
  validate(curve, "force plot");
  ForceFigure figure;
  figure.title = info.title;
  figure.axes = axes_of(curve);
  figure.samples = curve;
  for (ForceSample& s : figure.samples) {
    double angle = std::fmod(s.angle, kTwoPi);  // in (−2π, 2π)
    if (angle < 0.0) angle += kTwoPi;
    if (angle >= kTwoPi) angle -= kTwoPi;  // a tiny negative angle rounded up to 2π
    s.angle = angle;
    if (s.force.squaredNorm() > 0.0 || s.torque != 0.0) figure.no_force = false;
  }
  std::stable_sort(figure.samples.begin(), figure.samples.end(),
                   [](const ForceSample& a, const ForceSample& b) { return a.angle < b.angle; });
  return figure;
}

// Tick values of an axis: integer multiples of `step` from bottom to top (exact zero included).
template <typename Emit>
void for_each_tick(double bottom, double top, double step, const Emit& emit) {
  const long first = std::lround(bottom / step), last = std::lround(top / step);
  for (long i = first; i <= last; ++i) emit(static_cast<double>(i) * step);
}

void draw_force(cairo_t* cr, const ForceFigure& figure) {
  const double left = layout::kForceLeft, top = layout::kForceTop;
  const double width = layout::kForcePlotWidth, height = layout::kForcePlotHeight;
  const double right = left + width, bottom = top + height;
  const layout::ForceAxes& axes = figure.axes;

  const auto X = [&](double angle) { return left + angle / kTwoPi * width; };
  const auto Y = [&](double value, double low, double high) {
    return bottom - (std::clamp(value, low, high) - low) / (high - low) * height;
  };
  const auto Y_force = [&](double n) { return Y(n, axes.force_bottom, axes.force_top); };
  const auto Y_torque = [&](double nm) { return Y(nm, axes.torque_bottom, axes.torque_top); };

  white_background(cr, layout::kForceWidth, layout::kForceHeight);
  set_color(cr, kBlack);
  text(cr, left, 30, figure.title, Anchor::kStart, 17, true);

  // Grid: every 45°, every force tick; a darker zero line on a symmetric axis.
  set_color(cr, kGridColor);
  cairo_set_line_width(cr, 1);
  for (int deg = 45; deg < 360; deg += 45) {
    const double x = X(degrees_to_radians(deg));
    line(cr, x, top, x, bottom);
  }
  for_each_tick(axes.force_bottom, axes.force_top, axes.force_step,
                [&](double n) { line(cr, left, Y_force(n), right, Y_force(n)); });
  cairo_stroke(cr);
  if (axes.force_bottom < 0.0) {
    set_color(cr, kDivideColor);
    line(cr, left, Y_force(0.0), right, Y_force(0.0));
    cairo_stroke(cr);
  }

  // The lines, clipped to the plot: each runs on past 0° and 360° to the sample on the other
  // side of the revolution (the curve is periodic).
  cairo_save(cr);
  cairo_rectangle(cr, left, top, width, height);
  cairo_clip(cr);
  cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
  const auto draw_series = [&](const Series& series, const auto& y_of) {
    const ForceSample& first = figure.samples.front();
    const ForceSample& last = figure.samples.back();
    cairo_move_to(cr, X(last.angle - kTwoPi), y_of(series.value(last)));
    for (const ForceSample& s : figure.samples)
      cairo_line_to(cr, X(s.angle), y_of(series.value(s)));
    cairo_line_to(cr, X(first.angle + kTwoPi), y_of(series.value(first)));
    set_color(cr, series.color);
    cairo_set_line_width(cr, series.line_width);
    cairo_stroke(cr);
  };
  cairo_set_dash(cr, kTorqueDashes, 2, 0);
  draw_series(kTorqueSeries, Y_torque);
  cairo_set_dash(cr, nullptr, 0, 0);
  for (const Series& series : kForceSeries) draw_series(series, Y_force);
  cairo_restore(cr);
  cairo_set_line_width(cr, 1);

  // Frame and tick marks, stroked before any label: text() clears the current path.
  set_color(cr, kBlack);
  cairo_rectangle(cr, left, top, width, height);
  for (int deg = 0; deg <= 360; deg += 45) {
    const double x = X(degrees_to_radians(deg));
    line(cr, x, bottom, x, bottom + 4);
  }
  for_each_tick(axes.force_bottom, axes.force_top, axes.force_step,
                [&](double n) { line(cr, left - 4, Y_force(n), left, Y_force(n)); });
  cairo_stroke(cr);
  set_color(cr, layout::kTorqueColor);
  for_each_tick(axes.torque_bottom, axes.torque_top, axes.torque_step,
                [&](double nm) { line(cr, right, Y_torque(nm), right + 4, Y_torque(nm)); });
  cairo_stroke(cr);

  // Labels.
  set_color(cr, kBlack);
  for (int deg = 0; deg <= 360; deg += 45) {
    text(cr, X(degrees_to_radians(deg)), bottom + 18, std::to_string(deg), Anchor::kMiddle);
  }
  for_each_tick(axes.force_bottom, axes.force_top, axes.force_step,
                [&](double n) { text(cr, left - 7, Y_force(n) + 4, number(n), Anchor::kEnd); });
  set_color(cr, layout::kTorqueColor);
  for_each_tick(axes.torque_bottom, axes.torque_top, axes.torque_step,
                [&](double nm) { text(cr, right + 7, Y_torque(nm) + 4, number(nm)); });
  set_color(cr, kBlack);
  text(cr, left + 0.5 * width, bottom + 42, "spindle angle θ (deg)", Anchor::kMiddle, 13);
  text(cr, 30, top + 0.5 * height, "force on the tool, tool frame (N)", Anchor::kMiddle, 13, false,
       -0.5 * kPi);
  set_color(cr, layout::kTorqueColor);
  text(cr, right + 70, top + 0.5 * height, "torque about the axis (N·m)", Anchor::kMiddle, 13,
       false, 0.5 * kPi);

  // Legend, right-aligned above the plot: a short stretch of each line and its label.
  const Series* legend[] = {&kForceSeries[0], &kForceSeries[1], &kForceSeries[2], &kForceSeries[3],
                            &kTorqueSeries};
  double legend_width = 0.0;
  for (const Series* series : legend) legend_width += 22 + text_width(cr, series->label) + 18;
  double x = right - legend_width + 18;
  const double y = top - 14;
  for (const Series* series : legend) {
    set_color(cr, series->color);
    cairo_set_line_width(cr, 2);
    if (series == &kTorqueSeries) cairo_set_dash(cr, kTorqueDashes, 2, 0);
    line(cr, x, y - 4, x + 16, y - 4);
    cairo_stroke(cr);
    cairo_set_dash(cr, nullptr, 0, 0);
    cairo_set_line_width(cr, 1);
    set_color(cr, kBlack);
    text(cr, x + 22, y, series->label);
    x += 22 + text_width(cr, series->label) + 18;
  }

  if (figure.no_force) note(cr, left + 0.5 * width, top + 0.25 * height, "no cutting force");
}

// The words of the figure, for the SVG's <desc>.
std::string description() {
  std::string legend;
  for (const Series& series : kForceSeries) legend += std::string(series.label) + ", ";
  return fmt::format(
      "Force on the tool in the tool frame (x along the feed, z the tool axis) over one spindle "
      "revolution against the spindle angle θ (deg). Legend: {}and, dashed on the right axis, {}.",
      legend, kTorqueSeries.label);
}

}  // namespace

namespace plot_layout {

ForceAxes force_axes(const std::vector<ForceSample>& curve) {
  return prepare_force(curve, {}).axes;
}

}  // namespace plot_layout

std::string force_curve_png(const std::vector<ForceSample>& curve, const ForcePlotInfo& info) {
  const ForceFigure figure = prepare_force(curve, info);
  return render_png(layout::kForceWidth, layout::kForceHeight,
                    [&](cairo_t* cr) { draw_force(cr, figure); });
}

std::string force_curve_svg(const std::vector<ForceSample>& curve, const ForcePlotInfo& info) {
  const ForceFigure figure = prepare_force(curve, info);
  return with_svg_text(render_svg(layout::kForceWidth, layout::kForceHeight,
                                  [&](cairo_t* cr) { draw_force(cr, figure); }),
                       info.title, description());
}

std::string force_curve_csv(const std::vector<ForceSample>& curve) {
  validate(curve, "force curve CSV");
  std::string out = "angle_deg,fx_n,fy_n,fz_n,resultant_n,torque_nm\n";
  out.reserve(out.size() + curve.size() * 64);
  for (const ForceSample& s : curve) {
    fmt::format_to(std::back_inserter(out), "{:.4f},{:.4f},{:.4f},{:.4f},{:.4f},{:.6f}\n",
                   radians_to_degrees(s.angle), s.force.x(), s.force.y(), s.force.z(),
                   s.force.norm(), s.torque);
  }
  return out;
}

}  // namespace cwe

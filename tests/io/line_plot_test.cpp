// Line plots (line_plot.hpp): a point lands where its axes put it, on linear and logarithmic
// axes, and points an axis cannot show are left out, not drawn at an edge.

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "cwe/io/line_plot.hpp"
#include "plot_testing.hpp"

namespace cwe {
namespace {

// The plot area (line_plot.cpp): x from 100 to 940 px, y from 430 (bottom) up to 70.
constexpr double kLeft = 100, kRight = 940, kTop = 70, kBottom = 430;
constexpr unsigned kFirstColor = 0x1f77b4;

// A pixel of the first series' line (blue, 0x1f77b4), antialiased into the white or grey behind
// it: clearly more blue than red. White, grey and black are neither; the second series is orange.
bool first_series(unsigned rgb) {
  const int red = static_cast<int>(rgb >> 16), blue = static_cast<int>(rgb & 0xff);
  return blue - red > 50;
}

TEST(LinePlot, LogLogLineGoesThroughItsPoints) {
  LinePlot plot;
  plot.title = "y = x";
  plot.x_label = "x";
  plot.y_label = "y";
  plot.log_x = plot.log_y = true;
  // Decades 1 to 100 on both axes: (10, 10) is the middle of the plot. A zero and a NaN cannot
  // be shown on them and are left out.
  plot.series.push_back(
      {"y = x", {0.0, 1.0, 10.0, 100.0, std::nan("")}, {0.0, 1.0, 10.0, 100.0, 5.0}});
  const test::Image image(line_plot_png(plot));
  ASSERT_TRUE(image.ok());
  EXPECT_EQ(image.width(), kLinePlotWidth);
  EXPECT_TRUE(first_series(image.rgb(0.5 * (kLeft + kRight), 0.5 * (kTop + kBottom))));
  EXPECT_TRUE(
      first_series(image.rgb(kLeft + 0.25 * (kRight - kLeft), kBottom - 0.25 * (kBottom - kTop))));
  // Nothing drawn off the line.
  EXPECT_FALSE(
      first_series(image.rgb(kLeft + 0.75 * (kRight - kLeft), kBottom - 0.25 * (kBottom - kTop))));
}

TEST(LinePlot, LinearAxesStartAtZero) {
  LinePlot plot;
  plot.title = "flat";
  // x 0 to 10, y 0 to 3 (ticks of 0.5): y = 1 is a third of the way up.
  plot.series.push_back({"a", {0.0, 10.0}, {1.0, 1.0}});
  plot.series.push_back({"b", {0.0, 10.0}, {3.0, 3.0}});
  const test::Image image(line_plot_png(plot));
  ASSERT_TRUE(image.ok());
  EXPECT_TRUE(first_series(image.rgb(0.5 * (kLeft + kRight), kBottom - (kBottom - kTop) / 3.0)));
  EXPECT_FALSE(first_series(image.rgb(0.5 * (kLeft + kRight), kBottom - (kBottom - kTop) / 2.0)));
}

TEST(LinePlot, NoDataIsEmptyAxes) {
  LinePlot plot;
  plot.title = "nothing";
  plot.log_y = true;
  plot.series.push_back({"zeros", {1.0, 2.0}, {0.0, 0.0}});
  const test::Image image(line_plot_png(plot));
  ASSERT_TRUE(image.ok());
  for (double x = kLeft + 2; x < kRight - 2; x += 3) {
    for (double y = kTop + 2; y < kBottom - 2; y += 3) {
      ASSERT_FALSE(first_series(image.rgb(x, y))) << x << ", " << y;
    }
  }
  const std::string svg = line_plot_svg(plot);
  EXPECT_NE(svg.find("<title>nothing</title>"), std::string::npos);
}

}  // namespace
}  // namespace cwe

// Force curve plots and CSV: PNG and SVG are well formed and of the stated size, the axes end at
// nice values, each line lands where the documented layout puts it (the periodic curve closed
// across 0°/360°), the SVG names its legend, the CSV round-trips its numbers; NaN, infinities
// and an empty curve are input errors.
#include <gtest/gtest.h>

#include <cmath>
#include <cstddef>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "cwe/core/error.hpp"
#include "cwe/geometry/vec.hpp"
#include "cwe/io/force_plot.hpp"
#include "plot_testing.hpp"

namespace cwe {
namespace {

namespace layout = plot_layout;
using test::Image;
using test::is_png;
using test::is_svg;
using test::xml_tags_balanced;

const ForcePlotInfo kInfo{"CL 120 · move 14 (line 37) · fz 0.05 mm"};

// n samples at k·360°/n, all of the same force and torque.
std::vector<ForceSample> constant_curve(const Vec3& force, double torque, int n = 360) {
  std::vector<ForceSample> curve;
  for (int k = 0; k < n; ++k) curve.push_back({degrees_to_radians(k * 360.0 / n), force, torque});
  return curve;
}

// Pixel position of an angle (degrees) and of a value on an axis [bottom, top].
double x_of(double deg) { return layout::kForceLeft + deg / 360.0 * layout::kForcePlotWidth; }
double y_of(double value, double bottom, double top) {
  return layout::kForceTop + (top - value) / (top - bottom) * layout::kForcePlotHeight;
}

// Whether some pixel within `radius` pixels of (x, y) has exactly `color`: lines are
// antialiased, but every line is at least 2 px wide, so some pixel across it is fully covered.
bool color_near(const Image& image, double x, double y, unsigned color, int radius = 2) {
  const auto column = static_cast<int>(std::floor(x)), row = static_cast<int>(std::floor(y));
  return image.count(color, column - radius, row - radius, column + radius + 1, row + radius + 1) >
         0;
}

TEST(ForcePlot, AxesEndAtNiceValuesAboveThePeak) {
  // |F| = √2100 ≈ 45.8 N: steps of 10 N, top 50 N; torque 3 N·m: steps of 1, top 4 (3 + 2% > 3).
  layout::ForceAxes axes = layout::force_axes(constant_curve({10, 20, 40}, 3.0, 8));
  EXPECT_DOUBLE_EQ(axes.force_bottom, 0.0);
  EXPECT_DOUBLE_EQ(axes.force_top, 50.0);
  EXPECT_DOUBLE_EQ(axes.force_step, 10.0);
  EXPECT_DOUBLE_EQ(axes.torque_bottom, 0.0);
  EXPECT_DOUBLE_EQ(axes.torque_top, 4.0);
  EXPECT_DOUBLE_EQ(axes.torque_step, 1.0);

  // A negative component makes both axes symmetric: |F| = 80 N → ±100 N in steps of 20;
  // torque 5 N·m → ±6 N·m in steps of 2.
  axes = layout::force_axes(constant_curve({-80, 0, 0}, 5.0, 8));
  EXPECT_DOUBLE_EQ(axes.force_bottom, -100.0);
  EXPECT_DOUBLE_EQ(axes.force_top, 100.0);
  EXPECT_DOUBLE_EQ(axes.force_step, 20.0);
  EXPECT_DOUBLE_EQ(axes.torque_bottom, -6.0);
  EXPECT_DOUBLE_EQ(axes.torque_top, 6.0);
  EXPECT_DOUBLE_EQ(axes.torque_step, 2.0);

  // So does a negative torque; small forces get small steps.
  axes = layout::force_axes(constant_curve({0.03, 0.04, 0}, -0.002, 8));
  EXPECT_DOUBLE_EQ(axes.force_bottom, -0.06);
  EXPECT_DOUBLE_EQ(axes.force_top, 0.06);
  EXPECT_DOUBLE_EQ(axes.force_step, 0.02);
  EXPECT_DOUBLE_EQ(axes.torque_top, 0.0025);

  // Nothing but zeros: unit axes from 0.
  axes = layout::force_axes(constant_curve({0, 0, 0}, 0.0, 8));
  EXPECT_DOUBLE_EQ(axes.force_bottom, 0.0);
  EXPECT_DOUBLE_EQ(axes.force_top, 1.0);
  EXPECT_DOUBLE_EQ(axes.torque_top, 1.0);
}

TEST(ForcePlot, PngHasStatedSizeAndLinesWhereTheAxesPutThem) {
  const std::vector<ForceSample> curve = constant_curve({10, 20, 40}, 3.0);
  const std::string png = force_curve_png(curve, kInfo);
  ASSERT_TRUE(is_png(png));
  const Image image(png);
  ASSERT_TRUE(image.ok());
  EXPECT_EQ(image.width(), layout::kForceWidth);
  EXPECT_EQ(image.height(), layout::kForceHeight);

  // Axes 0…50 N and 0…4 N·m (see above). The torque line is dashed: look along a dash period.
  const double resultant = std::sqrt(2100.0);
  for (double deg : {20.0, 100.0, 250.0}) {
    const double x = x_of(deg);
    EXPECT_TRUE(color_near(image, x, y_of(10, 0, 50), layout::kForceXColor)) << deg;
    EXPECT_TRUE(color_near(image, x, y_of(20, 0, 50), layout::kForceYColor)) << deg;
    EXPECT_TRUE(color_near(image, x, y_of(40, 0, 50), layout::kForceZColor)) << deg;
    EXPECT_TRUE(color_near(image, x, y_of(resultant, 0, 50), layout::kResultantColor)) << deg;
    EXPECT_TRUE(image.count(layout::kTorqueColor, static_cast<int>(x) - 6,
                            static_cast<int>(y_of(3, 0, 4)) - 2, static_cast<int>(x) + 7,
                            static_cast<int>(y_of(3, 0, 4)) + 3) > 0)
        << deg;
    // Nothing of the force colours where no line runs.
    EXPECT_FALSE(color_near(image, x, y_of(30, 0, 50), layout::kForceXColor)) << deg;
    EXPECT_FALSE(color_near(image, x, y_of(30, 0, 50), layout::kResultantColor)) << deg;
  }
}

TEST(ForcePlot, CurveIsClosedAcrossTheRevolutionWhateverTheSampleOrder) {
  // Four samples, given out of order and one of them at −90° (= 270°): Fx = −80 N at 0°, 0
  // elsewhere. Axes ±100 N. Lines join the samples in angle order and run from 270° on to 0° at
  // 360°, so at 315° (and at 45°) Fx = −40 N and |F| = 40 N.
  const Vec3 zero(0, 0, 0);
  const std::vector<ForceSample> curve{{degrees_to_radians(90), zero, 0.0},
                                       {degrees_to_radians(-90), zero, 0.0},
                                       {degrees_to_radians(180), zero, 0.0},
                                       {0.0, Vec3(-80, 0, 0), 0.0}};
  const layout::ForceAxes axes = layout::force_axes(curve);
  ASSERT_DOUBLE_EQ(axes.force_top, 100.0);
  ASSERT_DOUBLE_EQ(axes.force_bottom, -100.0);
  const Image image(force_curve_png(curve, kInfo));
  ASSERT_TRUE(image.ok());
  for (double deg : {45.0, 315.0}) {
    EXPECT_TRUE(color_near(image, x_of(deg), y_of(-40, -100, 100), layout::kForceXColor)) << deg;
    EXPECT_TRUE(color_near(image, x_of(deg), y_of(40, -100, 100), layout::kResultantColor)) << deg;
  }
  for (double deg : {135.0, 225.0}) {  // between samples of zero force
    EXPECT_FALSE(color_near(image, x_of(deg), y_of(-40, -100, 100), layout::kForceXColor)) << deg;
    EXPECT_FALSE(color_near(image, x_of(deg), y_of(40, -100, 100), layout::kResultantColor)) << deg;
  }
}

TEST(ForcePlot, SvgIsWellFormedAndNamesItsLegend) {
  const std::string svg = force_curve_svg(constant_curve({10, -20, 40}, 3.0), kInfo);
  EXPECT_TRUE(is_svg(svg));
  EXPECT_TRUE(xml_tags_balanced(svg));
  EXPECT_NE(svg.find("width=\"1000"), std::string::npos);
  EXPECT_NE(svg.find("height=\"560"), std::string::npos);
  EXPECT_NE(svg.find("<title>" + kInfo.title + "</title>"), std::string::npos);
  for (const char* label : {"Fx (N)", "Fy (N)", "Fz (N)", "|F| (N)", "torque (N·m)"}) {
    EXPECT_NE(svg.find(label), std::string::npos) << label;
  }
  // Markup in the title is escaped.
  const std::string escaped = force_curve_svg(constant_curve({1, 0, 0}, 0.0), {"a < b & c"});
  EXPECT_TRUE(xml_tags_balanced(escaped));
  EXPECT_NE(escaped.find("<title>a &lt; b &amp; c</title>"), std::string::npos);
}

TEST(ForcePlot, SingleSampleAndNoForceDraw) {
  const std::vector<ForceSample> one{{1.0, Vec3(5, 5, 5), 0.1}};
  const Image image(force_curve_png(one, kInfo));
  ASSERT_TRUE(image.ok());
  EXPECT_EQ(image.width(), layout::kForceWidth);
  EXPECT_TRUE(is_svg(force_curve_svg(one, kInfo)));

  const std::vector<ForceSample> idle = constant_curve({0, 0, 0}, 0.0);
  const Image empty(force_curve_png(idle, {""}));
  ASSERT_TRUE(empty.ok());
  EXPECT_EQ(empty.height(), layout::kForceHeight);
  EXPECT_TRUE(xml_tags_balanced(force_curve_svg(idle, {""})));
}

TEST(ForcePlot, CsvHasHeaderOneRowPerSampleAndRoundTrips) {
  std::vector<ForceSample> curve;
  for (int k = 0; k < 72; ++k) {
    const double angle = degrees_to_radians(5.0 * k);
    curve.push_back({angle, Vec3(-123.456789 * std::cos(angle), 98.7654321 * std::sin(angle), -7.5),
                     0.0123456789 * (1.0 + std::sin(angle))});
  }
  const std::string csv = force_curve_csv(curve);
  std::istringstream in(csv);
  std::string row;
  ASSERT_TRUE(std::getline(in, row));
  EXPECT_EQ(row, "angle_deg,fx_n,fy_n,fz_n,resultant_n,torque_nm");
  std::size_t rows = 0;
  while (std::getline(in, row)) {
    ASSERT_LT(rows, curve.size());
    const ForceSample& s = curve[rows];
    std::vector<double> values;
    std::istringstream fields(row);
    std::string field;
    while (std::getline(fields, field, ',')) values.push_back(std::stod(field));
    ASSERT_EQ(values.size(), 6u) << row;
    // 4 decimals (5·10⁻⁵ rounding) for angles and forces, 6 for the torque.
    EXPECT_NEAR(values[0], 5.0 * static_cast<double>(rows), 5e-5) << row;
    EXPECT_NEAR(values[1], s.force.x(), 5e-5) << row;
    EXPECT_NEAR(values[2], s.force.y(), 5e-5) << row;
    EXPECT_NEAR(values[3], s.force.z(), 5e-5) << row;
    EXPECT_NEAR(values[4], s.force.norm(), 5e-5) << row;
    EXPECT_NEAR(values[5], s.torque, 5e-7) << row;
    ++rows;
  }
  EXPECT_EQ(rows, curve.size());
  EXPECT_EQ(csv.back(), '\n');
  EXPECT_NE(csv.find("\n0.0000,-123.4568,0.0000,-7.5000,123.6844,0.012346\n"), std::string::npos);

  EXPECT_EQ(force_curve_csv({}), "angle_deg,fx_n,fy_n,fz_n,resultant_n,torque_nm\n");
}

TEST(ForcePlot, NonFiniteValuesAndEmptyCurvesAreInputErrors) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_THROW(force_curve_png({}, kInfo), InputError);
  EXPECT_THROW(force_curve_svg({}, kInfo), InputError);
  EXPECT_THROW(layout::force_axes({}), InputError);

  std::vector<ForceSample> curve = constant_curve({1, 2, 3}, 0.5, 12);
  curve[4].force.y() = nan;
  EXPECT_THROW(force_curve_png(curve, kInfo), InputError);
  EXPECT_THROW(force_curve_svg(curve, kInfo), InputError);
  EXPECT_THROW(force_curve_csv(curve), InputError);

  curve = constant_curve({1, 2, 3}, 0.5, 12);
  curve[7].torque = inf;
  EXPECT_THROW(force_curve_png(curve, kInfo), InputError);
  EXPECT_THROW(force_curve_csv(curve), InputError);

  curve = constant_curve({1, 2, 3}, 0.5, 12);
  curve[0].angle = nan;
  EXPECT_THROW(force_curve_svg(curve, kInfo), InputError);

  curve = constant_curve({1, 2, 3}, 0.5, 12);
  curve[2].force.x() = -inf;
  EXPECT_THROW(force_curve_png(curve, kInfo), InputError);

  // Finite components whose magnitude overflows.
  curve = constant_curve({1e200, 1e200, 0}, 0.5, 12);
  EXPECT_THROW(force_curve_png(curve, kInfo), InputError);
}

}  // namespace
}  // namespace cwe

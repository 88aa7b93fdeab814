// Engagement plots: PNG and SVG are well formed and of the stated size, engaged regions land where
// the documented layout puts them, and degenerate inputs (empty maps, no engagement, no CLs,
// intervals touching 0 and 2π, huge paths) draw without trouble; NaN is an input error.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "cwe/core/error.hpp"
#include "cwe/geometry/vec.hpp"
#include "cwe/io/engagement_plot.hpp"
#include "plot_testing.hpp"

namespace cwe {
namespace {

namespace layout = plot_layout;
using test::Image;
using test::is_png;
using test::is_svg;

// Side discs 1 mm high from the tip to 4 mm, the lower two engaged over φ ∈ [20°, 100°]; with
// `rings`, a flat bottom of rings 0–2 and 2–4 mm, the outer engaged over φ ∈ [0°, 90°].
EngagementMap sample_map(bool rings) {
  EngagementMap map;
  for (int k = 0; k < 4; ++k) map.discs.push_back({double(k), double(k + 1), 0, {}});
  for (int k = 0; k < 2; ++k) {
    map.discs[k].phi = {{degrees_to_radians(20), degrees_to_radians(100)}};
  }
  if (rings) {
    map.rings = {{0, 2, {}}, {2, 4, {{0.0, 0.5 * kPi}}}};
  }
  map.engaged = true;
  return map;
}

const MapPlotInfo kInfo{"CL 120 · move 14 (line 37)", 5.0, 10.0};

// Pixel position of (φ degrees, depth mm) in the side panel.
struct SidePoint {
  double x, y;
};
SidePoint side_point(double phi_deg, double z, double panel_width, double depth_top) {
  return {layout::kSideLeft + phi_deg / 360.0 * panel_width,
          layout::kSideTop + layout::kSideHeight - z / depth_top * layout::kSideHeight};
}

TEST(EngagementPlot, MapPngHasStatedSizeAndFillsEngagedRectangles) {
  const EngagementMap map = sample_map(true);
  // Highest engaged disc top 2 mm: a nice value already, below the 10 mm flute.
  ASSERT_DOUBLE_EQ(layout::depth_axis_top(map, kInfo), 2.0);
  const std::string png = engagement_map_png(map, kInfo);
  ASSERT_TRUE(is_png(png));
  const Image image(png);
  ASSERT_TRUE(image.ok());
  EXPECT_EQ(image.width(), layout::kMapWidth);
  EXPECT_EQ(image.height(), layout::kMapHeight);

  const double w = layout::kSideWidthWithBottom;
  const SidePoint engaged = side_point(60, 0.75, w, 2.0);
  EXPECT_EQ(image.rgb(engaged.x, engaged.y), layout::kEngagedColor);
  const SidePoint engaged_high = side_point(30, 1.75, w, 2.0);
  EXPECT_EQ(image.rgb(engaged_high.x, engaged_high.y), layout::kEngagedColor);
  const SidePoint other_angle = side_point(150, 0.75, w, 2.0);
  EXPECT_NE(image.rgb(other_angle.x, other_angle.y), layout::kEngagedColor);
  const SidePoint other_phi_low = side_point(10, 0.75, w, 2.0);
  EXPECT_NE(image.rgb(other_phi_low.x, other_phi_low.y), layout::kEngagedColor);

  // Polar panel: ρ = 3 mm at φ = 45° is in the engaged outer ring; φ = 200° is not; the inner
  // ring is not engaged. Scale: tool radius 5 mm at kPolarRadius.
  const double k = layout::kPolarRadius / 5.0;
  const auto polar = [&](double phi_deg, double rho) {
    const double phi = degrees_to_radians(phi_deg);
    return image.rgb(layout::kPolarCenterX + rho * k * std::sin(phi),
                     layout::kPolarCenterY - rho * k * std::cos(phi));
  };
  EXPECT_EQ(polar(45, 3), layout::kEngagedColor);
  EXPECT_EQ(polar(80, 3.5), layout::kEngagedColor);   // clockwise from +y: towards +x (right)
  EXPECT_NE(polar(280, 3.5), layout::kEngagedColor);  // its mirror image across the y axis
  EXPECT_NE(polar(200, 3), layout::kEngagedColor);
  EXPECT_NE(polar(30, 1), layout::kEngagedColor);
}

// `cwe compare`'s maps: a second map over the first, translucent. Where only the first engages,
// its colour; where both, the overlay's over it; where only the overlay, the overlay's over the
// white background; elsewhere neither.
TEST(EngagementPlot, OverlayIsDrawnTranslucentOverTheMap) {
  const EngagementMap map = sample_map(true);
  EngagementMap other = sample_map(true);
  for (int k = 0; k < 2; ++k) {
    other.discs[k].phi = {{degrees_to_radians(60), degrees_to_radians(160)}};
  }
  MapPlotInfo info = kInfo;
  info.overlay = &other;
  info.label = "dexel";
  info.overlay_label = "brep";
  const Image image(engagement_map_png(map, info));
  ASSERT_TRUE(image.ok());
  const auto blend = [](unsigned over, unsigned under) {
    unsigned rgb = 0;
    for (int shift : {16, 8, 0}) {
      const double a = (over >> shift) & 0xff, b = (under >> shift) & 0xff;
      const auto c = static_cast<unsigned>(
          std::lround(layout::kOverlayAlpha * a + (1.0 - layout::kOverlayAlpha) * b));
      rgb |= c << shift;
    }
    return rgb;
  };
  const auto near = [](unsigned a, unsigned b) {
    for (int shift : {16, 8, 0}) {
      if (std::abs(static_cast<int>((a >> shift) & 0xff) - static_cast<int>((b >> shift) & 0xff)) >
          2) {
        return false;
      }
    }
    return true;
  };
  const double w = layout::kSideWidthWithBottom;
  const SidePoint first = side_point(40, 0.75, w, 2.0);
  EXPECT_EQ(image.rgb(first.x, first.y), layout::kEngagedColor);
  const SidePoint both = side_point(80, 0.75, w, 2.0);
  EXPECT_TRUE(near(image.rgb(both.x, both.y), blend(layout::kOverlayColor, layout::kEngagedColor)))
      << std::hex << image.rgb(both.x, both.y);
  const SidePoint second = side_point(130, 0.75, w, 2.0);
  EXPECT_TRUE(near(image.rgb(second.x, second.y), blend(layout::kOverlayColor, 0xffffff)))
      << std::hex << image.rgb(second.x, second.y);
  const SidePoint neither = side_point(200, 0.75, w, 2.0);
  EXPECT_EQ(image.rgb(neither.x, neither.y), 0xffffffu);
}

TEST(EngagementPlot, MapWithoutRingsUsesTheWholeWidthForTheSide) {
  const EngagementMap map = sample_map(false);
  const Image image(engagement_map_png(map, kInfo));
  ASSERT_TRUE(image.ok());
  const SidePoint engaged = side_point(90, 1.5, layout::kSideWidthAlone, 2.0);
  EXPECT_EQ(image.rgb(engaged.x, engaged.y), layout::kEngagedColor);
  const SidePoint beyond = side_point(200, 1.5, layout::kSideWidthAlone, 2.0);
  EXPECT_NE(image.rgb(beyond.x, beyond.y), layout::kEngagedColor);
}

TEST(EngagementPlot, MapSvgIsAWholeDocument) {
  const std::string svg = engagement_map_svg(sample_map(true), kInfo);
  EXPECT_TRUE(is_svg(svg));
  EXPECT_NE(svg.find("width=\"1000"), std::string::npos);
  EXPECT_NE(svg.find("height=\"600"), std::string::npos);
}

// The same map gives the same SVG bytes whatever was drawn before it (cairo numbers its
// surfaces across the process; figures are drawn on several threads in any order).
TEST(EngagementPlot, MapSvgBytesDoNotDependOnEarlierFigures) {
  const std::string first = engagement_map_svg(sample_map(true), kInfo);
  engagement_map_svg(sample_map(false), kInfo);
  engagement_map_png(sample_map(true), kInfo);
  EXPECT_EQ(engagement_map_svg(sample_map(true), kInfo), first);
}

TEST(EngagementPlot, EmptyMapAndMapWithoutEngagementDraw) {
  const EngagementMap empty;
  EXPECT_DOUBLE_EQ(layout::depth_axis_top(empty, kInfo), 5.0);
  EXPECT_DOUBLE_EQ(layout::depth_axis_top(empty, {}), 5.0);  // flute height unknown
  EXPECT_DOUBLE_EQ(layout::depth_axis_top(empty, {"", 1.0, 3.0}), 3.0);
  for (const MapPlotInfo& info : {kInfo, MapPlotInfo{}}) {
    const Image image(engagement_map_png(empty, info));
    ASSERT_TRUE(image.ok());
    EXPECT_EQ(image.width(), layout::kMapWidth);
    EXPECT_EQ(image.count(layout::kEngagedColor), 0);
    EXPECT_TRUE(is_svg(engagement_map_svg(empty, info)));
  }

  EngagementMap idle = sample_map(true);
  for (auto& d : idle.discs) d.phi.clear();
  idle.rings[1].phi = {Interval::empty()};  // empty intervals are skipped
  idle.engaged = false;
  const Image image(engagement_map_png(idle, kInfo));
  ASSERT_TRUE(image.ok());
  EXPECT_EQ(image.count(layout::kEngagedColor), 0);
  EXPECT_TRUE(is_svg(engagement_map_svg(idle, kInfo)));
}

TEST(EngagementPlot, IntervalsTouchingZeroAndTwoPi) {
  EngagementMap map;
  map.discs = {{0.0, 0.5, 0, {{0.0, 0.3}, {kTwoPi - 0.3, kTwoPi}}},
               {0.5, 1.0, 0, {Interval::full()}}};  // clipped to the whole circle
  map.rings = {{0.0, 1.0, {{0.0, kTwoPi}}}, {1.0, 2.0, {{kTwoPi - 0.2, kTwoPi}, {0.0, 0.2}}}};
  const MapPlotInfo info{"wrap", 2.0, 1.0};
  ASSERT_DOUBLE_EQ(layout::depth_axis_top(map, info), 1.0);
  const Image image(engagement_map_png(map, info));
  ASSERT_TRUE(image.ok());
  const double w = layout::kSideWidthWithBottom;
  for (double phi : {5.0, 355.0}) {
    const SidePoint p = side_point(phi, 0.25, w, 1.0);
    EXPECT_EQ(image.rgb(p.x, p.y), layout::kEngagedColor) << phi;
  }
  const SidePoint gap = side_point(120, 0.25, w, 1.0);
  EXPECT_NE(image.rgb(gap.x, gap.y), layout::kEngagedColor);
  const SidePoint full = side_point(120, 0.75, w, 1.0);
  EXPECT_EQ(image.rgb(full.x, full.y), layout::kEngagedColor);
  // The full inner ring is a disc; the outer ring is engaged either side of φ = 0.
  const double k = layout::kPolarRadius / 2.0;
  EXPECT_EQ(image.rgb(layout::kPolarCenterX + 0.5 * k, layout::kPolarCenterY + 0.3 * k),
            layout::kEngagedColor);
  EXPECT_EQ(image.rgb(layout::kPolarCenterX - 0.1 * k, layout::kPolarCenterY - 1.5 * k),
            layout::kEngagedColor);
  EXPECT_EQ(image.rgb(layout::kPolarCenterX + 0.1 * k, layout::kPolarCenterY - 1.5 * k),
            layout::kEngagedColor);
  EXPECT_NE(image.rgb(layout::kPolarCenterX, layout::kPolarCenterY + 1.5 * k),
            layout::kEngagedColor);
  EXPECT_TRUE(is_svg(engagement_map_svg(map, info)));
}

TEST(EngagementPlot, DepthAxisRoundsUpToANiceValue) {
  EngagementMap map;
  map.discs = {{0.0, 2.2, 0, {{0.0, 1.0}}}, {2.2, 4.4, 0, {}}};
  EXPECT_DOUBLE_EQ(layout::depth_axis_top(map, {"", 5, 30}), 2.5);
  map.discs[0].z1 = 0.2;
  EXPECT_DOUBLE_EQ(layout::depth_axis_top(map, {"", 5, 30}), 1.0);   // at least 1 mm
  EXPECT_DOUBLE_EQ(layout::depth_axis_top(map, {"", 5, 0.5}), 0.5);  // but not above the flute
  map.discs[0].z1 = 28;
  EXPECT_DOUBLE_EQ(layout::depth_axis_top(map, {"", 5, 29}), 29.0);
  EXPECT_DOUBLE_EQ(layout::depth_axis_top(map, {"", 5, 0}), 30.0);
}

TEST(EngagementPlot, NonFiniteMapValuesAreInputErrors) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  EngagementMap map = sample_map(true);
  map.discs[1].z1 = nan;
  EXPECT_THROW(engagement_map_png(map, kInfo), InputError);
  map = sample_map(true);
  map.discs[0].phi = {{0.1, nan}};
  EXPECT_THROW(engagement_map_svg(map, kInfo), InputError);
  map = sample_map(true);
  map.rings[0].r1 = inf;
  EXPECT_THROW(engagement_map_png(map, kInfo), InputError);
  EXPECT_THROW(engagement_map_png(sample_map(true), MapPlotInfo{"", nan, 1}), InputError);
}

std::vector<PathPlotPoint> sample_path(int n) {
  std::vector<PathPlotPoint> points;
  points.reserve(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    const bool engaged = i % 7 != 3;
    points.push_back({i, engaged, 10.0 + 0.001 * (i % 1000), 170.0 - 0.002 * (i % 500),
                      1.0 + std::sin(0.001 * i)});
  }
  return points;
}

TEST(EngagementPlot, PathPngHasStatedSizeAndMarkers) {
  // One CL, centred on the CL axis: entry 90°, exit 270°, depth 2 mm.
  const std::vector<PathPlotPoint> one{{7, true, 90.0, 270.0, 2.0}};
  const std::string png = engagement_path_png(one, "one CL");
  ASSERT_TRUE(is_png(png));
  const Image image(png);
  ASSERT_TRUE(image.ok());
  EXPECT_EQ(image.width(), layout::kPathWidth);
  EXPECT_EQ(image.height(), layout::kPathHeight);
  const double x = layout::kPathLeft + 0.5 * layout::kPathPlotWidth;
  const auto y_of = [](double deg) {
    return layout::kPathTop + layout::kPathPlotHeight * (1.0 - deg / 360.0);
  };
  EXPECT_EQ(image.rgb(x, y_of(90)), layout::kEntryColor);
  EXPECT_EQ(image.rgb(x, y_of(270)), layout::kExitColor);
  EXPECT_NE(image.rgb(x, y_of(180)), layout::kEntryColor);
  EXPECT_TRUE(is_svg(engagement_path_svg(one, "one CL")));
}

TEST(EngagementPlot, PathWithoutPointsOrEngagementDraws) {
  const Image empty(engagement_path_png({}, "nothing"));
  ASSERT_TRUE(empty.ok());
  EXPECT_EQ(empty.width(), layout::kPathWidth);
  EXPECT_EQ(empty.height(), layout::kPathHeight);
  EXPECT_TRUE(is_svg(engagement_path_svg({}, "nothing")));

  const std::vector<PathPlotPoint> idle{{0, false, 0, 0, 0}, {1, false, 0, 0, 0}};
  const Image image(engagement_path_png(idle, "idle"));
  ASSERT_TRUE(image.ok());
  // Nothing drawn inside the plot (the legend and the depth axis are outside it).
  const int left = static_cast<int>(layout::kPathLeft) + 1;
  const int top = static_cast<int>(layout::kPathTop) + 1;
  const int right = static_cast<int>(layout::kPathLeft + layout::kPathPlotWidth);
  const int bottom = static_cast<int>(layout::kPathTop + layout::kPathPlotHeight);
  for (unsigned color : {layout::kEntryColor, layout::kExitColor, layout::kDepthColor}) {
    EXPECT_EQ(image.count(color, left, top, right, bottom), 0) << std::hex << color;
  }
  EXPECT_TRUE(is_svg(engagement_path_svg(idle, "idle")));
}

TEST(EngagementPlot, HugePathStaysSmall) {
  const std::vector<PathPlotPoint> points = sample_path(100000);
  const std::string png = engagement_path_png(points, "100000 CLs");
  const Image image(png);
  ASSERT_TRUE(image.ok());
  EXPECT_EQ(image.width(), layout::kPathWidth);
  const std::string svg = engagement_path_svg(points, "100000 CLs");
  EXPECT_TRUE(is_svg(svg));
  // Thinned to the pixel grid: far fewer bytes than one SVG element per CL would need.
  EXPECT_LT(svg.size(), std::size_t{3000000});
}

TEST(EngagementPlot, NonFinitePathValuesAreInputErrors) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<PathPlotPoint> points = sample_path(10);
  points[4].axial_depth_mm = nan;  // engaged (4 % 7 != 3)
  EXPECT_THROW(engagement_path_png(points, "bad"), InputError);
  points[4].engaged = false;  // values of unengaged CLs are not drawn, so not checked
  EXPECT_NO_THROW(engagement_path_png(points, "fine"));
}

}  // namespace
}  // namespace cwe

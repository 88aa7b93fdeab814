#pragma once
// Engagement maps and engagement along a toolpath as figures (PNG or SVG), in the style of the
// engagement-map figures of the CWE literature (Aras 2008, Figs. 6.11–6.13): a light grid, the
// engaged region filled in one saturated colour, angles in degrees.
//
// Each figure is drawn once by a single cairo routine onto either an image surface (PNG) or an
// SVG surface, so both outputs show the same picture. The functions return the file's bytes and
// never write files or print: the caller decides where the bytes go (atomically).
//
// Conventions (docs/architecture.md): φ is measured from +y of the tool frame, clockwise seen from
// the shank; the front face (moving into material) is φ ∈ [0°, 180°], the back face (180°, 360°).
//
// Errors: cwe::InputError for values that cannot be drawn (NaN anywhere, infinite heights, radii
// or path values). Empty intervals (Interval::empty()) are skipped; intervals reaching outside
// [0, 2π] (Interval::full() included) are clipped to it. Cairo failures (out of memory) throw
// std::runtime_error.

#include <string>
#include <vector>

#include "cwe/engagement/engagement_map.hpp"

namespace cwe {

struct MapPlotInfo {
  std::string title;        // e.g. "CL 120 · move 14 (line 37)"
  double tool_radius = 0;   // mm, the cutter's largest radius (polar plot scale); <= 0: unknown
  double flute_height = 0;  // mm, the side map's full height (top of the φ–depth axis); <= 0:
                            // unknown
  // A second map of the same CL drawn over this one, translucent in plot_layout::kOverlayColor
  // (`cwe compare`: another workpiece's), with the legend's names of the two; none: the map
  // alone.
  const EngagementMap* overlay = nullptr;
  std::string label{}, overlay_label{};
};

// The engagement map of one cutter location as a figure of plot_layout::kMapWidth ×
// kMapHeight pixels.
//
// Left panel, φ–depth: φ in degrees 0…360 across (ticks every 45°), depth above the tip in mm up,
// from 0 to depth_axis_top(); each engaged φ interval of each disc is a filled rectangle
// [φ0, φ1] × [z0, z1] (at least one pixel wide, so grazing intervals stay visible); a dashed line
// at φ = 180° labelled "front | back".
// Right panel, only when the map has rings: the flat bottom as a polar plot, φ = 0 pointing up
// (+y of the tool frame) and increasing clockwise (the view from the shank), radius scaled so
// that max(tool_radius, largest ring radius) reaches plot_layout::kPolarRadius; rings are filled
// annular sectors; an arrow labelled "feed" marks +x (φ = 90°). Without rings the left panel
// takes the whole width.
std::string engagement_map_png(const EngagementMap& map, const MapPlotInfo& info);
std::string engagement_map_svg(const EngagementMap& map, const MapPlotInfo& info);

// One cutter location of a path plot.
struct PathPlotPoint {
  int cl = 0;  // CL index (horizontal axis)
  bool engaged = false;
  double phi_entry_deg = 0, phi_exit_deg = 0, axial_depth_mm = 0;
};

// Engagement along the whole path, plot_layout::kPathWidth × kPathHeight pixels: entry and exit
// angle (degrees, left axis 0…360) and axial depth (mm, right axis, 0 to a nice value >= 1 mm)
// against CL index. Only engaged points are drawn: entry and exit as markers of two colours,
// depth as a line broken wherever a CL is not engaged (an isolated engaged CL is a dot). Values
// of points that are not engaged are ignored. Points may come in any order (they are drawn
// sorted by CL). Angles outside 0…360 and negative depths are clipped to the axes. Large paths
// (10⁵ points and more) are drawn as three paths thinned to the pixel grid (one marker per pixel
// and colour; per pixel column of the depth line its first, lowest, highest and last point), so
// the SVG stays a few hundred kB. No points: empty axes with the note "no cutter locations".
std::string engagement_path_png(const std::vector<PathPlotPoint>& points, const std::string& title);
std::string engagement_path_svg(const std::vector<PathPlotPoint>& points, const std::string& title);

// The figures' geometry in pixels (SVG user units are the same), for callers that place things
// on the figures and for tests that look at pixels. y grows downwards.
namespace plot_layout {

// Map figure.
inline constexpr int kMapWidth = 1000;
inline constexpr int kMapHeight = 600;
// φ–depth panel: φ = 0° at kSideLeft, 360° at kSideLeft + width; depth 0 at kSideTop +
// kSideHeight (the bottom edge), depth_axis_top() at kSideTop.
inline constexpr double kSideLeft = 80;
inline constexpr double kSideTop = 70;
inline constexpr double kSideHeight = 440;
inline constexpr double kSideWidthWithBottom = 540;  // 1.5 px per degree, when the map has rings
inline constexpr double kSideWidthAlone = 864;       // 2.4 px per degree, when it has none
// Polar panel: centre and the radius of the scale circle, max(tool_radius, largest ring r1).
inline constexpr double kPolarCenterX = 790;
inline constexpr double kPolarCenterY = 300;
inline constexpr double kPolarRadius = 120;

// Path figure: CL axis from the smallest CL at kPathLeft to the largest at kPathLeft +
// kPathPlotWidth (one CL: that CL ± 1); angle 0° and depth 0 at the bottom edge kPathTop +
// kPathPlotHeight, 360° and the depth axis top at kPathTop.
inline constexpr int kPathWidth = 1200;
inline constexpr int kPathHeight = 500;
inline constexpr double kPathLeft = 80;
inline constexpr double kPathTop = 70;
inline constexpr double kPathPlotWidth = 1000;
inline constexpr double kPathPlotHeight = 350;

// Colours, 0xRRGGBB: the engaged region of a map; entry and exit markers and the depth line of
// a path plot.
inline constexpr unsigned kEngagedColor = 0xd62728;
inline constexpr unsigned kEntryColor = 0x1f77b4;
inline constexpr unsigned kExitColor = 0xff7f0e;
inline constexpr unsigned kDepthColor = 0x2ca02c;
inline constexpr unsigned kOverlayColor = 0x1f77b4;  // at kOverlayAlpha over kEngagedColor
inline constexpr double kOverlayAlpha = 0.5;

// Top of the φ–depth axis, mm: the top of the highest engaged disc rounded up to a nice value
// (multiple of a 1-2-2.5-5 step), at least 1 mm, but not above flute_height when that still
// shows all engagement; with no side engagement min(flute_height, 5) (5 when flute_height is
// unknown). Throws InputError like engagement_map_png.
double depth_axis_top(const EngagementMap& map, const MapPlotInfo& info);

}  // namespace plot_layout

}  // namespace cwe

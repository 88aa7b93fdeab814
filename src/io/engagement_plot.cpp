#include "cwe/io/engagement_plot.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numeric>
#include <tuple>
#include <utility>

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

// ---------------------------------------------------------------------------------------------
// The engagement map figure.

struct SideRect {  // engaged: φ0 <= φ1 in [0, 2π], z0 <= z1 (mm)
  double phi0, phi1, z0, z1;
};
struct BottomSector {  // engaged: φ0 <= φ1 in [0, 2π], 0 <= r0 <= r1 (mm)
  double phi0, phi1, r0, r1;
};

struct MapFigure {
  std::string title;
  bool has_discs = false;
  bool has_rings = false;
  std::vector<SideRect> side, overlay_side;
  std::vector<BottomSector> bottom, overlay_bottom;
  std::string label, overlay_label;
  double depth_top = 1.0;    // mm, top of the φ–depth axis
  double polar_scale = 1.0;  // mm at kPolarRadius
};

// Appends the drawable parts of `intervals` (clipped to [0, 2π]) to `out` via `emit(lo, hi)`.
template <typename Emit>
void clipped_intervals(const std::vector<Interval>& intervals, const std::string& where,
                       const Emit& emit) {
  for (std::size_t k = 0; k < intervals.size(); ++k) {
    const Interval& i = intervals[k];
    // Before any comparison: comparing a NaN raises FE_INVALID.
    if (std::isnan(i.lo) || std::isnan(i.hi)) {
      throw InputError(fmt::format("engagement map: {}, φ interval {} is NaN", where, k));
    }
    if (i.is_empty()) continue;
    if (i.hi < 0.0 || i.lo > kTwoPi) continue;  // wholly outside the circle: nothing to draw
    emit(std::clamp(i.lo, 0.0, kTwoPi), std::clamp(i.hi, 0.0, kTwoPi));
  }
}

MapFigure prepare_map(const EngagementMap& map, const MapPlotInfo& info) {
  if (!std::isfinite(info.tool_radius)) {
    throw InputError("engagement map plot: tool radius is not a finite number");
  }
  if (!std::isfinite(info.flute_height)) {
    throw InputError("engagement map plot: flute height is not a finite number");
  }
  MapFigure figure;
  figure.title = info.title;
  figure.label = info.label;
  figure.overlay_label = info.overlay_label;
  figure.has_discs = !map.discs.empty();
  figure.has_rings = !map.rings.empty();

  double highest = 0.0;  // top of the highest engaged disc
  double largest_radius = 0.0;
  const auto add = [&](const EngagementMap& m, std::vector<SideRect>& side,
                       std::vector<BottomSector>& bottom) {
    for (std::size_t d = 0; d < m.discs.size(); ++d) {
      const DiscEngagement& disc = m.discs[d];
      if (!std::isfinite(disc.z0) || !std::isfinite(disc.z1)) {
        throw InputError(fmt::format("engagement map: disc {} has a non-finite height", d));
      }
      const double z0 = std::min(disc.z0, disc.z1), z1 = std::max(disc.z0, disc.z1);
      clipped_intervals(disc.phi, fmt::format("disc {}", d), [&](double lo, double hi) {
        side.push_back({lo, hi, z0, z1});
        highest = std::max(highest, z1);
      });
    }
    for (std::size_t r = 0; r < m.rings.size(); ++r) {
      const RingEngagement& ring = m.rings[r];
      if (!std::isfinite(ring.r0) || !std::isfinite(ring.r1)) {
        throw InputError(fmt::format("engagement map: ring {} has a non-finite radius", r));
      }
      const double r0 = std::max(0.0, std::min(ring.r0, ring.r1));
      const double r1 = std::max(0.0, std::max(ring.r0, ring.r1));
      largest_radius = std::max(largest_radius, r1);
      clipped_intervals(ring.phi, fmt::format("ring {}", r), [&](double lo, double hi) {
        bottom.push_back({lo, hi, r0, r1});
      });
    }
  };
  add(map, figure.side, figure.bottom);
  if (info.overlay != nullptr) {
    add(*info.overlay, figure.overlay_side, figure.overlay_bottom);
    figure.has_discs = figure.has_discs || !info.overlay->discs.empty();
    figure.has_rings = figure.has_rings || !info.overlay->rings.empty();
  }

  if (highest > 0.0) {
    figure.depth_top = std::max(1.0, round_up(highest, nice_step(highest, 5)));
    // The flute height bounds the axis unless engagement reaches above it (a bad flute height).
    if (info.flute_height >= highest)
      figure.depth_top = std::min(figure.depth_top, info.flute_height);
  } else {
    figure.depth_top = info.flute_height > 0.0 ? std::min(info.flute_height, 5.0) : 5.0;
  }
  figure.polar_scale = std::max(info.tool_radius, largest_radius);
  if (!(figure.polar_scale > 0.0)) figure.polar_scale = 1.0;  // rings all of radius 0
  return figure;
}

void draw_side_panel(cairo_t* cr, const MapFigure& figure) {
  const double left = layout::kSideLeft, top = layout::kSideTop, height = layout::kSideHeight;
  const double width = figure.has_rings ? layout::kSideWidthWithBottom : layout::kSideWidthAlone;
  const double right = left + width, bottom = top + height;
  const auto X = [&](double phi) { return left + phi / kTwoPi * width; };
  const auto Y = [&](double z) {
    return bottom - std::clamp(z, 0.0, figure.depth_top) / figure.depth_top * height;
  };
  const double z_step = nice_step(figure.depth_top, 5);

  // Grid under the engagement.
  set_color(cr, kGridColor);
  cairo_set_line_width(cr, 1);
  for (int deg = 45; deg < 360; deg += 45) {
    if (deg != 180) line(cr, X(degrees_to_radians(deg)), top, X(degrees_to_radians(deg)), bottom);
  }
  for (int k = 1; k <= step_count(figure.depth_top, z_step); ++k) {
    line(cr, left, Y(k * z_step), right, Y(k * z_step));
  }
  cairo_stroke(cr);

  // Engaged rectangles as one path, filled once: neighbouring discs meet without seams. Each is
  // at least a pixel wide and high so that grazing contacts and thin discs stay visible. An
  // overlay's, translucent, over them.
  for (const auto& [rects, color, alpha] :
       {std::tuple{&figure.side, layout::kEngagedColor, 1.0},
        std::tuple{&figure.overlay_side, layout::kOverlayColor, layout::kOverlayAlpha}}) {
    for (const SideRect& r : *rects) {
      double x0 = X(r.phi0), x1 = X(r.phi1), y0 = Y(r.z1), y1 = Y(r.z0);
      if (x1 - x0 < 1.0) {
        x0 = std::clamp(0.5 * (x0 + x1) - 0.5, left, right - 1.0);
        x1 = x0 + 1.0;
      }
      if (y1 - y0 < 1.0) {
        y0 = std::clamp(0.5 * (y0 + y1) - 0.5, top, bottom - 1.0);
        y1 = y0 + 1.0;
      }
      cairo_rectangle(cr, x0, y0, x1 - x0, y1 - y0);
    }
    set_color(cr, color, alpha);
    cairo_fill(cr);
  }

  // Front | back divide.
  const double x_divide = X(kPi);
  const double dashes[] = {6.0, 3.0};
  cairo_set_dash(cr, dashes, 2, 0);
  set_color(cr, kDivideColor);
  line(cr, x_divide, top, x_divide, bottom);
  cairo_stroke(cr);
  cairo_set_dash(cr, nullptr, 0, 0);
  // The bar of "front | back" sits on the line.
  const double bar_offset = text_width(cr, "front ") + 0.5 * text_width(cr, "|");
  text(cr, x_divide - bar_offset, top - 7, "front | back");

  // Frame, ticks and labels.
  set_color(cr, kBlack);
  cairo_rectangle(cr, left, top, width, height);
  cairo_stroke(cr);
  for (int deg = 0; deg <= 360; deg += 45) {
    const double x = X(degrees_to_radians(deg));
    line(cr, x, bottom, x, bottom + 4);
    text(cr, x, bottom + 18, std::to_string(deg), Anchor::kMiddle);
  }
  for (int k = 0; k <= step_count(figure.depth_top, z_step); ++k) {
    const double y = Y(k * z_step);
    line(cr, left - 4, y, left, y);
    text(cr, left - 7, y + 4, number(k * z_step), Anchor::kEnd);
  }
  cairo_stroke(cr);
  text(cr, left + 0.5 * width, bottom + 42, "engagement angle φ (deg)", Anchor::kMiddle, 13);
  text(cr, 30, top + 0.5 * height, "depth above the tip (mm)", Anchor::kMiddle, 13, false,
       -0.5 * kPi);

  if (figure.side.empty()) {
    note(cr, left + 0.5 * width, top + 0.5 * height,
         figure.has_discs ? "no side engagement" : "no side map");
  }
}

void draw_bottom_panel(cairo_t* cr, const MapFigure& figure) {
  const double cx = layout::kPolarCenterX, cy = layout::kPolarCenterY;
  const double R = layout::kPolarRadius;
  const double px_per_mm = R / figure.polar_scale;
  // φ from +y (up on the page), clockwise: cairo's angles run from +x towards +y of the page
  // (down), i.e. clockwise too, so φ maps to cairo angle φ − π/2.
  const auto angle = [](double phi) { return phi - 0.5 * kPi; };
  const auto at = [&](double phi, double radius_px) {
    return std::pair{cx + radius_px * std::sin(phi), cy - radius_px * std::cos(phi)};
  };

  text(cr, cx, cy - R - 38, "flat bottom, seen from the shank (mm)", Anchor::kMiddle, 13);

  // Grid: circles at nice radii, spokes every 45°.
  const double r_step = nice_step(figure.polar_scale, 4);
  set_color(cr, kGridColor);
  cairo_set_line_width(cr, 1);
  for (int k = 1; k * r_step < figure.polar_scale * (1.0 - kTickSlack); ++k) {
    cairo_new_sub_path(cr);
    cairo_arc(cr, cx, cy, k * r_step * px_per_mm, 0, kTwoPi);
  }
  for (int deg = 0; deg < 360; deg += 45) {
    const auto [x, y] = at(degrees_to_radians(deg), R);
    line(cr, cx, cy, x, y);
  }
  cairo_stroke(cr);

  // Engaged sectors as one path (same orientation for all, so overlaps add, never cancel); an
  // overlay's, translucent, over them.
  for (const auto& [sectors, color, alpha] :
       {std::tuple{&figure.bottom, layout::kEngagedColor, 1.0},
        std::tuple{&figure.overlay_bottom, layout::kOverlayColor, layout::kOverlayAlpha}}) {
    for (const BottomSector& s : *sectors) {
      const double r1 = s.r1 * px_per_mm, r0 = s.r0 * px_per_mm;
      double phi0 = s.phi0, phi1 = s.phi1;
      if (r1 <= 0.0) continue;         // a ring of radius 0 has no area to show
      if ((phi1 - phi0) * r1 < 1.0) {  // grazing: one pixel wide at the outer radius
        const double mid = 0.5 * (phi0 + phi1), half = 0.5 / r1;
        phi0 = mid - half;
        phi1 = mid + half;
      }
      cairo_new_sub_path(cr);
      cairo_arc(cr, cx, cy, r1, angle(phi0), angle(phi1));
      if (r0 > 0.0) {
        cairo_arc_negative(cr, cx, cy, r0, angle(phi1), angle(phi0));
      } else {
        cairo_line_to(cr, cx, cy);  // a sector of the innermost ring is a pie slice
      }
      cairo_close_path(cr);
    }
    set_color(cr, color, alpha);
    cairo_fill(cr);
  }

  // Scale circle, angle labels, radius labels.
  set_color(cr, kBlack);
  cairo_new_sub_path(cr);
  cairo_arc(cr, cx, cy, R, 0, kTwoPi);
  cairo_stroke(cr);
  for (int deg = 0; deg < 360; deg += 45) {
    const auto [x, y] = at(degrees_to_radians(deg), R + 16);
    text(cr, x, y + 4, fmt::format("{}°", deg), Anchor::kMiddle, 11);
  }
  for (int k = 1; k * r_step <= figure.polar_scale * (1.0 + kTickSlack); ++k) {
    text(cr, cx - 3, cy - k * r_step * px_per_mm + 11, number(k * r_step), Anchor::kEnd, 10);
  }
  // Feed direction: +x of the tool frame, φ = 90°.
  const double x0 = cx + R + 32, x1 = cx + R + 72;
  cairo_set_line_width(cr, 2);
  line(cr, x0, cy, x1 - 6, cy);
  cairo_stroke(cr);
  cairo_move_to(cr, x1, cy);
  cairo_line_to(cr, x1 - 10, cy - 5);
  cairo_line_to(cr, x1 - 10, cy + 5);
  cairo_close_path(cr);
  cairo_fill(cr);
  cairo_set_line_width(cr, 1);
  text(cr, 0.5 * (x0 + x1), cy - 9, "feed", Anchor::kMiddle, 12);

  if (figure.bottom.empty()) {
    note(cr, cx, cy + R + 46, "no bottom engagement");
  }
}

void draw_map(cairo_t* cr, const MapFigure& figure) {
  white_background(cr, layout::kMapWidth, layout::kMapHeight);
  set_color(cr, kBlack);
  text(cr, 0.5 * layout::kMapWidth, 34, figure.title, Anchor::kMiddle, 17, true);
  draw_side_panel(cr, figure);
  if (figure.has_rings) draw_bottom_panel(cr, figure);
  if (!figure.overlay_label.empty()) {
    // Legend of the two maps, under the title.
    double x = 0.5 * layout::kMapWidth -
               0.5 * (text_width(cr, figure.label) + text_width(cr, figure.overlay_label) + 100);
    for (const auto& [name, color, alpha] :
         {std::tuple{&figure.label, layout::kEngagedColor, 1.0},
          std::tuple{&figure.overlay_label, layout::kOverlayColor, layout::kOverlayAlpha}}) {
      set_color(cr, color, alpha);
      cairo_rectangle(cr, x, 46, 14, 10);
      cairo_fill(cr);
      set_color(cr, kBlack);
      text(cr, x + 20, 56, *name);
      x += 20 + text_width(cr, *name) + 30;
    }
  }
}

// ---------------------------------------------------------------------------------------------
// The path figure.

void draw_path(cairo_t* cr, const std::vector<PathPlotPoint>& points, const std::string& title) {
  const double left = layout::kPathLeft, top = layout::kPathTop;
  const double width = layout::kPathPlotWidth, height = layout::kPathPlotHeight;
  const double right = left + width, bottom = top + height;

  // Drawing order: by CL.
  std::vector<std::size_t> order(points.size());
  std::iota(order.begin(), order.end(), std::size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return points[a].cl < points[b].cl; });

  // Axes' ranges.
  double cl_min = 0.0, cl_max = 1.0;
  if (!points.empty()) {
    cl_min = points[order.front()].cl;
    cl_max = points[order.back()].cl;
    if (cl_max == cl_min) {  // one CL (or all the same): centre it
      cl_min -= 1.0;
      cl_max += 1.0;
    }
  }
  double deepest = 0.0;
  std::size_t engaged_count = 0;
  for (const PathPlotPoint& p : points) {
    if (!p.engaged) continue;
    ++engaged_count;
    deepest = std::max(deepest, p.axial_depth_mm);
  }
  const double depth_step = nice_step(std::max(deepest, 1.0), 5);
  const double depth_top = std::max(1.0, round_up(deepest, depth_step));

  const auto X = [&](double cl) { return left + (cl - cl_min) / (cl_max - cl_min) * width; };
  const auto Y_angle = [&](double deg) {
    return bottom - std::clamp(deg, 0.0, 360.0) / 360.0 * height;
  };
  const auto Y_depth = [&](double mm) {
    return bottom - std::clamp(mm, 0.0, depth_top) / depth_top * height;
  };
  const double cl_step = nice_step(cl_max - cl_min, 10, true);
  const double first_cl_tick = std::ceil(cl_min / cl_step - kTickSlack) * cl_step;
  const int cl_ticks =
      static_cast<int>(std::floor((cl_max - first_cl_tick) / cl_step + kTickSlack));

  white_background(cr, layout::kPathWidth, layout::kPathHeight);
  set_color(cr, kBlack);
  text(cr, left, 30, title, Anchor::kStart, 17, true);

  // Grid.
  set_color(cr, kGridColor);
  cairo_set_line_width(cr, 1);
  for (int deg = 45; deg < 360; deg += 45) line(cr, left, Y_angle(deg), right, Y_angle(deg));
  for (int k = 0; k <= cl_ticks; ++k) {
    const double x = X(first_cl_tick + k * cl_step);
    line(cr, x, top, x, bottom);
  }
  cairo_stroke(cr);
  // The frame under the data: points at the first and last CL sit on it.
  set_color(cr, kBlack);
  cairo_rectangle(cr, left, top, width, height);
  cairo_stroke(cr);

  // Depth: a line through runs of consecutive engaged CLs, thinned per pixel column to the first,
  // lowest, highest and last point (what a raster can show), so that a long path is a short
  // path in the file. A run of one CL is a dot (a zero-length segment with round caps).
  cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
  cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
  std::size_t i = 0;
  while (i < order.size()) {
    if (!points[order[i]].engaged) {
      ++i;
      continue;
    }
    std::size_t end = i;
    while (end < order.size() && points[order[end]].engaged) ++end;
    bool first_vertex = true;
    std::size_t c = i;
    while (c < end) {
      const long pixel = std::lround(X(points[order[c]].cl));
      std::size_t c_end = c;
      std::size_t low = c, high = c;  // min and max depth in the column
      while (c_end < end && std::lround(X(points[order[c_end]].cl)) == pixel) {
        if (points[order[c_end]].axial_depth_mm < points[order[low]].axial_depth_mm) low = c_end;
        if (points[order[c_end]].axial_depth_mm > points[order[high]].axial_depth_mm) high = c_end;
        ++c_end;
      }
      std::size_t kept[] = {c, std::min(low, high), std::max(low, high), c_end - 1};
      for (std::size_t k = 0; k < 4; ++k) {
        if (k > 0 && kept[k] == kept[k - 1]) continue;
        const PathPlotPoint& p = points[order[kept[k]]];
        const double x = X(p.cl), y = Y_depth(p.axial_depth_mm);
        if (first_vertex) {
          cairo_move_to(cr, x, y);
          cairo_line_to(cr, x, y);  // the dot of a one-CL run; harmless otherwise
          first_vertex = false;
        } else {
          cairo_line_to(cr, x, y);
        }
      }
      c = c_end;
    }
    i = end;
  }
  set_color(cr, layout::kDepthColor);
  cairo_set_line_width(cr, 1.5);
  cairo_stroke(cr);
  cairo_set_line_cap(cr, CAIRO_LINE_CAP_BUTT);
  cairo_set_line_width(cr, 1);

  // Entry and exit markers: squares, at most one per pixel and colour; smaller when there are
  // many, so that dense stretches read as curves.
  const double marker = engaged_count <= 500 ? 5.0 : 3.0;
  const auto draw_markers = [&](unsigned color, auto angle_of) {
    const std::size_t columns = static_cast<std::size_t>(width) + 1;
    const std::size_t rows = static_cast<std::size_t>(height) + 1;
    std::vector<bool> taken(engaged_count > 0 ? columns * rows : 0, false);
    for (const PathPlotPoint& p : points) {
      if (!p.engaged) continue;
      const double x = X(p.cl), y = Y_angle(angle_of(p));
      const auto column_index = static_cast<std::size_t>(
          std::clamp(std::lround(x - left), 0L, static_cast<long>(columns - 1)));
      const auto row_index = static_cast<std::size_t>(
          std::clamp(std::lround(y - top), 0L, static_cast<long>(rows - 1)));
      const std::size_t cell = row_index * columns + column_index;
      if (taken[cell]) continue;
      taken[cell] = true;
      cairo_rectangle(cr, x - 0.5 * marker, y - 0.5 * marker, marker, marker);
    }
    set_color(cr, color);
    cairo_fill(cr);
  };
  draw_markers(layout::kEntryColor, [](const PathPlotPoint& p) { return p.phi_entry_deg; });
  draw_markers(layout::kExitColor, [](const PathPlotPoint& p) { return p.phi_exit_deg; });

  // Ticks, labels.
  set_color(cr, kBlack);
  for (int deg = 0; deg <= 360; deg += 45) {
    line(cr, left - 4, Y_angle(deg), left, Y_angle(deg));
    text(cr, left - 7, Y_angle(deg) + 4, std::to_string(deg), Anchor::kEnd);
  }
  for (int k = 0; k <= cl_ticks; ++k) {
    const double cl = first_cl_tick + k * cl_step;
    line(cr, X(cl), bottom, X(cl), bottom + 4);
    text(cr, X(cl), bottom + 18, fmt::format("{:.0f}", cl), Anchor::kMiddle);
  }
  cairo_stroke(cr);
  set_color(cr, layout::kDepthColor);
  for (int k = 0; k <= step_count(depth_top, depth_step); ++k) {
    const double y = Y_depth(k * depth_step);
    line(cr, right, y, right + 4, y);
    text(cr, right + 7, y + 4, number(k * depth_step));
  }
  cairo_stroke(cr);
  set_color(cr, kBlack);
  text(cr, left + 0.5 * width, bottom + 42, "CL index", Anchor::kMiddle, 13);
  text(cr, 28, top + 0.5 * height, "entry / exit angle φ (deg)", Anchor::kMiddle, 13, false,
       -0.5 * kPi);
  set_color(cr, layout::kDepthColor);
  text(cr, right + 70, top + 0.5 * height, "axial depth (mm)", Anchor::kMiddle, 13, false,
       0.5 * kPi);

  // Legend, right-aligned above the plot.
  const std::string labels[] = {"entry φ (deg)", "exit φ (deg)", "axial depth (mm)"};
  const unsigned colors[] = {layout::kEntryColor, layout::kExitColor, layout::kDepthColor};
  double legend_width = 0.0;
  for (const std::string& l : labels) legend_width += 22 + text_width(cr, l) + 18;
  double x = right - legend_width + 18;
  const double y = top - 14;
  for (int k = 0; k < 3; ++k) {
    set_color(cr, colors[k]);
    if (k < 2) {
      cairo_rectangle(cr, x + 5, y - 6, 6, 6);
      cairo_fill(cr);
    } else {
      cairo_set_line_width(cr, 2);
      line(cr, x, y - 3, x + 16, y - 3);
      cairo_stroke(cr);
      cairo_set_line_width(cr, 1);
    }
    set_color(cr, kBlack);
    text(cr, x + 22, y, labels[k]);
    x += 22 + text_width(cr, labels[k]) + 18;
  }

  if (engaged_count == 0) {
    note(cr, left + 0.5 * width, top + 0.5 * height,
         points.empty() ? "no cutter locations" : "no engaged cutter locations");
  }
}

void validate_path(const std::vector<PathPlotPoint>& points) {
  for (const PathPlotPoint& p : points) {
    if (!p.engaged) continue;
    if (!std::isfinite(p.phi_entry_deg) || !std::isfinite(p.phi_exit_deg) ||
        !std::isfinite(p.axial_depth_mm)) {
      throw InputError(fmt::format(
          "engagement path plot: CL {} has a non-finite entry angle, exit angle or depth", p.cl));
    }
  }
}

}  // namespace

namespace plot_layout {

double depth_axis_top(const EngagementMap& map, const MapPlotInfo& info) {
  return prepare_map(map, info).depth_top;
}

}  // namespace plot_layout

std::string engagement_map_png(const EngagementMap& map, const MapPlotInfo& info) {
  const MapFigure figure = prepare_map(map, info);
  return render_png(layout::kMapWidth, layout::kMapHeight,
                    [&](cairo_t* cr) { draw_map(cr, figure); });
}

std::string engagement_map_svg(const EngagementMap& map, const MapPlotInfo& info) {
  const MapFigure figure = prepare_map(map, info);
  return render_svg(layout::kMapWidth, layout::kMapHeight,
                    [&](cairo_t* cr) { draw_map(cr, figure); });
}

std::string engagement_path_png(const std::vector<PathPlotPoint>& points,
                                const std::string& title) {
  validate_path(points);
  return render_png(layout::kPathWidth, layout::kPathHeight,
                    [&](cairo_t* cr) { draw_path(cr, points, title); });
}

std::string engagement_path_svg(const std::vector<PathPlotPoint>& points,
                                const std::string& title) {
  validate_path(points);
  return render_svg(layout::kPathWidth, layout::kPathHeight,
                    [&](cairo_t* cr) { draw_path(cr, points, title); });
}

}  // namespace cwe

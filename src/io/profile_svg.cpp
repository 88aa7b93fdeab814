#include "cwe/io/profile_svg.hpp"

#include "patch_style.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include <fmt/format.h>

namespace cwe {
using io_detail::patch_color;
using io_detail::xml_escape;

std::string profile_svg(const Cutter& cutter) {
  const Profile& profile = cutter.profile();
  const double radius = std::max(profile.max_radius(), cutter.shank().diameter / 2.0);
  const double height = profile.height() + cutter.shank().length;
  // Drawing area: 360 px wide at most, 520 px high at most, margins for labels.
  const double scale = std::min(300.0 / (2.0 * radius), 460.0 / height);
  const double width_px = 2.0 * radius * scale + 260.0;
  const double height_px = height * scale + 110.0;
  const double axis_x = 40.0 + radius * scale;
  const double tip_y = height_px - 50.0;
  const auto X = [&](double rho) { return axis_x + rho * scale; };
  const auto Y = [&](double z) { return tip_y - z * scale; };

  std::string svg = fmt::format(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{:.0f}\" height=\"{:.0f}\" "
      "viewBox=\"0 0 {:.0f} {:.0f}\" font-family=\"sans-serif\" font-size=\"12\">\n"
      "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n",
      width_px, height_px, width_px, height_px);
  svg += fmt::format("<text x=\"10\" y=\"20\" font-size=\"14\" font-weight=\"bold\">{}</text>\n",
                     xml_escape(cutter.name()));

  // Shank (not cutting), dashed.
  const double shank_r = cutter.shank().diameter / 2.0;
  const double z0 = profile.height();
  const double z1 = profile.height() + cutter.shank().length;
  svg += fmt::format(
      "<polygon points=\"{:.2f},{:.2f} {:.2f},{:.2f} {:.2f},{:.2f} {:.2f},{:.2f}\" "
      "fill=\"#eeeeee\" "
      "stroke=\"#888888\" stroke-dasharray=\"4 3\"/>\n",
      X(-shank_r), Y(z0), X(-shank_r), Y(z1), X(shank_r), Y(z1), X(shank_r), Y(z0));

  // Solid silhouette, filled, then each patch stroked in its colour on both sides.
  std::vector<Vec2> outline;
  for (const auto& s : profile.segments()) {
    const int steps = s.kind == ProfileSegment::Kind::kArc ? 48 : 1;
    for (int k = outline.empty() ? 0 : 1; k <= steps; ++k)
      outline.push_back(s.point_at(double(k) / steps));
  }
  std::string points;
  for (const Vec2& p : outline) points += fmt::format("{:.2f},{:.2f} ", X(p.x()), Y(p.y()));
  for (auto it = outline.rbegin(); it != outline.rend(); ++it) {
    points += fmt::format("{:.2f},{:.2f} ", X(-it->x()), Y(it->y()));
  }
  svg += fmt::format("<polygon points=\"{}\" fill=\"#dde6f0\" stroke=\"none\"/>\n", points);
  for (const CutterPatch& patch : cutter.patches()) {
    const ProfileSegment& s = profile.segments()[static_cast<std::size_t>(patch.segment)];
    const int steps = s.kind == ProfileSegment::Kind::kArc ? 48 : 1;
    for (const double side : {1.0, -1.0}) {
      std::string line;
      for (int k = 0; k <= steps; ++k) {
        const Vec2 p = s.point_at(double(k) / steps);
        line += fmt::format("{:.2f},{:.2f} ", X(side * p.x()), Y(p.y()));
      }
      svg += fmt::format(
          "<polyline points=\"{}\" fill=\"none\" stroke=\"{}\" stroke-width=\"2.5\"/>\n", line,
          patch_color(patch.kind));
    }
  }
  // Top edge of the cutting part.
  svg += fmt::format(
      "<line x1=\"{:.2f}\" y1=\"{:.2f}\" x2=\"{:.2f}\" y2=\"{:.2f}\" stroke=\"#444\"/>\n",
      X(-profile.top_radius()), Y(z0), X(profile.top_radius()), Y(z0));
  // Axis and tip.
  svg += fmt::format(
      "<line x1=\"{0:.2f}\" y1=\"{1:.2f}\" x2=\"{0:.2f}\" y2=\"{2:.2f}\" stroke=\"#555\" "
      "stroke-dasharray=\"8 3 2 3\"/>\n",
      axis_x, tip_y + 8.0, Y(height) - 10.0);
  svg +=
      fmt::format("<circle cx=\"{:.2f}\" cy=\"{:.2f}\" r=\"3\" fill=\"black\"/>\n", axis_x, tip_y);
  svg += fmt::format("<text x=\"{:.2f}\" y=\"{:.2f}\" text-anchor=\"middle\">tip (0, 0)</text>\n",
                     axis_x, tip_y + 20.0);

  // Legend and dimensions, right of the drawing.
  double y = 50.0;
  const double lx = X(radius) + 30.0;
  const auto label = [&](const std::string& text, const char* color = "black") {
    svg += fmt::format("<text x=\"{:.2f}\" y=\"{:.2f}\" fill=\"{}\">{}</text>\n", lx, y, color,
                       xml_escape(text));
    y += 18.0;
  };
  label(fmt::format("diameter {:g} mm", cutter.diameter()));
  label(fmt::format("cutting length {:g} mm", cutter.flute_length()));
  label(fmt::format("{} flutes, helix {:g}°", cutter.flutes(),
                    radians_to_degrees(cutter.helix_angle())));
  label(fmt::format("shank {:g} × {:g} mm", cutter.shank().diameter, cutter.shank().length));
  if (cutter.apt()) label(to_string(*cutter.apt()));
  y += 10.0;
  for (const CutterPatch& patch : cutter.patches()) {
    label(fmt::format("■ {} (z {:g}–{:g})", to_string(patch.kind), patch.bounds.z_min,
                      patch.bounds.z_max),
          patch_color(patch.kind));
  }
  svg += "</svg>\n";
  return svg;
}

}  // namespace cwe

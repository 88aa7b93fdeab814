#include "cwe/io/fcs_svg.hpp"

#include <algorithm>
#include <vector>

#include <fmt/format.h>

#include "patch_style.hpp"

namespace cwe {

std::string fcs_svg(const Cutter& cutter, const FeasibleContactSurface& fcs,
                    const std::string& title) {
  using io_detail::patch_color;
  // Profile arc length at the start of each piece.
  std::vector<double> start{0.0};
  for (const auto& s : cutter.profile().segments()) start.push_back(start.back() + s.length());
  const double total = start.back();
  const double width = 720.0, height = 420.0, left = 60.0, top = 40.0;
  const auto X = [&](double phi) { return left + phi / kTwoPi * width; };
  const auto Y = [&](double s) { return top + height - s / total * height; };

  std::string svg = fmt::format(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{:.0f}\" height=\"{:.0f}\" "
      "font-family=\"sans-serif\" font-size=\"12\">\n<rect width=\"100%\" height=\"100%\" "
      "fill=\"white\"/>\n<text x=\"{}\" y=\"22\" font-size=\"14\" font-weight=\"bold\">{}</text>\n",
      left + width + 170, top + height + 60, left, io_detail::xml_escape(title));
  // Feasible bands: each section covers the profile between the midpoints to its neighbours.
  for (std::size_t i = 0; i < fcs.sections.size(); ++i) {
    const FcsSection& section = fcs.sections[i];
    const auto& segment = cutter.profile().segments()[static_cast<std::size_t>(section.patch)];
    const double s = start[static_cast<std::size_t>(section.patch)] + section.u * segment.length();
    const auto s_of = [&](std::size_t k) {
      const FcsSection& o = fcs.sections[k];
      return start[static_cast<std::size_t>(o.patch)] +
             o.u * cutter.profile().segments()[static_cast<std::size_t>(o.patch)].length();
    };
    const double below =
        i > 0 && fcs.sections[i - 1].patch == section.patch ? 0.5 * (s + s_of(i - 1)) : s;
    const double above = i + 1 < fcs.sections.size() && fcs.sections[i + 1].patch == section.patch
                             ? 0.5 * (s + s_of(i + 1))
                             : s;
    const double y0 = Y(above), y1 = std::max(Y(below), y0 + 1.0);
    for (const Interval& phi : section.phi) {
      svg += fmt::format(
          "<rect x=\"{:.2f}\" y=\"{:.2f}\" width=\"{:.2f}\" height=\"{:.2f}\" fill=\"{}\" "
          "fill-opacity=\"0.55\"/>\n",
          X(phi.lo), y0, std::max(X(phi.hi) - X(phi.lo), 1.0), y1 - y0,
          patch_color(cutter.patches()[static_cast<std::size_t>(section.patch)].kind));
    }
  }
  // Frame, φ axis ticks, the front/back divide, patch boundaries.
  svg += fmt::format(
      "<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"none\" stroke=\"black\"/>\n", left,
      top, width, height);
  for (int deg = 0; deg <= 360; deg += 45) {
    const double x = X(kTwoPi * deg / 360.0);
    svg += fmt::format(
        "<line x1=\"{0:.2f}\" y1=\"{1:.2f}\" x2=\"{0:.2f}\" y2=\"{2:.2f}\" stroke=\"#999\" "
        "stroke-dasharray=\"{3}\"/>\n",
        x, top, top + height, deg == 180 ? "6 3" : "1 3");
    svg += fmt::format("<text x=\"{:.2f}\" y=\"{:.2f}\" text-anchor=\"middle\">{}</text>\n", x,
                       top + height + 16, deg);
  }
  svg += fmt::format(
      "<text x=\"{:.2f}\" y=\"{:.2f}\" text-anchor=\"middle\">engagement angle φ (deg): front "
      "0–180, back 180–360</text>\n",
      left + width / 2, top + height + 36);
  for (std::size_t p = 0; p < cutter.patches().size(); ++p) {
    const double y = Y(start[p]);
    svg += fmt::format("<line x1=\"{}\" y1=\"{:.2f}\" x2=\"{}\" y2=\"{:.2f}\" stroke=\"black\"/>\n",
                       left, y, left + width, y);
    const double mid = Y(0.5 * (start[p] + start[p + 1]));
    svg += fmt::format("<text x=\"{:.2f}\" y=\"{:.2f}\" fill=\"{}\">{}{}{}</text>\n",
                       left + width + 8, mid + 4, patch_color(cutter.patches()[p].kind),
                       to_string(cutter.patches()[p].kind), fcs.front[p] ? " · front" : "",
                       fcs.back[p] ? " · back" : "");
  }
  svg += fmt::format(
      "<text x=\"16\" y=\"{:.2f}\" transform=\"rotate(-90 16 {:.2f})\" "
      "text-anchor=\"middle\">profile from the tip (mm)</text>\n",
      top + height / 2, top + height / 2);
  svg += fmt::format("<text x=\"{:.2f}\" y=\"{:.2f}\" text-anchor=\"end\">0</text>\n", left - 4,
                     Y(0) + 4);
  svg += fmt::format("<text x=\"{:.2f}\" y=\"{:.2f}\" text-anchor=\"end\">{:.3g}</text>\n",
                     left - 4, Y(total) + 4, total);
  svg += "</svg>\n";
  return svg;
}

}  // namespace cwe

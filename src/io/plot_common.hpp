#pragma once
// The cairo plumbing and drawing helpers shared by the figures of io (engagement maps, path
// plots, force curves); private to io.
//
// A figure is one drawing routine, `draw(cr)`, rendered onto an image surface (PNG) or an SVG
// surface, so both outputs show the same picture; SVG user units are the PNG's pixels. Cairo
// failures (out of memory) throw std::runtime_error.

#include <functional>
#include <string>

#include <cairo.h>

namespace cwe::io_detail {

using DrawFigure = std::function<void(cairo_t*)>;

// The figure's PNG (RGB24) or SVG 1.1 file bytes.
std::string render_png(int width, int height, const DrawFigure& draw);
std::string render_svg(int width, int height, const DrawFigure& draw);

// Cairo writes text as glyph outlines, so an SVG figure holds none of its words. This adds a
// <title> and a <desc> (XML-escaped) as the first children of the root <svg> element, for
// viewers, screen readers and search; `svg` must be a document from render_svg.
std::string with_svg_text(const std::string& svg, const std::string& title,
                          const std::string& description);

// Tick arithmetic works on numbers of a few significant digits: this much relative slack keeps
// 3.0000000000000004 mm from being rounded up to the next tick.
inline constexpr double kTickSlack = 1e-9;

// Colours, 0xRRGGBB, of the parts every figure has.
inline constexpr unsigned kBlack = 0x000000;
inline constexpr unsigned kGridColor = 0xdddddd;
inline constexpr unsigned kNoteColor = 0x777777;
inline constexpr unsigned kDivideColor = 0x555555;

void set_color(cairo_t* cr, unsigned rgb, double alpha = 1.0);

enum class Anchor { kStart, kMiddle, kEnd };

// Text with its baseline at y; `angle` (radians, cairo's sense: clockwise on screen) turns it
// about (x, y), -π/2 for a vertical axis label read bottom to top.
void text(cairo_t* cr, double x, double y, const std::string& s, Anchor anchor = Anchor::kStart,
          double size = 12, bool bold = false, double angle = 0);

// Advance width of `s` in the normal sans-serif face of `size`.
double text_width(cairo_t* cr, const std::string& s, double size = 12);

// A grey remark centred at (x, y) on a white box, readable over grid lines.
void note(cairo_t* cr, double x, double y, const std::string& s);

// Adds the segment to the current path (stroked by the caller).
void line(cairo_t* cr, double x0, double y0, double x1, double y1);

void white_background(cairo_t* cr, int width, int height);

// Step of a 1-2-2.5-5 (or 1-2-5 and at least 1 when `integral`) sequence giving about `ticks`
// intervals over `range` (> 0); 1 when range / ticks is not positive.
double nice_step(double range, int ticks, bool integral = false);

// The smallest multiple of `step` at or above value (>= 0).
double round_up(double value, double step);

// Number of whole steps in [0, top].
int step_count(double top, double step);

// A tick label: `v` with up to 6 significant digits, no trailing zeros.
std::string number(double v);

}  // namespace cwe::io_detail

#include "plot_common.hpp"

#include <algorithm>
#include <cmath>
#include <csetjmp>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <vector>

#include <cairo-svg.h>
#include <fmt/format.h>
#include <png.h>

#include "patch_style.hpp"

namespace cwe::io_detail {
namespace {

// ---------------------------------------------------------------------------------------------
// Cairo plumbing: one drawing routine, two surfaces.

struct SurfaceDeleter {
  void operator()(cairo_surface_t* s) const { cairo_surface_destroy(s); }
};
struct ContextDeleter {
  void operator()(cairo_t* c) const { cairo_destroy(c); }
};
using SurfacePtr = std::unique_ptr<cairo_surface_t, SurfaceDeleter>;
using ContextPtr = std::unique_ptr<cairo_t, ContextDeleter>;

// Cairo's stream callback; must not throw through C.
cairo_status_t append_to_string(void* closure, const unsigned char* data, unsigned int length) {
  try {
    static_cast<std::string*>(closure)->append(reinterpret_cast<const char*>(data), length);
    return CAIRO_STATUS_SUCCESS;
  } catch (...) {
    return CAIRO_STATUS_WRITE_ERROR;
  }
}

void check(cairo_status_t status, const char* what) {
  if (status != CAIRO_STATUS_SUCCESS) {
    throw std::runtime_error(fmt::format("{}: cairo: {}", what, cairo_status_to_string(status)));
  }
}

// libpng's write callback: appends to the std::string behind the io pointer (must not throw
// through C: a failed append is reported through png_error, which longjmps to encode_png).
void append_png(png_structp png, png_bytep data, png_size_t length) {
  try {
    static_cast<std::string*>(png_get_io_ptr(png))
        ->append(reinterpret_cast<const char*>(data), length);
  } catch (...) {
    png_error(png, "out of memory");
  }
}

// The PNG of a cairo RGB24 image (native-endian 0x00RRGGBB words): 8-bit RGB with a white
// background chunk, as cairo writes it, but with the "up" filter on every row and zlib level 3
// instead of libpng's per-row trial of all five filters at level 6. Cairo's way took about
// 250 M instructions for a 1000 × 600 map, more than the engagement of a thousand cutter
// locations; this takes a fifth of that for files about a tenth larger (a plot's flat colours
// repeat from row to row).
std::string encode_png(const unsigned char* data, int stride, int width, int height) {
  std::string bytes;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png != nullptr ? png_create_info_struct(png) : nullptr;
  if (info == nullptr) {
    png_destroy_write_struct(&png, nullptr);
    throw std::runtime_error("PNG figure: libpng: out of memory");
  }
  std::vector<png_byte> row(static_cast<std::size_t>(width) * 3);
  // No C++ object with a destructor is created between here and the last libpng call.
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    throw std::runtime_error("PNG figure: libpng could not encode it");
  }
  png_set_write_fn(png, &bytes, append_png, nullptr);
  png_set_IHDR(png, info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height), 8,
               PNG_COLOR_TYPE_RGB, PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT,
               PNG_FILTER_TYPE_DEFAULT);
  png_color_16 white{};
  white.red = white.green = white.blue = white.gray = 0xFF;
  png_set_bKGD(png, info, &white);
  png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_UP);
  png_set_compression_level(png, 3);
  png_write_info(png, info);
  for (int y = 0; y < height; ++y) {
    const auto* pixels = reinterpret_cast<const std::uint32_t*>(data + std::ptrdiff_t{y} * stride);
    for (int x = 0; x < width; ++x) {
      const std::uint32_t p = pixels[x];
      row[3 * static_cast<std::size_t>(x)] = static_cast<png_byte>(p >> 16);
      row[3 * static_cast<std::size_t>(x) + 1] = static_cast<png_byte>(p >> 8);
      row[3 * static_cast<std::size_t>(x) + 2] = static_cast<png_byte>(p);
    }
    png_write_row(png, row.data());
  }
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return bytes;
}

}  // namespace

std::string render_png(int width, int height, const DrawFigure& draw) {
  const SurfacePtr surface{cairo_image_surface_create(CAIRO_FORMAT_RGB24, width, height)};
  check(cairo_surface_status(surface.get()), "PNG figure");
  {
    const ContextPtr cr{cairo_create(surface.get())};
    draw(cr.get());
    check(cairo_status(cr.get()), "PNG figure");
  }
  cairo_surface_flush(surface.get());
  return encode_png(cairo_image_surface_get_data(surface.get()),
                    cairo_image_surface_get_stride(surface.get()), width, height);
}

namespace {

// Cairo numbers its surfaces across the process ("surface586"), so a figure's ids depended on how
// many figures were drawn before it, and on their timing when figures are drawn on several
// threads. Renumbered from 1 in order of appearance (references follow, being the same token),
// the same figure gives the same bytes.
std::string renumber_surfaces(const std::string& svg) {
  constexpr std::string_view kToken = "surface";
  std::vector<std::string> seen;
  std::string out;
  out.reserve(svg.size());
  std::size_t at = 0;
  for (std::size_t found = svg.find(kToken); found != std::string::npos;
       found = svg.find(kToken, at)) {
    std::size_t end = found + kToken.size();
    while (end < svg.size() && svg[end] >= '0' && svg[end] <= '9') ++end;
    out.append(svg, at, found + kToken.size() - at);
    at = end;
    if (end == found + kToken.size()) continue;  // the word without a number
    const std::string number = svg.substr(found + kToken.size(), end - found - kToken.size());
    const auto index =
        static_cast<std::size_t>(std::find(seen.begin(), seen.end(), number) - seen.begin());
    if (index == seen.size()) seen.push_back(number);
    out += std::to_string(index + 1);
  }
  out.append(svg, at, std::string::npos);
  return out;
}

}  // namespace

std::string render_svg(int width, int height, const DrawFigure& draw) {
  std::string bytes;
  const SurfacePtr surface{
      cairo_svg_surface_create_for_stream(append_to_string, &bytes, width, height)};
  check(cairo_surface_status(surface.get()), "SVG figure");
  // Unitless width and height: SVG user units, the same numbers as the PNG's pixels.
  cairo_svg_surface_set_document_unit(surface.get(), CAIRO_SVG_UNIT_USER);
  cairo_svg_surface_restrict_to_version(surface.get(), CAIRO_SVG_VERSION_1_1);
  {
    const ContextPtr cr{cairo_create(surface.get())};
    draw(cr.get());
    check(cairo_status(cr.get()), "SVG figure");
  }
  cairo_surface_finish(surface.get());  // writes the document's end
  check(cairo_surface_status(surface.get()), "SVG figure");
  return renumber_surfaces(bytes);
}

std::string with_svg_text(const std::string& svg, const std::string& title,
                          const std::string& description) {
  const std::size_t root = svg.find("<svg");
  const std::size_t root_end = root == std::string::npos ? root : svg.find('>', root);
  if (root_end == std::string::npos) {
    throw std::runtime_error("SVG figure: cairo wrote no <svg> element");
  }
  std::string out;
  out.reserve(svg.size() + title.size() + description.size() + 40);
  out.append(svg, 0, root_end + 1);
  out += "\n<title>" + xml_escape(title) + "</title>\n<desc>" + xml_escape(description) + "</desc>";
  out.append(svg, root_end + 1);
  return out;
}

// ---------------------------------------------------------------------------------------------
// Drawing helpers.

void set_color(cairo_t* cr, unsigned rgb, double alpha) {
  cairo_set_source_rgba(cr, ((rgb >> 16) & 0xff) / 255.0, ((rgb >> 8) & 0xff) / 255.0,
                        (rgb & 0xff) / 255.0, alpha);
}

void text(cairo_t* cr, double x, double y, const std::string& s, Anchor anchor, double size,
          bool bold, double angle) {
  cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL,
                         bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, size);
  cairo_text_extents_t extents;
  cairo_text_extents(cr, s.c_str(), &extents);
  const double dx = anchor == Anchor::kStart    ? 0.0
                    : anchor == Anchor::kMiddle ? -0.5 * extents.x_advance
                                                : -extents.x_advance;
  // Text leaves the path as it found it: lines queued before a label (tick marks) are still
  // stroked by the caller afterwards.
  cairo_path_t* queued = cairo_copy_path(cr);
  cairo_save(cr);
  cairo_translate(cr, x, y);
  cairo_rotate(cr, angle);
  cairo_move_to(cr, dx, 0);
  cairo_show_text(cr, s.c_str());
  cairo_new_path(cr);
  cairo_restore(cr);
  if (queued->status == CAIRO_STATUS_SUCCESS) cairo_append_path(cr, queued);
  cairo_path_destroy(queued);
}

double text_width(cairo_t* cr, const std::string& s, double size) {
  cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, size);
  cairo_text_extents_t extents;
  cairo_text_extents(cr, s.c_str(), &extents);
  return extents.x_advance;
}

void note(cairo_t* cr, double x, double y, const std::string& s) {
  const double size = 14, w = text_width(cr, s, size);
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_rectangle(cr, x - 0.5 * w - 6, y - size, w + 12, size + 8);
  cairo_fill(cr);
  set_color(cr, kNoteColor);
  text(cr, x, y, s, Anchor::kMiddle, size);
}

void line(cairo_t* cr, double x0, double y0, double x1, double y1) {
  cairo_move_to(cr, x0, y0);
  cairo_line_to(cr, x1, y1);
}

void white_background(cairo_t* cr, int width, int height) {
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_rectangle(cr, 0, 0, width, height);
  cairo_fill(cr);
}

double nice_step(double range, int ticks, bool integral) {
  const double raw = range / ticks;
  if (!(raw > 0.0)) return 1.0;
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  for (double m : {1.0, 2.0, 2.5, 5.0, 10.0}) {
    if (integral && m == 2.5 && magnitude < 10.0) continue;
    if (m * magnitude >= raw * (1.0 - kTickSlack))
      return integral ? std::max(1.0, m * magnitude) : m * magnitude;
  }
  return integral ? std::max(1.0, 10.0 * magnitude) : 10.0 * magnitude;
}

double round_up(double value, double step) {
  return std::max(0.0, std::ceil(value / step - kTickSlack)) * step;
}

int step_count(double top, double step) {
  return static_cast<int>(std::floor(top / step + kTickSlack));
}

std::string number(double v) { return fmt::format("{:g}", v); }

}  // namespace cwe::io_detail

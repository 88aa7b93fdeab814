#pragma once
// Helpers shared by the plot tests: a decoded PNG to look at pixels, file-signature checks, an
// XML well-nestedness check.

#include <cairo.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

namespace cwe::test {

// A decoded PNG (cairo image surface, RGB24 or ARGB32 on an opaque background).
class Image {
 public:
  explicit Image(const std::string& png) {
    Reader reader{png, 0};
    surface_.reset(cairo_image_surface_create_from_png_stream(&Reader::read, &reader));
    cairo_surface_flush(surface_.get());
  }
  bool ok() const { return cairo_surface_status(surface_.get()) == CAIRO_STATUS_SUCCESS; }
  int width() const { return cairo_image_surface_get_width(surface_.get()); }
  int height() const { return cairo_image_surface_get_height(surface_.get()); }
  // 0xRRGGBB of the pixel whose area contains (x, y).
  unsigned rgb(double x, double y) const {
    const unsigned char* data = cairo_image_surface_get_data(surface_.get());
    const int stride = cairo_image_surface_get_stride(surface_.get());
    const auto column = static_cast<int>(std::floor(x));
    const auto row = static_cast<int>(std::floor(y));
    std::uint32_t pixel = 0;
    std::memcpy(&pixel, data + row * stride + column * 4, sizeof pixel);
    return pixel & 0xffffffu;
  }
  // Pixels of exactly `color` in the rows [row0, row1) and columns [column0, column1); the whole
  // image by default.
  int count(unsigned color, int column0 = 0, int row0 = 0, int column1 = -1, int row1 = -1) const {
    if (column1 < 0) column1 = width();
    if (row1 < 0) row1 = height();
    int n = 0;
    for (int row = row0; row < row1; ++row) {
      for (int column = column0; column < column1; ++column) n += rgb(column, row) == color;
    }
    return n;
  }

 private:
  struct Reader {
    const std::string& bytes;
    std::size_t offset;
    static cairo_status_t read(void* closure, unsigned char* data, unsigned int length) {
      auto* self = static_cast<Reader*>(closure);
      if (self->bytes.size() - self->offset < length) return CAIRO_STATUS_READ_ERROR;
      std::memcpy(data, self->bytes.data() + self->offset, length);
      self->offset += length;
      return CAIRO_STATUS_SUCCESS;
    }
  };
  struct Deleter {
    void operator()(cairo_surface_t* s) const { cairo_surface_destroy(s); }
  };
  std::unique_ptr<cairo_surface_t, Deleter> surface_;
};

inline bool is_png(const std::string& bytes) {
  return bytes.compare(0, 8, std::string("\x89PNG\r\n\x1a\n", 8)) == 0;
}

inline bool is_svg(const std::string& bytes) {
  return (bytes.rfind("<?xml", 0) == 0 || bytes.rfind("<svg", 0) == 0) &&
         bytes.find("</svg>") != std::string::npos;
}

// Whether `bytes` is a well-nested XML document as far as its tags go: one root element, every
// start tag closed by its end tag in order (or self-closing), no stray '<' in text.
// Declarations (<?...?>, <!...>) are skipped; attribute values must not hold '>' (cairo's never
// do).
inline bool xml_tags_balanced(const std::string& bytes) {
  std::vector<std::string> open;
  bool had_root = false;
  std::size_t at = 0;
  while ((at = bytes.find('<', at)) != std::string::npos) {
    const std::size_t end = bytes.find('>', at);
    if (end == std::string::npos) return false;
    const std::string tag = bytes.substr(at + 1, end - at - 1);
    at = end + 1;
    if (tag.empty()) return false;
    if (tag[0] == '?' || tag[0] == '!') continue;
    if (tag[0] == '/') {
      if (open.empty() || open.back() != tag.substr(1)) return false;
      open.pop_back();
      continue;
    }
    if (open.empty() && had_root) return false;  // a second root
    had_root = true;
    if (tag.back() == '/') continue;
    open.push_back(tag.substr(0, tag.find_first_of(" \t\n/")));
  }
  return had_root && open.empty();
}

}  // namespace cwe::test

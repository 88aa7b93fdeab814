#include "cwe/io/mesh_io.hpp"

#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <unordered_map>
#include <vector>

#include <fmt/format.h>
#include <tbb/parallel_pipeline.h>
#include <tbb/task_arena.h>

#include "cwe/core/error.hpp"
#include "cwe/core/text_file.hpp"

namespace cwe {
namespace {

// STL reading ------------------------------------------------------------------------------

constexpr std::size_t kStlHeaderBytes = 80;
constexpr std::size_t kStlPreambleBytes = 84;  // header and the 32-bit triangle count
constexpr std::size_t kStlFacetBytes = 50;     // normal, three corners (12 floats), attribute

// Collects facets into a mesh, welding corners with equal coordinates into one vertex.
class MeshBuilder {
 public:
  // `corners` are finite. Returns false (and counts the facet) when two corners coincide.
  bool add(const std::array<Vec3, 3>& corners) {
    std::array<int, 3> t{};
    for (std::size_t k = 0; k < 3; ++k) t[k] = vertex(corners[k]);
    if (t[0] == t[1] || t[1] == t[2] || t[2] == t[0]) {
      ++degenerate_;
      return false;
    }
    mesh_.triangles.push_back(t);
    return true;
  }
  int degenerate() const { return degenerate_; }
  TriangleMesh take() { return std::move(mesh_); }

 private:
  using Key = std::array<double, 3>;
  struct KeyHash {
    std::size_t operator()(const Key& k) const {
      std::size_t h = 0;
      for (const double x : k) {
        std::uint64_t bits = 0;
        std::memcpy(&bits, &x, sizeof bits);
        h = (h ^ static_cast<std::size_t>(bits)) * 0x100000001b3ull + (h >> 29);
      }
      return h;
    }
  };

  int vertex(const Vec3& p) {
    // Adding +0 turns -0 into +0, so that the two zeros (equal as numbers) weld; keys are then
    // equal exactly when their bits are.
    const Key key{p.x() + 0.0, p.y() + 0.0, p.z() + 0.0};
    const auto [it, inserted] = index_.try_emplace(key, static_cast<int>(mesh_.vertices.size()));
    if (inserted) mesh_.vertices.emplace_back(key[0], key[1], key[2]);
    return it->second;
  }

  TriangleMesh mesh_;
  std::unordered_map<Key, int, KeyHash> index_;
  int degenerate_ = 0;
};

// Checks one coordinate as read (before it becomes a vertex); returns an empty string when it
// is acceptable, else what is wrong with it.
std::string coordinate_problem(double value) {
  if (!std::isfinite(value)) {
    return fmt::format("coordinate {} is not finite: expected a finite number", value);
  }
  if (std::abs(value) > kLargestInputValue) {
    return fmt::format("coordinate {} is out of range: expected at most {} in magnitude", value,
                       kLargestInputValue);
  }
  return {};
}

bool is_blank(char c) {
  return c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '\f' || c == '\v';
}

bool equals_ignoring_case(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    const auto lower = [](char c) { return c >= 'A' && c <= 'Z' ? static_cast<char>(c + 32) : c; };
    if (lower(a[i]) != lower(b[i])) return false;
  }
  return true;
}

// "solid" as the first word of the bytes.
bool starts_with_solid(std::string_view bytes) {
  std::size_t i = 0;
  while (i < bytes.size() && is_blank(bytes[i])) ++i;
  if (bytes.size() - i < 5 || !equals_ignoring_case(bytes.substr(i, 5), "solid")) return false;
  return bytes.size() - i == 5 || is_blank(bytes[i + 5]);
}

std::uint32_t stl_triangle_count(std::string_view bytes) {
  std::uint32_t n = 0;
  std::memcpy(&n, bytes.data() + kStlHeaderBytes, sizeof n);  // little-endian, as written
  return n;
}

// The bytes are a binary STL by size (84 + 50·n) and hold a byte no text file does (a control
// character other than blanks). A binary count below 2²⁴ alone has a zero byte, so every binary
// STL passes the second test; no ASCII STL does.
bool binary_by_content(std::string_view bytes) {
  if (bytes.size() < kStlPreambleBytes) return false;
  const std::uint64_t expected =
      kStlPreambleBytes + std::uint64_t{kStlFacetBytes} * stl_triangle_count(bytes);
  if (expected != bytes.size()) return false;
  for (std::size_t i = kStlHeaderBytes; i < bytes.size(); ++i) {
    const auto c = static_cast<unsigned char>(bytes[i]);
    if ((c < 0x20 && !is_blank(static_cast<char>(c))) || c == 0x7F) return true;
  }
  return false;
}

StlMesh parse_binary_stl(std::string_view bytes, const std::string& source) {
  const SourceLocation where{source};
  if (bytes.size() < kStlPreambleBytes) {
    throw InputError(where, fmt::format("truncated binary STL: {} bytes, expected at least 84 (an "
                                        "80-byte header and the triangle count)",
                                        bytes.size()));
  }
  const std::uint32_t n = stl_triangle_count(bytes);
  const std::uint64_t expected = kStlPreambleBytes + std::uint64_t{kStlFacetBytes} * n;
  if (bytes.size() < expected) {
    throw InputError(
        where, fmt::format("truncated binary STL: the header declares {} triangles, which take 84 "
                           "+ 50·{} = {} bytes, but the file has {} (triangle {} is incomplete)",
                           n, n, expected, bytes.size(),
                           (bytes.size() - kStlPreambleBytes) / kStlFacetBytes + 1));
  }
  if (bytes.size() > expected) {
    throw InputError(where,
                     fmt::format("binary STL has {} bytes after its {} triangles: expected 84 + "
                                 "50·n = {} bytes",
                                 bytes.size() - expected, n, expected));
  }
  if (n > static_cast<std::uint32_t>(std::numeric_limits<int>::max() / 3)) {
    throw InputError(where, fmt::format("binary STL declares {} triangles: expected at most {}", n,
                                        std::numeric_limits<int>::max() / 3));
  }
  MeshBuilder builder;
  for (std::uint32_t k = 0; k < n; ++k) {
    const std::size_t facet = kStlPreambleBytes + std::size_t{kStlFacetBytes} * k;
    std::array<Vec3, 3> corners;
    for (std::size_t v = 0; v < 3; ++v) {
      for (std::size_t axis = 0; axis < 3; ++axis) {
        const std::size_t offset = facet + 12 * (v + 1) + 4 * axis;  // after the normal
        std::uint32_t bits = 0;
        std::memcpy(&bits, bytes.data() + offset, sizeof bits);
        // Classified by its bits: converting a signalling NaN would raise "invalid".
        if ((bits & 0x7F800000u) == 0x7F800000u) {
          throw InputError(where,
                           fmt::format("triangle {} (byte {}): coordinate is {}: expected a "
                                       "finite number",
                                       k + 1, offset, bits & 0x007FFFFFu ? "NaN" : "infinite"));
        }
        float f = 0.0f;
        std::memcpy(&f, &bits, sizeof f);
        const std::string problem = coordinate_problem(f);
        if (!problem.empty()) {
          throw InputError(where, fmt::format("triangle {} (byte {}): {}", k + 1, offset, problem));
        }
        corners[v][static_cast<int>(axis)] = f;
      }
    }
    builder.add(corners);
  }
  StlMesh out;
  out.degenerate_dropped = builder.degenerate();
  out.mesh = builder.take();
  out.binary = true;
  return out;
}

// Whitespace-separated words of an ASCII STL with their line and column (from 1).
class StlWords {
 public:
  struct Word {
    std::string_view text;  // empty at the end of the bytes
    int line = 0;
    int column = 0;
  };

  StlWords(std::string_view text, const std::string& source) : text_(text), source_(source) {}

  Word next() {
    while (position_ < text_.size() && is_blank(text_[position_])) advance();
    Word word{{}, line_, column_};
    const std::size_t start = position_;
    while (position_ < text_.size() && !is_blank(text_[position_])) advance();
    word.text = text_.substr(start, position_ - start);
    return word;
  }

  // Skips what is left of the current line (a solid's name).
  void skip_line() {
    while (position_ < text_.size() && text_[position_] != '\n') advance();
  }

  [[noreturn]] void fail(const Word& at, const std::string& message) const {
    throw InputError(SourceLocation{source_, at.line, at.column}, message);
  }

  // The next word, which must be `keyword` (any case).
  Word expect(std::string_view keyword, std::string_view context) {
    const Word w = next();
    if (!equals_ignoring_case(w.text, keyword)) {
      fail(w, fmt::format("expected '{}' {}, found {}", keyword, context, describe(w)));
    }
    return w;
  }

  // The next word as a number. Coordinates are rounded to float, the precision of binary STL,
  // so that both encodings of one mesh read the same.
  double number(std::string_view what) {
    const Word w = next();
    std::string_view digits = w.text;
    if (digits.size() > 1 && digits[0] == '+') digits.remove_prefix(1);  // from_chars refuses '+'
    double value = 0.0;
    const auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
    if (digits.empty() || error != std::errc() || end != digits.data() + digits.size()) {
      // Out-of-range values (1e999) land here too.
      fail(w, fmt::format("expected a number for the {}, found {}", what, describe(w)));
    }
    return value;
  }

  Vec3 point(std::string_view what) {
    Vec3 p;
    for (int axis = 0; axis < 3; ++axis) {
      const Word at = peek();
      const double value = number(fmt::format("{} of {}", "xyz"[axis], what));
      const std::string problem = coordinate_problem(value);
      if (!problem.empty()) fail(at, problem);
      p[axis] = static_cast<double>(static_cast<float>(value));
    }
    return p;
  }

  Word peek() {
    const std::size_t position = position_;
    const int line = line_, column = column_;
    const Word w = next();
    position_ = position;
    line_ = line;
    column_ = column;
    return w;
  }

  static std::string describe(const Word& w) {
    if (w.text.empty()) return "the end of the file";
    constexpr std::size_t kShown = 40;
    return fmt::format("'{}{}'", w.text.substr(0, kShown), w.text.size() > kShown ? "…" : "");
  }

 private:
  void advance() {
    if (text_[position_] == '\n') {
      ++line_;
      column_ = 1;
    } else {
      ++column_;
    }
    ++position_;
  }

  std::string_view text_;
  const std::string& source_;
  std::size_t position_ = 0;
  int line_ = 1;
  int column_ = 1;
};

// solid name / facet normal n n n / outer loop / vertex x y z (×3) / endloop / endfacet / …
// endsolid name; several solids may follow one another.
StlMesh parse_ascii_stl(std::string_view text, const std::string& source) {
  StlWords words(text, source);
  MeshBuilder builder;
  words.expect("solid", "at the start of an ASCII STL");
  words.skip_line();
  for (;;) {
    const StlWords::Word w = words.next();
    if (equals_ignoring_case(w.text, "endsolid")) {
      words.skip_line();
      const StlWords::Word after = words.next();
      if (after.text.empty()) break;
      if (!equals_ignoring_case(after.text, "solid")) {
        words.fail(after, fmt::format("expected 'solid' or the end of the file after 'endsolid', "
                                      "found {}",
                                      StlWords::describe(after)));
      }
      words.skip_line();
      continue;
    }
    if (!equals_ignoring_case(w.text, "facet")) {
      words.fail(w, fmt::format("expected 'facet' or 'endsolid', found {}", StlWords::describe(w)));
    }
    words.expect("normal", "after 'facet'");
    // The normal is read (it must be numbers) but not used: the winding gives the orientation.
    for (const char* axis : {"x", "y", "z"})
      words.number(fmt::format("{} of the facet normal", axis));
    words.expect("outer", "after the facet normal");
    words.expect("loop", "after 'outer'");
    std::array<Vec3, 3> corners;
    int count = 0;
    for (;;) {
      const StlWords::Word v = words.next();
      if (equals_ignoring_case(v.text, "endloop")) break;
      if (!equals_ignoring_case(v.text, "vertex")) {
        words.fail(v,
                   fmt::format("expected 'vertex' or 'endloop', found {}", StlWords::describe(v)));
      }
      const Vec3 p = words.point("a vertex");
      if (count < 3) corners[static_cast<std::size_t>(count)] = p;
      ++count;
    }
    if (count != 3) {
      words.fail(w, fmt::format("facet with {} vertices: expected 3", count));
    }
    words.expect("endfacet", "after 'endloop'");
    builder.add(corners);
  }
  StlMesh out;
  out.degenerate_dropped = builder.degenerate();
  out.mesh = builder.take();
  out.binary = false;
  return out;
}

}  // namespace

StlMesh parse_stl(std::string_view bytes, const std::string& source) {
  if (bytes.empty()) {
    throw InputError(SourceLocation{source}, "empty file: expected an ASCII or binary STL");
  }
  StlMesh out = starts_with_solid(bytes) && !binary_by_content(bytes)
                    ? parse_ascii_stl(bytes, source)
                    : parse_binary_stl(bytes, source);
  if (out.mesh.triangles.empty()) {
    throw InputError(
        SourceLocation{source},
        out.degenerate_dropped > 0
            ? fmt::format("no triangles: all {} facets have coincident corners, expected at least "
                          "one proper triangle",
                          out.degenerate_dropped)
            : std::string("no triangles: expected at least one facet"));
  }
  return out;
}

StlMesh read_stl(const std::string& path) {
  return parse_stl(read_binary_file(path, "STL file"), path);
}

std::string stl_binary_header(std::string_view header, std::size_t triangles) {
  std::string out(84, ' ');
  out.replace(0, std::min<std::size_t>(header.size(), 80), header.substr(0, 80));
  const auto count = static_cast<std::uint32_t>(triangles);
  std::memcpy(out.data() + 80, &count, 4);
  return out;
}

void stl_binary_facets(std::span<const std::array<int, 3>> triangles,
                       std::span<const Vec3> vertices,
                       const std::function<void(std::string_view)>& write) {
  constexpr std::size_t kChunkTriangles = 4000;  // 200,000 bytes a piece
  // Pieces encoded in parallel and written in order. A piece's buffer is sized once and filled
  // in place (appending four bytes at a time was most of the time taken for a stock of a million
  // triangles), and is one of `tokens` reused in turn: pieces finish in order, so piece p's
  // buffer is free again when piece p + tokens starts.
  const std::size_t pieces = (triangles.size() + kChunkTriangles - 1) / kChunkTriangles;
  const auto tokens = static_cast<std::size_t>(2 * tbb::this_task_arena::max_concurrency());
  std::vector<std::string> buffers(tokens);
  std::size_t next = 0;
  tbb::parallel_pipeline(
      tokens,
      tbb::make_filter<void, std::size_t>(tbb::filter_mode::serial_in_order,
                                          [&](tbb::flow_control& control) -> std::size_t {
                                            if (next == pieces) {
                                              control.stop();
                                              return pieces;  // not used
                                            }
                                            return next++;
                                          }) &
          tbb::make_filter<std::size_t, std::size_t>(
              tbb::filter_mode::parallel,
              [&](std::size_t piece) {
                const std::size_t first = piece * kChunkTriangles;
                const std::size_t n = std::min(kChunkTriangles, triangles.size() - first);
                std::string& bytes = buffers[piece % tokens];
                bytes.assign(50 * n, '\0');
                char* at = bytes.data();
                for (std::size_t k = first; k < first + n; ++k) {
                  const auto& t = triangles[k];
                  const Vec3& a = vertices[static_cast<std::size_t>(t[0])];
                  const Vec3& b = vertices[static_cast<std::size_t>(t[1])];
                  const Vec3& c = vertices[static_cast<std::size_t>(t[2])];
                  Vec3 normal = (b - a).cross(c - a);
                  if (normal.norm() > 0.0) normal.normalize();
                  for (const Vec3* v : {static_cast<const Vec3*>(&normal), &a, &b, &c}) {
                    // STL is little-endian, as is every platform cwe builds on.
                    const float xyz[3] = {static_cast<float>(v->x()), static_cast<float>(v->y()),
                                          static_cast<float>(v->z())};
                    std::memcpy(at, xyz, sizeof xyz);
                    at += sizeof xyz;
                  }
                  at += 2;  // the attribute count, 0
                }
                return piece;
              }) &
          tbb::make_filter<std::size_t, void>(
              tbb::filter_mode::serial_in_order,
              [&](std::size_t piece) { write(buffers[piece % tokens]); }));
}

void stl_binary(const TriangleMesh& mesh, std::string_view header,
                const std::function<void(std::string_view)>& write) {
  write(stl_binary_header(header, mesh.triangles.size()));
  stl_binary_facets(mesh.triangles, mesh.vertices, write);
}

std::string stl_binary(const TriangleMesh& mesh, std::string_view header) {
  std::string bytes;
  bytes.reserve(84 + 50 * mesh.triangles.size());
  stl_binary(mesh, header, [&bytes](std::string_view piece) { bytes.append(piece); });
  return bytes;
}

// The vertex lines ("x y z", shortest round-trip doubles) then the face lines ("3 a b c") that
// PLY and OFF share, appended to `out`.
void append_vertices_and_faces(const TriangleMesh& mesh, std::string& out) {
  for (const Vec3& v : mesh.vertices) out += fmt::format("{} {} {}\n", v.x(), v.y(), v.z());
  for (const auto& t : mesh.triangles) out += fmt::format("3 {} {} {}\n", t[0], t[1], t[2]);
}

std::string ply_ascii(const TriangleMesh& mesh, std::string_view comment) {
  std::string out = fmt::format(
      "ply\nformat ascii 1.0\ncomment {}\nelement vertex {}\nproperty double x\nproperty double "
      "y\nproperty double z\nelement face {}\nproperty list uchar int vertex_indices\nend_header\n",
      comment, mesh.vertices.size(), mesh.triangles.size());
  append_vertices_and_faces(mesh, out);
  return out;
}

std::string off_ascii(const TriangleMesh& mesh, std::string_view comment) {
  std::string out =
      fmt::format("OFF\n# {}\n{} {} 0\n", comment, mesh.vertices.size(), mesh.triangles.size());
  append_vertices_and_faces(mesh, out);
  return out;
}

std::string obj_polylines(const std::vector<std::vector<Vec3>>& polylines,
                          std::string_view comment) {
  std::string out = fmt::format("# {}\n", comment);
  std::string lines;
  int next = 1;
  for (const auto& polyline : polylines) {
    if (polyline.size() < 2) continue;
    lines += "l";
    for (const Vec3& p : polyline) {
      out += fmt::format("v {} {} {}\n", p.x(), p.y(), p.z());
      lines += fmt::format(" {}", next++);
    }
    lines += "\n";
  }
  return out + lines;
}

}  // namespace cwe

#pragma once
// Mesh and polyline files as byte strings (write them with write_file_atomically), and STL
// reading (docs/stock.md states the reader's rules).

#include <array>
#include <cstddef>
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "cwe/geometry/triangle_mesh.hpp"

namespace cwe {

// Binary STL: 80-byte header (from `header`, truncated), facet normals from the winding,
// coordinates as 32-bit floats in millimetres.
std::string stl_binary(const TriangleMesh& mesh, std::string_view header);
// The same bytes handed to `write` in pieces of at most about 200 KB, in order: a stock of a
// million triangles (50 MB) goes to its file without a buffer of its size. The pieces are encoded
// on all threads while `write` takes them one at a time, in order.
void stl_binary(const TriangleMesh& mesh, std::string_view header,
                const std::function<void(std::string_view)>& write);
// The same in two parts, for a mesh written while it is made: the first 84 bytes (the header and
// the triangle count), then the facets of runs of triangles in order (each triangle's corners
// indexed in `vertices`), handed to `write` as above.
std::string stl_binary_header(std::string_view header, std::size_t triangles);
void stl_binary_facets(std::span<const std::array<int, 3>> triangles,
                       std::span<const Vec3> vertices,
                       const std::function<void(std::string_view)>& write);

// A triangle mesh read from an STL file.
struct StlMesh {
  // Vertices welded (equal coordinates are one vertex, so neighbouring facets share edges),
  // triangles in the file's order and winding; the facet normals of the file are ignored.
  TriangleMesh mesh;
  // Facets dropped because two of their corners are the same point (after welding).
  int degenerate_dropped = 0;
  bool binary = false;  // which of the two encodings the file used
};

// Reads a binary or ASCII STL file. The encoding is decided from the bytes, not the name: a file
// is ASCII when it starts with "solid" (after blanks) unless its size is that of a binary STL
// (84 + 50·n bytes for the n triangles its header declares) and it holds bytes that are not text
// (binary files from some exporters start their header with "solid" too). Vertices with equal
// coordinates (float equality of the file's values, -0 equal to 0) become one vertex.
// Throws InputError naming the file (and the line and column, for ASCII) and what was expected:
// a truncated or padded binary file, a token that is not a number or keyword, a facet with other
// than three vertices, a NaN, infinite or out-of-range (> kLargestInputValue) coordinate, or no
// triangle left.
StlMesh read_stl(const std::string& path);
// The same on bytes already read; `source` names them in errors.
StlMesh parse_stl(std::string_view bytes, const std::string& source);

// ASCII PLY with double-precision vertices and triangular faces.
std::string ply_ascii(const TriangleMesh& mesh, std::string_view comment);
// OFF (Object File Format, ASCII) with double-precision vertices and triangular faces; the
// comment as a `#` line after the OFF keyword.
std::string off_ascii(const TriangleMesh& mesh, std::string_view comment);

// Wavefront OBJ holding polylines (`v` vertices and one `l` element per polyline of ≥ 2 points).
std::string obj_polylines(const std::vector<std::vector<Vec3>>& polylines,
                          std::string_view comment);

}  // namespace cwe

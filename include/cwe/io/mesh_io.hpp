#pragma once
// Mesh and polyline files as byte strings (write them with write_file_atomically).

#include <string>
#include <string_view>
#include <vector>

#include "cwe/geometry/triangle_mesh.hpp"

namespace cwe {

// Binary STL: 80-byte header (from `header`, truncated), facet normals from the winding,
// coordinates as 32-bit floats in millimetres.
std::string stl_binary(const TriangleMesh& mesh, std::string_view header);

// ASCII PLY with double-precision vertices and triangular faces.
std::string ply_ascii(const TriangleMesh& mesh, std::string_view comment);

// Wavefront OBJ holding polylines (`v` vertices and one `l` element per polyline of ≥ 2 points).
std::string obj_polylines(const std::vector<std::vector<Vec3>>& polylines,
                          std::string_view comment);

}  // namespace cwe

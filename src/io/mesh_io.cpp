#include "cwe/io/mesh_io.hpp"

#include <cstdint>
#include <cstring>

#include <fmt/format.h>

namespace cwe {
namespace {

void put_float(std::string& out, double value) {
  const auto f = static_cast<float>(value);
  char bytes[4];
  std::memcpy(bytes, &f, 4);  // STL is little-endian, as is every platform cwe builds on
  out.append(bytes, 4);
}

}  // namespace

std::string stl_binary(const TriangleMesh& mesh, std::string_view header) {
  std::string out(80, ' ');
  out.replace(0, std::min<std::size_t>(header.size(), 80), header.substr(0, 80));
  const auto count = static_cast<std::uint32_t>(mesh.triangles.size());
  char bytes[4];
  std::memcpy(bytes, &count, 4);
  out.append(bytes, 4);
  out.reserve(out.size() + 50 * mesh.triangles.size());
  for (const auto& t : mesh.triangles) {
    const Vec3& a = mesh.vertices[static_cast<std::size_t>(t[0])];
    const Vec3& b = mesh.vertices[static_cast<std::size_t>(t[1])];
    const Vec3& c = mesh.vertices[static_cast<std::size_t>(t[2])];
    Vec3 n = (b - a).cross(c - a);
    if (n.norm() > 0.0) n.normalize();
    for (const Vec3* v : {static_cast<const Vec3*>(&n), &a, &b, &c}) {
      put_float(out, v->x());
      put_float(out, v->y());
      put_float(out, v->z());
    }
    out.append(2, '\0');
  }
  return out;
}

std::string ply_ascii(const TriangleMesh& mesh, std::string_view comment) {
  std::string out = fmt::format(
      "ply\nformat ascii 1.0\ncomment {}\nelement vertex {}\nproperty double x\nproperty double "
      "y\nproperty double z\nelement face {}\nproperty list uchar int vertex_indices\nend_header\n",
      comment, mesh.vertices.size(), mesh.triangles.size());
  for (const Vec3& v : mesh.vertices) out += fmt::format("{} {} {}\n", v.x(), v.y(), v.z());
  for (const auto& t : mesh.triangles) out += fmt::format("3 {} {} {}\n", t[0], t[1], t[2]);
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

// CGAL is used here only, behind cwe::convex_hull: it stays out of every public header.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_3.h>

#include <map>

#include "cwe/geometry/triangle_mesh.hpp"

namespace cwe {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;

}  // namespace

TriangleMesh convex_hull(const std::vector<Vec3>& points) {
  TriangleMesh out;
  if (points.size() < 4) return out;
  std::vector<Point> input;
  input.reserve(points.size());
  for (const Vec3& p : points) input.emplace_back(p.x(), p.y(), p.z());
  Mesh hull;
  CGAL::convex_hull_3(input.begin(), input.end(), hull);
  if (hull.number_of_faces() < 4) return out;  // degenerate: a point, segment or polygon
  std::map<Mesh::Vertex_index, int> index;
  for (const Mesh::Vertex_index v : hull.vertices()) {
    const Point& p = hull.point(v);
    index[v] = static_cast<int>(out.vertices.size());
    out.vertices.emplace_back(p.x(), p.y(), p.z());
  }
  for (const Mesh::Face_index f : hull.faces()) {
    std::array<int, 3> triangle{};
    int k = 0;
    for (const Mesh::Vertex_index v : hull.vertices_around_face(hull.halfedge(f))) {
      if (k < 3) triangle[static_cast<std::size_t>(k)] = index[v];
      ++k;
    }
    if (k == 3) out.triangles.push_back(triangle);
  }
  return out;
}

}  // namespace cwe

// CGAL is used here only, behind cwe::convex_hull: it stays out of every public header.
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/convex_hull_3.h>

#include <algorithm>
#include <array>
#include <map>
#include <set>

#include "cwe/geometry/triangle_mesh.hpp"

namespace cwe {
namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;

// Union–find over faces.
int root_of(std::vector<int>& parent, int i) {
  while (parent[static_cast<std::size_t>(i)] != i) {
    i = parent[static_cast<std::size_t>(i)] =
        parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(i)])];
  }
  return i;
}

// The triangles of one planar facet of the hull (a convex polygon that CGAL split in an order
// of its own), re-split as a fan from its lowest vertex. The facet's boundary is its directed
// edges whose reverse it does not hold. Returns false (keep CGAL's triangles) if the boundary is
// not one simple cycle or a fan triangle would be degenerate.
bool fan_of_facet(const std::vector<std::array<int, 3>>& triangles,
                  const std::vector<Point>& points, std::vector<std::array<int, 3>>& fan) {
  std::set<std::pair<int, int>> edges;
  for (const auto& t : triangles) {
    for (int k = 0; k < 3; ++k) edges.insert({t[static_cast<std::size_t>(k)], t[(k + 1) % 3]});
  }
  std::map<int, int> next;
  for (const auto& [a, b] : edges) {
    if (edges.count({b, a}) == 0 && !next.emplace(a, b).second) return false;
  }
  if (next.size() < 3) return false;
  std::vector<int> cycle{next.begin()->first};  // the lowest vertex
  while (cycle.size() <= next.size()) {
    const auto it = next.find(cycle.back());
    if (it == next.end()) return false;
    if (it->second == cycle.front()) break;
    cycle.push_back(it->second);
  }
  if (cycle.size() != next.size()) return false;
  for (std::size_t i = 1; i + 1 < cycle.size(); ++i) {
    const std::array<int, 3> t{cycle[0], cycle[i], cycle[i + 1]};
    if (CGAL::collinear(points[static_cast<std::size_t>(t[0])], points[static_cast<std::size_t>(t[1])],
                        points[static_cast<std::size_t>(t[2])])) {
      return false;
    }
    fan.push_back(t);
  }
  return true;
}

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

  // CGAL's order of vertices and faces, and its split of a planar facet into triangles, follow
  // its internal containers, which depend on the heap's history. The mesh is written in a
  // canonical form instead, so that the same points always give the same bytes: vertices sorted
  // by coordinates, each planar facet a fan from its lowest vertex, each triangle starting at its
  // lowest vertex, triangles sorted.
  std::vector<Mesh::Vertex_index> vertices(hull.vertices().begin(), hull.vertices().end());
  std::sort(vertices.begin(), vertices.end(), [&hull](Mesh::Vertex_index a, Mesh::Vertex_index b) {
    return hull.point(a) < hull.point(b);  // lexicographic x, y, z
  });
  std::map<Mesh::Vertex_index, int> index;
  std::vector<Point> sorted;
  for (const Mesh::Vertex_index v : vertices) {
    index[v] = static_cast<int>(sorted.size());
    sorted.push_back(hull.point(v));
    out.vertices.emplace_back(sorted.back().x(), sorted.back().y(), sorted.back().z());
  }
  std::vector<std::array<int, 3>> triangles;
  std::map<Mesh::Face_index, int> face_number;
  for (const Mesh::Face_index f : hull.faces()) {
    std::array<int, 3> triangle{};
    int k = 0;
    for (const Mesh::Vertex_index v : hull.vertices_around_face(hull.halfedge(f))) {
      if (k < 3) triangle[static_cast<std::size_t>(k)] = index[v];
      ++k;
    }
    if (k != 3) continue;
    face_number[f] = static_cast<int>(triangles.size());
    triangles.push_back(triangle);
  }
  // Planar facets: faces joined across an edge whose four points are coplanar (exact).
  std::vector<int> parent(triangles.size());
  for (std::size_t i = 0; i < parent.size(); ++i) parent[i] = static_cast<int>(i);
  for (const Mesh::Edge_index e : hull.edges()) {
    const Mesh::Halfedge_index h = hull.halfedge(e), g = hull.opposite(h);
    const auto f = face_number.find(hull.face(h)), f2 = face_number.find(hull.face(g));
    if (f == face_number.end() || f2 == face_number.end()) continue;
    const Point& far = hull.point(hull.target(hull.next(g)));
    if (CGAL::coplanar(hull.point(hull.source(h)), hull.point(hull.target(h)),
                       hull.point(hull.target(hull.next(h))), far)) {
      parent[static_cast<std::size_t>(root_of(parent, f->second))] = root_of(parent, f2->second);
    }
  }
  std::map<int, std::vector<std::array<int, 3>>> facets;
  for (std::size_t i = 0; i < triangles.size(); ++i) {
    facets[root_of(parent, static_cast<int>(i))].push_back(triangles[i]);
  }
  for (const auto& [root, facet] : facets) {
    std::vector<std::array<int, 3>> fan;
    if (facet.size() < 2 || !fan_of_facet(facet, sorted, fan)) fan = facet;
    for (std::array<int, 3> t : fan) {
      // Rotate (keeping the orientation) to start at the lowest index.
      std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
      out.triangles.push_back(t);
    }
  }
  std::sort(out.triangles.begin(), out.triangles.end());
  return out;
}

}  // namespace cwe

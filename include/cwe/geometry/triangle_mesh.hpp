#pragma once
// Indexed triangle meshes: the exchange format for swept volumes and workpiece exports.
//
// Triangles are counter-clockwise seen from outside (outward normals by the right-hand rule).
// A mesh is closed (watertight) when every edge is shared by exactly two triangles that use it in
// opposite directions.

#include <algorithm>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "cwe/geometry/aabb.hpp"
#include "cwe/geometry/vec.hpp"

namespace cwe {

struct TriangleMesh {
  std::vector<Vec3> vertices;
  std::vector<std::array<int, 3>> triangles;

  bool empty() const { return triangles.empty(); }
  // Enclosed volume by the divergence theorem (mm³); meaningful for closed meshes, positive when
  // the triangles face outwards.
  double volume() const;
  double area() const;  // mm²
  Aabb bounds() const;
  // Appends another mesh (its vertices renumbered).
  void append(const TriangleMesh& other);
};

// Edge statistics that decide closedness, with where the first offending edges are (so that a
// refusal can say where to look).
struct MeshClosure {
  // End points of an edge (mm), as the mesh's vertices.
  using Edge = std::array<Vec3, 2>;
  // At most this many example edges of each kind are kept.
  static constexpr int kMaxExamples = 5;

  int edges = 0;
  int boundary_edges = 0;      // used by one triangle
  int non_manifold_edges = 0;  // used by three or more
  int misoriented_edges = 0;   // used twice in the same direction
  // The first (up to kMaxExamples) edges of each kind, ordered by their vertex indices (lower
  // index first): the same mesh always gives the same examples.
  std::vector<Edge> boundary_examples;
  std::vector<Edge> non_manifold_examples;
  std::vector<Edge> misoriented_examples;
  bool closed() const {
    return edges > 0 && boundary_edges == 0 && non_manifold_edges == 0 && misoriented_edges == 0;
  }
  // What keeps the mesh from closing, for an error message: each kind of bad edge counted,
  // with the examples' end points ("3 boundary edges (…) at (0, 0, 0)–(1, 0, 0), …").
  std::string problem() const;
};

MeshClosure check_closure(const TriangleMesh& mesh);
// A key for the undirected edge between vertices a and b (either order), for hashing edges.
inline std::uint64_t edge_key(int a, int b) {
  const auto lo = static_cast<std::uint64_t>(std::min(a, b));
  const auto hi = static_cast<std::uint64_t>(std::max(a, b));
  return lo << 32 | hi;
}
// The mesh's edge-connected pieces (triangles joined through shared edges, not through a vertex
// alone), each with its own vertices, in the order of their first triangles: on a closed mesh,
// its closed surfaces.
std::vector<TriangleMesh> edge_connected_parts(const TriangleMesh& mesh);
// Throws InputError naming `source` where `mesh` cannot bound a stock: it has no triangles, or
// it is not closed (MeshClosure::problem says where).
void require_closed_stock(const TriangleMesh& mesh, const std::string& source);

// Removes folds: pairs of triangles on the same three vertices that face opposite ways. A pair
// encloses nothing and uses each of its edges once each way, so the enclosed volume and the
// closure of the rest are unchanged. A tessellation leaves them where a face narrower than its
// weld tolerance collapses onto a line (seen on a B-rep stock's sliver between two 5-axis
// passes: an edge used four times). Triangles that repeat one facing way are kept (check_closure
// reports them). Returns how many triangles were removed; the others keep their order.
int remove_folds(TriangleMesh& mesh);

// The convex hull of the points as a closed, outward-facing triangle mesh (CGAL's
// convex_hull_3 with exact predicates). Empty when the points span less than a volume
// (fewer than four, or all coplanar).
TriangleMesh convex_hull(const std::vector<Vec3>& points);

}  // namespace cwe

// CGAL is used here only, behind MeshStock and MeshRegion: it stays out of every public header.
// GCC 12 sees uninitialised kernel functors in CGAL's self-intersection test with the exact
// kernel (a false alarm in CGAL's templates): not this file's code.
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <CGAL/Exact_predicates_exact_constructions_kernel.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/bbox.h>
#include <CGAL/Polygon_mesh_processing/corefinement.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Surface_mesh.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <span>
#include <unordered_map>
#include <vector>

#include <fmt/format.h>
#include <boost/optional.hpp>

#include "cwe/core/computation_error.hpp"
#include "cwe/core/error.hpp"
#include "cwe/workpiece/mesh/mesh_stock.hpp"

namespace cwe {
namespace {

namespace PMP = CGAL::Polygon_mesh_processing;
using Exact = CGAL::Exact_predicates_exact_constructions_kernel;
using Point = Exact::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;

using Inexact = CGAL::Exact_predicates_inexact_constructions_kernel;
using InexactMesh = CGAL::Surface_mesh<Inexact::Point_3>;

// A point's coordinates as doubles, from their exact values (to_double of a lazy number may
// return the middle of its interval instead), for the meshes handed out: stock.stl and the
// removal volumes.
Vec3 rounded(const Point& p) {
  return {CGAL::to_double(CGAL::exact(p.x())), CGAL::to_double(CGAL::exact(p.y())),
          CGAL::to_double(CGAL::exact(p.z()))};
}

// The mesh's triangles with vertices rounded to doubles (indices renumbered densely).
TriangleMesh to_triangles(const Mesh& mesh) {
  TriangleMesh out;
  std::unordered_map<std::uint32_t, int> index;
  index.reserve(mesh.number_of_vertices());
  for (const Mesh::Vertex_index v : mesh.vertices()) {
    index[static_cast<std::uint32_t>(v)] = static_cast<int>(out.vertices.size());
    out.vertices.push_back(rounded(mesh.point(v)));
  }
  out.triangles.reserve(mesh.number_of_faces());
  for (const Mesh::Face_index f : mesh.faces()) {
    std::array<int, 3> t{};
    int k = 0;
    for (const Mesh::Vertex_index v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) {
      if (k < 3) t[static_cast<std::size_t>(k)] = index[static_cast<std::uint32_t>(v)];
      ++k;
    }
    if (k == 3) out.triangles.push_back(t);
  }
  return out;
}

// A TriangleMesh as a Surface_mesh of either kernel; false when a triangle cannot be added (an
// edge used by a third triangle or twice in one direction), with that triangle's index.
template <class SurfaceMesh>
bool to_surface_mesh(const TriangleMesh& in, SurfaceMesh& out, std::size_t& bad) {
  using P = typename SurfaceMesh::Point;
  std::vector<typename SurfaceMesh::Vertex_index> v;
  v.reserve(in.vertices.size());
  for (const Vec3& p : in.vertices) v.push_back(out.add_vertex(P(p.x(), p.y(), p.z())));
  for (std::size_t k = 0; k < in.triangles.size(); ++k) {
    const auto& t = in.triangles[k];
    const auto f =
        out.add_face(v[static_cast<std::size_t>(t[0])], v[static_cast<std::size_t>(t[1])],
                     v[static_cast<std::size_t>(t[2])]);
    if (f == SurfaceMesh::null_face()) {
      bad = k;
      return false;
    }
  }
  return true;
}

// A point's coordinates as doubles from their interval approximations (no exact evaluation):
// within a few ulps of the exact values.
Vec3 approximate(const Point& p) {
  return {CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z())};
}

// The mesh's box and enclosed volume from the vertices' approximations (divergence theorem
// about the box's centre, which keeps the terms small): the volume within ~1e-12 of the exact
// one relative to the box. An empty mesh: an empty box and 0.
void measure(const Mesh& mesh, Aabb& bounds, double& volume) {
  bounds = Aabb();
  volume = 0.0;
  if (mesh.is_empty()) return;
  const CGAL::Bbox_3 box = PMP::bbox(mesh);
  bounds.extend(Vec3(box.xmin(), box.ymin(), box.zmin()));
  bounds.extend(Vec3(box.xmax(), box.ymax(), box.zmax()));
  const Vec3 c = 0.5 * (bounds.min + bounds.max);
  double six = 0.0;
  for (const Mesh::Face_index f : mesh.faces()) {
    const Mesh::Halfedge_index h = mesh.halfedge(f);
    const Vec3 a = approximate(mesh.point(mesh.source(h))) - c;
    const Vec3 b = approximate(mesh.point(mesh.target(h))) - c;
    const Vec3 d = approximate(mesh.point(mesh.target(mesh.next(h)))) - c;
    six += a.dot(b.cross(d));
  }
  volume = six / 6.0;
}

// Makes the coordinates of the vertices the last boolean made (those in the cut's box) exact
// now: a lazy point keeps the expression that made it, and through it the points that expression
// used, boolean after boolean; an exact point is a leaf.
void make_exact(Mesh& mesh, const Aabb& cut) {
  Aabb near = cut;
  near.inflate(1e-6 * std::max(1.0, cut.size().maxCoeff()));
  for (const Mesh::Vertex_index v : mesh.vertices()) {
    const Vec3 p = approximate(mesh.point(v));
    if ((p.array() >= near.min.array()).all() && (p.array() <= near.max.array()).all()) {
      CGAL::exact(mesh.point(v));
    }
  }
}

}  // namespace

struct MeshRegion::Solid {
  InexactMesh mesh;
  std::unique_ptr<CGAL::Side_of_triangle_mesh<InexactMesh, Inexact>> inside;
};

MeshRegion::MeshRegion() = default;
MeshRegion::~MeshRegion() = default;
MeshRegion::MeshRegion(MeshRegion&&) noexcept = default;
MeshRegion& MeshRegion::operator=(MeshRegion&&) noexcept = default;

MeshRegion::MeshRegion(const TriangleMesh& mesh) {
  if (mesh.empty()) return;
  bounds_ = mesh.bounds();
  solid_ = std::make_unique<Solid>();
  std::size_t bad = 0;
  if (!to_surface_mesh(mesh, solid_->mesh, bad)) {
    throw ComputationError("mesh removal: the removed volume is not a 2-manifold");
  }
  solid_->inside =
      std::make_unique<CGAL::Side_of_triangle_mesh<InexactMesh, Inexact>>(solid_->mesh);
  // The search tree is built at the first query: one now, so that later ones only read it.
  (*solid_->inside)(Inexact::Point_3(bounds_.min.x(), bounds_.min.y(), bounds_.min.z()));
}

bool MeshRegion::contains(const Vec3& point) const {
  if (!solid_) return false;
  for (int a = 0; a < 3; ++a) {
    if (!(point[a] > bounds_.min[a] && point[a] < bounds_.max[a])) return false;
  }
  return (*solid_->inside)(Inexact::Point_3(point.x(), point.y(), point.z())) ==
         CGAL::ON_BOUNDED_SIDE;
}

struct MeshStock::Solid {
  Mesh mesh;
};

MeshStock::MeshStock(std::unique_ptr<Solid> solid) : solid_(std::move(solid)) {
  measure(solid_->mesh, bounds_, volume_);
}
MeshStock::~MeshStock() = default;
MeshStock::MeshStock(MeshStock&&) noexcept = default;
MeshStock& MeshStock::operator=(MeshStock&&) noexcept = default;

MeshStock MeshStock::from_box(const Aabb& box) {
  if (box.is_empty() || !box.min.allFinite() || !box.max.allFinite() ||
      !((box.max - box.min).minCoeff() > 0.0)) {
    throw InputError("mesh stock: the box must have a positive size along x, y and z");
  }
  TriangleMesh m;
  for (int k = 0; k < 8; ++k) {
    m.vertices.emplace_back((k & 1) ? box.max.x() : box.min.x(),
                            (k & 2) ? box.max.y() : box.min.y(),
                            (k & 4) ? box.max.z() : box.min.z());
  }
  // Two triangles per face, counter-clockwise seen from outside.
  m.triangles = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                 {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  return from_mesh(m, "stock box");
}

MeshStock MeshStock::from_mesh(const TriangleMesh& mesh, const std::string& source) {
  auto solid = std::make_unique<Solid>();
  std::size_t bad = 0;
  if (!to_surface_mesh(mesh, solid->mesh, bad)) {
    const auto& t = mesh.triangles[bad];
    const Vec3& p = mesh.vertices[static_cast<std::size_t>(t[0])];
    throw InputError(SourceLocation{source},
                     fmt::format("triangle {} (at {:g}, {:g}, {:g}) shares an edge with two other "
                                 "triangles or runs an edge the same way as its neighbour: "
                                 "expected a closed, consistently oriented surface",
                                 bad + 1, p.x(), p.y(), p.z()));
  }
  if (!CGAL::is_closed(solid->mesh)) {
    throw InputError(SourceLocation{source},
                     "the surface is not closed (some edges have one triangle): expected the "
                     "closed surface of a solid");
  }
  if (PMP::does_self_intersect(solid->mesh)) {
    throw InputError(SourceLocation{source},
                     "the surface crosses itself: expected the surface of a solid");
  }
  if (!PMP::is_outward_oriented(solid->mesh)) {
    throw InputError(SourceLocation{source},
                     "the triangles face inwards: expected outward normals (counter-clockwise "
                     "seen from outside)");
  }
  return MeshStock(std::move(solid));
}

double MeshStock::subtract(const TriangleMesh& tool, TriangleMesh* removed) {
  return subtract(std::span<const TriangleMesh>(&tool, 1), removed);
}

double MeshStock::subtract(std::span<const TriangleMesh> pieces, TriangleMesh* removed) {
  // The pieces that reach the stock, as exact meshes, merged into one solid where they can be.
  std::vector<const TriangleMesh*> near;
  for (const TriangleMesh& piece : pieces) {
    if (!piece.empty() && piece.bounds().intersects(bounds())) near.push_back(&piece);
  }
  if (near.empty()) return 0.0;
  std::vector<Solid> cutters(near.size());
  for (std::size_t k = 0; k < near.size(); ++k) {
    std::size_t bad = 0;
    if (!to_surface_mesh(*near[k], cutters[k].mesh, bad) || !CGAL::is_closed(cutters[k].mesh)) {
      throw ComputationError("mesh removal: the swept volume's mesh is not a closed surface");
    }
  }
  if (cutters.size() > 1) {
    // Pairwise, in a balanced tree: each mesh takes part in log2(n) unions, and the coordinates
    // the unions make stay that few constructions deep.
    std::vector<Solid> level = cutters;
    std::vector<Aabb> boxes;
    for (const TriangleMesh* piece : near) boxes.push_back(piece->bounds());
    bool merged = true;
    while (level.size() > 1 && merged) {
      std::vector<Solid> up((level.size() + 1) / 2);
      std::vector<Aabb> up_boxes(up.size());
      for (std::size_t k = 0; k < up.size() && merged; ++k) {
        if (2 * k + 1 == level.size()) {
          up[k] = std::move(level[2 * k]);
          up_boxes[k] = boxes[2 * k];
          continue;
        }
        try {
          merged =
              PMP::corefine_and_compute_union(level[2 * k].mesh, level[2 * k + 1].mesh, up[k].mesh);
        } catch (const std::exception&) {
          merged = false;
        }
        up_boxes[k] = boxes[2 * k];
        up_boxes[k].extend(boxes[2 * k + 1]);
        if (merged) make_exact(up[k].mesh, up_boxes[k]);
      }
      level = std::move(up);
      boxes = std::move(up_boxes);
    }
    Solid& joined = level.front();
    // Pieces that only touch (along an edge: no 2-manifold union) are subtracted one by one.
    if (merged) {
      cutters.clear();
      cutters.push_back(std::move(joined));
    }
  }
  double taken = 0.0;
  for (Solid& cutter : cutters) taken += subtract_solid(cutter, removed);
  return taken;
}

double MeshStock::subtract_solid(Solid& solid, TriangleMesh* removed) {
  Mesh& cutter = solid.mesh;
  Aabb cut;
  double cut_volume = 0.0;
  measure(cutter, cut, cut_volume);
  if (!cut.intersects(bounds())) return 0.0;
  // With `removed`, the difference goes to a new mesh: the stock stays as it was (corefined) in
  // case the intersection has to be taken again.
  Mesh common, after;
  std::array<boost::optional<Mesh*>, 4> output;
  output[PMP::Corefinement::TM1_MINUS_TM2] = removed != nullptr ? &after : &solid_->mesh;
  if (removed != nullptr) output[PMP::Corefinement::INTERSECTION] = &common;
  std::array<bool, 4> done{};
  try {
    done = PMP::corefine_and_compute_boolean_operations(solid_->mesh, cutter, output);
    if (done[PMP::Corefinement::TM1_MINUS_TM2] && removed != nullptr &&
        !done[PMP::Corefinement::INTERSECTION]) {
      // The removed volume pinches (touches itself along an edge: a helix's ramp ending where
      // the circle after it cleans the floor), which no 2-manifold holds. Grown by a relative
      // 1e-9 about its box's centre, the cutter leaves a sliver of that size there instead: the
      // RV is only read for engagement, a hair outside (contact/1000) the tool.
      common.clear();
      const Point centre(0.5 * (cut.min.x() + cut.max.x()), 0.5 * (cut.min.y() + cut.max.y()),
                         0.5 * (cut.min.z() + cut.max.z()));
      for (const Mesh::Vertex_index v : cutter.vertices()) {
        cutter.point(v) = centre + (cutter.point(v) - centre) * Exact::FT(1.0 + 1e-9);
      }
      done[PMP::Corefinement::INTERSECTION] =
          PMP::corefine_and_compute_intersection(solid_->mesh, cutter, common);
    }
  } catch (const std::exception& e) {
    throw ComputationError(fmt::format("mesh removal: CGAL's corefinement failed ({})", e.what()));
  }
  if (!done[PMP::Corefinement::TM1_MINUS_TM2] ||
      (removed != nullptr && !done[PMP::Corefinement::INTERSECTION])) {
    throw ComputationError(
        "mesh removal: CGAL's corefinement could not build the difference (the result would "
        "not be a 2-manifold)");
  }
  if (removed != nullptr) solid_->mesh = std::move(after);
  make_exact(solid_->mesh, cut);
  if (!solid_->mesh.is_empty() && !CGAL::is_closed(solid_->mesh)) {
    throw ComputationError("mesh removal: the difference is not a closed surface");
  }
  const double before = volume_;
  measure(solid_->mesh, bounds_, volume_);
  const double taken = before - volume_;
  // Rounding of the volume sums: a relative 1e-9 of the stock's volume is far above it.
  const double slack = 1e-9 * std::max(before, 1.0);
  if (taken < -slack || taken > cut_volume + slack) {
    throw ComputationError(
        fmt::format("mesh removal: the stock's volume changed by {:g} mm³, outside [0, {:g}] mm³ "
                    "(the swept volume's)",
                    -taken, cut_volume));
  }
  if (removed != nullptr) removed->append(to_triangles(common));
  return std::max(0.0, taken);
}

std::size_t MeshStock::triangles() const { return solid_->mesh.number_of_faces(); }

TriangleMesh MeshStock::mesh() const { return to_triangles(solid_->mesh); }

}  // namespace cwe

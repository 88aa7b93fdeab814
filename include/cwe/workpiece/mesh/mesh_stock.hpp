#pragma once
// The in-process workpiece as a closed triangle mesh, the polyhedral method of the thesis
// (Aras 2008 §6.2; docs/engagement.md): removal by CGAL's corefinement booleans on exact
// coordinates. CGAL stays behind this header (src/workpiece/mesh/mesh_stock.cpp).
//
// The solid is a Surface_mesh over CGAL's exact-construction kernel, so a boolean is decided
// exactly on the coordinates it is given, coplanar and coincident faces included (a pass along a
// wall that an earlier pass left, a floor at the same depth).
// Coordinates stay exact from boolean to boolean: the vertices a boolean makes are evaluated
// exactly at once (a lazy point would keep the chain of constructions behind it). Rounding them
// to doubles instead, even where no face then crossed another, left inputs on which CGAL's next
// boolean failed or crashed (a FreeCAD pocket program, its second move).
//
// What a boolean removed comes back as triangles (rounded to doubles), for a MeshRegion.

#include <memory>
#include <span>
#include <string>

#include "cwe/geometry/aabb.hpp"
#include "cwe/geometry/triangle_mesh.hpp"

namespace cwe {

// A closed solid as triangles with a search tree over them, for point-inside queries (a removal
// volume RV = W ∩ SV, read by the polyhedral engagement).
class MeshRegion {
 public:
  MeshRegion();
  // `mesh` must be closed and outward-facing (as MeshStock::subtract returns it); it may be
  // empty. ComputationError if its triangles do not make a 2-manifold.
  explicit MeshRegion(const TriangleMesh& mesh);
  ~MeshRegion();
  MeshRegion(MeshRegion&&) noexcept;
  MeshRegion& operator=(MeshRegion&&) noexcept;

  bool empty() const { return solid_ == nullptr; }
  const Aabb& bounds() const { return bounds_; }
  // Is `point` strictly inside? Safe to call concurrently.
  bool contains(const Vec3& point) const;

 private:
  struct Solid;
  Aabb bounds_;
  std::unique_ptr<Solid> solid_;
};

class MeshStock {
 public:
  // A box (InputError when it is empty or not finite).
  static MeshStock from_box(const Aabb& box);
  // A closed, outward-facing, self-intersection-free mesh; `source` names it in errors
  // (InputError naming the first open, non-manifold or crossing place).
  static MeshStock from_mesh(const TriangleMesh& mesh, const std::string& source);

  ~MeshStock();
  MeshStock(MeshStock&&) noexcept;
  MeshStock& operator=(MeshStock&&) noexcept;

  // Subtracts the closed solid `tool` (a swept volume or a piece of one); the volume removed, mm³.
  // With `removed`, what was removed (stock ∩ tool) is appended to it. Throws ComputationError
  // when CGAL cannot compute the result or the result is not a closed solid whose volume fell
  // by between 0 and the tool's volume; the stock must not be used after that.
  double subtract(const TriangleMesh& tool, TriangleMesh* removed = nullptr);
  // Subtracts a move's pieces (closed solids: linear pieces' hulls, or an arc's wedge and the
  // tool at its ends) in one boolean: their union first, which spares the stock the faces each
  // piece would cut into the next one's (a helix's or a 5-axis move's pieces overlap along the
  // whole move). Pieces whose union is not a 2-manifold (they only touch) are subtracted one
  // by one. The volume removed, mm³; `removed` and the errors as above, the bound being the
  // union's volume.
  double subtract(std::span<const TriangleMesh> pieces, TriangleMesh* removed = nullptr);

  double volume() const { return volume_; }  // mm³
  const Aabb& bounds() const { return bounds_; }
  std::size_t triangles() const;
  // The stock's triangles, vertices rounded to doubles.
  TriangleMesh mesh() const;

 private:
  struct Solid;
  explicit MeshStock(std::unique_ptr<Solid> solid);
  double subtract_solid(Solid& cutter, TriangleMesh* removed);
  std::unique_ptr<Solid> solid_;
  Aabb bounds_;  // of the vertices, kept with the volume after each boolean
  double volume_ = 0.0;
};

}  // namespace cwe

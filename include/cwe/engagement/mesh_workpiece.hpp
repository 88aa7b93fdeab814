#pragma once
// The polyhedral workpiece behind the workpiece seam (workpiece.hpp), the thesis's polyhedral
// method (Aras 2008 §6.2; docs/engagement.md): each linear piece of a move's sweep is faceted
// (the hull of the tool's facets at both ends, linear_piece_mesh; a planar arc as the tool's
// section revolved, planar_arc_sweep), a move's pieces are joined into one solid and subtracted
// from the closed stock mesh by CGAL's corefinement (MeshStock), a move at a time. For
// engagement, the move's removal volume RV = W ∩ SV comes back from the same boolean, and a cell
// of the engagement grid (EngagementGrid) that moves into the material (f > 0) at a cutter
// location is engaged when the point a hair (contact/1000) outside it along its normal lies
// inside the RV and, on a curved move, in none of the move's pieces before the location (a
// helix's turn above took it): that point is outside every earlier position of the convex tool
// on the move, so the material there is what the move still has to cut (the thesis's section of
// the RV at the location, §6.2).
//
// Faceting: `facet` is the longest edge (mm) of the tool's rings at its largest radius R, the
// thesis's facet size; the chords lie within h = R − √(R² − facet²/4) of the true surface, and
// so does every swept piece, which moves a boundary by up to about h.

#include <memory>
#include <span>
#include <vector>

#include "cwe/engagement/workpiece.hpp"
#include "cwe/workpiece/mesh/mesh_stock.hpp"

namespace cwe {

class MeshWorkpiece : public Workpiece {
 public:
  // Works on `stock`, which must outlive it. `facet` as above; `spacing`, the engagement grid's
  // default disc height and cell size (the simulation's resolution). InputError for a facet or
  // spacing that is not positive.
  MeshWorkpiece(MeshStock& stock, double facet, double spacing);
  double cell_volume() const override;
  std::vector<double> remove(std::span<const MoveSweep> sweeps) override;
  std::unique_ptr<StepEngagement> engagement(const Cutter& cutter,
                                             const EngagementOptions& options) override;

  double facet() const { return facet_; }
  // The chord height h of `facet` on `cutter` (see above), mm.
  static double facet_depth(const Cutter& cutter, double facet);
  // The swept piece's closed mesh, faceted for this workpiece.
  TriangleMesh piece_mesh(const LinearSweep& piece) const;
  // Removes one sweep (its pieces' union); what it removed is appended to `removed` when given.
  double remove(const MoveSweep& sweep, TriangleMesh* removed);

 private:
  MeshStock& stock_;
  double facet_;
  double spacing_;
};

}  // namespace cwe

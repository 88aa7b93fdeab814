#pragma once
// The B-rep workpiece behind the workpiece seam: BrepStock (an exact OpenCASCADE solid,
// cwe/workpiece/brep/brep_stock.hpp) cut move by move with exact swept volumes: lines with a
// constant axis (3-axis, 3+2), planar arcs and helices with the tool along the arc's normal, for
// convex cutters; simultaneous 5-axis lines lofted through their poses within the sweep
// tolerance. Other moves (an arc off the tool's axis), and those whose own sweep is refused, are
// cut as the linear pieces of their MoveSweep, each swept exactly with its mean axis: the motion
// within the sweep tolerance, as on the other workpieces. A concave profile, or a sweep or a cut
// that fails its checks, is refused with a ComputationError naming the move.
//
// Engagement, the thesis's solid-model CWE (Aras 2008 §6.1; docs/brep.md): each move's cut also
// gives its removal volume RV = W ∩ SV, exactly, from the same intersection. At a cutter
// location, the circle of each disc and ring of the engagement grid (EngagementGrid), a hair
// (2e-7 mm) outside the cutter, is cut at its crossings with the RV's faces and at the
// roots of f = N·V; an arc between two cuts is engaged when its midpoint moves into the material,
// lies inside the RV and was not taken earlier on the move (a helix's turn above: MovePieces).
// The intervals are exact to OpenCASCADE's tolerances; the grid sets only the discs' heights.

#include <memory>
#include <span>
#include <vector>

#include "cwe/engagement/workpiece.hpp"
#include "cwe/workpiece/brep/brep_stock.hpp"

namespace cwe {

class BrepWorkpiece : public Workpiece {
 public:
  // The stock must outlive the workpiece. `spacing`: the engagement grid's default disc height
  // (the simulation's resolution); InputError when it is not positive.
  BrepWorkpiece(BrepStock& stock, double spacing);

  // A relative 1e-7 of the stock's volume when the run starts: below it a cut is within the
  // volume integration's error of nothing (BrepStock::cut's slack).
  double cell_volume() const override { return cell_; }
  std::vector<double> remove(std::span<const MoveSweep> sweeps) override;
  std::unique_ptr<StepEngagement> engagement(const Cutter& cutter,
                                             const EngagementOptions& options) override;

  // Cuts one move's sweep; the volume removed, mm³. With `removed`, the solids of the move's
  // removal volume are appended to it.
  double remove(const MoveSweep& sweep, std::vector<BrepStock::Solid>* removed = nullptr);

 private:
  BrepStock& stock_;
  double cell_ = 0.0;
  double spacing_ = 0.0;
};

}  // namespace cwe

#pragma once
// The B-rep workpiece behind the workpiece seam: BrepStock (an exact OpenCASCADE solid,
// cwe/workpiece/brep/brep_stock.hpp) cut move by move with exact swept volumes. Removal only so
// far: lines with a constant axis (3-axis, 3+2), planar arcs and helices with the tool along the
// arc's normal, for convex cutters; a simultaneous 5-axis move, or a sweep that fails its checks
// (a bull-nose round a corner), is refused with a ComputationError naming the move. The thesis's
// solid-model CWE (§6.1) on it is still to come: engagement() throws InputError.

#include <memory>
#include <span>
#include <vector>

#include "cwe/engagement/workpiece.hpp"
#include "cwe/workpiece/brep/brep_stock.hpp"

namespace cwe {

class BrepWorkpiece : public Workpiece {
 public:
  // The stock must outlive the workpiece.
  explicit BrepWorkpiece(BrepStock& stock);

  // A relative 1e-7 of the stock's volume when the run starts: below it a cut is within the
  // volume integration's error of nothing (BrepStock::cut's slack).
  double cell_volume() const override { return cell_; }
  std::vector<double> remove(std::span<const MoveSweep> sweeps) override;
  // Throws InputError: the engagement on the B-rep workpiece is not built yet.
  std::unique_ptr<StepEngagement> engagement(const Cutter& cutter,
                                             const EngagementOptions& options) override;

  // Cuts one move's sweep; the volume removed, mm³.
  double remove(const MoveSweep& sweep);

 private:
  BrepStock& stock_;
  double cell_ = 0.0;
};

}  // namespace cwe

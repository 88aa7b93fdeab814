#include "cwe/engagement/brep_workpiece.hpp"

#include <cmath>

#include "cwe/core/computation_error.hpp"
#include "cwe/core/error.hpp"
#include "cwe/geometry/tolerance.hpp"

namespace cwe {

BrepWorkpiece::BrepWorkpiece(BrepStock& stock)
    : stock_(stock), cell_(1e-7 * std::max(stock.volume(), 1.0)) {}

double BrepWorkpiece::remove(const MoveSweep& sweep) {
  const Move& move = sweep.move();
  const ConvexParts& parts = sweep.parts();
  if (parts.parts().size() != 1 || parts.parts().front().offset != 0.0) {
    throw ComputationError(
        "B-rep removal: the cutter's profile has a concave part; the B-rep workpiece sweeps "
        "convex cutters (every APT cutter)");
  }
  const Cutter& cutter = *parts.parts().front().cutter;
  const Vec3 axis = move.start_axis.normalized();
  const bool constant_axis = move.axis_angle() <= tol::kAngle;
  if (!move.is_arc() && constant_axis) return stock_.cut_linear(cutter, move.start, move.end, axis);
  if (move.is_arc() && constant_axis &&
      std::abs(axis.dot(move.normal.normalized())) > 1.0 - 1e-12) {
    return move.axial == 0.0 ? stock_.cut_planar_arc(cutter, move) : stock_.cut_helix(cutter, move);
  }
  throw ComputationError(
      move.is_arc()
          ? "B-rep removal: the B-rep workpiece does not yet sweep arcs with the tool off the "
            "arc's normal"
          : "B-rep removal: the B-rep workpiece does not yet sweep simultaneous 5-axis moves");
}

std::vector<double> BrepWorkpiece::remove(std::span<const MoveSweep> sweeps) {
  std::vector<double> volumes;
  volumes.reserve(sweeps.size());
  for (std::size_t k = 0; k < sweeps.size(); ++k) {
    try {
      volumes.push_back(remove(sweeps[k]));
    } catch (const ComputationError& e) {
      throw ComputationError(k, e.what());
    }
  }
  return volumes;
}

std::unique_ptr<StepEngagement> BrepWorkpiece::engagement(const Cutter& /*cutter*/,
                                                          const EngagementOptions& /*options*/) {
  throw InputError(SourceLocation{"--workpiece"},
                   "the B-rep workpiece removes material only (its engagement is still to come): "
                   "run it with --stock-only");
}

}  // namespace cwe

#pragma once
// The workpiece seam (docs/architecture.md): what the main loop (cwe/simulation) asks of an
// in-process workpiece, whatever represents it. A backend implements both classes: the
// tri-dexel one is DexelWorkpiece (dexel_workpiece.hpp); the mesh and B-rep backends will be a
// folder under workpiece/ for the representation plus one here for their implementation.

#include <memory>
#include <span>
#include <vector>

#include "cwe/engagement/engagement_map.hpp"
#include "cwe/envelope/move_sweep.hpp"
#include "cwe/kinematics/tool_state.hpp"
#include "cwe/tool/cutter.hpp"

namespace cwe {

// One cutter's engagement on a workpiece, a step at a time: each step (the motion from a cutter
// location to the next) is removed and recorded, and the engagement at the location is where
// that removal touches the cutter (CWE = FCS ∩ (W ∩ SV), docs/engagement.md).
class StepEngagement {
 public:
  virtual ~StepEngagement() = default;
  // Removes `sweep`; the volume removed, mm³. With `record`, `at` reports on this step; without,
  // the sweep is motion between locations (a stretch before a move's first location).
  virtual double remove(const MoveSweep& sweep, bool record) = 0;
  // The engagement at `state` with the last step removed with `record`.
  virtual EngagementMap at(const ToolState& state) const = 0;
};

class Workpiece {
 public:
  virtual ~Workpiece() = default;
  // The smallest volume the workpiece resolves, mm³: a move that removes less cut nothing.
  virtual double cell_volume() const = 0;
  // Removes the sweeps, in order, in one pass where the backend can; the volume each removed.
  virtual std::vector<double> remove(std::span<const MoveSweep> sweeps) = 0;
  // The step engagement of `cutter` on this workpiece. An `options.contact` of 0 is the caller's
  // to set (the sweep tolerance).
  virtual std::unique_ptr<StepEngagement> engagement(const Cutter& cutter,
                                                     const EngagementOptions& options) = 0;
};

}  // namespace cwe

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
#include "cwe/geometry/aabb.hpp"
#include "cwe/kinematics/tool_state.hpp"
#include "cwe/tool/cutter.hpp"

namespace cwe {

// One cutter's engagement on a workpiece, a step at a time: each step (the motion from a cutter
// location to the next) is removed and recorded, and the engagement at the location is where
// that removal touches the cutter (CWE = FCS ∩ (W ∩ SV), docs/engagement.md).
//
// Steps are removed in order, one at a time or several in one call (remove_parts); the
// engagement of a step reads only that step's record, so the main loop finds the engagement of
// several locations at once, and while later steps are being removed (EngagementRun).
class StepEngagement {
 public:
  // What one step removed, as the backend records it.
  class Step {
   public:
    virtual ~Step() = default;
  };
  virtual ~StepEngagement() = default;
  // An empty record (to be filled by remove, and reused step after step).
  virtual std::unique_ptr<Step> new_step() const = 0;
  // Removes `sweep`; the volume removed, mm³. With `step`, what the sweep removed replaces the
  // record's contents, for `at`; without, the sweep is motion between locations (a stretch
  // before a move's first location).
  virtual double remove(const MoveSweep& sweep, Step* step) = 0;
  // A part of the path: `sweep`, removed into `step` (null for motion between locations).
  struct Part {
    const MoveSweep* sweep = nullptr;
    Step* step = nullptr;
  };
  // Removes the parts in order, each as remove(*sweep, step) would one after the other, with
  // each step's record its own; the volume each removed, mm³. Each step appears once. The
  // default removes them one by one; the tri-dexel backend in one parallel pass over its rays.
  virtual std::vector<double> remove_parts(std::span<const Part> parts) {
    std::vector<double> volumes;
    volumes.reserve(parts.size());
    for (const Part& part : parts) volumes.push_back(remove(*part.sweep, part.step));
    return volumes;
  }
  // How many steps the main loop may give one remove_parts(): at most steps_per_removal(), and
  // while the records' estimated sizes (record_bytes of each step's sweep, an upper estimate
  // of its record's memory) stay within the loop's budget; one step at least. The defaults give
  // one step at a time.
  virtual std::size_t steps_per_removal() const { return 1; }
  virtual std::size_t record_bytes(const MoveSweep& /*sweep*/) const { return 0; }
  // True for a backend that removes a move in one piece (the mesh workpiece: booleans step by
  // step would split the cut faces at every step). The loop then gives remove_move() each
  // move's whole sweep before any of its parts, and remove() only records the move's steps
  // (and returns 0). False (the default): moves are removed part by part.
  virtual bool removes_whole_moves() const { return false; }
  // Removes the sweep of a whole move (removes_whole_moves() backends only); the volume, mm³.
  virtual double remove_move(const MoveSweep& /*sweep*/) { return 0.0; }
  // Work on a step's record that the removals after it need not wait for (the tri-dexel
  // record's index): called once after the step's removal and before `at`, on any thread,
  // concurrently with other steps' calls and with `remove` of later steps into other records.
  // A wrapper of another StepEngagement passes it on. The default has nothing to do.
  virtual void finish(Step& /*step*/) const {}
  // The engagement at `state`, where `step` records the step that starts there (finished). Safe
  // to call concurrently with other calls of `at` and with `remove` of later steps into other
  // records.
  virtual EngagementMap at(const ToolState& state, const Step& step) const = 0;
};

class Workpiece {
 public:
  virtual ~Workpiece() = default;
  // The smallest volume the workpiece resolves, mm³: a move that removes less cut nothing.
  virtual double cell_volume() const = 0;
  // A box holding all the material there will ever be (removal only takes it away), within
  // which alone sweeps need their deviation bound (MoveSweep's region); empty when the backend
  // keeps its sweeps accurate everywhere.
  virtual Aabb region() const { return Aabb(); }
  // Removes the sweeps, in order, in one pass where the backend can; the volume each removed.
  virtual std::vector<double> remove(std::span<const MoveSweep> sweeps) = 0;
  // The step engagement of `cutter` on this workpiece. An `options.contact` of 0 is the caller's
  // to set (the sweep tolerance).
  virtual std::unique_ptr<StepEngagement> engagement(const Cutter& cutter,
                                                     const EngagementOptions& options) = 0;
};

}  // namespace cwe

#pragma once
// What a job's run hands on at every cutter location, and the interface of whatever receives it
// (the CSV, JSONL and figure writers, or a caller's own code): one call per CL, in order.

#include <cstddef>
#include <string>

#include "cwe/engagement/engagement_map.hpp"
#include "cwe/kinematics/tool_state.hpp"
#include "cwe/process/force_model.hpp"
#include "cwe/tool/cutter.hpp"
#include "cwe/toolpath/cl_sampling.hpp"
#include "cwe/toolpath/move.hpp"

namespace cwe {

// One cutter location of a job. The references live for the call only.
struct ClResult {
  std::size_t index = 0;  // over the whole job, from 0
  const ClPoint& cl;      // `cl.move` counts the moves of the whole job, from 0
  const ToolState& state;
  const EngagementMap& map;
  const Cutter& cutter;
  std::size_t operation = 0;  // the job's program, from 0
  int tool = 0;               // the tool number (0: the program loads none)
  const std::string& file;    // the source file of the move
  const Move& move;           // the move of the CL
  // With a force model: the model, the feed rate (mm/min) and spindle speed (rev/min) of the
  // move as it takes them, and the forces when the run evaluates them.
  const ForceModel* force_model = nullptr;
  double feed_rate = 0.0;
  double spindle_speed = 0.0;
  const ClForces* forces = nullptr;
};

class ClSink {
 public:
  virtual ~ClSink() = default;
  virtual void add(const ClResult& result) = 0;
  // Whether CL `index` should come with its force-versus-angle curve (ClForces::curve).
  virtual bool wants_curve(std::size_t /*index*/, bool /*engaged*/) { return false; }
};

}  // namespace cwe

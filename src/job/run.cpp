#include "cwe/job/run.hpp"

#include <algorithm>
#include <utility>

#include "cwe/engagement/dexel_workpiece.hpp"
#include "cwe/engagement/mesh_workpiece.hpp"
#include "cwe/io/occt.hpp"
#include "cwe/io/step.hpp"

namespace cwe {
namespace {

// A CL's forces, evaluated with its engagement (EngagementRun's prepare), without the curve.
struct PreparedForces : ClExtra {
  ClForces forces;
};

// Adds one operation's removal figures to the job's.
void merge(RemovalSummary& job, const RemovalSummary& op, int move_offset) {
  job.moves += op.moves;
  job.feed_moves += op.feed_moves;
  job.rapid_moves += op.rapid_moves;
  job.cutting_moves += op.cutting_moves;
  job.linear_pieces += op.linear_pieces;
  job.deviation_bound = std::max(job.deviation_bound, op.deviation_bound);
  for (RapidCut cut : op.rapid_cuts) {
    if (job.rapid_cuts.size() == RemovalSummary::kRapidCutsKept) break;
    cut.move += move_offset;
    job.rapid_cuts.push_back(cut);
  }
  job.rapid_cut_count += op.rapid_cut_count;
}

// Runs the job on `workpiece` (the seam, cwe/engagement/workpiece.hpp), filling `result`'s
// figures but for its volumes.
void run_on(const PreparedJob& job, Workpiece& workpiece, const RunOptions& options,
            std::span<ClSink* const> sinks, const Progress& progress, JobResult& result) {
  const SimulationOptions& simulation = job.simulation;
  const std::size_t all_moves = move_count(job);
  std::size_t moves_before = 0, cls_before = 0, done = 0;
  // The operation running (its CLs all come to `sink` before its run's finish() returns).
  const PreparedOperation* op = nullptr;
  const auto sink = [&](const ClEngagement& e) {
    const ClPoint& cl = e.cl;
    const ToolState& state = e.state;
    const EngagementMap& map = e.map;
    const std::size_t k = cls_before + e.index;
    ClPoint global = cl;
    global.move += static_cast<int>(moves_before);
    ++result.cl_points;
    if (map.engaged) ++result.engaged_cl_points;
    result.deepest = std::max(result.deepest, map.axial_depth);
    result.largest_area = std::max(result.largest_area, map.area);
    const std::string& file = e.file.empty() ? op->path : e.file;
    std::optional<ClForces> forces;
    double feed = 0.0, spindle = 0.0;
    if (op->forces) {
      spindle = spindle_speed(e.move, *job.forces);
      feed = feed_rate(e.move, *job.forces);
    }
    if (op->forces && options.forces) {
      // Every sink is asked (no short cut): a sink's choice may keep state from CL to CL.
      bool curve = false;
      for (ClSink* s : sinks) curve = s->wants_curve(k, map.engaged) || curve;
      // The forces came with the engagement (prepare, below); a CL whose curve is wanted has
      // them evaluated again with it (the same figures: the curve only adds to them).
      forces = curve ? op->forces->evaluate(map, state,
                                            feed_per_tooth(feed, op->forces->flutes(), spindle),
                                            spindle, true)
                     : static_cast<const PreparedForces*>(e.extra)->forces;
      result.extremes.add(*forces, k, file, cl.line);
    }
    const ClResult at{k,
                      global,
                      state,
                      map,
                      op->cutter,
                      op->operation,
                      op->tool,
                      file,
                      e.move,
                      op->forces ? &*op->forces : nullptr,
                      feed,
                      spindle,
                      forces ? &*forces : nullptr};
    for (ClSink* s : sinks) s->add(at);
  };
  // The forces at a CL need no order: they are evaluated beside its engagement, in parallel.
  const auto prepare = [&](const ClEngagement& e) -> std::unique_ptr<ClExtra> {
    if (!(op->forces && options.forces)) return nullptr;
    auto prepared = std::make_unique<PreparedForces>();
    const double spindle = spindle_speed(e.move, *job.forces);
    const double fpt =
        feed_per_tooth(feed_rate(e.move, *job.forces), op->forces->flutes(), spindle);
    prepared->forces = op->forces->evaluate(e.map, e.state, fpt, spindle, false);
    return prepared;
  };
  // One of these runs the current operation.
  std::optional<RemovalRun> removal;
  std::optional<EngagementRun> engagement;
  OperationVisitor visitor;
  visitor.begin = [&](std::size_t o) {
    op = &job.operations[o];
    if (!options.engagement) {
      removal.emplace(workpiece, op->cutter, simulation);
    } else {
      engagement.emplace(workpiece, op->cutter, EngagementRunOptions{simulation, op->sampling, {}},
                         sink, MoveRemoved{}, prepare);
    }
  };
  visitor.move = [&](const Move& m, const std::vector<std::string>& files) {
    if (removal) {
      removal->add(m, files);
    } else {
      engagement->add(m, files);
    }
    if (progress) progress(++done, all_moves);
  };
  visitor.end = [&](std::size_t) {
    result.per_operation.push_back(removal ? removal->finish() : engagement->finish());
    removal.reset();
    engagement.reset();
    merge(result.removal, result.per_operation.back(), static_cast<int>(moves_before));
    moves_before += op->moves.size();
    // EngagementRun counts as it samples: the operation's CLs are numbered 0 … cl_points - 1.
    if (options.engagement) cls_before += op->cl_points;
  };
  for_each_move(job, visitor);
}

// A mesh's or a solid's volume as the rays' three figures.
template <class Stock>
TriDexel::Volume volume_of(const Stock& stock) {
  TriDexel::Volume v;
  v.by_family.fill(stock.volume());
  return v;
}

}  // namespace

void ForceExtremes::add(const ClForces& f, std::size_t cl, const std::string& file, int line) {
  if (f.cutting) ++cutting;
  const auto update = [&](Extreme& e, double value) {
    if (value > e.value) e = {value, cl, file, line};
  };
  update(force, f.peak_resultant);
  update(torque, f.peak_torque);
  update(power, f.mean_power);
  update(chip, f.max_chip);
}

JobResult run_job(const PreparedJob& job, TriDexel stock, const RunOptions& options,
                  std::span<ClSink* const> sinks, const Progress& progress) {
  JobResult result(std::move(stock));
  result.initial_volume = result.stock->volume();
  DexelWorkpiece workpiece(*result.stock);
  run_on(job, workpiece, options, sinks, progress, result);
  result.final_volume = result.stock->volume();
  return result;
}

JobResult run_job(const PreparedJob& job, MeshStock stock, const RunOptions& options,
                  std::span<ClSink* const> sinks, const Progress& progress) {
  JobResult result(std::move(stock));
  result.initial_volume = volume_of(*result.mesh);
  MeshWorkpiece workpiece(*result.mesh, job.facet, job.simulation.resolution);
  run_on(job, workpiece, options, sinks, progress, result);
  result.final_volume = volume_of(*result.mesh);
  return result;
}

JobResult run_job(const PreparedJob& job, BrepStock stock, const RunOptions& options,
                  std::span<ClSink* const> sinks, const Progress& progress) {
  JobResult result(std::move(stock));
  result.initial_volume = volume_of(*result.brep);
  const std::unique_ptr<Workpiece> workpiece =
      brep_workpiece(*result.brep, job.simulation.resolution);
  run_on(job, *workpiece, options, sinks, progress, result);
  result.final_volume = volume_of(*result.brep);
  return result;
}

JobStock make_job_stock(const PreparedJob& job) {
  JobStock stock;
  if (job.workpiece == WorkpieceKind::kBrep) {
    stock.brep.emplace(job.stock.is_box ? brep_stock(job.stock.box)
                       : job.stock.step ? brep_stock(*job.stock.step)
                                        : brep_stock(*job.stock.mesh_solid));
  } else if (job.workpiece == WorkpieceKind::kMesh) {
    stock.mesh.emplace(make_mesh_stock(job.stock, job.simulation));
  } else {
    stock.rays.emplace(make_stock(job.stock, job.simulation));
  }
  return stock;
}

JobResult run_job(const PreparedJob& job, JobStock stock, const RunOptions& options,
                  std::span<ClSink* const> sinks, const Progress& progress) {
  if (stock.brep) return run_job(job, std::move(*stock.brep), options, sinks, progress);
  if (stock.mesh) return run_job(job, std::move(*stock.mesh), options, sinks, progress);
  return run_job(job, std::move(*stock.rays), options, sinks, progress);
}

}  // namespace cwe

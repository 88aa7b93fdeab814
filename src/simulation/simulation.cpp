#include "cwe/simulation/simulation.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <filesystem>
#include <memory>

#include <fmt/format.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_pipeline.h>
#include <tbb/task_arena.h>

#include "cwe/core/assert.hpp"
#include "cwe/core/computation_error.hpp"
#include "cwe/core/numbers.hpp"
#include "cwe/engagement/dexel_workpiece.hpp"
#include "cwe/io/mesh_io.hpp"

namespace cwe {

StockSpec parse_stock_spec(const std::string& text, const SourceLocation& source) {
  constexpr std::string_view kBox = "box:";
  StockSpec spec;
  if (text.rfind(kBox, 0) != 0) {
    if (text.empty()) {
      throw InputError(source, "empty stock: expected box:…, an STL file or a STEP file");
    }
    spec.is_box = false;
    spec.path = text;
    return spec;
  }
  std::string_view body = std::string_view(text).substr(kBox.size());
  // A trailing ":in" or ":mm" gives the numbers' unit (default mm).
  double scale = 1.0;
  if (body.ends_with(":in")) {
    scale = 25.4;
    body.remove_suffix(3);
  } else if (body.ends_with(":mm")) {
    body.remove_suffix(3);
  }
  const NumberList list = parse_number_list(body);
  if (list.bad) {
    throw InputError(source, fmt::format("stock '{}': '{}' is not a number; expected "
                                         "box:xmin,ymin,zmin,xmax,ymax,zmax in mm (or …:in)",
                                         text, *list.bad));
  }
  std::vector<double> values = list.values;
  for (double& v : values) v *= scale;
  if (values.size() != 6) {
    throw InputError(source, fmt::format("stock '{}': expected six numbers "
                                         "box:xmin,ymin,zmin,xmax,ymax,zmax, got {}",
                                         text, values.size()));
  }
  spec.box = Aabb{{values[0], values[1], values[2]}, {values[3], values[4], values[5]}};
  for (int a = 0; a < 3; ++a) {
    if (!(spec.box.min[a] < spec.box.max[a])) {
      throw InputError(source, fmt::format("stock '{}': {} min {} is not below max {}", text,
                                           "xyz"[a], spec.box.min[a], spec.box.max[a]));
    }
  }
  return spec;
}

StockSpec read_stock_spec(const std::string& text, const SourceLocation& source) {
  StockSpec spec = parse_stock_spec(text, source);
  if (!spec.is_box) {
    std::error_code ec;
    if (!std::filesystem::exists(spec.path, ec)) {
      throw InputError(source, fmt::format("'{}': no such file; expected "
                                           "box:xmin,ymin,zmin,xmax,ymax,zmax, a closed STL file "
                                           "or a STEP file",
                                           spec.path));
    }
    if (spec.is_step()) {
      spec.step = std::make_shared<const StepModel>(StepModel::read(spec.path));
    } else {
      spec.mesh = std::make_shared<const TriangleMesh>(read_stl(spec.path).mesh);
    }
  }
  return spec;
}

double stock_top(const StockSpec& spec) { return stock_box(spec).max.z(); }

Aabb stock_box(const StockSpec& spec) {
  if (spec.is_box) return spec.box;
  if (spec.step) return spec.step->bounds();
  CWE_ASSERT(spec.mesh != nullptr, "the STL stock is read before its box is asked for");
  return spec.mesh->bounds();
}

double step_tessellation(const SimulationOptions& options, bool mesh_workpiece) {
  return mesh_workpiece ? options.effective_tolerance() : options.resolution / 10.0;
}

namespace {

// A STEP stock's triangles (read now when read_stock_spec has not).
TriangleMesh step_triangles(const StockSpec& spec, double deviation) {
  const StepModel model = spec.step ? *spec.step : StepModel::read(spec.path);
  try {
    return model.tessellate(deviation);
  } catch (const ComputationError& e) {
    throw InputError(SourceLocation{spec.path}, e.what());
  }
}

}  // namespace

TriDexel make_stock(const StockSpec& spec, const SimulationOptions& options) {
  if (!std::isfinite(options.resolution) || options.resolution <= 0.0) {
    throw InputError(SourceLocation{"--resolution"},
                     fmt::format("{} mm: expected a positive ray spacing", options.resolution));
  }
  if (spec.is_box) return TriDexel::from_box(spec.box, options.resolution);
  if (spec.is_step()) {
    return TriDexel::from_mesh(step_triangles(spec, step_tessellation(options, false)),
                               options.resolution, spec.path);
  }
  if (spec.mesh) return TriDexel::from_mesh(*spec.mesh, options.resolution, spec.path);
  return TriDexel::from_mesh(read_stl(spec.path).mesh, options.resolution, spec.path);
}

MeshStock make_mesh_stock(const StockSpec& spec, const SimulationOptions& options) {
  if (spec.is_box) return MeshStock::from_box(spec.box);
  if (spec.is_step()) {
    return MeshStock::from_mesh(step_triangles(spec, step_tessellation(options, true)), spec.path);
  }
  if (spec.mesh) return MeshStock::from_mesh(*spec.mesh, spec.path);
  return MeshStock::from_mesh(read_stl(spec.path).mesh, spec.path);
}

namespace {

// The file of a move whose source names none.
const std::string kNoFile;

// Counts a move (index `index`, a rapid or not; a rapid at `location`) and its removal into the
// summary.
void record_move(RemovalSummary& summary, std::size_t index, bool rapid,
                 const SourceLocation& location, int pieces, double deviation, double volume,
                 double cell, const MoveRemoved& removed) {
  ++summary.moves;
  ++(rapid ? summary.rapid_moves : summary.feed_moves);
  summary.linear_pieces += pieces;
  summary.deviation_bound = std::max(summary.deviation_bound, deviation);
  if (removed) removed(index, volume);
  // Float rounding of ray ends can shave slivers off rays a move only touches; a move cuts when
  // it removes at least one cell's worth, s³. A rapid is reported from ten cells on: subdivided
  // moves (arcs, 5-axis) leave slivers up to their tolerance thick that a retract may clear.
  const bool cuts = volume >= cell;
  if (cuts) ++summary.cutting_moves;
  if (volume >= 10.0 * cell && rapid) {
    if (summary.rapid_cuts.size() < RemovalSummary::kRapidCutsKept) {
      summary.rapid_cuts.push_back({static_cast<int>(index), location, volume});
    }
    ++summary.rapid_cut_count;
  }
}

// A failed computation's message, prefixed with the move's place ("file:line: ").
std::string at_move(const SourceLocation& at, const char* what) {
  return fmt::format("{}:{}: {}", at.source.empty() ? "toolpath" : at.source, at.line, what);
}

// A MoveRemoved that also keeps the volumes in `summary.removed_by_move` (the Toolpath
// functions).
MoveRemoved keeping(std::vector<double>& volumes) {
  return [&volumes](std::size_t, double volume) { volumes.push_back(volume); };
}

}  // namespace

RemovalRun::RemovalRun(Workpiece& stock, const Cutter& cutter, const SimulationOptions& options,
                       MoveRemoved removed)
    : stock_(stock),
      parts_(cutter, options.effective_tolerance()),
      removed_(std::move(removed)),
      cell_(stock.cell_volume()) {}

void RemovalRun::add(const Move& move, const std::vector<std::string>& sources) {
  sweeps_.emplace_back(parts_, move, stock_.region());
  pending_.push_back(
      {move.is_rapid(), SourceLocation{source_file(move, sources, kNoFile), move.line}});
  pieces_ += sweeps_.back().pieces().size();
  if (pieces_ >= kBatchPieces) flush();
}

void RemovalRun::flush() {
  if (sweeps_.empty()) return;
  std::vector<double> volume;
  try {
    volume = stock_.remove(sweeps_);
  } catch (const ComputationError& e) {
    const std::size_t k = std::min(e.item().value_or(0), pending_.size() - 1);
    throw ComputationError(at_move(pending_[k].at, e.what()));
  }
  for (std::size_t m = 0; m < sweeps_.size(); ++m) {
    record_move(summary_, static_cast<std::size_t>(summary_.moves), pending_[m].rapid,
                pending_[m].rapid ? pending_[m].at : SourceLocation{},
                static_cast<int>(sweeps_[m].pieces().size()), sweeps_[m].deviation_bound(),
                volume[m], cell_, removed_);
  }
  sweeps_.clear();
  pending_.clear();
  pieces_ = 0;
}

RemovalSummary RemovalRun::finish() {
  flush();
  return std::move(summary_);
}

RemovalSummary remove_toolpath(Workpiece& stock, const Cutter& cutter, const Toolpath& path,
                               const SimulationOptions& options, const Progress& progress) {
  std::vector<double> volumes;
  RemovalRun run(stock, cutter, options, keeping(volumes));
  const std::size_t total = path.moves.size();
  for (std::size_t i = 0; i < total; ++i) {
    const std::size_t removed = volumes.size();
    run.add(path.moves[i], path.sources);
    if (progress && volumes.size() != removed) progress(volumes.size(), total);  // a batch
  }
  const std::size_t removed = volumes.size();
  RemovalSummary summary = run.finish();
  if (progress && volumes.size() != removed) progress(volumes.size(), total);
  summary.removed_by_move = std::move(volumes);
  return summary;
}

RemovalSummary remove_toolpath(TriDexel& stock, const Cutter& cutter, const Toolpath& path,
                               const SimulationOptions& options, const Progress& progress) {
  DexelWorkpiece workpiece(stock);
  return remove_toolpath(workpiece, cutter, path, options, progress);
}

namespace {

// Removed material within the sweep tolerance of the cutter touches it (5-axis pieces turn about
// their mean axis, so a cutter location and the end of the step before it differ by up to the
// tolerance).
EngagementOptions with_contact(EngagementOptions engagement, double tolerance) {
  if (engagement.contact == 0.0) engagement.contact = tolerance;
  return engagement;
}

SamplingOptions feed_only(SamplingOptions sampling) {
  sampling.include_rapids = false;
  return sampling;
}

}  // namespace

EngagementRun::EngagementRun(Workpiece& stock, const Cutter& cutter,
                             const EngagementRunOptions& options, const EngagementSink& sink,
                             MoveRemoved removed, ClPrepare prepare)
    : cell_(stock.cell_volume()),
      region_(stock.region()),
      parts_(cutter, options.simulation.effective_tolerance()),
      engage_(stock.engagement(
          cutter, with_contact(options.engagement, options.simulation.effective_tolerance()))),
      sampler_(feed_only(options.sampling)),
      sink_(sink),
      removed_(std::move(removed)),
      prepare_(std::move(prepare)),
      batch_locations_(std::max<std::size_t>(1, options.batch_locations)),
      batch_moves_(std::max<std::size_t>(1, options.batch_moves)) {
  // Groups of steps in flight: enough to keep every thread busy while one removes. Their
  // records are made as the groups first need them.
  const int tokens = std::max(4, 2 * tbb::this_task_arena::max_concurrency());
  steps_.resize(static_cast<std::size_t>(tokens));
}

EngagementRun::~EngagementRun() = default;

void EngagementRun::add(const Move& move, const std::vector<std::string>& sources) {
  const std::size_t index = added_++;
  sampler_.next(move, static_cast<int>(index), sampled_);
  const std::string& file = source_file(move, sources, kNoFile);
  if (files_.empty() || files_.back() != file) files_.push_back(file);
  moves_.push_back({move, index, files_.size() - 1, cls_.size(), sampled_.size()});
  for (const ClPoint& cl : sampled_) {
    const ToolState state = tool_state(cl, previous_x_);
    previous_x_ = state.tcs.x();
    cls_.push_back({cl, state});
  }
  if (cls_.size() >= batch_locations_ || moves_.size() >= batch_moves_) flush();
}

void EngagementRun::flush() {
  if (moves_.empty()) return;
  // A step in flight: its location, its record and the engagement found there.
  struct Slot {
    std::size_t index = 0;  // of the location among the run's
    const PendingMove* move = nullptr;
    const PendingCl* at = nullptr;
    StepEngagement::Step* step = nullptr;
    EngagementMap map;
    std::unique_ptr<ClExtra> extra;  // what prepare_ made of it
    ClEngagement engagement(const std::vector<std::string>& files) const {
      return {index, move->move, files[move->file], at->cl, at->state, map, extra.get()};
    }
  };
  // The steps removed by one remove_parts(), with the motion between them. Group n uses token
  // n mod tokens: the pipeline holds at most `tokens` groups and finishes them in order, so
  // group n is done before group n + tokens starts.
  struct Group {
    std::vector<Slot> slots;
    std::deque<MoveSweep> sweeps;  // of the parts (a deque: parts point into it)
    std::vector<StepEngagement::Part> parts;
    std::vector<std::size_t> part_move;  // index in moves_ of each part's move
  };
  const std::size_t tokens = steps_.size();
  std::vector<Group> groups(tokens);
  const std::size_t budget = kRecordBudget / tokens;
  const std::size_t most_steps = std::max<std::size_t>(1, engage_->steps_per_removal());
  std::size_t m = 0, next = 0;  // the move being removed and its next location
  bool entered = false;         // whether move m's motion before its first location is given
  std::size_t recorded = 0;     // moves whose removal is summed up (record_move)
  std::size_t started = 0;      // groups started
  // Per move of the batch, summed as its parts are removed.
  std::vector<int> pieces(moves_.size(), 0);
  std::vector<double> deviation(moves_.size(), 0.0), volume(moves_.size(), 0.0);
  // A backend that removes moves whole does so before their parts are recorded; the parts'
  // pieces are then not counted again.
  const bool whole = engage_->removes_whole_moves();
  // A step recorded for its engagement keeps the pieces of the whole tool's reach: its record
  // is read against the tool's surface within the contact tolerance, and pieces for the reach
  // into the stock alone (MoveSweep's region) would move that surface by up to the tolerance,
  // several times the error of the whole reach's pieces there (on the bundled example's 5-axis
  // pass, exit angles 2.8° off a 0.001 mm reference at the 99th percentile instead of 0.3°).
  // Motion without a record needs the sweep within the tolerance only where the stock is.
  const auto sweep_of = [&](const Move& move, double u0, double u1, bool recorded_step) {
    return MoveSweep(
        parts_, u0 == 0.0 && u1 == 1.0 ? move : move.part(u0, u1), region_,
        recorded_step ? MoveSweep::PieceReach::kWholeTool : MoveSweep::PieceReach::kRegion);
  };
  const auto add_part = [&](Group& group, MoveSweep sweep, StepEngagement::Step* step) {
    if (!whole) {
      pieces[m] += static_cast<int>(sweep.pieces().size());
      deviation[m] = std::max(deviation[m], sweep.deviation_bound());
    }
    group.sweeps.push_back(std::move(sweep));
    group.parts.push_back({&group.sweeps.back(), step});
    group.part_move.push_back(m);
  };
  const auto remove_whole = [&](const PendingMove& pending) {
    const MoveSweep sweep(parts_, pending.move, region_);
    pieces[m] += static_cast<int>(sweep.pieces().size());
    deviation[m] = std::max(deviation[m], sweep.deviation_bound());
    try {
      volume[m] += engage_->remove_move(sweep);
    } catch (const ComputationError& e) {
      throw ComputationError(
          at_move(SourceLocation{files_[pending.file], pending.move.line}, e.what()));
    }
  };
  const auto move_done = [&] {
    ++m;
    next = 0;
    entered = false;
  };
  // The moves done so far, summed up in order.
  const auto record_done = [&] {
    for (; recorded < m; ++recorded) {
      const PendingMove& done = moves_[recorded];
      const bool rapid = done.move.is_rapid();
      record_move(summary_, done.index, rapid,
                  rapid ? SourceLocation{files_[done.file], done.move.line} : SourceLocation{},
                  pieces[recorded], deviation[recorded], volume[recorded], cell_, removed_);
    }
  };
  // Removal, in order: each step from a location to the next is removed into its own record
  // (CWE = FCS ∩ (W ∩ SV): the engagement at a location is where that removal touches the
  // cutter); motion before a move's first location, and moves without one, are removed whole.
  // A group gathers parts until it holds the steps the backend takes at once.
  const auto remove_next = [&](tbb::flow_control& control) -> Group* {
    const std::size_t token = started % tokens;
    Group& group = groups[token];
    auto& records = steps_[token];
    group.slots.clear();
    group.parts.clear();
    group.sweeps.clear();
    group.part_move.clear();
    std::size_t bytes = 0;
    while (m < moves_.size()) {
      const PendingMove& pending = moves_[m];
      if (!entered) {
        // A move removed whole goes after the parts before it (the steps it must not touch).
        if (whole) {
          if (!group.parts.empty()) break;
          remove_whole(pending);
        }
        entered = true;
        if (pending.cl_count == 0) {
          add_part(group, sweep_of(pending.move, 0.0, 1.0, false), nullptr);
          move_done();
          continue;
        }
        const double first = cls_[pending.first_cl].cl.u;
        if (first > 0.0) add_part(group, sweep_of(pending.move, 0.0, first, false), nullptr);
      }
      if (group.slots.size() == most_steps) break;
      const PendingCl* at = &cls_[pending.first_cl + next];
      const bool last = next + 1 == pending.cl_count;
      MoveSweep sweep = sweep_of(pending.move, at->cl.u, last ? 1.0 : (at + 1)->cl.u, true);
      const std::size_t step_bytes = engage_->record_bytes(sweep);
      if (!group.slots.empty() && bytes + step_bytes > budget) break;
      bytes += step_bytes;
      if (records.size() == group.slots.size()) records.push_back(engage_->new_step());
      Slot& slot = group.slots.emplace_back();
      slot.step = records[group.slots.size() - 1].get();
      slot.index = index_++;
      slot.move = &pending;
      slot.at = at;
      add_part(group, std::move(sweep), slot.step);
      ++next;
      if (last) move_done();
    }
    if (group.parts.empty()) {
      record_done();
      control.stop();
      return nullptr;
    }
    ++started;
    const std::vector<double> removed = engage_->remove_parts(group.parts);
    for (std::size_t p = 0; p < removed.size(); ++p) volume[group.part_move[p]] += removed[p];
    record_done();
    return &group;
  };
  tbb::parallel_pipeline(
      tokens,
      tbb::make_filter<void, Group*>(tbb::filter_mode::serial_in_order, remove_next) &
          tbb::make_filter<Group*, Group*>(
              tbb::filter_mode::parallel,
              [this](Group* group) {
                tbb::parallel_for(std::size_t{0}, group->slots.size(), [&](std::size_t k) {
                  Slot& slot = group->slots[k];
                  engage_->finish(*slot.step);
                  slot.map = engage_->at(slot.at->state, *slot.step);
                  if (prepare_) slot.extra = prepare_(slot.engagement(files_));
                });
                return group;
              }) &
          tbb::make_filter<Group*, void>(tbb::filter_mode::serial_in_order, [this](Group* group) {
            for (Slot& slot : group->slots) {
              sink_(slot.engagement(files_));
              slot.extra.reset();
            }
          }));
  moves_.clear();
  files_.clear();
  cls_.clear();
}

RemovalSummary EngagementRun::finish() {
  flush();
  return std::move(summary_);
}

RemovalSummary simulate_engagement(Workpiece& stock, const Cutter& cutter, const Toolpath& path,
                                   const EngagementRunOptions& options, const EngagementSink& sink,
                                   const Progress& progress) {
  std::vector<double> volumes;
  EngagementRun run(stock, cutter, options, sink, keeping(volumes));
  const std::size_t total = path.moves.size();
  for (std::size_t i = 0; i < total; ++i) {
    run.add(path.moves[i], path.sources);
    if (progress) progress(i + 1, total);
  }
  RemovalSummary summary = run.finish();
  summary.removed_by_move = std::move(volumes);
  return summary;
}

RemovalSummary simulate_engagement(TriDexel& stock, const Cutter& cutter, const Toolpath& path,
                                   const EngagementRunOptions& options, const EngagementSink& sink,
                                   const Progress& progress) {
  DexelWorkpiece workpiece(stock);
  return simulate_engagement(workpiece, cutter, path, options, sink, progress);
}

}  // namespace cwe

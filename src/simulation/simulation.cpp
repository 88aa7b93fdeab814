#include "cwe/simulation/simulation.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <memory>

#include <fmt/format.h>

#include "cwe/core/assert.hpp"
#include "cwe/core/numbers.hpp"
#include "cwe/engagement/dexel_workpiece.hpp"
#include "cwe/io/mesh_io.hpp"

namespace cwe {

StockSpec parse_stock_spec(const std::string& text, const SourceLocation& source) {
  constexpr std::string_view kBox = "box:";
  StockSpec spec;
  if (text.rfind(kBox, 0) != 0) {
    if (text.empty()) throw InputError(source, "empty stock: expected box:… or an STL file");
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
                                           "box:xmin,ymin,zmin,xmax,ymax,zmax or a closed STL file",
                                           spec.path));
    }
    spec.mesh = std::make_shared<const TriangleMesh>(read_stl(spec.path).mesh);
  }
  return spec;
}

double stock_top(const StockSpec& spec) { return stock_box(spec).max.z(); }

Aabb stock_box(const StockSpec& spec) {
  if (spec.is_box) return spec.box;
  CWE_ASSERT(spec.mesh != nullptr, "the STL stock is read before its box is asked for");
  return spec.mesh->bounds();
}

TriDexel make_stock(const StockSpec& spec, const SimulationOptions& options) {
  if (!std::isfinite(options.resolution) || options.resolution <= 0.0) {
    throw InputError(SourceLocation{"--resolution"},
                     fmt::format("{} mm: expected a positive ray spacing", options.resolution));
  }
  if (spec.is_box) return TriDexel::from_box(spec.box, options.resolution);
  if (spec.mesh) return TriDexel::from_mesh(*spec.mesh, options.resolution, spec.path);
  return TriDexel::from_mesh(read_stl(spec.path).mesh, options.resolution, spec.path);
}

namespace {

// Where a rapid is in its file (a rapid that cuts is listed); nothing for a feed move, so that
// the moves that are not listed cost no copy of their file's name.
SourceLocation rapid_location(const Move& move, const std::vector<std::string>& sources) {
  static const std::string kNoFile;
  if (!move.is_rapid()) return {};
  return SourceLocation{source_file(move, sources, kNoFile), move.line};
}

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
  sweeps_.emplace_back(parts_, move);
  pending_.push_back({move.is_rapid(), rapid_location(move, sources)});
  pieces_ += sweeps_.back().pieces().size();
  if (pieces_ >= kBatchPieces) flush();
}

void RemovalRun::flush() {
  if (sweeps_.empty()) return;
  const std::vector<double> volume = stock_.remove(sweeps_);
  for (std::size_t m = 0; m < sweeps_.size(); ++m) {
    record_move(summary_, static_cast<std::size_t>(summary_.moves), pending_[m].rapid,
                pending_[m].location, static_cast<int>(sweeps_[m].pieces().size()),
                sweeps_[m].deviation_bound(), volume[m], cell_, removed_);
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
                             MoveRemoved removed)
    : cell_(stock.cell_volume()),
      parts_(cutter, options.simulation.effective_tolerance()),
      engage_(stock.engagement(
          cutter, with_contact(options.engagement, options.simulation.effective_tolerance()))),
      sampler_(feed_only(options.sampling)),
      sink_(sink),
      removed_(std::move(removed)) {}

EngagementRun::~EngagementRun() = default;

void EngagementRun::add(const Move& move, const std::vector<std::string>& sources) {
  const std::size_t i = moves_++;
  sampler_.next(move, static_cast<int>(i), cls_);
  int pieces = 0;
  double deviation = 0.0, volume = 0.0;
  const auto remove_part = [&](double u0, double u1, bool record = false) {
    const MoveSweep sweep(parts_, u0 == 0.0 && u1 == 1.0 ? move : move.part(u0, u1));
    pieces += static_cast<int>(sweep.pieces().size());
    deviation = std::max(deviation, sweep.deviation_bound());
    volume += engage_->remove(sweep, record);
  };
  if (cls_.empty()) {
    remove_part(0.0, 1.0);
  } else {
    if (cls_.front().u > 0.0) remove_part(0.0, cls_.front().u);
    for (std::size_t k = 0; k < cls_.size(); ++k) {
      // The step from this location to the next is removed first: the engagement here is where
      // that removal touches the cutter (CWE = FCS ∩ (W ∩ SV)).
      const ToolState state = tool_state(cls_[k], previous_x_);
      previous_x_ = state.tcs.x();
      remove_part(cls_[k].u, k + 1 < cls_.size() ? cls_[k + 1].u : 1.0, true);
      sink_(index_++, cls_[k], state, engage_->at(state));
    }
  }
  record_move(summary_, i, move.is_rapid(), rapid_location(move, sources), pieces, deviation,
              volume, cell_, removed_);
}

RemovalSummary EngagementRun::finish() { return std::move(summary_); }

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

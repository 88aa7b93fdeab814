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

// Counts a move and its removal into the summary.
void record_move(RemovalSummary& summary, const Toolpath& path, std::size_t index, int pieces,
                 double deviation, double volume, double cell) {
  const Move& move = path.moves[index];
  ++summary.moves;
  ++(move.is_rapid() ? summary.rapid_moves : summary.feed_moves);
  summary.linear_pieces += pieces;
  summary.deviation_bound = std::max(summary.deviation_bound, deviation);
  summary.removed_by_move.push_back(volume);
  // Float rounding of ray ends can shave slivers off rays a move only touches; a move cuts when
  // it removes at least one cell's worth, s³. A rapid is reported from ten cells on: subdivided
  // moves (arcs, 5-axis) leave slivers up to their tolerance thick that a retract may clear.
  const bool cuts = volume >= cell;
  if (cuts) ++summary.cutting_moves;
  if (volume >= 10.0 * cell && move.is_rapid()) {
    const std::string file =
        move.source >= 0 && static_cast<std::size_t>(move.source) < path.sources.size()
            ? path.sources[static_cast<std::size_t>(move.source)]
            : std::string();
    summary.rapid_cuts.push_back(
        {static_cast<int>(index), SourceLocation{file, move.line}, volume});
  }
}

}  // namespace

RemovalSummary remove_toolpath(Workpiece& stock, const Cutter& cutter, const Toolpath& path,
                               const SimulationOptions& options, const Progress& progress) {
  RemovalSummary summary;
  const ConvexParts parts(cutter, options.effective_tolerance());
  const std::size_t total = path.moves.size();
  const double cell = stock.cell_volume();
  // Moves are removed in batches of about kBatchPieces linear pieces (one pass of the
  // workpiece: the same result as one by one).
  constexpr std::size_t kBatchPieces = 64;
  std::vector<MoveSweep> sweeps;
  for (std::size_t first = 0; first < total;) {
    sweeps.clear();
    std::size_t pieces = 0;
    for (std::size_t i = first; i < total && pieces < kBatchPieces; ++i) {
      sweeps.emplace_back(parts, path.moves[i]);
      pieces += sweeps.back().pieces().size();
    }
    const std::vector<double> volume = stock.remove(sweeps);
    for (std::size_t m = 0; m < sweeps.size(); ++m) {
      record_move(summary, path, first + m, static_cast<int>(sweeps[m].pieces().size()),
                  sweeps[m].deviation_bound(), volume[m], cell);
    }
    first += sweeps.size();
    if (progress) progress(first, total);
  }
  return summary;
}

RemovalSummary remove_toolpath(TriDexel& stock, const Cutter& cutter, const Toolpath& path,
                               const SimulationOptions& options, const Progress& progress) {
  DexelWorkpiece workpiece(stock);
  return remove_toolpath(workpiece, cutter, path, options, progress);
}

RemovalSummary simulate_engagement(Workpiece& stock, const Cutter& cutter, const Toolpath& path,
                                   const EngagementRunOptions& options, const EngagementSink& sink,
                                   const Progress& progress) {
  RemovalSummary summary;
  const double tolerance = options.simulation.effective_tolerance();
  const ConvexParts parts(cutter, tolerance);
  // Removed material within the sweep tolerance of the cutter touches it (5-axis pieces turn
  // about their mean axis, so a cutter location and the end of the step before it differ by up
  // to the tolerance).
  EngagementOptions engagement = options.engagement;
  if (engagement.contact == 0.0) engagement.contact = tolerance;
  const std::unique_ptr<StepEngagement> engage = stock.engagement(cutter, engagement);
  SamplingOptions feed_only = options.sampling;
  feed_only.include_rapids = false;
  ClSampler sampler(feed_only);
  std::vector<ClPoint> cls;  // of the current move
  const std::size_t total = path.moves.size();
  const double cell = stock.cell_volume();
  std::size_t index = 0;  // of the next CL among all of the path's
  Vec3 previous_x = Vec3::Zero();
  for (std::size_t i = 0; i < total; ++i) {
    const Move& move = path.moves[i];
    sampler.next(move, static_cast<int>(i), cls);
    int pieces = 0;
    double deviation = 0.0, volume = 0.0;
    const auto remove_part = [&](double u0, double u1, bool record = false) {
      const MoveSweep sweep(parts, u0 == 0.0 && u1 == 1.0 ? move : move.part(u0, u1));
      pieces += static_cast<int>(sweep.pieces().size());
      deviation = std::max(deviation, sweep.deviation_bound());
      volume += engage->remove(sweep, record);
    };
    if (cls.empty()) {
      remove_part(0.0, 1.0);
    } else {
      if (cls.front().u > 0.0) remove_part(0.0, cls.front().u);
      for (std::size_t k = 0; k < cls.size(); ++k) {
        // The step from this location to the next is removed first: the engagement here is
        // where that removal touches the cutter (CWE = FCS ∩ (W ∩ SV)).
        const ToolState state = tool_state(cls[k], previous_x);
        previous_x = state.tcs.x();
        remove_part(cls[k].u, k + 1 < cls.size() ? cls[k + 1].u : 1.0, true);
        sink(index++, cls[k], state, engage->at(state));
      }
    }
    record_move(summary, path, i, pieces, deviation, volume, cell);
    if (progress) progress(i + 1, total);
  }
  return summary;
}

RemovalSummary simulate_engagement(TriDexel& stock, const Cutter& cutter, const Toolpath& path,
                                   const EngagementRunOptions& options, const EngagementSink& sink,
                                   const Progress& progress) {
  DexelWorkpiece workpiece(stock);
  return simulate_engagement(workpiece, cutter, path, options, sink, progress);
}

}  // namespace cwe

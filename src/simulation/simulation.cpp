#include "cwe/simulation/simulation.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "cwe/core/numbers.hpp"
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

TriDexel make_stock(const StockSpec& spec, const SimulationOptions& options) {
  if (!std::isfinite(options.resolution) || options.resolution <= 0.0) {
    throw InputError(SourceLocation{"--resolution"},
                     fmt::format("{} mm: expected a positive ray spacing", options.resolution));
  }
  if (spec.is_box) return TriDexel::from_box(spec.box, options.resolution);
  return TriDexel::from_mesh(read_stl(spec.path).mesh, options.resolution, spec.path);
}

namespace {

// A linear sweep as a dexel cut: its box, its chords and, where it has one, its cheap reach.
TriDexel::Cut cut_of(const LinearSweep& piece) {
  TriDexel::Cut cut{piece.bounds(), [&piece](const Ray& ray) { return piece.chord(ray); }, {}};
  if (piece.has_reach()) cut.reach = [&piece](const Ray& ray) { return piece.reach(ray); };
  return cut;
}

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

// Removes one sweep; returns the volume removed. `record`, when given, receives what was taken.
double remove_sweep(TriDexel& stock, const MoveSweep& sweep, RemovalRecord* record = nullptr) {
  std::vector<TriDexel::Cut> cuts;
  for (const LinearSweep& piece : sweep.pieces()) {
    cuts.push_back(cut_of(piece));
  }
  double volume = 0.0;
  for (const TriDexel::Removal& r : stock.remove(cuts, record)) volume += r.volume;
  return volume;
}

}  // namespace

RemovalSummary remove_toolpath(TriDexel& stock, const Cutter& cutter, const Toolpath& path,
                               const SimulationOptions& options, const Progress& progress) {
  RemovalSummary summary;
  const ConvexParts parts(cutter, options.effective_tolerance());
  const std::size_t total = path.moves.size();
  const double cell = std::pow(stock.spacing(), 3);
  // Moves are removed in batches of about kBatchPieces linear pieces (TriDexel::remove with
  // several cuts: the same result as one by one, in one parallel pass).
  constexpr std::size_t kBatchPieces = 64;
  std::vector<MoveSweep> sweeps;
  std::vector<TriDexel::Cut> cuts;
  std::vector<std::size_t> owner;  // batch move of each cut
  for (std::size_t first = 0; first < total;) {
    sweeps.clear();
    std::size_t pieces = 0;
    for (std::size_t i = first; i < total && pieces < kBatchPieces; ++i) {
      sweeps.emplace_back(parts, path.moves[i]);
      pieces += sweeps.back().pieces().size();
    }
    cuts.clear();
    owner.clear();
    for (std::size_t m = 0; m < sweeps.size(); ++m) {
      for (const LinearSweep& piece : sweeps[m].pieces()) {
        cuts.push_back(cut_of(piece));
        owner.push_back(m);
      }
    }
    const std::vector<TriDexel::Removal> removed = stock.remove(cuts);
    std::vector<double> volume(sweeps.size(), 0.0);
    for (std::size_t k = 0; k < cuts.size(); ++k) volume[owner[k]] += removed[k].volume;
    for (std::size_t m = 0; m < sweeps.size(); ++m) {
      record_move(summary, path, first + m, static_cast<int>(sweeps[m].pieces().size()),
                  sweeps[m].deviation_bound(), volume[m], cell);
    }
    first += sweeps.size();
    if (progress) progress(first, total);
  }
  return summary;
}

RemovalSummary simulate_engagement(TriDexel& stock, const Cutter& cutter, const Toolpath& path,
                                   const SimulationOptions& options,
                                   const SamplingOptions& sampling,
                                   const EngagementOptions& engagement, const EngagementSink& sink,
                                   const Progress& progress) {
  RemovalSummary summary;
  const ConvexParts parts(cutter, options.effective_tolerance());
  // Removed material within the sweep tolerance of the cutter touches it (5-axis pieces turn
  // about their mean axis, so a cutter location and the end of the step before it differ by up
  // to the tolerance).
  EngagementOptions engagement_options = engagement;
  if (engagement_options.contact == 0.0) engagement_options.contact = options.effective_tolerance();
  const DexelEngagement engage(cutter, stock.spacing(), engagement_options);
  RemovalRecord step;
  SamplingOptions feed_only = sampling;
  feed_only.include_rapids = false;
  const std::vector<ClPoint> cls = sample_cl_points(path, feed_only);
  const std::size_t total = path.moves.size();
  const double cell = std::pow(stock.spacing(), 3);
  std::size_t next = 0;  // the next CL sample
  Vec3 previous_x = Vec3::Zero();
  for (std::size_t i = 0; i < total; ++i) {
    const Move& move = path.moves[i];
    std::size_t end = next;
    while (end < cls.size() && cls[end].move == static_cast<int>(i)) ++end;
    int pieces = 0;
    double deviation = 0.0, volume = 0.0;
    const auto remove_part = [&](double u0, double u1, RemovalRecord* record = nullptr) {
      const MoveSweep sweep(parts, u0 == 0.0 && u1 == 1.0 ? move : move.part(u0, u1));
      pieces += static_cast<int>(sweep.pieces().size());
      deviation = std::max(deviation, sweep.deviation_bound());
      volume += remove_sweep(stock, sweep, record);
    };
    if (next == end) {
      remove_part(0.0, 1.0);
    } else {
      if (cls[next].u > 0.0) remove_part(0.0, cls[next].u);
      for (std::size_t k = next; k < end; ++k) {
        // The step from this location to the next is removed first: the engagement here is
        // where that removal touches the cutter (CWE = FCS ∩ (W ∩ SV)).
        const ToolState state = tool_state(cls[k], previous_x);
        previous_x = state.tcs.x();
        remove_part(cls[k].u, k + 1 < end ? cls[k + 1].u : 1.0, &step);
        sink(k, cls[k], state, engage.at(stock, step, state));
      }
    }
    next = end;
    record_move(summary, path, i, pieces, deviation, volume, cell);
    if (progress) progress(i + 1, total);
  }
  return summary;
}

}  // namespace cwe

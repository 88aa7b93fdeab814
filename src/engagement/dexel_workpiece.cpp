#include "cwe/engagement/dexel_workpiece.hpp"

#include <algorithm>
#include <cmath>

#include "cwe/engagement/dexel_engagement.hpp"
#include "cwe/workpiece/dexel/removal_record.hpp"

namespace cwe {
namespace {

// A linear sweep as a dexel cut: its box (cut down to the tool's part that can reach the stock:
// MoveSweep::reach_bounds), its chords (ray by ray and row by row) and, where it has one, its
// cheap reach.
TriDexel::Cut cut_of(const LinearSweep& piece, const Aabb& bounds) {
  TriDexel::Cut cut{bounds,
                    [&piece](const Ray& ray) { return piece.chord(ray); },
                    {},
                    [&piece](const Ray& ray, int across, std::span<const double> at,
                             std::span<Interval> chords) { piece.chords(ray, across, at, chords); },
                    [&piece](const Ray& ray, int across) { return piece.row_key(ray, across); },
                    [&piece](const Ray& ray, int across) { return piece.row_span(ray, across); }};
  if (piece.has_reach()) cut.reach = [&piece](const Ray& ray) { return piece.reach(ray); };
  return cut;
}

// The cuts of a sweep's pieces, appended to `cuts`; their number.
std::size_t append_cuts(const MoveSweep& sweep, std::vector<TriDexel::Cut>& cuts) {
  for (std::size_t k = 0; k < sweep.pieces().size(); ++k) {
    cuts.push_back(cut_of(sweep.pieces()[k], sweep.reach_bounds(k)));
  }
  return sweep.pieces().size();
}

// A step's record: the dexel stretches it removed.
struct DexelStep : StepEngagement::Step {
  RemovalRecord removed;
};

class DexelStepEngagement : public StepEngagement {
 public:
  DexelStepEngagement(TriDexel& stock, const Cutter& cutter, const EngagementOptions& options)
      : stock_(stock), engage_(cutter, stock.spacing(), options) {}

  std::unique_ptr<Step> new_step() const override { return std::make_unique<DexelStep>(); }

  // One step: a group of one.
  double remove(const MoveSweep& sweep, Step* step) override {
    const Part part{&sweep, step};
    return remove_parts({&part, 1}).front();
  }

  std::vector<double> remove_parts(std::span<const Part> parts) override {
    std::vector<TriDexel::Cut> cuts;
    std::vector<RemovalRecord*> records;
    std::vector<std::size_t> owner;  // part of each cut
    for (std::size_t p = 0; p < parts.size(); ++p) {
      const MoveSweep& sweep = *parts[p].sweep;
      RemovalRecord* record =
          parts[p].step != nullptr ? &static_cast<DexelStep*>(parts[p].step)->removed : nullptr;
      // A step without pieces removed nothing; its record is emptied here, as no cut will. A
      // record holding far more than this step can need gives its buffers back, so that the
      // records kept stay within what the groups in flight may hold (EngagementRun's budget).
      if (record != nullptr) {
        if (record->held_bytes() > std::max(2 * record_bytes(sweep), kKeptRecordBytes)) {
          record->release();
        }
        if (sweep.pieces().empty()) record->clear();
      }
      const std::size_t added = append_cuts(sweep, cuts);
      records.insert(records.end(), added, record);
      owner.insert(owner.end(), added, p);
    }
    std::vector<double> volumes(parts.size(), 0.0);
    // The records are indexed by finish(), beside their engagement.
    const std::vector<TriDexel::Removal> removed =
        stock_.remove(cuts, records, TriDexel::Indexing::kDeferred);
    for (std::size_t k = 0; k < cuts.size(); ++k) volumes[owner[k]] += removed[k].volume;
    return volumes;
  }

  // What a record may keep beyond its step's need, bytes.
  static constexpr std::size_t kKeptRecordBytes = std::size_t{1} << 20;

  // Steps enough to give every thread tiles of its own, and records small beside the rays.
  std::size_t steps_per_removal() const override { return 8; }
  // A stretch for each ray of the sweep's boxes within the stock (a ray crossing material more
  // than once may lose more, which the budget's margin absorbs).
  std::size_t record_bytes(const MoveSweep& sweep) const override {
    double rays = 0.0;
    for (std::size_t k = 0; k < sweep.pieces().size(); ++k) {
      const Aabb& reach = sweep.reach_bounds(k);
      const Aabb box{reach.min.cwiseMax(stock_.domain().min),
                     reach.max.cwiseMin(stock_.domain().max)};
      if (box.is_empty()) continue;
      for (int a = 0; a < 3; ++a) {
        const int b = (a + 1) % 3, c = (a + 2) % 3;
        rays +=
            (box.size()[b] / stock_.spacing(b) + 1.0) * (box.size()[c] / stock_.spacing(c) + 1.0);
      }
    }
    return static_cast<std::size_t>(rays) * sizeof(RemovalRecord::Stretch);
  }

  void finish(Step& step) const override { static_cast<DexelStep&>(step).removed.index(); }

  // Reads the stock's grid only (never its rays), so later removals may run meanwhile.
  EngagementMap at(const ToolState& state, const Step& step) const override {
    return engage_.at(stock_, static_cast<const DexelStep&>(step).removed, state);
  }

 private:
  TriDexel& stock_;
  DexelEngagement engage_;
};

}  // namespace

double DexelWorkpiece::cell_volume() const { return std::pow(stock_.spacing(), 3); }

std::vector<double> DexelWorkpiece::remove(std::span<const MoveSweep> sweeps) {
  std::vector<TriDexel::Cut> cuts;
  std::vector<std::size_t> owner;  // sweep of each cut
  for (std::size_t m = 0; m < sweeps.size(); ++m) {
    owner.insert(owner.end(), append_cuts(sweeps[m], cuts), m);
  }
  const std::vector<TriDexel::Removal> removed = stock_.remove(cuts);
  std::vector<double> volume(sweeps.size(), 0.0);
  for (std::size_t k = 0; k < cuts.size(); ++k) volume[owner[k]] += removed[k].volume;
  return volume;
}

std::unique_ptr<StepEngagement> DexelWorkpiece::engagement(const Cutter& cutter,
                                                           const EngagementOptions& options) {
  return std::make_unique<DexelStepEngagement>(stock_, cutter, options);
}

}  // namespace cwe

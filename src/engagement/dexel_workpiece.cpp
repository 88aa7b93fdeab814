#include "cwe/engagement/dexel_workpiece.hpp"

#include <cmath>

#include "cwe/engagement/dexel_engagement.hpp"
#include "cwe/workpiece/dexel/removal_record.hpp"

namespace cwe {
namespace {

// A linear sweep as a dexel cut: its box (cut down to the tool's part that can reach the stock:
// MoveSweep::reach_bounds), its chords (ray by ray and row by row) and, where it has one, its
// cheap reach.
TriDexel::Cut cut_of(const LinearSweep& piece, const Aabb& bounds) {
  TriDexel::Cut cut{
      bounds,
      [&piece](const Ray& ray) { return piece.chord(ray); },
      {},
      [&piece](const Ray& ray, int across, std::span<const double> at, std::span<Interval> chords) {
        piece.chords(ray, across, at, chords);
      }};
  if (piece.has_reach()) cut.reach = [&piece](const Ray& ray) { return piece.reach(ray); };
  return cut;
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

  double remove(const MoveSweep& sweep, Step* step) override {
    std::vector<TriDexel::Cut> cuts;
    for (std::size_t k = 0; k < sweep.pieces().size(); ++k) {
      cuts.push_back(cut_of(sweep.pieces()[k], sweep.reach_bounds(k)));
    }
    RemovalRecord* record = step != nullptr ? &static_cast<DexelStep*>(step)->removed : nullptr;
    double volume = 0.0;
    for (const TriDexel::Removal& r : stock_.remove(cuts, record)) volume += r.volume;
    return volume;
  }

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
    for (std::size_t k = 0; k < sweeps[m].pieces().size(); ++k) {
      cuts.push_back(cut_of(sweeps[m].pieces()[k], sweeps[m].reach_bounds(k)));
      owner.push_back(m);
    }
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

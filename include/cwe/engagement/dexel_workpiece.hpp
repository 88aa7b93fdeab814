#pragma once
// The tri-dexel workpiece behind the workpiece seam (workpiece.hpp): removal by the exact ray
// chords of each sweep's linear pieces (TriDexel::remove), engagement by DexelEngagement from
// what the step removed (RemovalRecord).

#include <memory>
#include <span>
#include <vector>

#include "cwe/engagement/workpiece.hpp"
#include "cwe/workpiece/dexel/tri_dexel.hpp"

namespace cwe {

class DexelWorkpiece : public Workpiece {
 public:
  // Works on `stock`, which must outlive it.
  explicit DexelWorkpiece(TriDexel& stock) : stock_(stock) {}
  double cell_volume() const override;
  // The stock's domain, grown by the rounding of the rays' stored ends (a ray filled to the
  // far face stores that face's coordinate as a float, which may lie just beyond it).
  Aabb region() const override {
    Aabb box = stock_.domain();
    box.inflate(4.0 * stock_.float_rounding());
    return box;
  }
  std::vector<double> remove(std::span<const MoveSweep> sweeps) override;
  std::unique_ptr<StepEngagement> engagement(const Cutter& cutter,
                                             const EngagementOptions& options) override;

 private:
  TriDexel& stock_;
};

}  // namespace cwe

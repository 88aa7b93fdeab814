#pragma once
// What one TriDexel::remove took from the rays: for every ray it changed, the stretches of
// material removed, in that ray's own coordinate (mm from the domain's lower face) and exactly as
// the ray stored them (float ends). For the removal of one step of a move this is the step's
// removal volume W ∩ SV (Aras 2008 eq. 6.3) as dexel segments, which is what engagement reads:
// a cutter point is engaged where the step removes material next to it.

#include <array>
#include <cstddef>
#include <span>
#include <vector>

namespace cwe {

class RemovalRecord {
 public:
  struct Stretch {
    std::size_t ray = 0;  // index of the ray within its family (TriDexel::SurfaceRay::index)
    float lo = 0.0f, hi = 0.0f;
  };

  void clear();
  bool empty() const;
  // The stretches removed from ray `ray` of family `axis` (0 x, 1 y, 2 z), ascending.
  std::span<const Stretch> on_ray(int axis, std::size_t ray) const;
  // Every stretch of a family, sorted by ray and then by position.
  const std::vector<Stretch>& family(int axis) const {
    return stretches_[static_cast<std::size_t>(axis)];
  }

 private:
  friend class TriDexel;
  std::array<std::vector<Stretch>, 3> stretches_;
};

}  // namespace cwe

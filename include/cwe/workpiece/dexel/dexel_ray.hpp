#pragma once
// The material along one dexel ray: sorted, disjoint closed intervals of the ray coordinate.
//
// Compact storage (16 bytes a ray, 8 more per interval beyond the second): coordinates are
// floats measured from the ray's own origin (the stock's lower face), which keeps 1e-5 mm
// resolution over a metre, two orders below any ray spacing cwe is meant for. Up to two
// intervals live inline; more go to a heap array of exactly `count` intervals, tagged by a bit
// pattern that is never read as a float.

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <vector>

#include "cwe/geometry/interval.hpp"

namespace cwe {

class alignas(8) DexelRay {
 public:
  DexelRay() { clear(); }
  DexelRay(const DexelRay& other);
  DexelRay& operator=(const DexelRay& other);
  DexelRay(DexelRay&& other) noexcept;
  DexelRay& operator=(DexelRay&& other) noexcept;
  ~DexelRay() { release(); }

  // A ray with one interval of material (none unless lo < hi).
  explicit DexelRay(float lo, float hi);

  int count() const;
  // The i-th interval (lo, hi), ascending.
  Interval interval(int i) const;
  std::vector<Interval> intervals() const;
  bool empty() const { return count() == 0; }
  double length() const;  // total material length
  // From the first interval's lower end to the last one's upper end (empty if no material).
  Interval extent() const;
  // Material in the open interval (lo, hi)? Inline: removal asks it of every ray it reaches.
  bool overlaps(double lo, double hi) const {
    if (on_heap()) return heap_overlaps(lo, hi);
    // An empty slot holds (+inf, -inf) and never overlaps.
    return (slot_[0] < hi && slot_[1] > lo) || (slot_[2] < hi && slot_[3] > lo);
  }

  // overlaps(lo, hi), and where it is false, the material's nearest ends about (lo, hi): `below`
  // rises to the largest material end at or below lo and `above` falls to the smallest start at
  // or above hi (the ray has no material strictly between them). Removal keeps these bounds for
  // rows of rays to skip them whole (TriDexel::remove).
  bool overlaps_or_bound(double lo, double hi, float& below, float& above) const {
    if (on_heap()) return heap_overlaps_or_bound(lo, hi, below, above);
    if ((slot_[0] < hi && slot_[1] > lo) || (slot_[2] < hi && slot_[3] > lo)) return true;
    // Each slot now lies wholly at or below lo, or at or above hi; the empty one is (+∞, −∞),
    // below everything.
    for (int k = 0; k < 4; k += 2) {
      if (slot_[k + 1] <= lo) {
        below = std::max(below, slot_[k + 1]);
      } else {
        above = std::min(above, slot_[k]);
      }
    }
    return false;
  }
  // Material at coordinate t (closed intervals).
  bool contains(double t) const;
  // Removes [lo, hi]; returns the length of material removed (> 0 exactly when the ray
  // changed; 0 when [lo, hi] misses the material or is a point). Never adds material. When
  // `removed` is given, the stretches of material taken (float ends, ascending, each of positive
  // length) are appended to it.
  double subtract(double lo, double hi, std::vector<Interval>* removed = nullptr);
  // Replaces the contents with sorted intervals; those that touch or overlap once rounded to
  // float are merged, and those that round to a point are dropped.
  void assign(const std::vector<Interval>& intervals);
  void clear();

  // Heap bytes owned by this ray (0 for up to two intervals).
  std::size_t heap_bytes() const {
    return on_heap() ? static_cast<std::size_t>(count()) * 2 * sizeof(float) : 0;
  }

 private:
  // Bits of slot_[0] that mark heap storage (a quiet-NaN pattern, compared only as an integer).
  static constexpr std::uint32_t kHeapTag = 0x7FC0DE5Au;
  bool on_heap() const {
    std::uint32_t b = 0;
    std::memcpy(&b, &slot_[0], sizeof b);
    return b == kHeapTag;
  }
  bool heap_overlaps(double lo, double hi) const;
  bool heap_overlaps_or_bound(double lo, double hi, float& below, float& above) const;
  const float* data() const;
  float* heap();  // the heap array (on_heap() only)
  void release();
  void store(const float* pairs, int n);  // n sorted, disjoint (lo, hi) pairs

  float slot_[4];
};

static_assert(sizeof(DexelRay) == 16, "a dexel ray is 16 bytes");

}  // namespace cwe

#pragma once
// The material along one dexel ray: sorted, disjoint closed intervals of the ray coordinate.
//
// Compact storage (16 bytes a ray, 8 more per interval beyond the second): coordinates are
// floats measured from the ray's own origin (the stock's lower face), which keeps 1e-5 mm
// resolution over a metre, two orders below any ray spacing cwe is meant for. Up to two
// intervals live inline; more go to a heap array of exactly `count` intervals, tagged by a bit
// pattern that is never read as a float.

#include <algorithm>
#include <concepts>
#include <cstdint>
#include <cstring>
#include <limits>
#include <type_traits>
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
    if (on_heap()) {
      // Through copies: the caller's bounds stay in registers, their address never escaping.
      float low = below, high = above;
      const bool hit = heap_overlaps_or_bound(lo, hi, low, high);
      below = low;
      above = high;
      return hit;
    }
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
  // subtract(lo, hi) handing each stretch taken to `taken(lo, hi)` (float ends, ascending, each
  // of positive length) as it is cut: inline, for removal's records (TriDexel::remove).
  template <class Taken>
  requires std::invocable<Taken&, float, float>
  double subtract(double lo, double hi, Taken&& taken);
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
  // The pair (a, b) as the 8 bytes two slots hold it.
  static std::uint64_t pair_bits(float a, float b) {
    const float pair[2] = {a, b};
    std::uint64_t bits = 0;
    std::memcpy(&bits, pair, sizeof bits);
    return bits;
  }
  bool heap_overlaps(double lo, double hi) const;
  // subtract() of a ray on the heap, handing each stretch taken to emit(context, lo, hi).
  double heap_subtract(double lo, double hi, void (*emit)(void*, float, float), void* context);
  bool heap_overlaps_or_bound(double lo, double hi, float& below, float& above) const;
  const float* data() const;
  float* heap();  // the heap array (on_heap() only)
  void release();
  void store(const float* pairs, int n);  // n sorted, disjoint (lo, hi) pairs

  float slot_[4];
};

static_assert(sizeof(DexelRay) == 16, "a dexel ray is 16 bytes");

template <class Taken>
requires std::invocable<Taken&, float, float>
double DexelRay::subtract(double lo, double hi, Taken&& taken) {
  // Removing a point (or nothing) leaves the material's measure as it is.
  if (!(lo < hi)) return 0.0;
  if (on_heap()) {
    return heap_subtract(
        lo, hi,
        [](void* context, float a, float b) {
          (*static_cast<std::remove_reference_t<Taken>*>(context))(a, b);
        },
        static_cast<void*>(&taken));
  }
  // Inline (nearly every ray): both slots read once, each piece that is kept written once. A
  // slot the cut meets (more than at an end point) loses the stretch within it and keeps what
  // lies below and above the cut, open at the cut: stored closed, as material is measured by
  // length, and dropped when it rounds to nothing in float. The empty slot (+inf, -inf) meets
  // nothing. The pieces, at most three, are gathered as 8-byte pairs in order (without a branch
  // per piece) and written back over the slots; three move the ray to the heap.
  constexpr float kInf = std::numeric_limits<float>::infinity();
  const float a0 = slot_[0], b0 = slot_[1], a1 = slot_[2], b1 = slot_[3];
  const bool met0 = hi > a0 && lo < b0;
  const bool met1 = hi > a1 && lo < b1;
  if (!met0 && !met1) {
    // Unchanged; a lone interval in the second slot moves to the first, as a cut leaves it.
    if (!(a0 <= b0)) {
      slot_[0] = a1;
      slot_[1] = b1;
      slot_[2] = kInf;
      slot_[3] = -kInf;
    }
    return 0.0;
  }
  const auto cut_lo = static_cast<float>(lo), cut_hi = static_cast<float>(hi);
  // Most cuts along a pass meet one slot and trim one end of it (each step widens the notch the
  // pass left): one float changes, and the slots keep their order (the first is not empty).
  if (met0 != met1 && a0 <= b0) {
    const int k = met0 ? 0 : 2;
    const float a = slot_[k], b = slot_[k + 1];
    const bool keep_low = a < cut_lo, keep_high = cut_hi < b;
    if (keep_low != keep_high) {
      const float taken_lo = std::max(a, cut_lo), taken_hi = std::min(b, cut_hi);
      if (taken_lo < taken_hi) taken(taken_lo, taken_hi);
      slot_[keep_low ? k + 1 : k] = keep_low ? cut_lo : cut_hi;
      return std::max(static_cast<double>(taken_hi) - static_cast<double>(taken_lo),
                      std::numeric_limits<double>::min());
    }
  }
  double removed = 0.0;
  if (met0) {
    const float taken_lo = std::max(a0, cut_lo), taken_hi = std::min(b0, cut_hi);
    removed += static_cast<double>(taken_hi) - static_cast<double>(taken_lo);
    if (taken_lo < taken_hi) taken(taken_lo, taken_hi);
  }
  if (met1) {
    const float taken_lo = std::max(a1, cut_lo), taken_hi = std::min(b1, cut_hi);
    removed += static_cast<double>(taken_hi) - static_cast<double>(taken_lo);
    if (taken_lo < taken_hi) taken(taken_lo, taken_hi);
  }
  // Each candidate is written at the next free place and kept by counting it.
  std::uint64_t kept[4];
  int n = 0;
  const auto offer = [&](float a, float b, bool keep) {
    kept[n] = pair_bits(a, b);
    n += keep ? 1 : 0;
  };
  offer(a0, met0 ? cut_lo : b0, met0 ? a0 < cut_lo : a0 <= b0);
  offer(cut_hi, b0, met0 && cut_hi < b0);
  offer(a1, met1 ? cut_lo : b1, met1 ? a1 < cut_lo : a1 <= b1);
  offer(cut_hi, b1, met1 && cut_hi < b1);
  if (n <= 2) {
    const std::uint64_t empty = pair_bits(kInf, -kInf);
    const std::uint64_t first = n > 0 ? kept[0] : empty, second = n > 1 ? kept[1] : empty;
    std::memcpy(&slot_[0], &first, sizeof first);
    std::memcpy(&slot_[2], &second, sizeof second);
  } else {
    float pairs[8];
    std::memcpy(pairs, kept, sizeof(std::uint64_t) * static_cast<std::size_t>(n));
    store(pairs, n);
  }
  // A cut that changed the ray by less than float rounding still counts as a change.
  return std::max(removed, std::numeric_limits<double>::min());
}

}  // namespace cwe

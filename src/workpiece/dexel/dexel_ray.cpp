#include "cwe/workpiece/dexel/dexel_ray.hpp"

#include <algorithm>
#include <cstring>
#include <limits>
#include <utility>
#include <vector>

#include "cwe/core/assert.hpp"

namespace cwe {
namespace {

constexpr float kEmptyLo = std::numeric_limits<float>::infinity();
constexpr float kEmptyHi = -std::numeric_limits<float>::infinity();

// Heap arrays of three intervals, kept by each thread for its next ray. A cut through the middle
// of an inline ray's material makes one, and the next cut along often takes it back (a pass
// beside an earlier one first notches each ray across, then widens the notch into the gap): a
// pocket's removal made and dropped a million of them, a tenth of its time in malloc and free,
// whose bins are locked between threads. At most kSpareArrays wait per thread (160 KiB with
// malloc's headers and the list).
constexpr int kSpareCount = 3;
constexpr std::size_t kSpareArrays = 4096;
struct SpareArrays {
  std::vector<float*> arrays;
  SpareArrays() { arrays.reserve(kSpareArrays); }
  SpareArrays(const SpareArrays&) = delete;
  SpareArrays& operator=(const SpareArrays&) = delete;
  ~SpareArrays() {
    for (float* array : arrays) delete[] array;
  }
};
thread_local SpareArrays spare;

// Each names `spare` once: every use of a thread_local with a destructor calls its guard.
float* new_pairs(int n) {
  if (n == kSpareCount) {
    std::vector<float*>& arrays = spare.arrays;
    if (!arrays.empty()) {
      float* array = arrays.back();
      arrays.pop_back();
      return array;
    }
  }
  return new float[2 * static_cast<std::size_t>(n)];
}

void delete_pairs(float* array, int n) {
  if (n == kSpareCount) {
    std::vector<float*>& arrays = spare.arrays;
    if (arrays.size() < kSpareArrays) {
      arrays.push_back(array);
      return;
    }
  }
  delete[] array;
}

}  // namespace

int DexelRay::count() const {
  if (on_heap()) {
    std::uint32_t n = 0;
    std::memcpy(&n, &slot_[1], sizeof n);
    return static_cast<int>(n);
  }
  return (slot_[0] <= slot_[1] ? 1 : 0) + (slot_[2] <= slot_[3] ? 1 : 0);
}

const float* DexelRay::data() const {
  if (!on_heap()) return slot_;
  const float* heap = nullptr;
  std::memcpy(&heap, &slot_[2], sizeof heap);
  return heap;
}

Interval DexelRay::extent() const {
  if (on_heap()) {
    const float* p = data();
    return {p[0], p[2 * count() - 1]};
  }
  // Inline, either slot may be the empty one.
  const bool first = slot_[0] <= slot_[1], second = slot_[2] <= slot_[3];
  if (first) return {slot_[0], second ? slot_[3] : slot_[1]};
  return second ? Interval{slot_[2], slot_[3]} : Interval::empty();
}

bool DexelRay::heap_overlaps(double lo, double hi) const {
  const float* pairs = data();
  const int n = count();
  for (int k = 0; k < n; ++k) {
    if (pairs[2 * k] < hi && pairs[2 * k + 1] > lo) return true;
  }
  return false;
}

bool DexelRay::heap_overlaps_or_bound(double lo, double hi, float& below, float& above) const {
  // The bounds move only when nothing overlaps: kept aside until the last interval is passed.
  float low = below, high = above;
  const float* pairs = data();
  const int n = count();
  for (int k = 0; k < n; ++k) {
    if (pairs[2 * k] < hi && pairs[2 * k + 1] > lo) return true;
    if (pairs[2 * k + 1] <= lo) {
      low = std::max(low, pairs[2 * k + 1]);
    } else {
      high = std::min(high, pairs[2 * k]);
    }
  }
  below = low;
  above = high;
  return false;
}

float* DexelRay::heap() {
  float* array = nullptr;
  std::memcpy(&array, &slot_[2], sizeof array);
  return array;
}

void DexelRay::release() {
  if (on_heap()) delete_pairs(heap(), count());
}

void DexelRay::clear() {
  slot_[0] = kEmptyLo;
  slot_[1] = kEmptyHi;
  slot_[2] = kEmptyLo;
  slot_[3] = kEmptyHi;
}

DexelRay::DexelRay(float lo, float hi) {
  clear();
  if (lo < hi) {  // as assign() has it: a point holds no material
    slot_[0] = lo;
    slot_[1] = hi;
  }
}

// A ray of at most two intervals is its four floats: copied as they are (a stock box fills
// millions of rays from one), without the vector a heap ray's copy goes through.
DexelRay::DexelRay(const DexelRay& other) {
  if (!other.on_heap()) {
    std::memcpy(slot_, other.slot_, sizeof slot_);
    return;
  }
  clear();
  assign(other.intervals());
}

DexelRay& DexelRay::operator=(const DexelRay& other) {
  if (this == &other) return *this;
  if (!other.on_heap()) {
    release();
    std::memcpy(slot_, other.slot_, sizeof slot_);
    return *this;
  }
  assign(other.intervals());
  return *this;
}

DexelRay::DexelRay(DexelRay&& other) noexcept {
  std::memcpy(slot_, other.slot_, sizeof slot_);
  other.clear();  // the heap array, if any, now belongs to this ray
}

DexelRay& DexelRay::operator=(DexelRay&& other) noexcept {
  if (this != &other) {
    release();
    std::memcpy(slot_, other.slot_, sizeof slot_);
    other.clear();
  }
  return *this;
}

Interval DexelRay::interval(int i) const {
  CWE_ASSERT(i >= 0 && i < count(), "dexel interval index out of range");
  const float* d = data();
  if (!on_heap() && i == 0 && !(slot_[0] <= slot_[1])) i = 1;  // only the second slot is used
  return {d[2 * i], d[2 * i + 1]};
}

std::vector<Interval> DexelRay::intervals() const {
  std::vector<Interval> out;
  const int n = count();
  out.reserve(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) out.push_back(interval(i));
  return out;
}

// Both walk the stored pairs in place: they run for every sample point of an engagement map and
// every ray of a volume, where a vector per call would cost more than the walk.
double DexelRay::length() const {
  if (!on_heap()) {
    return (slot_[0] <= slot_[1] ? static_cast<double>(slot_[1]) - slot_[0] : 0.0) +
           (slot_[2] <= slot_[3] ? static_cast<double>(slot_[3]) - slot_[2] : 0.0);
  }
  const float* pairs = data();
  double total = 0.0;
  for (int k = 0, n = count(); k < n; ++k) {
    total += static_cast<double>(pairs[2 * k + 1]) - pairs[2 * k];
  }
  return total;
}

bool DexelRay::contains(double t) const {
  if (!on_heap()) {
    return (slot_[0] <= t && t <= slot_[1]) || (slot_[2] <= t && t <= slot_[3]);
  }
  const float* pairs = data();
  for (int k = 0, n = count(); k < n; ++k) {
    if (pairs[2 * k] <= t && t <= pairs[2 * k + 1]) return true;
  }
  return false;
}

void DexelRay::assign(const std::vector<Interval>& intervals) {
  std::vector<float> pairs;
  pairs.reserve(2 * intervals.size());
  for (const Interval& i : intervals) {
    const auto lo = static_cast<float>(i.lo), hi = static_cast<float>(i.hi);
    if (!(lo < hi)) continue;  // a point (or less) after rounding holds no material
    if (!pairs.empty() && lo <= pairs.back()) {  // touches the previous one after rounding
      pairs.back() = std::max(pairs.back(), hi);
      continue;
    }
    pairs.push_back(lo);
    pairs.push_back(hi);
  }
  store(pairs.data(), static_cast<int>(pairs.size() / 2));
}

void DexelRay::store(const float* pairs, int n) {
  if (on_heap() && count() == n) {  // same size: reuse the array (the common shortening cut)
    std::memcpy(heap(), pairs, sizeof(float) * 2 * static_cast<std::size_t>(n));
    return;
  }
  release();
  clear();
  if (n == 0) return;
  if (n <= 2) {  // element by element: a fixed-size copy the compiler inlines
    for (int k = 0; k < 2 * n; ++k) slot_[k] = pairs[k];
    return;
  }
  float* heap = new_pairs(n);
  std::memcpy(heap, pairs, sizeof(float) * 2 * static_cast<std::size_t>(n));
  std::memcpy(&slot_[0], &kHeapTag, sizeof kHeapTag);
  const auto count32 = static_cast<std::uint32_t>(n);
  std::memcpy(&slot_[1], &count32, sizeof count32);
  std::memcpy(&slot_[2], &heap, sizeof heap);
}

double DexelRay::subtract(double lo, double hi, std::vector<Interval>* removed) {
  if (removed == nullptr) return subtract(lo, hi, [](float, float) {});
  return subtract(lo, hi, [removed](float a, float b) { removed->push_back({a, b}); });
}

double DexelRay::heap_subtract(double lo, double hi, void (*emit)(void*, float, float),
                               void* context) {
  const auto cut_lo = static_cast<float>(lo), cut_hi = static_cast<float>(hi);
  const Interval span = extent();
  if (span.is_empty() || hi <= span.lo || lo >= span.hi) return 0.0;
  const int n = count();
  constexpr int kInline = 8;
  float local[2 * (kInline + 1)];
  std::vector<float> spill;
  float* kept = local;
  if (n > kInline) {
    spill.resize(2 * static_cast<std::size_t>(n) + 2);
    kept = spill.data();
  }
  // As the inline path of subtract(): what is left of a pair is kept, what is cut is handed on.
  double removed = 0.0;
  bool changed = false;
  int kept_count = 0;
  const auto keep = [&](float a, float b) {
    kept[2 * kept_count] = a;
    kept[2 * kept_count + 1] = b;
    ++kept_count;
  };
  const float* pairs = data();
  for (int k = 0; k < n; ++k) {
    const float a = pairs[2 * k], b = pairs[2 * k + 1];
    if (hi <= a || lo >= b) {
      keep(a, b);
      continue;
    }
    changed = true;
    const float taken_lo = std::max(a, cut_lo), taken_hi = std::min(b, cut_hi);
    removed += static_cast<double>(taken_hi) - static_cast<double>(taken_lo);
    if (taken_lo < taken_hi) emit(context, taken_lo, taken_hi);
    if (a < cut_lo) keep(a, cut_lo);
    if (cut_hi < b) keep(cut_hi, b);
  }
  if (!changed) return 0.0;
  store(kept, kept_count);
  return std::max(removed, std::numeric_limits<double>::min());
}

}  // namespace cwe

#include "cwe/workpiece/dexel/dexel_ray.hpp"

#include <algorithm>
#include <cstring>
#include <limits>
#include <utility>

#include "cwe/core/assert.hpp"

namespace cwe {
namespace {

// Bits of slot_[0] that mark heap storage (a quiet-NaN pattern, compared only as an integer).
constexpr std::uint32_t kHeapTag = 0x7FC0DE5Au;
constexpr float kEmptyLo = std::numeric_limits<float>::infinity();
constexpr float kEmptyHi = -std::numeric_limits<float>::infinity();

std::uint32_t bits(float f) {
  std::uint32_t b = 0;
  std::memcpy(&b, &f, sizeof b);
  return b;
}

}  // namespace

bool DexelRay::on_heap() const { return bits(slot_[0]) == kHeapTag; }

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

void DexelRay::release() {
  if (on_heap()) delete[] data();
}

void DexelRay::clear() {
  slot_[0] = kEmptyLo;
  slot_[1] = kEmptyHi;
  slot_[2] = kEmptyLo;
  slot_[3] = kEmptyHi;
}

DexelRay::DexelRay(float lo, float hi) {
  clear();
  if (lo <= hi) {
    slot_[0] = lo;
    slot_[1] = hi;
  }
}

DexelRay::DexelRay(const DexelRay& other) {
  clear();
  assign(other.intervals());
}

DexelRay& DexelRay::operator=(const DexelRay& other) {
  if (this != &other) assign(other.intervals());
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

double DexelRay::length() const {
  double total = 0.0;
  for (const Interval& i : intervals()) total += i.hi - i.lo;
  return total;
}

bool DexelRay::contains(double t) const {
  for (const Interval& i : intervals()) {
    if (i.contains(t)) return true;
  }
  return false;
}

void DexelRay::assign(const std::vector<Interval>& intervals) {
  release();
  clear();
  const std::size_t n = intervals.size();
  if (n <= 2) {
    for (std::size_t i = 0; i < n; ++i) {
      slot_[2 * i] = static_cast<float>(intervals[i].lo);
      slot_[2 * i + 1] = static_cast<float>(intervals[i].hi);
    }
    return;
  }
  auto* heap = new float[2 * n];
  for (std::size_t i = 0; i < n; ++i) {
    heap[2 * i] = static_cast<float>(intervals[i].lo);
    heap[2 * i + 1] = static_cast<float>(intervals[i].hi);
  }
  std::memcpy(&slot_[0], &kHeapTag, sizeof kHeapTag);
  const auto count32 = static_cast<std::uint32_t>(n);
  std::memcpy(&slot_[1], &count32, sizeof count32);
  std::memcpy(&slot_[2], &heap, sizeof heap);
}

bool DexelRay::subtract(double lo, double hi) {
  if (!(lo <= hi)) return false;
  const int n = count();
  bool changed = false;
  std::vector<Interval> kept;
  kept.reserve(static_cast<std::size_t>(n) + 1);
  for (int k = 0; k < n; ++k) {
    const Interval i = interval(k);
    if (hi < i.lo || lo > i.hi) {  // untouched
      kept.push_back(i);
      continue;
    }
    changed = true;
    // What is left is open at the cut; stored closed, as material is measured by length.
    if (i.lo < lo) kept.push_back({i.lo, lo});
    if (hi < i.hi) kept.push_back({hi, i.hi});
  }
  if (changed) assign(kept);
  return changed;
}

std::size_t DexelRay::heap_bytes() const {
  return on_heap() ? static_cast<std::size_t>(count()) * 2 * sizeof(float) : 0;
}

}  // namespace cwe

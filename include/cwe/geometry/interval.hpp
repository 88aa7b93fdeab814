#pragma once
// Closed parameter intervals [lo, hi] on the real line, as ray intersectors return them.
//
// Interval::empty() is (+inf, -inf) and Interval::full() is (-inf, +inf), the convention of
// Embree's ray intervals; a degenerate interval lo == hi (a ray tangent to a surface) is not
// empty.

#include <algorithm>
#include <limits>
#include <vector>

namespace cwe {

struct Interval {
  double lo = std::numeric_limits<double>::infinity();
  double hi = -std::numeric_limits<double>::infinity();

  static constexpr Interval empty() { return {}; }
  static constexpr Interval full() {
    return {-std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
  }
  static constexpr Interval point(double t) { return {t, t}; }

  constexpr bool is_empty() const { return !(lo <= hi); }
  constexpr double length() const { return is_empty() ? 0.0 : hi - lo; }
  constexpr bool contains(double t) const { return lo <= t && t <= hi; }

  constexpr friend bool operator==(const Interval&, const Interval&) = default;
};

constexpr Interval intersect(const Interval& a, const Interval& b) {
  const Interval r{std::max(a.lo, b.lo), std::min(a.hi, b.hi)};
  return r.is_empty() ? Interval::empty() : r;
}

// Smallest interval containing both.
constexpr Interval hull(const Interval& a, const Interval& b) {
  if (a.is_empty()) return b;
  if (b.is_empty()) return a;
  return {std::min(a.lo, b.lo), std::max(a.hi, b.hi)};
}

// Sorted, disjoint union of the non-empty intervals given; intervals that overlap or are closer
// than `merge_gap` are merged.
std::vector<Interval> normalize(std::vector<Interval> intervals, double merge_gap = 0.0);

}  // namespace cwe

#include "cwe/geometry/interval.hpp"

#include "cwe/core/assert.hpp"

namespace cwe {

std::vector<Interval> normalize(std::vector<Interval> intervals, double merge_gap) {
  CWE_ASSERT(merge_gap >= 0.0, "merge_gap must be non-negative");
  std::erase_if(intervals, [](const Interval& interval) { return interval.is_empty(); });
  std::sort(intervals.begin(), intervals.end(), [](const Interval& a, const Interval& b) {
    return a.lo < b.lo || (a.lo == b.lo && a.hi < b.hi);
  });
  std::vector<Interval> merged;
  merged.reserve(intervals.size());
  for (const Interval& interval : intervals) {
    // Closed intervals that touch (gap 0) are one interval. The sum form stays free of
    // inf - inf when an end is infinite.
    if (!merged.empty() && interval.lo <= merged.back().hi + merge_gap) {
      merged.back().hi = std::max(merged.back().hi, interval.hi);
    } else {
      merged.push_back(interval);
    }
  }
  return merged;
}

}  // namespace cwe

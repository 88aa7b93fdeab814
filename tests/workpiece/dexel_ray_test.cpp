#include "cwe/workpiece/dexel/dexel_ray.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

#include "random.hpp"

namespace cwe {
namespace {

// Reference model: exact double intervals with the same subtraction rule.
std::vector<Interval> subtract_reference(const std::vector<Interval>& in, double lo, double hi) {
  std::vector<Interval> out;
  for (const Interval& i : in) {
    if (hi < i.lo || lo > i.hi) {
      out.push_back(i);
      continue;
    }
    if (i.lo < lo) out.push_back({i.lo, lo});
    if (hi < i.hi) out.push_back({hi, i.hi});
  }
  return out;
}

TEST(DexelRay, InlineUpToTwoIntervalsThenHeap) {
  DexelRay r(0.0f, 10.0f);
  EXPECT_EQ(r.count(), 1);
  EXPECT_EQ(r.heap_bytes(), 0u);
  EXPECT_GT(r.subtract(2, 3), 0.0);
  EXPECT_EQ(r.count(), 2);
  EXPECT_EQ(r.heap_bytes(), 0u);
  EXPECT_GT(r.subtract(5, 6), 0.0);
  EXPECT_EQ(r.count(), 3);
  EXPECT_EQ(r.heap_bytes(), 3u * 8u);
  EXPECT_DOUBLE_EQ(r.length(), 8.0);
  EXPECT_TRUE(r.contains(4.0));
  EXPECT_FALSE(r.contains(5.5));
  EXPECT_EQ(r.subtract(20, 30), 0.0);  // nothing there: unchanged
  // Copies and moves keep the contents; a moved-from ray is empty.
  DexelRay copy = r;
  EXPECT_EQ(copy.intervals(), r.intervals());
  DexelRay moved = std::move(copy);
  EXPECT_EQ(moved.count(), 3);
  EXPECT_TRUE(copy.empty());  // NOLINT(bugprone-use-after-move): documented state
  EXPECT_GT(moved.subtract(-1, 100), 0.0);
  EXPECT_TRUE(moved.empty());
  EXPECT_EQ(moved.heap_bytes(), 0u);
}

// An inline ray (up to two intervals) is copied as its bytes: onto an empty ray, onto a heap ray
// (whose array is released) and from a ray whose first interval was cut away.
TEST(DexelRay, InlineCopiesKeepTheIntervals) {
  DexelRay two(0.0f, 10.0f);
  ASSERT_GT(two.subtract(0, 4), 0.0);  // [4, 10]
  ASSERT_GT(two.subtract(6, 7), 0.0);  // [4, 6], [7, 10]
  DexelRay heap(0.0f, 10.0f);
  for (const double at : {1.0, 3.0, 5.0}) ASSERT_GT(heap.subtract(at, at + 0.5), 0.0);
  ASSERT_GT(heap.heap_bytes(), 0u);
  const DexelRay copied(two);
  EXPECT_EQ(copied.intervals(), two.intervals());
  heap = two;
  EXPECT_EQ(heap.intervals(), two.intervals());
  EXPECT_EQ(heap.heap_bytes(), 0u);
  EXPECT_DOUBLE_EQ(heap.length(), 5.0);
  EXPECT_GT(heap.subtract(5, 8), 0.0);  // the copy cuts like the original
  EXPECT_EQ(heap.intervals(), (std::vector<Interval>{{4, 5}, {8, 10}}));
  EXPECT_EQ(two.count(), 2);
  // A point holds no material, as assign() has it.
  EXPECT_TRUE(DexelRay(3.0f, 3.0f).empty());
}

// Property: random cuts keep the intervals sorted and disjoint, never add material, and agree
// with the double-precision reference to float rounding (1e-5 mm at 100 mm).
TEST(DexelRay, RandomCutsMatchTheReference) {
  test::Random random(51);
  for (int trial = 0; trial < 200; ++trial) {
    DexelRay r(0.0f, 100.0f);
    std::vector<Interval> reference{{0.0, 100.0}};
    for (int k = 0; k < 30; ++k) {
      const double a = random.uniform(-5, 105);
      const double b = a + random.uniform(0, 8);
      const double before = r.length();
      const std::vector<Interval> was = r.intervals();
      std::vector<Interval> taken;
      const double removed = r.subtract(a, b, &taken);
      reference = subtract_reference(reference, a, b);
      ASSERT_LE(r.length(), before);
      // What it reports taking: the stretches it lost, in order, whose lengths sum to the
      // returned length (the same float differences summed the same way); > 0 when the ray
      // changed (also, by design, for a cut that changed it by less than float rounding).
      if (r.intervals() != was) {
        ASSERT_GT(removed, 0.0);
      }
      double sum = 0.0;
      for (std::size_t i = 0; i < taken.size(); ++i) {
        ASSERT_LT(taken[i].lo, taken[i].hi);
        if (i > 0) {
          ASSERT_LT(taken[i - 1].hi, taken[i].lo);
        }
        ASSERT_GE(taken[i].lo, std::max(a, was.front().lo) - 1e-5);
        ASSERT_LE(taken[i].hi, std::min(b, was.back().hi) + 1e-5);
        sum += taken[i].hi - taken[i].lo;
      }
      if (!taken.empty()) {
        ASSERT_EQ(removed, sum);
      }
      ASSERT_NEAR(before - r.length(), removed, 1e-4);
      ASSERT_NEAR(before - r.length(), sum, 1e-4);
      const auto got = r.intervals();
      ASSERT_EQ(got.size(), reference.size());
      // The extent spans the first to the last interval, in every storage layout.
      const Interval extent = r.extent();
      if (got.empty()) {
        ASSERT_TRUE(extent.is_empty());
      } else {
        ASSERT_EQ(extent.lo, got.front().lo);
        ASSERT_EQ(extent.hi, got.back().hi);
      }
      // Overlap with an open probe interval, against the reference.
      const double p = random.uniform(-5, 105), q = p + random.uniform(0, 10);
      bool expected = false;
      for (const Interval& i : got) expected = expected || (i.lo < q && i.hi > p);
      ASSERT_EQ(r.overlaps(p, q), expected);
      // Where it misses, the nearest material ends about (p, q).
      float below = -std::numeric_limits<float>::infinity();
      float above = std::numeric_limits<float>::infinity();
      ASSERT_EQ(r.overlaps_or_bound(p, q, below, above), expected);
      if (!expected) {
        double nearest_below = -std::numeric_limits<double>::infinity();
        double nearest_above = std::numeric_limits<double>::infinity();
        for (const Interval& i : got) {
          if (i.hi <= p) nearest_below = std::max(nearest_below, i.hi);
          if (i.lo >= q) nearest_above = std::min(nearest_above, i.lo);
        }
        ASSERT_EQ(below, nearest_below);
        ASSERT_EQ(above, nearest_above);
      }
      for (std::size_t i = 0; i < got.size(); ++i) {
        ASSERT_NEAR(got[i].lo, reference[i].lo, 1e-5);
        ASSERT_NEAR(got[i].hi, reference[i].hi, 1e-5);
        ASSERT_LT(got[i].lo, got[i].hi);
        if (i > 0) {
          ASSERT_LT(got[i - 1].hi, got[i].lo);
        }
      }
    }
  }
}

// The subtraction rule written out plainly, on float pairs: a pair the cut meets (more than at
// an end point) hands on the stretch within the cut and keeps what lies below and above it,
// with the cut's ends rounded to float; pieces of no length are dropped. Returns the removed
// length as DexelRay::subtract does (the float differences summed in order; at least the
// smallest normal double when the ray changed).
double subtract_rule(std::vector<Interval>& pairs, double lo, double hi,
                     std::vector<Interval>& taken) {
  if (!(lo < hi)) return 0.0;
  const auto cut_lo = static_cast<float>(lo), cut_hi = static_cast<float>(hi);
  std::vector<Interval> kept;
  double removed = 0.0;
  bool changed = false;
  for (const Interval& pair : pairs) {
    const auto a = static_cast<float>(pair.lo), b = static_cast<float>(pair.hi);
    if (hi <= a || lo >= b) {
      kept.push_back(pair);
      continue;
    }
    changed = true;
    const float taken_lo = std::max(a, cut_lo), taken_hi = std::min(b, cut_hi);
    removed += static_cast<double>(taken_hi) - static_cast<double>(taken_lo);
    if (taken_lo < taken_hi) taken.push_back({taken_lo, taken_hi});
    if (a < cut_lo) kept.push_back({a, cut_lo});
    if (cut_hi < b) kept.push_back({cut_hi, b});
  }
  pairs = kept;
  return changed ? std::max(removed, std::numeric_limits<double>::min()) : 0.0;
}

// Every cut follows the rule to the last bit (intervals, length and stretches taken), inline
// and on the heap, where cuts end at the material's ends, a float step or a double step beside
// them, halfway between two floats, or within one float (which leaves touching pieces).
TEST(DexelRay, SubtractFollowsTheRuleBitForBit) {
  test::Random random(52);
  int inline_cuts = 0, heap_cuts = 0, splits = 0, trims = 0;
  for (int trial = 0; trial < 1000; ++trial) {
    DexelRay r(0.0f, 100.0f);
    std::vector<Interval> rule{{0.0, 100.0}};
    for (int k = 0; k < 40 && !rule.empty(); ++k) {
      // An end of the material, or a random place, nudged by nothing, a double or a float step,
      // or half a float step.
      const auto near = [&] {
        const Interval& pair =
            rule[static_cast<std::size_t>(random.integer(0, static_cast<int>(rule.size()) - 1))];
        const int pick = random.integer(0, 2);
        const double at = pick == 0 ? pair.lo : pick == 1 ? pair.hi : random.uniform(-5, 105);
        const auto f = static_cast<float>(at);
        const double ulp = static_cast<double>(std::nextafter(f, 1e9f)) - f;
        switch (random.integer(0, 5)) {
          case 0:
            return at;
          case 1:
            return std::nextafter(at, 1e9);
          case 2:
            return std::nextafter(at, -1e9);
          case 3:
            return at + ulp / 2;
          case 4:
            return at + random.integer(-3, 3) * ulp;
          default:
            return at + random.uniform(-2, 2);
        }
      };
      double lo = near(), hi = near();
      // Half the cuts end near the material too; the others end within a float or two of
      // where they start, across pieces, or (most likely splitting a piece) within 2 mm.
      const int length = random.integer(0, 5);
      if (length == 0) hi = lo + random.uniform(0, 1e-6);
      if (length == 1) hi = lo + random.uniform(5, 40);
      if (length == 2) hi = lo + random.uniform(0, 2);
      if (hi < lo) std::swap(lo, hi);
      std::vector<Interval> taken, taken_rule;
      const bool was_inline = r.heap_bytes() == 0;
      const std::vector<Interval> was = r.intervals();
      const double removed = r.subtract(lo, hi, &taken);
      const double removed_rule = subtract_rule(rule, lo, hi, taken_rule);
      ASSERT_EQ(r.intervals(), rule) << "trial " << trial << " cut " << k;
      ASSERT_EQ(std::bit_cast<std::uint64_t>(removed), std::bit_cast<std::uint64_t>(removed_rule))
          << "trial " << trial << " cut " << k;
      ASSERT_EQ(taken, taken_rule) << "trial " << trial << " cut " << k;
      if (removed > 0.0) {
        ++(was_inline ? inline_cuts : heap_cuts);
        if (was_inline && r.heap_bytes() > 0) ++splits;
        // A trim: one end of one interval moved, the others as they were (subtract's fast path).
        const std::vector<Interval> now = r.intervals();
        if (was_inline && now.size() == was.size()) {
          int moved = 0;
          for (std::size_t i = 0; i < now.size(); ++i) {
            moved += (now[i].lo != was[i].lo) + (now[i].hi != was[i].hi);
          }
          if (moved == 1) ++trims;
        }
      }
    }
  }
  // The draws reach every path: inline cuts, heap cuts, inline rays split into three and
  // intervals trimmed at one end.
  EXPECT_GT(inline_cuts, 1000) << inline_cuts;
  EXPECT_GT(heap_cuts, 500) << heap_cuts;
  EXPECT_GT(splits, 200) << splits;
  EXPECT_GT(trims, 500) << trims;
}

}  // namespace
}  // namespace cwe

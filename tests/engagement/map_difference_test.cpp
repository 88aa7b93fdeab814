// The area one engagement map engages and another does not (map_difference.hpp), against the
// thesis's own measure: a quadtree over the (φ, depth) plane (Aras 2008, fig. 6.53), refined
// where a cell is neither wholly inside nor wholly outside the region. The quadtree's error is
// at most the area of its mixed leaves, which the oracle adds up: the exact figure must lie
// within it.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "../random.hpp"
#include "cwe/engagement/map_difference.hpp"
#include "cwe/tool/tool_spec.hpp"

namespace cwe {
namespace {

// Sorted, disjoint random intervals within [0, 2π] (some empty lists, some whole circles).
std::vector<Interval> random_phi(test::Random& random) {
  const int kind = random.integer(0, 5);
  if (kind == 0) return {};
  if (kind == 1) return {{0.0, kTwoPi}};
  std::vector<double> ends;
  for (int k = 0; k < 2 * random.integer(1, 3); ++k) ends.push_back(random.uniform(0.0, kTwoPi));
  std::sort(ends.begin(), ends.end());
  std::vector<Interval> phi;
  for (std::size_t k = 0; k + 1 < ends.size(); k += 2) phi.push_back({ends[k], ends[k + 1]});
  return phi;
}

// A map of a flat end mill of radius 5: discs of height `disc` up to 3 mm, rings of width
// `ring` out to 5 mm, each with random intervals.
EngagementMap random_map(test::Random& random, double disc, double ring) {
  EngagementMap map;
  for (double z = 0.0; z < 3.0 - 1e-9; z += disc) {
    map.discs.push_back({z, std::min(3.0, z + disc), 1, random_phi(random)});
  }
  for (double r = 0.0; r < 5.0 - 1e-9; r += ring) {
    map.rings.push_back({r, std::min(5.0, r + ring), random_phi(random)});
  }
  map.engaged = true;
  return map;
}

// Whether the strips cover the cell [φ0, φ1] × [h0, h1] wholly (1), not at all (0) or partly
// (2). `strips` are (lo, hi, φ intervals).
struct Strip {
  double lo, hi;
  const std::vector<Interval>* phi;
};
int cover(const std::vector<Strip>& strips, double f0, double f1, double h0, double h1) {
  bool some = false, all = true;
  double covered_to = h0;
  for (const Strip& s : strips) {
    if (s.hi <= h0 || s.lo >= h1) continue;
    if (s.lo > covered_to) all = false;  // a gap in height: outside there
    covered_to = std::max(covered_to, s.hi);
    bool whole = false, none = true;
    for (const Interval& i : *s.phi) {
      if (i.lo <= f0 && i.hi >= f1) whole = true;
      if (i.hi > f0 && i.lo < f1) none = false;
    }
    if (!none) some = true;
    if (!whole) all = false;
  }
  if (covered_to < h1) all = false;
  return all ? 1 : (some ? 2 : 0);
}

// The quadtree's area of the region covered by exactly one of a and b, with `weight(h0, h1)` the
// surface per radian of a band, and the area of its mixed leaves (its error bound).
struct Quadtree {
  double area = 0.0, mixed = 0.0;
};
template <class Weight>
void refine(const std::vector<Strip>& a, const std::vector<Strip>& b, double f0, double f1,
            double h0, double h1, int depth, const Weight& weight, Quadtree& q) {
  const int ca = cover(a, f0, f1, h0, h1), cb = cover(b, f0, f1, h0, h1);
  const double cell = (f1 - f0) * weight(h0, h1);
  if (ca != 2 && cb != 2) {
    if (ca != cb) q.area += cell;
    return;
  }
  if (depth == 0) {
    q.mixed += cell;
    return;
  }
  const double fm = 0.5 * (f0 + f1), hm = 0.5 * (h0 + h1);
  for (const auto& [g0, g1] : {std::pair{f0, fm}, std::pair{fm, f1}}) {
    for (const auto& [k0, k1] : {std::pair{h0, hm}, std::pair{hm, h1}}) {
      refine(a, b, g0, g1, k0, k1, depth - 1, weight, q);
    }
  }
}

TEST(MapDifference, ExclusiveAreaIsTheQuadtreesLimit) {
  const Cutter cutter = cutter_from_spec("flat:10,20");
  test::Random random(613);
  for (int trial = 0; trial < 8; ++trial) {
    SCOPED_TRACE(testing::Message() << "trial " << trial);
    // Different grids: the slabs between both maps' strip edges are what the exact measure sums.
    const EngagementMap a = random_map(random, 0.1, 0.1);
    const EngagementMap b = random_map(random, 0.07, 0.13);
    std::vector<Strip> da, db, ra, rb;
    for (const DiscEngagement& d : a.discs) da.push_back({d.z0, d.z1, &d.phi});
    for (const DiscEngagement& d : b.discs) db.push_back({d.z0, d.z1, &d.phi});
    for (const RingEngagement& r : a.rings) ra.push_back({r.r0, r.r1, &r.phi});
    for (const RingEngagement& r : b.rings) rb.push_back({r.r0, r.r1, &r.phi});
    Quadtree q;
    // The cylinder's surface per radian is 5 dz; the bottom's r dr.
    refine(
        da, db, 0.0, kTwoPi, 0.0, 3.0, 14, [](double h0, double h1) { return 5.0 * (h1 - h0); }, q);
    refine(
        ra, rb, 0.0, kTwoPi, 0.0, 5.0, 14,
        [](double h0, double h1) { return 0.5 * (h1 * h1 - h0 * h0); }, q);
    const double exact = exclusive_area(a, b, cutter.profile());
    EXPECT_GT(exact, 0.0);
    EXPECT_LE(q.mixed, 1e-2 * exact);  // the quadtree is fine enough to say something
    EXPECT_GE(exact, q.area - 1e-9);
    EXPECT_LE(exact, q.area + q.mixed + 1e-9);
    // Symmetric, and zero against itself.
    EXPECT_NEAR(exclusive_area(b, a, cutter.profile()), exact, 1e-9 * exact);
    EXPECT_EQ(exclusive_area(a, a, cutter.profile()), 0.0);
  }
}

TEST(MapDifference, AnglesWrapAndOnlyCountWhereBothEngage) {
  const Cutter cutter = cutter_from_spec("flat:10,20");
  EngagementMap reference, other;
  reference.engaged = other.engaged = true;
  reference.phi_entry = kTwoPi - 0.01;  // just below 360°
  other.phi_entry = 0.01;               // just above 0°: 0.02 rad further on
  reference.phi_exit = 0.5;
  other.phi_exit = 0.4;
  reference.axial_depth = 3.0;
  other.axial_depth = 2.9;
  MapDifference d = map_difference(reference, other, cutter.profile());
  EXPECT_TRUE(d.both_engaged);
  EXPECT_NEAR(d.entry, 0.02, 1e-12);
  EXPECT_NEAR(d.exit, -0.1, 1e-12);
  EXPECT_NEAR(d.axial_depth, -0.1, 1e-12);
  other.engaged = false;
  d = map_difference(reference, other, cutter.profile());
  EXPECT_FALSE(d.both_engaged);
  EXPECT_EQ(d.entry, 0.0);
}

}  // namespace
}  // namespace cwe

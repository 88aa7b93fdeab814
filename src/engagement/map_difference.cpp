#include "cwe/engagement/map_difference.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "cwe/engagement/engagement_grid.hpp"
#include "cwe/geometry/vec.hpp"

namespace cwe {
namespace {

double length(const std::vector<Interval>& set) {
  double sum = 0.0;
  for (const Interval& i : set) sum += i.hi - i.lo;
  return sum;
}

// The length of the symmetric difference of two sorted, disjoint interval lists.
double symmetric_difference(const std::vector<Interval>& a, const std::vector<Interval>& b) {
  double common = 0.0;
  std::size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    common += std::max(0.0, std::min(a[i].hi, b[j].hi) - std::max(a[i].lo, b[j].lo));
    (a[i].hi < b[j].hi ? i : j)++;
  }
  return length(a) + length(b) - 2.0 * common;
}

// A band of a map: [lo, hi] (heights or radii) and its φ intervals.
struct Strip {
  double lo, hi;
  const std::vector<Interval>* phi;
};

// Over the slabs between the strips' edges of both stacks (each sorted, not overlapping), the
// symmetric difference of the φ sets covering each slab times `per_radian(lo, hi)`.
template <class PerRadian>
double exclusive(const std::vector<Strip>& a, const std::vector<Strip>& b,
                 const PerRadian& per_radian) {
  std::vector<double> edges;
  for (const std::vector<Strip>* stack : {&a, &b}) {
    for (const Strip& s : *stack) {
      edges.push_back(s.lo);
      edges.push_back(s.hi);
    }
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  static const std::vector<Interval> kNone;
  const auto covering = [](const std::vector<Strip>& stack, double at) -> const auto& {
    const auto s = std::upper_bound(stack.begin(), stack.end(), at,
                                    [](double x, const Strip& strip) { return x < strip.hi; });
    return s != stack.end() && s->lo <= at ? *s->phi : kNone;
  };
  double area = 0.0;
  for (std::size_t k = 0; k + 1 < edges.size(); ++k) {
    const double lo = edges[k], hi = edges[k + 1], mid = 0.5 * (lo + hi);
    const double d = symmetric_difference(covering(a, mid), covering(b, mid));
    if (d > 0.0) area += d * per_radian(lo, hi);
  }
  return area;
}

std::vector<Strip> discs_of(const EngagementMap& map) {
  std::vector<Strip> strips;
  for (const DiscEngagement& d : map.discs) strips.push_back({d.z0, d.z1, &d.phi});
  return strips;
}

std::vector<Strip> rings_of(const EngagementMap& map) {
  std::vector<Strip> strips;
  for (const RingEngagement& r : map.rings) strips.push_back({r.r0, r.r1, &r.phi});
  return strips;
}

// b − a wrapped into (−π, π].
double angle_between(double a, double b) {
  double d = std::remainder(b - a, 2.0 * kPi);
  if (d <= -kPi) d += 2.0 * kPi;
  return d;
}

}  // namespace

double exclusive_area(const EngagementMap& a, const EngagementMap& b, const Profile& profile) {
  const double side = exclusive(discs_of(a), discs_of(b), [&](double lo, double hi) {
    return side_area_per_radian(profile, lo, hi);
  });
  const double bottom = exclusive(rings_of(a), rings_of(b),
                                  [](double lo, double hi) { return 0.5 * (hi * hi - lo * lo); });
  return side + bottom;
}

MapDifference map_difference(const EngagementMap& reference, const EngagementMap& other,
                             const Profile& profile) {
  MapDifference d;
  d.both_engaged = reference.engaged && other.engaged;
  if (d.both_engaged) {
    d.entry = angle_between(reference.phi_entry, other.phi_entry);
    d.exit = angle_between(reference.phi_exit, other.phi_exit);
  }
  d.axial_depth = other.axial_depth - reference.axial_depth;
  d.area = other.area - reference.area;
  d.exclusive_area = exclusive_area(reference, other, profile);
  return d;
}

}  // namespace cwe

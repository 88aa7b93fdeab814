#pragma once
// How two engagement maps of one cutter at one cutter location differ (`cwe compare`,
// docs/accuracy.md): their entry and exit angles, axial depths and areas, and the area of the
// cutter's surface that one engages and the other does not.
//
// The thesis measured that last figure with a quadtree over the (φ, depth) plane (Aras 2008,
// fig. 6.53). A map is a stack of strips (a disc's heights, or a ring's radii, times its φ
// intervals), so the measure the quadtree converges to is computed exactly here: over each slab
// between the two maps' strip edges, the length of the symmetric difference of their φ sets
// times the band's surface per radian. The tests check it against a quadtree.

#include "cwe/engagement/engagement_map.hpp"
#include "cwe/tool/profile.hpp"

namespace cwe {

struct MapDifference {
  // other − reference. Angles in radians wrapped into (−π, π], and only where both maps are
  // engaged (else 0, with `both_engaged` false).
  bool both_engaged = false;
  double entry = 0.0;
  double exit = 0.0;
  double axial_depth = 0.0;  // mm
  double area = 0.0;         // mm²
  // The surface engaged by exactly one of the two maps, mm² (side and flat bottom).
  double exclusive_area = 0.0;
};

// The surface of the cutter (its profile) engaged by exactly one of `a` and `b`, mm².
double exclusive_area(const EngagementMap& a, const EngagementMap& b, const Profile& profile);

MapDifference map_difference(const EngagementMap& reference, const EngagementMap& other,
                             const Profile& profile);

}  // namespace cwe

#pragma once
// Rays (lines) p(t) = origin + t·direction, t ∈ ℝ, and segments as rays restricted to [0, 1].
// The direction need not be unit: intersectors return parameters t of this ray.

#include "cwe/geometry/interval.hpp"
#include "cwe/geometry/vec.hpp"

namespace cwe {

struct Ray {
  Vec3 origin = Vec3::Zero();
  Vec3 direction = Vec3::UnitZ();

  Vec3 at(double t) const { return origin + t * direction; }

  // The segment from a to b as a ray whose parameter runs from 0 at a to 1 at b.
  static Ray segment(const Vec3& a, const Vec3& b) { return {a, b - a}; }
};

// Restricts a ray interval to the segment parameters [0, 1].
inline Interval clip_to_segment(const Interval& interval) {
  return intersect(interval, Interval{0.0, 1.0});
}

}  // namespace cwe

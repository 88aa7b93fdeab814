#pragma once
// Axis-aligned bounding box. Default-constructed boxes are empty (min = +inf, max = -inf) and
// absorb the first point or box they are extended by.

#include <limits>

#include "cwe/geometry/vec.hpp"

namespace cwe {

struct Aabb {
  Vec3 min = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 max = Vec3::Constant(-std::numeric_limits<double>::infinity());

  static Aabb from_corners(const Vec3& a, const Vec3& b) {
    return {a.cwiseMin(b), a.cwiseMax(b)};
  }

  bool is_empty() const { return !(min.array() <= max.array()).all(); }
  Vec3 size() const { return is_empty() ? Vec3::Zero() : Vec3(max - min); }
  Vec3 center() const { return 0.5 * (min + max); }
  double volume() const { const Vec3 s = size(); return s.x() * s.y() * s.z(); }

  void extend(const Vec3& p) { min = min.cwiseMin(p); max = max.cwiseMax(p); }
  void extend(const Aabb& b) {
    if (b.is_empty()) return;
    min = min.cwiseMin(b.min);
    max = max.cwiseMax(b.max);
  }
  // Grows the box by `margin` on every side (no-op on an empty box).
  void inflate(double margin) {
    if (is_empty()) return;
    min.array() -= margin;
    max.array() += margin;
  }

  // Closed-set tests: touching boxes intersect, points on the boundary are contained.
  bool contains(const Vec3& p) const {
    return (p.array() >= min.array()).all() && (p.array() <= max.array()).all();
  }
  bool intersects(const Aabb& b) const {
    return (min.array() <= b.max.array()).all() && (b.min.array() <= max.array()).all();
  }
};

}  // namespace cwe

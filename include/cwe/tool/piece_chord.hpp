#pragma once
// Ray chords through the solid of one profile piece revolved about the tool axis (TCS): the one
// home of the per-surface chord maths that Cutter::intersect_patch and the sweeps share. Inline,
// because the sweeps call it per piece for every ray they cut.

#include <algorithm>

#include "cwe/geometry/intersect.hpp"
#include "cwe/tool/profile.hpp"

namespace cwe {

// Ray parameters with z ∈ [z0, z1].
inline Interval height_slab(const Ray& ray, double z0, double z1) {
  const Vec3& o = ray.origin;
  const Vec3& d = ray.direction;
  if (d.z() == 0.0) return o.z() >= z0 && o.z() <= z1 ? Interval::full() : Interval::empty();
  const double a = (z0 - o.z()) / d.z(), b = (z1 - o.z()) / d.z();
  return {std::min(a, b), std::max(a, b)};
}

// The solid frustum under a non-horizontal line piece.
inline Frustum frustum_of(const ProfileSegment& s) {
  return {Vec3(0.0, 0.0, s.start.y()), Vec3::UnitZ(), s.start.x(), s.end.x(),
          s.end.y() - s.start.y()};
}

// The tube about an arc piece's centre circle.
inline Torus torus_of(const ProfileSegment& s) {
  return {Vec3(0.0, 0.0, s.center.y()), Vec3::UnitZ(), std::max(0.0, s.center.x()), s.radius};
}

// The core cylinder ρ ≤ c_ρ of an arc piece, within its height range (empty on the axis).
inline Interval core_chord(const ProfileSegment& s, const Ray& ray) {
  const double inner = std::max(0.0, s.center.x());
  if (!(inner > 0.0)) return Interval::empty();
  const double z0 = std::min(s.start.y(), s.end.y()), z1 = std::max(s.start.y(), s.end.y());
  return intersect(ray, Frustum{Vec3(0.0, 0.0, z0), Vec3::UnitZ(), inner, inner, z1 - z0});
}

// The chord of the solid a line or a convex (counter-clockwise) arc piece sweeps about the axis,
// { z in the piece's height range, ρ ≤ the piece's radius at z }: one interval, that solid being
// convex.
inline Interval convex_piece_chord(const ProfileSegment& s, const Ray& ray) {
  if (s.kind == ProfileSegment::Kind::kLine) {
    if (s.start.y() == s.end.y()) {
      return intersect(ray, Disc{Vec3(0.0, 0.0, s.start.y()), Vec3::UnitZ(),
                                 std::max(s.start.x(), s.end.x())});
    }
    return intersect(ray, frustum_of(s));
  }
  const Interval band =
      height_slab(ray, std::min(s.start.y(), s.end.y()), std::max(s.start.y(), s.end.y()));
  if (band.is_empty()) return band;
  if (s.center.x() <= 0.0)  // a ball: the sphere within the band
    return intersect(intersect(ray, Sphere{Vec3(0.0, 0.0, s.center.y()), s.radius}), band);
  // A convex corner, ρ ≤ c_ρ + √(r² - (z - c_z)²), is the tube together with the core cylinder
  // ρ ≤ c_ρ, within the band.
  Interval chord = core_chord(s, ray);
  for (const Interval& i : intersect(ray, torus_of(s))) chord = hull(chord, intersect(i, band));
  return chord;
}

}  // namespace cwe

#include "cwe/toolpath/move.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <Eigen/Geometry>

#include "cwe/core/memory_limit.hpp"
#include "cwe/geometry/tolerance.hpp"
#include "cwe/toolpath/toolpath.hpp"

namespace cwe {
namespace {

// Rotation of v by angle about the unit vector k (Rodrigues).
Vec3 rotate(const Vec3& v, const Vec3& k, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return v * c + k.cross(v) * s + k * (k.dot(v)) * (1.0 - c);
}

// A unit vector perpendicular to a (for antipodal slerp).
Vec3 any_perpendicular(const Vec3& a) {
  const Vec3 trial = std::abs(a.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
  return (trial - a * a.dot(trial)).normalized();
}

}  // namespace

Vec3 slerp(const Vec3& a, const Vec3& b, double u) {
  const double angle = std::atan2(a.cross(b).norm(), a.dot(b));
  if (angle <= tol::kAngle) return (a + u * (b - a)).normalized();  // same direction
  Vec3 k = a.cross(b);
  // Antipodal axes: any great circle is the shortest; pick a fixed one.
  k = k.norm() > tol::kAngle ? Vec3(k.normalized()) : any_perpendicular(a);
  return rotate(a, k, u * angle).normalized();
}

int Move::extra_turns() const {
  if (!is_arc()) return 0;
  // sweep = 2πk + θ with 0 < θ ≤ 2π; tolerate rounding of an exact full turn.
  return std::max(0, static_cast<int>(std::ceil(sweep / kTwoPi - tol::kAngle)) - 1);
}

double Move::radius() const { return is_arc() ? (start - center).norm() : 0.0; }

Vec3 Move::position(double u) const {
  if (!is_arc()) return start + u * (end - start);
  return center + rotate(start - center, normal, u * sweep) + (u * axial) * normal;
}

Vec3 Move::axis(double u) const { return slerp(start_axis, end_axis, u); }

Vec3 Move::tangent(double u) const {
  if (!is_arc()) return end - start;
  const Vec3 radial = rotate(start - center, normal, u * sweep);
  return sweep * normal.cross(radial) + axial * normal;
}

Vec3 Move::axis_rate(double /*u*/) const {
  // Slerp turns at a constant rate about the fixed axis k = a × b / |a × b|.
  const double angle = axis_angle();
  if (angle <= tol::kAngle) return Vec3::Zero();
  const Vec3 k = start_axis.cross(end_axis);
  return (k.norm() > tol::kAngle ? Vec3(k.normalized()) : any_perpendicular(start_axis)) * angle;
}

double Move::length() const {
  if (!is_arc()) return (end - start).norm();
  return std::hypot(radius() * sweep, axial);
}

double Move::axis_angle() const {
  return std::atan2(start_axis.cross(end_axis).norm(), start_axis.dot(end_axis));
}

Aabb Move::bounds() const {
  Aabb box;
  box.extend(start);
  box.extend(end);
  if (!is_arc()) return box;
  const Vec3 radial = start - center;
  const double r = radial.norm();
  if (std::abs(axial) <= tol::kLength) {
    // Plane arc: the extreme along each world axis e is c ± r·ê, ê the unit projection of e
    // onto the arc's plane; it counts when the arc's sweep reaches it.
    for (int i = 0; i < 3; ++i) {
      const Vec3 e = Vec3::Unit(i);
      const Vec3 in_plane = e - normal * normal.dot(e);
      if (in_plane.norm() <= tol::kAngle) continue;  // e along the normal: ends decide
      for (const double side : {1.0, -1.0}) {
        const Vec3 p = side * r * in_plane.normalized();
        double angle = std::atan2(radial.cross(p).dot(normal), radial.dot(p));
        if (angle < 0.0) angle += kTwoPi;
        if (angle <= sweep) box.extend(center + p);
      }
    }
    return box;
  }
  // Helix: a polygon of at most 2° steps, grown by its sagitta so it contains the curve.
  const double max_step = degrees_to_radians(2.0);
  const int steps = std::max(1, static_cast<int>(std::ceil(sweep / max_step)));
  for (int k = 1; k < steps; ++k) box.extend(position(static_cast<double>(k) / steps));
  box.inflate(r * (1.0 - std::cos(0.5 * sweep / steps)));
  return box;
}

Move Move::part(double u0, double u1) const {
  Move m = *this;
  m.start = position(u0);
  m.end = position(u1);
  m.start_axis = axis(u0);
  m.end_axis = axis(u1);
  if (is_arc()) {
    m.center = center + (u0 * axial) * normal;  // at the part's start height
    m.sweep = (u1 - u0) * sweep;
    m.axial = (u1 - u0) * axial;
  }
  return m;
}

const std::string& source_file(const Move& move, const std::vector<std::string>& sources,
                               const std::string& otherwise) {
  return move.source >= 0 && static_cast<std::size_t>(move.source) < sources.size()
             ? sources[static_cast<std::size_t>(move.source)]
             : otherwise;
}

void hold_move(std::vector<Move>& moves, const Move& move, const SourceLocation& where) {
  if (moves.size() == moves.capacity()) {
    // std::vector doubles; the old block is held while the new one is filled.
    const double grown = 3.0 * static_cast<double>(std::max<std::size_t>(moves.size(), 1));
    check_memory(grown * static_cast<double>(sizeof(Move)),
                 fmt::format("holding {} moves of the program", 2 * moves.size()), where,
                 "split the program into several, or raise the limit");
  }
  moves.push_back(move);
}

}  // namespace cwe

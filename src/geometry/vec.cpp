#include "cwe/geometry/vec.hpp"

#include <Eigen/Geometry>

#include "cwe/core/assert.hpp"
#include "cwe/geometry/tolerance.hpp"

namespace cwe {

namespace {

// Writes the component of `v` perpendicular to the unit vector `z` to `result` and returns true;
// returns false when `v` is zero or within tol::kAngle of parallel to z, where the direction of
// that component would be mostly rounding.
bool perpendicular_part(const Vec3& v, const Vec3& z, Vec3& result) {
  const double length = v.norm();
  if (length == 0.0) return false;
  const Vec3 perpendicular = v - v.dot(z) * z;
  // |perpendicular| = |v| sin(angle between v and z).
  if (perpendicular.norm() <= tol::kAngle * length) return false;
  result = perpendicular;
  return true;
}

}  // namespace

Frame Frame::from_z(const Vec3& origin, const Vec3& z, const Vec3& x_hint) {
  const double z_length = z.norm();
  CWE_ASSERT(z_length > 0.0, "Frame::from_z needs a non-zero z axis");
  const Vec3 unit_z = z / z_length;
  Vec3 x;
  // Hint parallel to z (or zero): fall back to world X, then world Y. Two world axes cannot
  // both be parallel to z, so the second fallback always succeeds.
  if (!perpendicular_part(x_hint, unit_z, x) && !perpendicular_part(Vec3::UnitX(), unit_z, x)) {
    [[maybe_unused]] const bool found = perpendicular_part(Vec3::UnitY(), unit_z, x);
    CWE_ASSERT(found, "world Y is not parallel to z when world X is");
  }
  x.normalize();
  // A second Gram-Schmidt pass: when the hint was nearly parallel to z, the first projection
  // leaves a component along z of the order of rounding / sin(angle).
  x -= x.dot(unit_z) * unit_z;
  x.normalize();
  Frame frame;
  frame.origin = origin;
  frame.axes.col(0) = x;
  frame.axes.col(1) = unit_z.cross(x);
  frame.axes.col(2) = unit_z;
  return frame;
}

}  // namespace cwe

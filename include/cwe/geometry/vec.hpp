#pragma once
// Vectors and orthonormal frames (Eigen). <Eigen/Core> plus <Eigen/Geometry> (cross products);
// never <Eigen/Dense>, to keep this widely included header light.

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace cwe {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kTwoPi = 2.0 * kPi;

inline double degrees_to_radians(double degrees) { return degrees * (kPi / 180.0); }
inline double radians_to_degrees(double radians) { return radians * (180.0 / kPi); }

// A right-handed orthonormal frame: origin plus unit axes x, y, z (z = x × y).
// to_local/to_world convert points; the *_direction forms convert vectors.
struct Frame {
  Vec3 origin = Vec3::Zero();
  Mat3 axes = Mat3::Identity();  // columns are x, y, z in world coordinates

  Vec3 x() const { return axes.col(0); }
  Vec3 y() const { return axes.col(1); }
  Vec3 z() const { return axes.col(2); }

  Vec3 to_local(const Vec3& world_point) const {
    return axes.transpose() * (world_point - origin);
  }
  Vec3 to_world(const Vec3& local_point) const { return origin + axes * local_point; }
  Vec3 direction_to_local(const Vec3& world_vector) const {
    return axes.transpose() * world_vector;
  }
  Vec3 direction_to_world(const Vec3& local_vector) const { return axes * local_vector; }

  // The frame with the given origin and z axis (normalised), x the component of x_hint
  // perpendicular to z. When x_hint is (nearly) parallel to z, x falls back to world X, then
  // world Y, projected: the choice is stable, never NaN. z must be non-zero.
  static Frame from_z(const Vec3& origin, const Vec3& z, const Vec3& x_hint);
};

}  // namespace cwe

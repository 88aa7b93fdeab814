#include "cwe/kinematics/tool_state.hpp"

#include <cmath>

#include "cwe/core/assert.hpp"
#include "cwe/geometry/tolerance.hpp"

namespace cwe {

const char* to_string(MotionClass motion) {
  switch (motion) {
    case MotionClass::kAscending:
      return "ascending";
    case MotionClass::kHorizontal:
      return "horizontal";
    case MotionClass::kDescending:
      return "descending";
    case MotionClass::kPlunge:
      return "plunge";
    case MotionClass::kRetract:
      return "retract";
    case MotionClass::kResting:
      return "resting";
  }
  return "?";
}

ToolState tool_state(const Vec3& tip, const Vec3& axis, const Vec3& tip_velocity,
                     const Vec3& angular_velocity, const Vec3& previous_x) {
  CWE_ASSERT(std::abs(axis.squaredNorm() - 1.0) <= tol::kAngle, "tool axis must be a unit vector");
  ToolState s;
  s.tip_velocity = tip_velocity;
  s.angular_velocity = angular_velocity;
  const double speed = tip_velocity.norm();
  const Vec3 lateral = tip_velocity - axis * axis.dot(tip_velocity);
  // Lateral speed below this fraction of the speed counts as purely axial motion.
  const bool axial_only = lateral.norm() <= tol::kAngle * speed;
  if (speed <= 0.0 || !std::isfinite(speed)) {
    s.motion = MotionClass::kResting;
    s.feed_angle = kPi / 2.0;
  } else {
    s.feed_angle = std::atan2(lateral.norm(), axis.dot(tip_velocity));
    if (axial_only) {
      s.motion = axis.dot(tip_velocity) > 0.0 ? MotionClass::kRetract : MotionClass::kPlunge;
    } else if (std::abs(s.feed_angle - kPi / 2.0) <= tol::kAngle) {
      s.motion = MotionClass::kHorizontal;
    } else {
      s.motion = s.feed_angle < kPi / 2.0 ? MotionClass::kAscending : MotionClass::kDescending;
    }
  }
  // x hint: the lateral feed, else the previous x, else world X (Frame::from_z falls back to
  // world Y when that is parallel to the axis).
  Vec3 hint = Vec3::UnitX();
  if (speed > 0.0 && !axial_only) {
    hint = lateral;
  } else if ((previous_x - axis * axis.dot(previous_x)).norm() > tol::kAngle) {
    hint = previous_x;
  }
  s.tcs = Frame::from_z(tip, axis, hint);
  return s;
}

ToolState tool_state(const Move& move, double u, const Vec3& previous_x) {
  return tool_state(move.position(u), move.axis(u), move.tangent(u), move.axis_rate(u), previous_x);
}

ToolState tool_state(const ClPoint& point, const Vec3& previous_x) {
  return tool_state(point.position, point.axis, point.velocity, point.angular_velocity, previous_x);
}

}  // namespace cwe

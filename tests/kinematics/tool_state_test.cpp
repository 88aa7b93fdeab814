#include "cwe/kinematics/tool_state.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "random.hpp"

namespace cwe {
namespace {

void expect_orthonormal(const Frame& f) {
  EXPECT_NEAR((f.axes.transpose() * f.axes - Mat3::Identity()).norm(), 0.0, 1e-14);
  EXPECT_NEAR(f.axes.determinant(), 1.0, 1e-14);
}

TEST(ToolState, HorizontalFeedAlongX) {
  const ToolState s = tool_state(Vec3(1, 2, 3), Vec3::UnitZ(), Vec3(10, 0, 0), Vec3::Zero());
  EXPECT_TRUE(s.tcs.x().isApprox(Vec3::UnitX()));
  EXPECT_TRUE(s.tcs.y().isApprox(Vec3::UnitY()));  // y = z × x: left of the feed
  EXPECT_NEAR(s.feed_angle, kPi / 2, 1e-15);
  EXPECT_EQ(s.motion, MotionClass::kHorizontal);
  EXPECT_TRUE(s.tip_velocity_tcs().isApprox(Vec3(10, 0, 0)));
}

TEST(ToolState, RampsAndAxialMotions) {
  const double down = degrees_to_radians(10.0);
  const ToolState ramp = tool_state(Vec3::Zero(), Vec3::UnitZ(),
                                    Vec3(0, std::cos(down), -std::sin(down)), Vec3::Zero());
  EXPECT_EQ(ramp.motion, MotionClass::kDescending);
  EXPECT_NEAR(ramp.feed_angle, kPi / 2 + down, 1e-15);
  EXPECT_TRUE(ramp.tcs.x().isApprox(Vec3::UnitY()));
  const ToolState up = tool_state(Vec3::Zero(), Vec3::UnitZ(), Vec3(1, 0, 1), Vec3::Zero());
  EXPECT_EQ(up.motion, MotionClass::kAscending);
  EXPECT_NEAR(up.feed_angle, kPi / 4, 1e-15);

  // A plunge has no lateral feed: x comes from the previous x, else world X.
  const ToolState plunge =
      tool_state(Vec3::Zero(), Vec3::UnitZ(), Vec3(0, 0, -5), Vec3::Zero(), Vec3(0, 1, 0.3));
  EXPECT_EQ(plunge.motion, MotionClass::kPlunge);
  EXPECT_NEAR(plunge.feed_angle, kPi, 1e-15);
  EXPECT_TRUE(plunge.tcs.x().isApprox(Vec3::UnitY()));
  const ToolState fresh = tool_state(Vec3::Zero(), Vec3::UnitZ(), Vec3(0, 0, -5), Vec3::Zero());
  EXPECT_TRUE(fresh.tcs.x().isApprox(Vec3::UnitX()));
  EXPECT_EQ(tool_state(Vec3::Zero(), Vec3::UnitZ(), Vec3(0, 0, 2), Vec3::Zero()).motion,
            MotionClass::kRetract);
  const ToolState rest = tool_state(Vec3::Zero(), Vec3::UnitX(), Vec3::Zero(), Vec3::Zero());
  EXPECT_EQ(rest.motion, MotionClass::kResting);
  expect_orthonormal(rest.tcs);
  EXPECT_TRUE(rest.tcs.z().isApprox(Vec3::UnitX()));
}

TEST(ToolState, TiltedAxesGiveOrthonormalFramesWithXAlongTheFeed) {
  test::Random random(5);
  for (int k = 0; k < 200; ++k) {
    const Vec3 axis = random.unit_vector();
    const Vec3 v = random.unit_vector() * random.uniform(0.1, 100.0);
    const ToolState s = tool_state(random.point_in_box(100), axis, v, random.unit_vector());
    expect_orthonormal(s.tcs);
    EXPECT_TRUE(s.tcs.z().isApprox(axis, 1e-14));
    // The tip velocity lies in the x-z plane with a non-negative x component.
    const Vec3 local = s.tip_velocity_tcs();
    EXPECT_NEAR(local.y(), 0.0, 1e-12 * v.norm());
    EXPECT_GE(local.x(), 0.0);
    EXPECT_NEAR(std::atan2(local.x(), local.z()), s.feed_angle, 1e-12);
  }
}

// V(P) = V_F + ω × (P - F) is the derivative of a point carried rigidly by a 5-axis move.
TEST(ToolState, PointVelocityIsTheRigidBodyDerivative) {
  Move m;
  m.start = Vec3(0, 0, 0);
  m.end = Vec3(30, 5, -2);
  m.start_axis = Vec3::UnitZ();
  m.end_axis = Vec3(0.3, -0.4, 1).normalized();
  const Vec3 body = Vec3(4, -1, 7);  // relative to the tip at u = 0
  const Vec3 k = m.start_axis.cross(m.end_axis).normalized();
  const auto carried = [&](double u) {
    const double angle = u * m.axis_angle();
    const Vec3 r = body * std::cos(angle) + k.cross(body) * std::sin(angle) +
                   k * k.dot(body) * (1 - std::cos(angle));
    return Vec3(m.position(u) + r);
  };
  for (const double u : {0.1, 0.5, 0.8}) {
    const ToolState s = tool_state(m, u);
    const double h = 1e-6;
    const Vec3 numeric = (carried(u + h) - carried(u - h)) / (2 * h);
    // Central differences: O(h²)·|second derivative| ≈ 1e-11, plus rounding 1e-16·|p|/h.
    EXPECT_LT((numeric - s.point_velocity(carried(u))).norm(), 1e-8);
  }
}

}  // namespace
}  // namespace cwe

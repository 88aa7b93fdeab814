#include "cwe/tool/profile.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "cwe/tool/tool_spec.hpp"
#include "tool_testing.hpp"

namespace cwe {
namespace {

using Seg = ProfileSegment;

// Ball end mill of radius 5 and height 20, built by hand.
Profile ball_profile() {
  return Profile({Seg::arc({0, 0}, {5, 5}, {0, 5}, true), Seg::line({5, 5}, {5, 20})});
}

TEST(ProfileSegment, LineGeometry) {
  const Seg s = Seg::line({1, 0}, {4, 4});
  EXPECT_DOUBLE_EQ(s.length(), 5.0);
  EXPECT_TRUE(s.point_at(0.5).isApprox(Vec2(2.5, 2.0)));
  // Rising to the right: the solid is on the left, the outward normal points right-down.
  EXPECT_TRUE(s.normal_at(0.3).isApprox(Vec2(0.8, -0.6)));
  EXPECT_DOUBLE_EQ(s.radius_at(2.0), 2.5);
}

TEST(ProfileSegment, ArcGeometry) {
  // Quarter circle of radius 5 about (0, 5) from the tip to the equator: a ball end.
  const Seg s = Seg::arc({0, 0}, {5, 5}, {0, 5}, true);
  EXPECT_NEAR(s.length(), 5.0 * kPi / 2.0, 1e-12);
  EXPECT_NEAR(s.start_angle(), -kPi / 2.0, 1e-15);
  EXPECT_NEAR(s.end_angle(), 0.0, 1e-15);
  const Vec2 mid = s.point_at(0.5);
  EXPECT_NEAR(mid.x(), 5.0 * std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(mid.y(), 5.0 - 5.0 * std::sqrt(0.5), 1e-12);
  // Outward normal of a convex arc points away from the centre.
  EXPECT_TRUE(s.normal_at(0.5).isApprox((mid - s.center).normalized(), 1e-12));
  EXPECT_NEAR(s.radius_at(1.0), std::sqrt(25.0 - 16.0), 1e-12);
  EXPECT_DOUBLE_EQ(s.max_radius(), 5.0);
}

TEST(ProfileSegment, ConcaveArcNormalPointsToCentre) {
  // Corner-rounding arc: clockwise, left of its centre; the solid is outside the circle.
  const Seg s = Seg::arc({2, 1}, {5, 4}, {5, 1}, false);
  const Vec2 p = s.point_at(0.5);
  EXPECT_TRUE(s.normal_at(0.5).isApprox((s.center - p).normalized(), 1e-12));
  EXPECT_NEAR(s.radius_at(1.0), 2.0, 1e-12);
  EXPECT_NEAR(s.radius_at(4.0), 5.0, 1e-12);
  EXPECT_NEAR(s.radius_at(2.5), 5.0 - std::sqrt(9.0 - 2.25), 1e-12);
}

TEST(ProfileSegment, ClosestPoint) {
  const Seg s = Seg::arc({0, 0}, {5, 5}, {0, 5}, true);
  const auto c = s.closest(Vec2(10, 5));
  EXPECT_NEAR(c.u, 1.0, 1e-12);
  EXPECT_NEAR(c.distance, 5.0, 1e-12);
  const auto inner = s.closest(Vec2(3 * std::sqrt(0.5), 5 - 3 * std::sqrt(0.5)));
  EXPECT_NEAR(inner.u, 0.5, 1e-12);
  EXPECT_NEAR(inner.distance, 2.0, 1e-12);
}

TEST(Profile, BallRadiusAndMembership) {
  const Profile p = ball_profile();
  EXPECT_DOUBLE_EQ(p.height(), 20.0);
  EXPECT_DOUBLE_EQ(p.max_radius(), 5.0);
  EXPECT_NEAR(p.radius_at(1.0), 3.0, 1e-12);
  EXPECT_DOUBLE_EQ(p.radius_at(12.0), 5.0);
  EXPECT_DOUBLE_EQ(p.radius_at(-0.1), 0.0);
  EXPECT_DOUBLE_EQ(p.radius_at(20.1), 0.0);
  EXPECT_TRUE(p.contains(2.9, 1.0));
  EXPECT_FALSE(p.contains(3.1, 1.0));
  EXPECT_TRUE(p.contains(0.0, 0.0));
  EXPECT_FALSE(p.contains(0.1, 0.0));
  EXPECT_NEAR(p.length(), 5.0 * kPi / 2.0 + 15.0, 1e-12);
}

// lowest_reaching is heights_reaching's lower end, to the last bit, on profiles with and without
// a quarter ball at the foot (whose radii up to the ball's it answers in closed form), for radii
// below the tip, across the ball, at its rim, beyond it and beyond the tool.
TEST(Profile, LowestReachingIsTheHeightsLowerEnd) {
  for (const char* spec : {"ball:6,20", "ball:10,8", "taper-ball:4,3,20", "bull:10,2,20",
                           "flat:10,20", "taper-flat:6,5,20", "chamfer:12,90,15"}) {
    SCOPED_TRACE(spec);
    const Cutter cutter = cutter_from_spec(spec);
    const Profile& p = cutter.profile();
    const double big = p.max_radius();
    std::vector<double> radii{
        -1.0, 0.0, big, std::nextafter(big, 0.0), std::nextafter(big, 9e9), big + 1.0};
    for (int k = 1; k < 400; ++k) radii.push_back(big * k / 397.0);
    for (const double r : radii) {
      const Interval heights = p.heights_reaching(r);
      EXPECT_EQ(p.lowest_reaching(r), heights.is_empty() ? 0.0 : heights.lo) << "r = " << r;
    }
  }
}

// heights_reaching against dense sampling of the profile's radius: the sampled heights where the
// tool is at least r wide span the interval to within a sampling step.
TEST(Profile, HeightsReachingSpanTheSampledHeights) {
  for (const char* spec : {"ball:6,20", "taper-ball:4,3,20", "bull:10,2,20", "flat:10,20",
                           "taper-flat:6,5,20", "chamfer:12,90,15"}) {
    SCOPED_TRACE(spec);
    const Cutter cutter = cutter_from_spec(spec);
    const Profile& p = cutter.profile();
    constexpr int kSamples = 20000;
    const double step = p.height() / kSamples;
    for (int k = 0; k <= 50; ++k) {
      const double r = p.max_radius() * k / 50.0;
      double lo = std::numeric_limits<double>::infinity(), hi = -lo;
      for (int m = 0; m <= kSamples; ++m) {
        const double z = m * step;
        if (p.radius_at(z) >= r) lo = std::min(lo, z), hi = std::max(hi, z);
      }
      const Interval heights = p.heights_reaching(r);
      ASSERT_FALSE(heights.is_empty()) << "r = " << r;
      EXPECT_NEAR(heights.lo, lo, step) << "r = " << r;
      EXPECT_NEAR(heights.hi, hi, step) << "r = " << r;
    }
  }
  // A flat end's side spans the whole height exactly.
  const Cutter flat = cutter_from_spec("flat:10,20");
  for (const double r : {-1.0, 0.0, 2.5, 5.0}) {
    EXPECT_EQ(flat.profile().heights_reaching(r).lo, 0.0);
    EXPECT_EQ(flat.profile().heights_reaching(r).hi, 20.0);
  }
  EXPECT_TRUE(flat.profile().heights_reaching(std::nextafter(5.0, 9.0)).is_empty());
}

// Up to the radius where the first piece's answer begins to change (a flat bottom's rim, or the
// axis for a tool without one), the tool reaches r over its whole height exactly; just beyond,
// it does not.
TEST(Profile, HeightsReachingIsTheWholeHeightUpToTheFirstChange) {
  const std::pair<const char*, double> tools[] = {
      {"flat:10,20", 5.0}, {"bull:10,2,20", 3.0},     {"taper-flat:6,5,20", 3.0},
      {"ball:6,20", 0.0},  {"chamfer:12,90,15", 0.0}, {"taper-ball:4,3,20", 0.0}};
  for (const auto& [spec, edge] : tools) {
    SCOPED_TRACE(spec);
    const Cutter cutter = cutter_from_spec(spec);
    const Profile& p = cutter.profile();
    for (const double r : {-1.0, 0.0, edge / 2.0, std::nextafter(edge, -1.0), edge}) {
      const Interval heights = p.heights_reaching(r);
      EXPECT_EQ(heights.lo, 0.0) << "r = " << r;
      EXPECT_EQ(heights.hi, p.height()) << "r = " << r;
    }
    const Interval beyond = p.heights_reaching(edge + 1e-3);
    EXPECT_TRUE(beyond.is_empty() || beyond.lo > 0.0) << beyond.lo;
  }
}

TEST(Profile, SnapsEndPointsWithinInputTolerance) {
  const Profile p({Seg::line({0, 0}, {5, 0}), Seg::line({5.0001, 0}, {5, 10})});
  EXPECT_EQ(p.segments()[1].start, Vec2(5, 0));
}

TEST(Profile, RejectsBrokenOutlines) {
  EXPECT_INPUT_ERROR(Profile({}), "at least one piece");
  EXPECT_INPUT_ERROR(Profile({Seg::line({1, 0}, {5, 0}), Seg::line({5, 0}, {5, 10})}),
                     "piece 1: the profile must start at the tip (0, 0)");
  EXPECT_INPUT_ERROR(Profile({Seg::line({0, 0}, {5, 0}), Seg::line({5.1, 0}, {5, 10})}),
                     "piece 2: starts at (5.1, 0) but the previous piece ends at (5, 0)");
  EXPECT_INPUT_ERROR(Profile({Seg::line({0, 0}, {5, 2}), Seg::line({5, 2}, {6, 1})}),
                     "piece 2: goes down");
  EXPECT_INPUT_ERROR(Profile({Seg::line({0, 0}, {5, 0}), Seg::line({5, 0}, {5, 0})}),
                     "piece 2: has zero length");
  EXPECT_INPUT_ERROR(Profile({Seg::line({0, 0}, {5, 0})}), "height > 0");
  EXPECT_INPUT_ERROR(Profile({Seg::line({0, 0}, {5, 5}), Seg::line({5, 5}, {0, 8})}),
                     "top radius > 0");
  // A three-quarter circle passes its top point: the profile would fold back down.
  EXPECT_INPUT_ERROR(Profile({Seg::line({0, 0}, {5, 0}), Seg::arc({5, 0}, {2, 3}, {5, 3}, true)}),
                     "passes through its top or bottom point");
  // A right half circle from its bottom to its top rises monotonically: accepted.
  EXPECT_NO_THROW(Profile({Seg::line({0, 0}, {5, 0}), Seg::arc({5, 0}, {5, 10}, {5, 5}, true)}));
  // Clockwise on the right of its centre descends.
  EXPECT_INPUT_ERROR(Profile({Seg::line({0, 0}, {5, 3}), Seg::arc({5, 3}, {8, 0}, {5, 0}, false)}),
                     "piece 2: goes down");
  // A concave arc whose circle reaches past the axis.
  const Vec2 c(2.5, 5.0);
  const Vec2 a = c + 3.0 * Vec2(std::cos(4 * kPi / 3), std::sin(4 * kPi / 3));
  const Vec2 b = c + 3.0 * Vec2(std::cos(2 * kPi / 3), std::sin(2 * kPi / 3));
  EXPECT_INPUT_ERROR(
      Profile({Seg::line({0, 0}, a), Seg::arc(a, b, c, false), Seg::line(b, {3, 10})}),
      "piece 2: arc crosses the axis");
  EXPECT_INPUT_ERROR(Profile({Seg::line({0, 0}, {5, 0}), Seg::arc({5, 0}, {9, 5}, {5, 4}, true)}),
                     "arc end is");
}

}  // namespace
}  // namespace cwe

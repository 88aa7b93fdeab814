#include "cwe/tool/apt.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "tool_testing.hpp"

namespace cwe {
namespace {

using Seg = ProfileSegment;
using test::expect_same_profile;

// Profiles are built from the user's numbers with a few trigonometric operations: they agree
// with hand-built ones to rounding of values of size ~10 mm, far below 1e-9 mm.
constexpr double kTight = 1e-9;

Profile profile_of(const AptCutter& apt) { return apt_profile(apt); }

TEST(AptPresets, FlatEndMillIsDiscPlusCylinder) {
  const AptCutter apt = flat_end_mill(10.0, 25.0);
  EXPECT_EQ(to_string(apt), "CUTTER/10,0,5,0,0,0,25");
  expect_same_profile(profile_of(apt),
                      Profile({Seg::line({0, 0}, {5, 0}), Seg::line({5, 0}, {5, 25})}), kTight);
}

TEST(AptPresets, BallEndMillIsQuarterArcPlusCylinder) {
  expect_same_profile(profile_of(ball_end_mill(10.0, 25.0)),
                      Profile({Seg::arc({0, 0}, {5, 5}, {0, 5}, true), Seg::line({5, 5}, {5, 25})}),
                      kTight);
}

TEST(AptPresets, BullNose) {
  expect_same_profile(profile_of(bull_nose_end_mill(10.0, 2.0, 25.0)),
                      Profile({Seg::line({0, 0}, {3, 0}), Seg::arc({3, 0}, {5, 2}, {3, 2}, true),
                               Seg::line({5, 2}, {5, 25})}),
                      kTight);
}

TEST(AptPresets, TaperFlatWidensUpwards) {
  const double t = std::tan(degrees_to_radians(5.0));
  expect_same_profile(profile_of(taper_flat_end_mill(6.0, 5.0, 20.0)),
                      Profile({Seg::line({0, 0}, {3, 0}), Seg::line({3, 0}, {3 + 20 * t, 20})}),
                      kTight);
}

TEST(AptPresets, NegativeTaperNarrowsUpwards) {
  const double t = std::tan(degrees_to_radians(-3.0));
  expect_same_profile(profile_of(taper_flat_end_mill(10.0, -3.0, 20.0)),
                      Profile({Seg::line({0, 0}, {5, 0}), Seg::line({5, 0}, {5 + 20 * t, 20})}),
                      kTight);
}

TEST(AptPresets, TaperBallSideIsTangentToTheBall) {
  const double beta = degrees_to_radians(3.0);
  const Profile p = profile_of(taper_ball_end_mill(4.0, 3.0, 30.0));
  ASSERT_EQ(p.segments().size(), 2u);
  const Seg& arc = p.segments()[0];
  const Seg& side = p.segments()[1];
  EXPECT_NEAR((arc.center - Vec2(0, 2)).norm(), 0.0, kTight);
  EXPECT_NEAR(arc.radius, 2.0, kTight);
  // The side leaves the ball at angle -β and rises at β from the axis, tangent (G1).
  EXPECT_NEAR((side.start - Vec2(2 * std::cos(beta), 2 - 2 * std::sin(beta))).norm(), 0.0, kTight);
  EXPECT_NEAR((arc.tangent_at(1.0) - side.tangent_at(0.0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(std::atan2(side.tangent_at(0.0).x(), side.tangent_at(0.0).y()), beta, 1e-12);
  EXPECT_NEAR(side.end.y(), 30.0, kTight);
}

TEST(AptPresets, ChamferMill) {
  // 90° included angle: a 45° cone from the tip to the diameter, then a cylinder.
  expect_same_profile(profile_of(chamfer_mill(12.0, 90.0, 15.0)),
                      Profile({Seg::line({0, 0}, {6, 6}), Seg::line({6, 6}, {6, 15})}), kTight);
  // A 118° drill point.
  const Profile drill = profile_of(chamfer_mill(8.0, 118.0, 30.0));
  const Vec2 corner = drill.segments()[0].end;
  EXPECT_NEAR(corner.x(), 4.0, kTight);
  EXPECT_NEAR(std::atan2(corner.x(), corner.y()), degrees_to_radians(59.0), 1e-12);
}

// The same cutter described two ways gives the same profile.
TEST(AptPresets, PresetsAgreeWhereTheyDescribeTheSameCutter) {
  const Profile flat = profile_of(flat_end_mill(10.0, 30.0));
  const Profile ball = profile_of(ball_end_mill(10.0, 30.0));
  expect_same_profile(profile_of(bull_nose_end_mill(10.0, 0.0, 30.0)), flat, kTight);
  expect_same_profile(profile_of(bull_nose_end_mill(10.0, 5.0, 30.0)), ball, kTight);
  expect_same_profile(profile_of(taper_flat_end_mill(10.0, 0.0, 30.0)), flat, kTight);
  expect_same_profile(profile_of(taper_ball_end_mill(10.0, 0.0, 30.0)), ball, kTight);
  expect_same_profile(profile_of(chamfer_mill(10.0, 180.0, 30.0)), flat, kTight);
  expect_same_profile(profile_of(apt_from_values(std::array{10.0})),
                      profile_of(flat_end_mill(10.0)), kTight);
  expect_same_profile(profile_of(apt_from_values(std::array{10.0, 2.0})),
                      profile_of(bull_nose_end_mill(10.0, 2.0)), kTight);
  expect_same_profile(profile_of(apt_from_values(std::array{10.0, 5.0, 0.0, 5.0, 0.0, 0.0, 30.0})),
                      ball, kTight);
}

TEST(AptPresets, DefaultHeightIsThreeDiameters) {
  EXPECT_DOUBLE_EQ(flat_end_mill(10.0).h, 30.0);
  EXPECT_DOUBLE_EQ(apt_from_values(std::array{6.0, 3.0}).h, 18.0);
}

// The general case: conical bottom, corner radius and taper together. The profile must be G1
// (tangent-continuous) at both joints and its lines must have the APT angles.
TEST(AptGeneral, ConeCornerTaperIsTangentContinuous) {
  const double alpha = degrees_to_radians(10.0), beta = degrees_to_radians(5.0);
  const double r = 1.0, e = 3.0;
  const double f = (r + e * std::sin(alpha)) / std::cos(alpha);
  const double d =
      2 * std::cos(alpha) * (r + e * std::cos(beta) - f * std::sin(beta)) / std::cos(alpha + beta);
  const Profile p = profile_of({d, r, e, f, 10.0, 5.0, 20.0});
  ASSERT_EQ(p.segments().size(), 3u);
  const Seg& bottom = p.segments()[0];
  const Seg& corner = p.segments()[1];
  const Seg& side = p.segments()[2];
  EXPECT_NEAR(std::atan2(bottom.tangent_at(0).y(), bottom.tangent_at(0).x()), alpha, 1e-12);
  EXPECT_NEAR((bottom.tangent_at(1) - corner.tangent_at(0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((corner.tangent_at(1) - side.tangent_at(0)).norm(), 0.0, 1e-12);
  EXPECT_NEAR(std::atan2(side.tangent_at(0).x(), side.tangent_at(0).y()), beta, 1e-12);
  // The extended bottom and side lines meet at diameter d.
  const Vec2 b0 = bottom.start, bd = bottom.tangent_at(0);
  const Vec2 s0 = side.start, sd = side.tangent_at(0);
  const double t = (s0 - b0).x() * sd.y() - (s0 - b0).y() * sd.x();
  const double det = bd.x() * sd.y() - bd.y() * sd.x();
  EXPECT_NEAR((b0 + (t / det) * bd).x(), d / 2.0, 1e-12);
}

TEST(AptErrors, NameTheParameterThatDisagrees) {
  EXPECT_INPUT_ERROR(profile_of({10, 2, 3, 2.5, 0, 0, 30}), "f = 2.5 does not fit r, e and alpha");
  EXPECT_INPUT_ERROR(profile_of({12, 2, 3, 2, 0, 0, 30}),
                     "d = 12 does not fit the other parameters");
  EXPECT_INPUT_ERROR(profile_of({10, 0, 5, 0, 90, 0, 30}), "alpha = 90°");
  EXPECT_INPUT_ERROR(profile_of({10, 0, 5, 0, 0, 95, 30}), "beta = 95°");
  EXPECT_INPUT_ERROR(profile_of({10, 0, 5, 5, 45, 45, 30}), "alpha + beta = 90°");
  EXPECT_INPUT_ERROR(profile_of({10, 5, 0, 5, 0, 0, 3}), "h = 3 is below the top of the corner");
  EXPECT_INPUT_ERROR(profile_of({10, 0, 5, 0, 0, -20, 30}), "tapers onto the axis");
  EXPECT_INPUT_ERROR(profile_of({-10, 0, 5, 0, 0, 0, 30}), "d = -10");
  EXPECT_INPUT_ERROR(profile_of({10, -1, 5, 0, 0, 0, 30}), "r = -1");
  EXPECT_INPUT_ERROR(bull_nose_end_mill(10, 6), "r = 6: the corner radius must be in [0, D/2]");
  EXPECT_INPUT_ERROR(chamfer_mill(10, 0), "tip angle = 0°");
  EXPECT_INPUT_ERROR(flat_end_mill(0), "D = 0: the diameter must be positive");
  EXPECT_INPUT_ERROR(apt_from_values(std::array{10.0, 1.0, 2.0}), "3 values is ambiguous");
  EXPECT_INPUT_ERROR(apt_from_values(std::array{1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0, 1.0}), "1 to 7 values");
}

// CAM systems write 4 decimals: rounding of that size is accepted.
TEST(AptErrors, AcceptsFourDecimalRounding) {
  const double f =
      (1.0 + 3.0 * std::sin(degrees_to_radians(10.0))) / std::cos(degrees_to_radians(10.0));
  const double d = 2 * std::cos(degrees_to_radians(10.0)) * (1.0 + 3.0 - 0.0) /
                   std::cos(degrees_to_radians(10.0));
  const double f4 = std::round(f * 1e4) / 1e4;
  const double d4 = std::round(d * 1e4) / 1e4;
  EXPECT_NO_THROW(profile_of({d4, 1.0, 3.0, f4, 10.0, 0.0, 20.0}));
}

}  // namespace
}  // namespace cwe

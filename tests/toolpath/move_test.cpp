#include "cwe/toolpath/move.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "cwe/toolpath/cl_sampling.hpp"
#include "random.hpp"

namespace cwe {
namespace {

Move line(const Vec3& a, const Vec3& b, double feed = 600.0) {
  Move m;
  m.start = a;
  m.end = b;
  m.feed_rate = feed;
  return m;
}

// Helix about +Z through the origin: radius 5, from angle 0, `sweep` rad, rising `axial` mm.
Move helix(double sweep, double axial, const Vec3& normal = Vec3::UnitZ()) {
  Move m;
  m.shape = MoveShape::kArc;
  m.center = Vec3::Zero();
  m.normal = normal;
  m.start = Vec3(5, 0, 0);
  m.sweep = sweep;
  m.axial = axial;
  m.end = m.position(1.0);
  m.feed_rate = 600.0;
  return m;
}

TEST(Move, LineGeometry) {
  const Move m = line({0, 0, 0}, {3, 4, 0});
  EXPECT_DOUBLE_EQ(m.length(), 5.0);
  EXPECT_TRUE(m.position(0.5).isApprox(Vec3(1.5, 2, 0)));
  EXPECT_TRUE(m.tangent(0.2).isApprox(Vec3(3, 4, 0)));
  EXPECT_EQ(m.extra_turns(), 0);
  EXPECT_TRUE(m.axis_rate(0.5).isZero());
}

TEST(Move, ArcFollowsTheRightHandRule) {
  // Counter-clockwise about +Z: a quarter turn from +X reaches +Y.
  const Move ccw = helix(kPi / 2, 0.0);
  EXPECT_TRUE(ccw.end.isApprox(Vec3(0, 5, 0), 1e-15) || (ccw.end - Vec3(0, 5, 0)).norm() < 1e-14);
  // About -Z (G2 in the XY plane): clockwise, reaching -Y.
  const Move cw = helix(kPi / 2, 0.0, -Vec3::UnitZ());
  EXPECT_LT((cw.end - Vec3(0, -5, 0)).norm(), 1e-14);
  EXPECT_NEAR(ccw.length(), 5 * kPi / 2, 1e-14);
}

TEST(Move, HelixLengthTurnsAndTangent) {
  const Move m = helix(2 * kTwoPi + kPi, 6.0);  // two extra turns and a half, rising 6 mm
  EXPECT_EQ(m.extra_turns(), 2);
  EXPECT_NEAR(m.length(), std::hypot(5 * (5 * kPi), 6.0), 1e-12);
  EXPECT_LT((m.end - Vec3(-5, 0, 6)).norm(), 1e-13);
  EXPECT_EQ(helix(kTwoPi, 0.0).extra_turns(), 0);  // one full circle
  EXPECT_EQ(helix(2 * kTwoPi, 0.0).extra_turns(), 1);
  // The tangent is the derivative of the position (central differences, error O(h²)).
  test::Random random(3);
  for (int k = 0; k < 50; ++k) {
    const double u = random.uniform(0.01, 0.99), h = 1e-6;
    const Vec3 numeric = (m.position(u + h) - m.position(u - h)) / (2 * h);
    EXPECT_LT((numeric - m.tangent(u)).norm(), 1e-6 * m.tangent(u).norm());
    // Constant speed along a helix.
    EXPECT_NEAR(m.tangent(u).norm(), m.length(), 1e-9);
  }
}

TEST(Move, BoundsAreTight) {
  const Aabb quarter = helix(kPi / 2, 0.0).bounds();
  EXPECT_LT((quarter.min - Vec3(0, 0, 0)).norm(), 1e-14);
  EXPECT_LT((quarter.max - Vec3(5, 5, 0)).norm(), 1e-14);
  const Aabb half = helix(kPi, 0.0, -Vec3::UnitZ()).bounds();  // clockwise through -Y
  EXPECT_LT((half.min - Vec3(-5, -5, 0)).norm(), 1e-14);
  EXPECT_LT((half.max - Vec3(5, 0, 0)).norm(), 1e-14);
  // A helix: every point inside, and the box exceeds the curve by at most r(1 - cos 1°).
  const Move h = helix(3 * kPi + 0.3, 4.0);
  const Aabb box = h.bounds();
  Aabb sampled;
  for (int k = 0; k <= 20000; ++k) {
    const Vec3 p = h.position(k / 20000.0);
    EXPECT_TRUE(box.contains(p));
    sampled.extend(p);
  }
  EXPECT_LT((box.max - sampled.max).maxCoeff(),
            5.0 * (1 - std::cos(degrees_to_radians(1.0))) + 1e-9);
  EXPECT_LT((sampled.min - box.min).maxCoeff(),
            5.0 * (1 - std::cos(degrees_to_radians(1.0))) + 1e-9);
}

TEST(Move, AxisSlerpAndRate) {
  Move m = line({0, 0, 0}, {10, 0, 0});
  m.start_axis = Vec3::UnitZ();
  m.end_axis = Vec3(1, 0, 0);
  EXPECT_NEAR(m.axis_angle(), kPi / 2, 1e-15);
  const Vec3 mid = m.axis(0.5);
  EXPECT_LT((mid - Vec3(std::sqrt(0.5), 0, std::sqrt(0.5))).norm(), 1e-15);
  // dn/du = ω_u × n, checked by central differences.
  for (double u : {0.1, 0.5, 0.9}) {
    const double h = 1e-6;
    const Vec3 numeric = (m.axis(u + h) - m.axis(u - h)) / (2 * h);
    EXPECT_LT((numeric - m.axis_rate(u).cross(m.axis(u))).norm(), 1e-8);
  }
  // Antipodal axes still interpolate to unit vectors.
  EXPECT_NEAR(slerp(Vec3::UnitZ(), -Vec3::UnitZ(), 0.5).norm(), 1.0, 1e-15);
}

Toolpath path_of(std::vector<Move> moves) {
  Toolpath p;
  p.sources = {"test"};
  p.moves = std::move(moves);
  return p;
}

// Property: samples reproduce move lengths and end points, and step spacing never exceeds the
// requested step.
TEST(ClSampling, ReproducesLengthsAndEndPoints) {
  Move rapid = line({0, 0, 10}, {0, 0, 1});
  rapid.mode = MotionMode::kRapid;
  const Move a = line({0, 0, 1}, {0, 0, -2}, 100);
  const Move b = line({0, 0, -2}, {12.3, 0, -2}, 600);
  Move c = helix(kTwoPi + 1.0, -1.0);
  c.start = b.end + Vec3(5, 0, 0);  // not connected: sampling does not care
  c.center = b.end;
  c.end = c.position(1.0);
  const Toolpath path = path_of({rapid, a, b, c});
  SamplingOptions options;
  options.step = 0.25;
  const auto points = sample_cl_points(path, options);
  ASSERT_FALSE(points.empty());
  EXPECT_EQ(points.front().move, 1);  // the rapid is skipped
  double total = 0.0;
  for (int m = 1; m < 4; ++m) {
    int count = 0;
    for (const auto& p : points) count += p.move == m;
    const double length = path.moves[m].length();
    EXPECT_EQ(count, static_cast<int>(std::ceil(length / options.step)));
    total += length;
  }
  // Consecutive samples of a move are one step of u apart: the chord never exceeds the step.
  for (std::size_t i = 1; i < points.size(); ++i) {
    if (points[i].move != points[i - 1].move) continue;
    EXPECT_LE((points[i].position - points[i - 1].position).norm(), options.step + 1e-12);
    EXPECT_GT(points[i].path_length, points[i - 1].path_length);
  }
  // The last sample plus its step lands on the end of its move.
  const auto& last = points.back();
  const double du = 1.0 / std::ceil(path.moves[3].length() / options.step);
  EXPECT_LT((path.moves[3].position(last.u + du) - path.moves[3].end).norm(), 1e-12);
  EXPECT_NEAR(last.path_length + du * path.moves[3].length(), total, 1e-9);
}

TEST(ClSampling, MoveByMoveCountedAndWholeAgree) {
  // A rapid, a line, a helix, a zero-length move and a 5-axis turn: the sampler's moves, the
  // count and the whole list are one sampling.
  Move turn = line({5, 0, 0}, {6, 0, 0}, 360.0);
  turn.end_axis = Vec3(0, 1, 1).normalized();
  Move rapid = line({0, 0, 5}, {0, 0, 0});
  rapid.mode = MotionMode::kRapid;
  const Toolpath path = path_of({rapid, line({0, 0, 0}, {3.3, 0, 0}), helix(kPi, 2.0),
                                 line({1, 1, 1}, {1, 1, 1}), turn});
  SamplingOptions options;
  options.step = 0.3;
  const std::vector<ClPoint> whole = sample_cl_points(path, options);
  EXPECT_EQ(count_cl_points(path, options), whole.size());
  ClSampler sampler(options);
  std::vector<ClPoint> one;
  std::size_t k = 0;
  for (std::size_t m = 0; m < path.moves.size(); ++m) {
    sampler.next(path.moves[m], static_cast<int>(m), one);
    EXPECT_EQ(one.size(), static_cast<std::size_t>(sampler.steps(path.moves[m])));
    for (const ClPoint& p : one) {
      ASSERT_LT(k, whole.size());
      EXPECT_EQ(p.position, whole[k].position);
      EXPECT_EQ(p.path_length, whole[k].path_length);
      EXPECT_EQ(p.move, whole[k].move);
      ++k;
    }
  }
  EXPECT_EQ(k, whole.size());
  EXPECT_EQ(sampler.steps(path.moves[0]), 0);  // the rapid
  EXPECT_EQ(sampler.steps(path.moves[3]), 0);  // no motion
  EXPECT_EQ(sampler.steps(path.moves[1]), 11);  // ⌈3.3 / 0.3⌉
}

// A move that would get more CL points than one move may hold (a typo: X999999999, a CL step of
// 1e-9) is an error at its file and line before any is made, never an int overflow.
TEST(ClSampling, TooManyPointsInOneMoveIsALocatedError) {
  Toolpath path;
  path.sources = {"p.ngc"};
  Move m;
  m.end = Vec3(1e9, 0, 0);
  m.feed_rate = 100;
  m.line = 7;
  path.moves.push_back(m);
  try {
    count_cl_points(path, SamplingOptions{});
    ADD_FAILURE() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.location().source, "p.ngc");
    EXPECT_EQ(e.location().line, 7);
    EXPECT_NE(e.message().find("2e+09 cutter locations"), std::string::npos) << e.what();
  }
  // At the limit it is counted: 1e6 steps of 1 mm.
  path.moves[0].end = Vec3(1e6, 0, 0);
  SamplingOptions one_mm;
  one_mm.step = 1.0;
  EXPECT_EQ(count_cl_points(path, one_mm), 1000000u);
}

TEST(ClSampling, VelocitiesFromTheFeedRate) {
  const Toolpath path = path_of({line({0, 0, 0}, {10, 0, 0}, 600)});  // 10 mm/s along +X
  const auto points = sample_cl_points(path);
  ASSERT_EQ(points.size(), 20u);
  EXPECT_TRUE(points[3].velocity.isApprox(Vec3(10, 0, 0)));
  EXPECT_TRUE(points[3].feed_direction.isApprox(Vec3::UnitX()));
  EXPECT_TRUE(points[3].angular_velocity.isZero());
  // A helix at 600 mm/min: speed 10 mm/s along the tangent.
  const Toolpath h = path_of({helix(kPi, 2.0)});
  for (const auto& p : sample_cl_points(h)) EXPECT_NEAR(p.velocity.norm(), 10.0, 1e-9);
}

TEST(ClSampling, FiveAxisAngularStepAndPureRotation) {
  Move turn = line({0, 0, 0}, {0, 0, 0}, 360.0);  // re-orientation only, 360 deg/min
  turn.end_axis = Vec3(0, 1, 0);
  const Toolpath path = path_of({turn});
  SamplingOptions options;
  options.angular_step = degrees_to_radians(2.0);
  const auto points = sample_cl_points(path, options);
  ASSERT_EQ(points.size(), 45u);  // 90° in 2° steps
  EXPECT_TRUE(points[0].feed_direction.isZero());
  // 360 deg/min = 6 deg/s about the axis k = z × y = -x.
  EXPECT_LT((points[10].angular_velocity - Vec3(-degrees_to_radians(6.0), 0, 0)).norm(), 1e-12);
}

TEST(ClSampling, DegenerateMovesAndBadSteps) {
  const Toolpath path = path_of({line({1, 1, 1}, {1, 1, 1})});
  EXPECT_TRUE(sample_cl_points(path).empty());
  SamplingOptions bad;
  bad.step = 0.0;
  EXPECT_THROW(sample_cl_points(path, bad), InputError);
  bad.step = 0.5;
  bad.angular_step = -1.0;
  EXPECT_THROW(sample_cl_points(path, bad), InputError);
  EXPECT_DOUBLE_EQ(default_cl_step(6.0), 0.3);
  EXPECT_DOUBLE_EQ(default_cl_step(20.0), 0.5);
}

}  // namespace
}  // namespace cwe

namespace cwe {
namespace {

// A part of a move is the same motion over a sub-range of u: positions and axes agree at every
// parameter, for lines with a turning axis and for helices.
TEST(Move, PartFollowsTheMove) {
  Move line;
  line.start = {1, 2, 3};
  line.end = {11, -4, 0};
  line.start_axis = Vec3::UnitZ();
  line.end_axis = Vec3(0.3, 0.2, 1).normalized();
  Move helix;
  helix.shape = MoveShape::kArc;
  helix.start = {8, 0, 5};
  helix.center = {5, 0, 5};
  helix.normal = -Vec3::UnitZ();
  helix.sweep = 2.5 * kPi;
  helix.axial = 3.0;
  helix.end = helix.position(1.0);
  for (const Move& move : {line, helix}) {
    const double u0 = 0.3, u1 = 0.75;
    const Move part = move.part(u0, u1);
    EXPECT_EQ(part.shape, move.shape);
    for (int k = 0; k <= 10; ++k) {
      const double v = k / 10.0, u = u0 + v * (u1 - u0);
      EXPECT_LT((part.position(v) - move.position(u)).norm(), 1e-12) << v;
      EXPECT_LT((part.axis(v) - move.axis(u)).norm(), 1e-12) << v;
    }
    EXPECT_NEAR(part.length(), (u1 - u0) * move.length(), 1e-12);
  }
}

}  // namespace
}  // namespace cwe

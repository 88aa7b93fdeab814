// Tests of the small value types: Interval (and normalize), Aabb, Frame::from_z, Ray.
#include <cmath>
#include <limits>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "cwe/core/assert.hpp"
#include "cwe/geometry/aabb.hpp"
#include "cwe/geometry/interval.hpp"
#include "cwe/geometry/ray.hpp"
#include "cwe/geometry/vec.hpp"
#include "random.hpp"

namespace cwe {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

TEST(Interval, EmptyFullPoint) {
  EXPECT_TRUE(Interval::empty().is_empty());
  EXPECT_FALSE(Interval::full().is_empty());
  EXPECT_FALSE(Interval::point(2.0).is_empty());  // a tangent contact is not empty
  EXPECT_EQ(Interval::point(2.0).length(), 0.0);
  EXPECT_EQ(Interval::empty().length(), 0.0);
  EXPECT_TRUE(Interval::full().contains(1e300));
  EXPECT_FALSE(Interval::empty().contains(0.0));
  EXPECT_TRUE((Interval{1.0, 2.0}).contains(1.0));  // closed
  EXPECT_TRUE((Interval{1.0, 2.0}).contains(2.0));
}

TEST(Interval, IntersectAndHull) {
  EXPECT_EQ(intersect(Interval{0, 2}, Interval{1, 3}), (Interval{1, 2}));
  EXPECT_EQ(intersect(Interval{0, 1}, Interval{1, 3}), Interval::point(1));  // touching
  EXPECT_TRUE(intersect(Interval{0, 1}, Interval{2, 3}).is_empty());
  EXPECT_EQ(intersect(Interval{0, 1}, Interval{2, 3}), Interval::empty());  // canonical empty
  EXPECT_EQ(intersect(Interval::full(), Interval{2, 3}), (Interval{2, 3}));
  EXPECT_TRUE(intersect(Interval::empty(), Interval::full()).is_empty());
  EXPECT_EQ(hull(Interval{0, 1}, Interval{2, 3}), (Interval{0, 3}));
  EXPECT_EQ(hull(Interval::empty(), Interval{2, 3}), (Interval{2, 3}));
  EXPECT_EQ(hull(Interval{2, 3}, Interval::empty()), (Interval{2, 3}));
  EXPECT_TRUE(hull(Interval::empty(), Interval::empty()).is_empty());
  EXPECT_EQ(clip_to_segment(Interval{-1, 0.5}), (Interval{0, 0.5}));
  EXPECT_TRUE(clip_to_segment(Interval{1.5, 2}).is_empty());
}

TEST(Interval, NormalizeCases) {
  EXPECT_TRUE(normalize({}).empty());
  EXPECT_TRUE(normalize({Interval::empty(), Interval::empty()}).empty());
  const std::vector<Interval> merged =
      normalize({{5, 6}, Interval::empty(), {0, 1}, {0.5, 2}, {2, 3}, {3.5, 4}});
  // [0,1] ∪ [0.5,2] ∪ [2,3] touch (closed): one interval; [3.5, 4] and [5, 6] stay apart.
  EXPECT_EQ(merged, (std::vector<Interval>{{0, 3}, {3.5, 4}, {5, 6}}));
  // With a gap allowance of 0.5 the first two join, the third (gap 1) stays apart.
  EXPECT_EQ(normalize({{0, 1}, {1.5, 2}, {3, 4}}, 0.5), (std::vector<Interval>{{0, 2}, {3, 4}}));
  // Infinite ends and contained intervals.
  EXPECT_EQ(normalize({{-kInfinity, 0}, {-5, -4}, {1, kInfinity}, {2, 3}}),
            (std::vector<Interval>{{-kInfinity, 0}, {1, kInfinity}}));
  EXPECT_EQ(normalize({Interval::full(), {1, 2}}), (std::vector<Interval>{Interval::full()}));
  // Degenerate intervals survive and merge with neighbours they touch.
  EXPECT_EQ(normalize({Interval::point(1), Interval::point(1), {1, 2}, Interval::point(5)}),
            (std::vector<Interval>{{1, 2}, Interval::point(5)}));
}

TEST(Interval, NormalizeRandomAgainstMembership) {
  // Oracle: a point is in the union before iff it is in exactly one interval after, and the
  // result is sorted and separated by more than the gap.
  test::Random rng(61);
  for (int trial = 0; trial < 500; ++trial) {
    std::vector<Interval> intervals;
    const int count = rng.integer(0, 8);
    for (int i = 0; i < count; ++i) {
      const double a = rng.uniform(0.0, 10.0);
      const double b = a + rng.uniform(-1.0, 2.0);  // some empty (b < a)
      intervals.push_back({a, b});
    }
    const std::vector<Interval> result = normalize(intervals);
    for (std::size_t i = 0; i < result.size(); ++i) {
      EXPECT_FALSE(result[i].is_empty());
      if (i > 0) {
        EXPECT_LT(result[i - 1].hi, result[i].lo);
      }
    }
    for (int k = 0; k <= 1300; ++k) {
      const double t = -1.0 + k * 0.01;
      bool before = false;
      for (const Interval& interval : intervals) before = before || interval.contains(t);
      int after = 0;
      for (const Interval& interval : result) after += interval.contains(t) ? 1 : 0;
      EXPECT_EQ(after, before ? 1 : 0) << "t = " << t;
    }
  }
}

TEST(Aabb, Basics) {
  Aabb box;
  EXPECT_TRUE(box.is_empty());
  EXPECT_EQ(box.size(), Vec3::Zero());
  EXPECT_EQ(box.volume(), 0.0);
  EXPECT_FALSE(box.contains(Vec3::Zero()));
  box.inflate(1.0);  // no-op on an empty box
  EXPECT_TRUE(box.is_empty());
  box.extend(Vec3(1, 2, 3));
  EXPECT_FALSE(box.is_empty());  // a single point is a degenerate, non-empty box
  EXPECT_EQ(box.min, Vec3(1, 2, 3));
  EXPECT_EQ(box.max, Vec3(1, 2, 3));
  box.extend(Vec3(-1, 4, 0));
  EXPECT_EQ(box.min, Vec3(-1, 2, 0));
  EXPECT_EQ(box.max, Vec3(1, 4, 3));
  EXPECT_EQ(box.size(), Vec3(2, 2, 3));
  EXPECT_EQ(box.center(), Vec3(0, 3, 1.5));
  EXPECT_EQ(box.volume(), 12.0);
  EXPECT_TRUE(box.contains(Vec3(1, 4, 3)));  // closed
  EXPECT_FALSE(box.contains(Vec3(1.5, 3, 1)));
  box.inflate(0.5);
  EXPECT_EQ(box.min, Vec3(-1.5, 1.5, -0.5));
  EXPECT_EQ(box.max, Vec3(1.5, 4.5, 3.5));
  Aabb other = Aabb::from_corners(Vec3(3, 0, 0), Vec3(1.5, 1.5, 1));
  EXPECT_EQ(other.min, Vec3(1.5, 0, 0));
  EXPECT_EQ(other.max, Vec3(3, 1.5, 1));
  EXPECT_TRUE(box.intersects(other));  // touching at x = 1.5, y = 1.5
  EXPECT_TRUE(other.intersects(box));
  other = Aabb::from_corners(Vec3(3, 0, 0), Vec3(1.6, 1.5, 1));
  EXPECT_FALSE(box.intersects(other));
  EXPECT_FALSE(box.intersects(Aabb{}));
  Aabb combined;
  combined.extend(Aabb{});  // extending by an empty box keeps it empty
  EXPECT_TRUE(combined.is_empty());
  combined.extend(box);
  combined.extend(other);
  EXPECT_EQ(combined.min, Vec3(-1.5, 0, -0.5));
  EXPECT_EQ(combined.max, Vec3(3, 4.5, 3.5));
}

void expect_orthonormal_right_handed(const Frame& frame) {
  // Orthonormal to a few ulps: the construction normalises twice (≤ ~10 u per entry).
  const Mat3 gram = frame.axes.transpose() * frame.axes;
  EXPECT_LE((gram - Mat3::Identity()).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_NEAR(frame.axes.determinant(), 1.0, 1e-15);
  EXPECT_LE((frame.x().cross(frame.y()) - frame.z()).norm(), 1e-15);
}

TEST(Frame, FromZ) {
  test::Random rng(62);
  for (int trial = 0; trial < 1000; ++trial) {
    const Vec3 origin = rng.point_in_box(10.0);
    const Vec3 z = rng.unit_vector() * rng.uniform(0.01, 100.0);
    const Vec3 hint = rng.unit_vector() * rng.uniform(0.01, 100.0);
    const Frame frame = Frame::from_z(origin, z, hint);
    expect_orthonormal_right_handed(frame);
    EXPECT_LE((frame.z() - z.normalized()).norm(), 1e-15);
    // x is the hint's direction perpendicular to z (away from the parallel fallback).
    const Vec3 perpendicular = hint - hint.dot(z.normalized()) * z.normalized();
    if (perpendicular.norm() > 1e-3 * hint.norm()) {
      // The projection's direction is exact to rounding over sin(angle) ≥ 1e-3: 1e-12.
      EXPECT_LE((frame.x() - perpendicular.normalized()).norm(), 1e-12);
    }
    // Points and directions round-trip.
    const Vec3 p = rng.point_in_box(10.0);
    EXPECT_LE((frame.to_world(frame.to_local(p)) - p).norm(), 1e-13);
    EXPECT_LE((frame.direction_to_world(frame.direction_to_local(p)) - p).norm(), 1e-13);
    EXPECT_NEAR(frame.to_local(origin + z).z(), z.norm(), 1e-12 * z.norm());
  }
}

TEST(Frame, FromZFallbacks) {
  // Hint parallel to z: world X projected.
  Frame frame = Frame::from_z(Vec3::Zero(), Vec3(0, 1, 1), Vec3(0, 2, 2));
  expect_orthonormal_right_handed(frame);
  EXPECT_LE((frame.x() - Vec3::UnitX()).norm(), 1e-15);
  // Zero hint: the same fallback.
  frame = Frame::from_z(Vec3::Zero(), Vec3(0, 0, 3), Vec3::Zero());
  expect_orthonormal_right_handed(frame);
  EXPECT_EQ(frame.x(), Vec3::UnitX());
  EXPECT_EQ(frame.y(), Vec3::UnitY());
  // Hint and world X both parallel to z: world Y.
  frame = Frame::from_z(Vec3::Zero(), Vec3(-2, 0, 0), Vec3(1, 0, 0));
  expect_orthonormal_right_handed(frame);
  EXPECT_EQ(frame.x(), Vec3::UnitY());
  EXPECT_EQ(frame.z(), -Vec3::UnitX());
  // Hint within tol::kAngle (1e-9) of z counts as parallel; 1e-6 away it does not, and still
  // gives an orthonormal frame despite the cancellation in the projection.
  frame = Frame::from_z(Vec3::Zero(), Vec3::UnitZ(), Vec3(0, 1e-10, 1));
  EXPECT_EQ(frame.x(), Vec3::UnitX());
  frame = Frame::from_z(Vec3::Zero(), Vec3::UnitZ(), Vec3(0, 1e-6, 1));
  expect_orthonormal_right_handed(frame);
  EXPECT_LE((frame.x() - Vec3::UnitY()).norm(), 1e-9);
#if defined(CWE_ENABLE_ASSERTS) && CWE_ENABLE_ASSERTS
  // A zero z axis is a caller bug.
  EXPECT_THROW(Frame::from_z(Vec3::Zero(), Vec3::Zero(), Vec3::UnitX()), InternalError);
#endif
}

TEST(Ray, SegmentAndAt) {
  const Ray segment = Ray::segment(Vec3(1, 2, 3), Vec3(3, 2, 1));
  EXPECT_EQ(segment.at(0.0), Vec3(1, 2, 3));
  EXPECT_EQ(segment.at(1.0), Vec3(3, 2, 1));
  EXPECT_EQ(segment.at(0.5), Vec3(2, 2, 2));
  EXPECT_EQ(degrees_to_radians(180.0), kPi);
  EXPECT_EQ(radians_to_degrees(kPi), 180.0);
}

}  // namespace
}  // namespace cwe

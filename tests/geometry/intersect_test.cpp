// Tests of ray ∩ primitive (intersect.hpp). Each solid is checked against a brute-force oracle:
// dense point sampling of contains() along random rays. End points are checked against the
// implicit equation, and the degenerate cases of the header are pinned one by one.
#include "cwe/geometry/intersect.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "random.hpp"

namespace cwe {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// Samples per ray in the sampling oracle: spacing = 3·(bounding radius) / 2000 ≤ 0.009, well
// below every feature of the random solids (radii ≥ 0.1, tubes ≥ 0.2 thick: 20+ samples across).
constexpr int kSamplesPerRay = 2000;

// Samples closer than this (relative to the solid's size, as a distance along the ray) to an
// interval end are not compared: contains() and the interval may disagree there by rounding.
// End points are accurate to far better (~1e3 u·size, ~1e-13) except on near-tangent rays,
// where they move by up to √(rounding)·size ≈ 1e-8·size and where chords below ~2e-7·size may
// be reported as a point (kGeometricRounding); 1e-6 covers both with margin.
constexpr double kEndExclusion = 1e-6;

std::vector<Interval> as_vector(const Interval& interval) {
  if (interval.is_empty()) return {};
  return {interval};
}

std::vector<Interval> as_vector(const IntervalPair& pair) { return {pair.begin(), pair.end()}; }

std::string describe(const Ray& ray) {
  return "ray origin (" + std::to_string(ray.origin.x()) + ", " + std::to_string(ray.origin.y()) +
         ", " + std::to_string(ray.origin.z()) + ") direction (" +
         std::to_string(ray.direction.x()) + ", " + std::to_string(ray.direction.y()) + ", " +
         std::to_string(ray.direction.z()) + ")";
}

// Intervals are non-empty, sorted and disjoint.
void expect_well_formed(const std::vector<Interval>& intervals) {
  for (std::size_t i = 0; i < intervals.size(); ++i) {
    EXPECT_FALSE(intervals[i].is_empty());
    if (i > 0) {
      EXPECT_LT(intervals[i - 1].hi, intervals[i].lo);
    }
  }
}

// The oracle: along the ray, samples inside an interval are in the solid and samples outside all
// intervals are not, except within `exclusion` (a ray parameter) of an end.
template <typename Inside>
int count_sampling_mismatches(const Ray& ray, const std::vector<Interval>& intervals,
                              Inside&& inside, double t_lo, double t_hi, double exclusion) {
  int mismatches = 0;
  const double step = (t_hi - t_lo) / kSamplesPerRay;
  for (int k = 0; k <= kSamplesPerRay; ++k) {
    const double t = t_lo + k * step;
    bool in_interval = false;
    bool near_end = false;
    for (const Interval& interval : intervals) {
      in_interval = in_interval || interval.contains(t);
      near_end = near_end || std::abs(t - interval.lo) <= exclusion ||
                 std::abs(t - interval.hi) <= exclusion;
    }
    if (near_end) continue;
    if (in_interval != inside(ray.at(t))) {
      if (mismatches < 3) {
        ADD_FAILURE() << describe(ray) << ": at t = " << t << " interval says " << in_interval
                      << ", contains() says " << !in_interval;
      }
      ++mismatches;
    }
  }
  return mismatches;
}

// Ray parameters covering a ball of `radius` about `center` (with margin).
Interval parameter_range(const Ray& ray, const Vec3& center, double radius) {
  const double length = ray.direction.norm();
  const double closest = -(ray.origin - center).dot(ray.direction) / (length * length);
  const double half = 1.5 * radius / length;
  return {closest - half, closest + half};
}

// A random ray that mostly passes through a box of `spread` about `center`, starting up to
// `distance` away, with a direction of random length in [0.1, 10] (the parameters t must not
// assume a unit direction).
Ray random_ray(test::Random& rng, const Vec3& center, double spread, double distance) {
  const Vec3 origin = center + rng.unit_vector() * rng.uniform(0.0, distance);
  Vec3 direction = center + rng.point_in_box(spread) - origin;
  if (direction.norm() < 1e-3) direction = rng.unit_vector();
  return {origin, direction.normalized() * rng.uniform(0.1, 10.0)};
}

// Any unit vector perpendicular to the unit vector n.
Vec3 random_perpendicular(test::Random& rng, const Vec3& n) {
  Vec3 v;
  do {
    v = rng.unit_vector();
    v -= v.dot(n) * n;
  } while (v.norm() < 0.1);
  return v.normalized();
}

// --- Half-space, plane, disc.

TEST(IntersectPlane, HalfspaceCases) {
  const Plane plane{Vec3(0, 0, 1), Vec3::UnitZ()};
  // Crossing downward: inside from the crossing on; upward: inside up to it.
  EXPECT_EQ(intersect(Ray{Vec3(0, 0, 3), Vec3(0, 0, -4)}, plane), (Interval{0.5, kInfinity}));
  EXPECT_EQ(intersect(Ray{Vec3(0, 0, 3), Vec3(0, 0, 4)}, plane), (Interval{-kInfinity, -0.5}));
  // Parallel: in or out as a whole.
  EXPECT_EQ(intersect(Ray{Vec3(0, 0, 0), Vec3(1, 2, 0)}, plane), Interval::full());
  EXPECT_TRUE(intersect(Ray{Vec3(0, 0, 2), Vec3(1, 2, 0)}, plane).is_empty());
  // On the boundary plane: closed, so inside.
  EXPECT_EQ(intersect(Ray{Vec3(5, 0, 1), Vec3(1, 0, 0)}, plane), Interval::full());
  // Zero direction: by the origin.
  EXPECT_EQ(intersect(Ray{Vec3(0, 0, -1), Vec3::Zero()}, plane), Interval::full());
  EXPECT_TRUE(intersect(Ray{Vec3(0, 0, 2), Vec3::Zero()}, plane).is_empty());
  // Nearly parallel: the crossing -1/1e-320 overflows; the whole line is on the origin's side.
  EXPECT_TRUE(intersect(Ray{Vec3(0, 0, 2), Vec3(1, 0, 1e-320)}, plane).is_empty());
  EXPECT_EQ(intersect(Ray{Vec3(0, 0, 0), Vec3(1, 0, -1e-320)}, plane), Interval::full());
}

TEST(IntersectPlane, HalfspaceRandomAgainstSampling) {
  test::Random rng(21);
  for (int trial = 0; trial < 300; ++trial) {
    const Plane plane{rng.point_in_box(5.0), rng.unit_vector()};
    const Ray ray = random_ray(rng, plane.point, 2.0, 8.0);
    const Interval interval = intersect(ray, plane);
    const Interval range = parameter_range(ray, plane.point, 10.0);
    const double exclusion = kEndExclusion * 10.0 / ray.direction.norm();
    EXPECT_EQ(count_sampling_mismatches(
                  ray, as_vector(interval),
                  [&](const Vec3& p) { return implicit_value(plane, p) <= 0.0; }, range.lo,
                  range.hi, exclusion),
              0);
    for (const double end : {interval.lo, interval.hi}) {
      // The crossing is on the plane to the rounding of the coordinates (≤ 20, so ~1e3 u·20).
      if (std::isfinite(end)) {
        EXPECT_NEAR(implicit_value(plane, ray.at(end)), 0.0, 1e-11);
      }
    }
  }
}

TEST(IntersectPlane, SurfaceCases) {
  const Plane plane{Vec3(0, 0, 1), Vec3::UnitZ()};
  EXPECT_EQ(intersect_surface(Ray{Vec3(0, 0, 3), Vec3(0, 0, -4)}, plane), Interval::point(0.5));
  // In the plane (within kLength = 1e-6), and parallel: the whole line.
  EXPECT_EQ(intersect_surface(Ray{Vec3(0, 0, 1), Vec3(1, 1, 0)}, plane), Interval::full());
  EXPECT_EQ(intersect_surface(Ray{Vec3(0, 0, 1 + 0.5e-6), Vec3(1, 1, 0)}, plane), Interval::full());
  EXPECT_TRUE(intersect_surface(Ray{Vec3(0, 0, 1 + 2e-6), Vec3(1, 1, 0)}, plane).is_empty());
  EXPECT_TRUE(intersect_surface(Ray{Vec3(0, 0, 3), Vec3(1, 1, 0)}, plane).is_empty());
  // Zero direction: on the plane or not.
  EXPECT_EQ(intersect_surface(Ray{Vec3(4, 0, 1), Vec3::Zero()}, plane), Interval::full());
  EXPECT_TRUE(intersect_surface(Ray{Vec3(4, 0, 2), Vec3::Zero()}, plane).is_empty());
}

TEST(IntersectDisc, Cases) {
  const Disc disc{Vec3(1, 0, 0), Vec3::UnitZ(), 2.0};
  // Crossing inside the radius, outside it, and exactly on the rim (closed).
  EXPECT_EQ(intersect(Ray{Vec3(1, 1, 2), Vec3(0, 0, -1)}, disc), Interval::point(2.0));
  EXPECT_TRUE(intersect(Ray{Vec3(1, 3, 2), Vec3(0, 0, -1)}, disc).is_empty());
  EXPECT_EQ(intersect(Ray{Vec3(3, 0, 2), Vec3(0, 0, -2)}, disc), Interval::point(1.0));
  // Parallel, off the plane.
  EXPECT_TRUE(intersect(Ray{Vec3(1, 0, 1), Vec3(1, 0, 0)}, disc).is_empty());
  // Coplanar: the chord of the disc. Through the centre along x with |d| = 2: x from -1 to 3.
  Interval chord = intersect(Ray{Vec3(-5, 0, 0), Vec3(2, 0, 0)}, disc);
  EXPECT_NEAR(chord.lo, 2.0, 1e-14);
  EXPECT_NEAR(chord.hi, 4.0, 1e-14);
  // Coplanar, tangent to the rim (y = 2): [t, t] at x = 1.
  chord = intersect(Ray{Vec3(-5, 2, 0), Vec3(1, 0, 0)}, disc);
  EXPECT_EQ(chord.lo, chord.hi);
  EXPECT_NEAR(chord.lo, 6.0, 1e-14);
  // Coplanar, missing the disc.
  EXPECT_TRUE(intersect(Ray{Vec3(-5, 2.5, 0), Vec3(1, 0, 0)}, disc).is_empty());
  // Coplanar within kLength, tilted by less than kAngle: still the chord.
  chord = intersect(Ray{Vec3(-5, 0, 0.5e-6), Vec3(1, 0, 1e-10)}, disc);
  EXPECT_NEAR(chord.lo, 4.0, 1e-9);
  EXPECT_NEAR(chord.hi, 8.0, 1e-9);
  // Zero direction: on the disc or not.
  EXPECT_EQ(intersect(Ray{Vec3(2, 1, 0), Vec3::Zero()}, disc), Interval::full());
  EXPECT_TRUE(intersect(Ray{Vec3(4, 1, 0), Vec3::Zero()}, disc).is_empty());
  EXPECT_TRUE(intersect(Ray{Vec3(2, 1, 1), Vec3::Zero()}, disc).is_empty());
}

TEST(IntersectDisc, RandomCrossings) {
  test::Random rng(22);
  for (int trial = 0; trial < 1000; ++trial) {
    const Disc disc{rng.point_in_box(5.0), rng.unit_vector(), rng.uniform(0.1, 3.0)};
    const Ray ray = random_ray(rng, disc.center, disc.radius, 8.0);
    const Interval hit = intersect(ray, disc);
    // Independent oracle: the crossing with the plane, then the radius test, skipping rims
    // (within 1e-9 relative, where rounding may decide either way).
    const double rate = ray.direction.dot(disc.normal);
    if (std::abs(rate) < 1e-3) continue;  // near-parallel rays are the Cases test's business
    const double t = -(ray.origin - disc.center).dot(disc.normal) / rate;
    const double distance = (ray.at(t) - disc.center).norm();
    if (std::abs(distance - disc.radius) <= 1e-9 * disc.radius) continue;
    if (distance < disc.radius) {
      ASSERT_FALSE(hit.is_empty());
      EXPECT_EQ(hit.lo, hit.hi);
      // Same formula up to rounding: ~1e3 u of the parameter's size.
      EXPECT_NEAR(hit.lo, t, 1e-12 * (1.0 + std::abs(t)));
    } else {
      EXPECT_TRUE(hit.is_empty());
    }
  }
}

// --- Sphere.

// Random spheres with centres in a box of half-size `placement`, rays starting up to
// `distance` (plus a few radii) away.
void check_sphere_against_sampling(test::Random& rng, int trials, double placement,
                                   double distance) {
  for (int trial = 0; trial < trials; ++trial) {
    const Sphere sphere{rng.point_in_box(placement), rng.uniform(0.1, 3.0)};
    const Ray ray =
        random_ray(rng, sphere.center, sphere.radius * 1.2, distance + 4.0 * sphere.radius);
    const Interval interval = intersect(ray, sphere);
    const Interval range = parameter_range(ray, sphere.center, sphere.radius);
    const double exclusion = kEndExclusion * sphere.radius / ray.direction.norm();
    ASSERT_EQ(count_sampling_mismatches(
                  ray, as_vector(interval), [&](const Vec3& p) { return contains(sphere, p); },
                  range.lo, range.hi, exclusion),
              0);
    // End points on the sphere: the end point carries ~1e3 u·size of rounding (size: the
    // coordinates it was computed from) and |p - c|² - r² has gradient 2r there, so
    // |implicit| ≲ 2e-13·r·size; 1e-12·r·size leaves margin. (A chord collapsed to [t, t] as
    // tangent is deeper by at most kGeometricRounding·2r·size ≈ 1.4e-14·r·size.)
    const double size = sphere.radius + sphere.center.norm() + ray.origin.norm();
    for (const Interval& part : as_vector(interval)) {
      for (const double end : {part.lo, part.hi}) {
        EXPECT_NEAR(implicit_value(sphere, ray.at(end)), 0.0, 1e-12 * sphere.radius * size)
            << describe(ray);
      }
    }
  }
}

TEST(IntersectSphere, RandomRaysAgainstSampling) {
  test::Random rng(31);
  check_sphere_against_sampling(rng, 800, 5.0, 0.0);
}

TEST(IntersectSphere, RandomRaysAtModelScale) {
  // Coordinates up to kModelScale (1 m): the rounding of the input grows, the tests scale with it.
  test::Random rng(33);
  check_sphere_against_sampling(rng, 200, 1000.0, 1000.0);
}

TEST(IntersectSphere, Cases) {
  const Sphere sphere{Vec3(1, 2, 3), 2.0};
  // Through the centre, |d| = 2: the chord [−1, 1] around t = 2.
  Interval chord = intersect(Ray{Vec3(1, 2, -1), Vec3(0, 0, 2)}, sphere);
  EXPECT_NEAR(chord.lo, 1.0, 1e-15);
  EXPECT_NEAR(chord.hi, 3.0, 1e-15);
  // Origin inside: the interval contains 0.
  chord = intersect(Ray{Vec3(1.5, 2, 3), Vec3(1, 0, 0)}, sphere);
  EXPECT_TRUE(chord.contains(0.0));
  EXPECT_NEAR(chord.lo, -2.5, 1e-15);
  EXPECT_NEAR(chord.hi, 1.5, 1e-15);
  // Tangent: [t, t].
  chord = intersect(Ray{Vec3(3, 2, -4), Vec3(0, 0, 1)}, sphere);
  EXPECT_EQ(chord.lo, chord.hi);
  EXPECT_NEAR(chord.lo, 7.0, 1e-14);
  // Miss.
  EXPECT_TRUE(intersect(Ray{Vec3(3.001, 2, -4), Vec3(0, 0, 1)}, sphere).is_empty());
  // Zero direction.
  EXPECT_EQ(intersect(Ray{Vec3(1, 2, 4), Vec3::Zero()}, sphere), Interval::full());
  EXPECT_TRUE(intersect(Ray{Vec3(1, 2, 6), Vec3::Zero()}, sphere).is_empty());
  // Zero radius: the centre point alone.
  chord = intersect(Ray{Vec3(1, 2, 0), Vec3(0, 0, 1)}, Sphere{Vec3(1, 2, 3), 0.0});
  EXPECT_EQ(chord, Interval::point(3.0));
}

TEST(IntersectSphere, RandomTangentRays) {
  test::Random rng(32);
  // Near the origin, and at model scale (coordinates ~1e3, whose rounding the allowances scale
  // with).
  for (const double placement : {0.0, 1000.0}) {
    for (int trial = 0; trial < 1000; ++trial) {
      const Sphere sphere{rng.point_in_box(5.0) + rng.point_in_box(placement),
                          rng.uniform(0.1, 3.0)};
      const Vec3 normal = rng.unit_vector();
      const Vec3 along = random_perpendicular(rng, normal);
      const double length = rng.uniform(0.1, 10.0);
      const double s = rng.uniform(-5.0, 5.0);  // distance from the origin to the contact
      const Vec3 contact = sphere.center + sphere.radius * normal;
      const Ray ray{contact - s * along, length * along};
      const Interval hit = intersect(ray, sphere);
      ASSERT_FALSE(hit.is_empty()) << describe(ray);
      EXPECT_EQ(hit.lo, hit.hi) << describe(ray);
      // The contact parameter s / length, to the rounding of the coordinates (≤ 15).
      EXPECT_NEAR(hit.lo, s / length, 1e-12 * (15.0 + 2.0 * placement) / length);
    }
  }
}

// --- Frustum (cylinder, cone, truncated cone).

Frustum random_frustum(test::Random& rng) {
  Frustum frustum;
  frustum.base = rng.point_in_box(5.0);
  frustum.axis = rng.unit_vector();
  frustum.height = rng.uniform(0.2, 3.0);
  const double r0 = rng.uniform(0.1, 2.0);
  const double r1 = rng.uniform(0.1, 2.0);
  switch (rng.integer(0, 3)) {
    case 0:  // cylinder
      frustum.radius0 = frustum.radius1 = r0;
      break;
    case 1:  // cone, apex at the base
      frustum.radius0 = 0.0;
      frustum.radius1 = r1;
      break;
    case 2:  // cone, apex at the top
      frustum.radius0 = r0;
      frustum.radius1 = 0.0;
      break;
    default:
      frustum.radius0 = r0;
      frustum.radius1 = r1;
  }
  return frustum;
}

// Random frustums placed in a box of half-size `placement`; rays start up to `distance` (plus
// a few sizes) away and aim at a random point near the solid, at the centre of the base (the
// apex of a cone), or at a point of the top rim.
void check_frustum_against_sampling(test::Random& rng, int trials, double placement,
                                    double distance) {
  for (int trial = 0; trial < trials; ++trial) {
    Frustum frustum = random_frustum(rng);
    frustum.base += rng.point_in_box(placement);
    const Vec3& n = frustum.axis;
    const Vec3 middle = frustum.base + 0.5 * frustum.height * n;
    const double bound =
        std::hypot(0.5 * frustum.height, std::max(frustum.radius0, frustum.radius1));
    Ray ray = random_ray(rng, middle, bound, distance + 4.0 * bound);
    const int aim = rng.integer(0, 3);
    if (aim == 2) {
      ray.direction = (frustum.base - ray.origin).normalized() * ray.direction.norm();
    } else if (aim == 3) {
      const Vec3 rim =
          frustum.base + frustum.height * n + frustum.radius1 * random_perpendicular(rng, n);
      ray.direction = (rim - ray.origin).normalized() * ray.direction.norm();
    }
    const Interval interval = intersect(ray, frustum);
    const Interval range = parameter_range(ray, middle, bound);
    const double exclusion = kEndExclusion * bound / ray.direction.norm();
    ASSERT_EQ(count_sampling_mismatches(
                  ray, as_vector(interval), [&](const Vec3& p) { return contains(frustum, p); },
                  range.lo, range.hi, exclusion),
              0)
        << "r0 " << frustum.radius0 << " r1 " << frustum.radius1 << " h " << frustum.height;
    // End points lie on an end face (height s = 0 or h) or on the side (implicit = 0). The end
    // point carries ~1e3 u·size of rounding; the side's implicit |radial|² - r(s)² has gradient
    // ≤ 2·r_max·(1 + slope): 1e-12 relative bounds both with margin.
    const double slope = std::abs(frustum.radius1 - frustum.radius0) / frustum.height;
    const double size = bound + frustum.base.norm() + ray.origin.norm();
    const double largest_radius = std::max(frustum.radius0, frustum.radius1);
    for (const double end : {interval.lo, interval.hi}) {
      if (interval.is_empty()) break;
      const Vec3 p = ray.at(end);
      const double s = (p - frustum.base).dot(n);
      const bool on_face =
          std::abs(s) <= 1e-12 * size || std::abs(s - frustum.height) <= 1e-12 * size;
      const bool on_side =
          std::abs(implicit_value(frustum, p)) <= 1e-12 * size * largest_radius * (1.0 + slope);
      EXPECT_TRUE(on_face || on_side) << describe(ray) << " end " << end << " s " << s
                                      << " implicit " << implicit_value(frustum, p);
    }
  }
}

TEST(IntersectFrustum, RandomRaysAgainstSampling) {
  test::Random rng(41);
  check_frustum_against_sampling(rng, 1000, 0.0, 0.0);
}

TEST(IntersectFrustum, RandomRaysAtModelScale) {
  test::Random rng(43);
  check_frustum_against_sampling(rng, 300, 1000.0, 1000.0);
}

TEST(IntersectFrustum, CylinderCases) {
  const Frustum cylinder{Vec3(0, 0, 1), Vec3::UnitZ(), 1.0, 1.0, 2.0};  // z in [1, 3]
  // Along the axis, inside: the height slab (|d| = 2, from z = 0).
  Interval hit = intersect(Ray{Vec3(0.5, 0, 0), Vec3(0, 0, 2)}, cylinder);
  EXPECT_NEAR(hit.lo, 0.5, 1e-15);
  EXPECT_NEAR(hit.hi, 1.5, 1e-15);
  // Against the axis direction.
  hit = intersect(Ray{Vec3(0, 0.5, 4), Vec3(0, 0, -1)}, cylinder);
  EXPECT_NEAR(hit.lo, 1.0, 1e-15);
  EXPECT_NEAR(hit.hi, 3.0, 1e-15);
  // Along the axis, outside the radius; exactly on the wall (closed: inside).
  EXPECT_TRUE(intersect(Ray{Vec3(1.5, 0, 0), Vec3(0, 0, 1)}, cylinder).is_empty());
  hit = intersect(Ray{Vec3(0, 1, 0), Vec3(0, 0, 1)}, cylinder);
  EXPECT_NEAR(hit.lo, 1.0, 1e-15);
  EXPECT_NEAR(hit.hi, 3.0, 1e-15);
  // Across the axis: the chord x in [-1, 1].
  hit = intersect(Ray{Vec3(-3, 0, 2), Vec3(1, 0, 0)}, cylinder);
  EXPECT_NEAR(hit.lo, 2.0, 1e-15);
  EXPECT_NEAR(hit.hi, 4.0, 1e-15);
  // Across, above or below the slab.
  EXPECT_TRUE(intersect(Ray{Vec3(-3, 0, 3.5), Vec3(1, 0, 0)}, cylinder).is_empty());
  // In the plane of an end face (closed: the face belongs to the solid).
  hit = intersect(Ray{Vec3(-3, 0, 3), Vec3(1, 0, 0)}, cylinder);
  EXPECT_NEAR(hit.lo, 2.0, 1e-15);
  EXPECT_NEAR(hit.hi, 4.0, 1e-15);
  // Tangent to the side, across the axis: [t, t].
  hit = intersect(Ray{Vec3(-3, 1, 2), Vec3(1, 0, 0)}, cylinder);
  EXPECT_EQ(hit.lo, hit.hi);
  EXPECT_NEAR(hit.lo, 3.0, 1e-14);
  // Oblique through both end faces.
  hit = intersect(Ray{Vec3(0, 0, 0), Vec3(0.1, 0, 1)}, cylinder);
  EXPECT_NEAR(hit.lo, 1.0, 1e-15);
  EXPECT_NEAR(hit.hi, 3.0, 1e-15);
  // Nearly parallel to the axis: 1e-8 rad (general branch, A ≈ 1e-16) and 1e-10 rad (below
  // kAngle: the parallel branch); both cross the whole slab.
  for (const double tilt : {1e-8, 1e-10}) {
    hit = intersect(Ray{Vec3(0.5, 0, 0), Vec3(tilt, 0, 1)}, cylinder);
    EXPECT_NEAR(hit.lo, 1.0, 1e-14) << tilt;
    EXPECT_NEAR(hit.hi, 3.0, 1e-14) << tilt;
  }
  // Tilted by 1e-8 rad, starting 1e-9 inside the wall: leaves through the side at t = 0.1. The
  // crossing is ill-conditioned (rounding of C ≈ 1e-16 over B ≈ 2e-8): good to ~1e-8.
  hit = intersect(Ray{Vec3(1 - 1e-9, 0, 1), Vec3(1e-8, 0, 1)}, cylinder);
  EXPECT_NEAR(hit.lo, 0.0, 1e-14);
  EXPECT_NEAR(hit.hi, 0.1, 1e-7);
  // Origin inside; zero direction in and out.
  EXPECT_TRUE(intersect(Ray{Vec3(0, 0, 2), Vec3(1, 1, 1)}, cylinder).contains(0.0));
  EXPECT_EQ(intersect(Ray{Vec3(0, 0, 2), Vec3::Zero()}, cylinder), Interval::full());
  EXPECT_TRUE(intersect(Ray{Vec3(0, 0, 4), Vec3::Zero()}, cylinder).is_empty());
}

TEST(IntersectFrustum, ConeCases) {
  // Apex at the origin, radius 1 at z = 1 (45°).
  const Frustum cone{Vec3::Zero(), Vec3::UnitZ(), 0.0, 1.0, 1.0};
  // Along the axis through the apex: the whole height.
  Interval hit = intersect(Ray{Vec3(0, 0, -1), Vec3(0, 0, 1)}, cone);
  EXPECT_NEAR(hit.lo, 1.0, 1e-15);
  EXPECT_NEAR(hit.hi, 2.0, 1e-15);
  // Starting on the apex.
  hit = intersect(Ray{Vec3::Zero(), Vec3(0, 0, 1)}, cone);
  EXPECT_NEAR(hit.lo, 0.0, 1e-15);
  EXPECT_NEAR(hit.hi, 1.0, 1e-15);
  // Parallel to the axis at distance 0.5: entered through the side at z = 0.5.
  hit = intersect(Ray{Vec3(0.5, 0, -1), Vec3(0, 0, 1)}, cone);
  EXPECT_NEAR(hit.lo, 1.5, 1e-14);
  EXPECT_NEAR(hit.hi, 2.0, 1e-15);
  // ... outside the largest radius: empty.
  EXPECT_TRUE(intersect(Ray{Vec3(1.5, 0, -1), Vec3(0, 0, 1)}, cone).is_empty());
  // Through the apex, across the axis: only the apex, [t, t].
  hit = intersect(Ray{Vec3(-2, 0, 0), Vec3(1, 0, 0)}, cone);
  EXPECT_EQ(hit.lo, hit.hi);
  EXPECT_NEAR(hit.lo, 2.0, 1e-7);  // a tangent point's position along the ray is √(rounding)
  // Through the apex, shallower than the cone (30° from horizontal): the apex only.
  hit = intersect(Ray{Vec3(-2, 0, -1), Vec3(2, 0, 1)}, cone);
  EXPECT_EQ(hit.lo, hit.hi);
  EXPECT_NEAR(hit.lo, 1.0, 1e-7);
  // Through the apex, steeper than the cone: from the apex to the top face.
  hit = intersect(Ray{Vec3(-0.5, 0, -1), Vec3(0.5, 0, 1)}, cone);
  EXPECT_NEAR(hit.lo, 1.0, 1e-12);
  EXPECT_NEAR(hit.hi, 2.0, 1e-15);
  // Along a generator (on the surface): the whole generator, apex to rim.
  hit = intersect(Ray{Vec3(-1, 0, -1), Vec3(1, 0, 1)}, cone);
  EXPECT_NEAR(hit.lo, 1.0, 1e-12);
  EXPECT_NEAR(hit.hi, 2.0, 1e-12);
  // Parallel to a generator, inside: enters through the side, leaves through the top.
  // Points (t - 0.5, 0, t): inside where |t - 0.5| ≤ t ≤ 1, i.e. t in [0.25, 1].
  hit = intersect(Ray{Vec3(-0.5, 0, 0), Vec3(1, 0, 1)}, cone);
  EXPECT_NEAR(hit.lo, 0.25, 1e-14);
  EXPECT_NEAR(hit.hi, 1.0, 1e-14);
  // The other nappe (below the apex) is not part of the solid.
  EXPECT_TRUE(intersect(Ray{Vec3(-3, 0, -0.5), Vec3(1, 0, 0)}, cone).is_empty());
  // Apex on top (radius0 > radius1 = 0), along the axis, and a zero-height frustum (a disc).
  const Frustum inverted{Vec3::Zero(), Vec3::UnitZ(), 2.0, 0.0, 2.0};
  hit = intersect(Ray{Vec3(1, 0, -1), Vec3(0, 0, 1)}, inverted);  // r(s) = 2 - s ≥ 1: s ≤ 1
  EXPECT_NEAR(hit.lo, 1.0, 1e-15);
  EXPECT_NEAR(hit.hi, 2.0, 1e-14);
  const Frustum flat{Vec3::Zero(), Vec3::UnitZ(), 1.0, 2.0, 0.0};
  EXPECT_EQ(intersect(Ray{Vec3(1.5, 0, 1), Vec3(0, 0, -1)}, flat), Interval::point(1.0));
  EXPECT_TRUE(intersect(Ray{Vec3(2.5, 0, 1), Vec3(0, 0, -1)}, flat).is_empty());
}

TEST(IntersectFrustum, RandomTangentRays) {
  test::Random rng(42);
  // Near the origin, and at model scale (coordinates ~1e3, whose rounding the allowances scale
  // with).
  for (const double placement : {0.0, 1000.0}) {
    for (int trial = 0; trial < 1000; ++trial) {
      Frustum frustum = random_frustum(rng);
      frustum.base += rng.point_in_box(placement);
      const Vec3& n = frustum.axis;
      const Vec3 radial = random_perpendicular(rng, n);
      const double s = rng.uniform(0.1, 0.9) * frustum.height;
      const double radius =
          frustum.radius0 + (frustum.radius1 - frustum.radius0) * (s / frustum.height);
      const Vec3 contact = frustum.base + s * n + radius * radial;
      // The tangent plane at the contact holds the circumferential direction and the generator;
      // any line in it other than the generator touches the convex solid at the contact only.
      const Vec3 around = n.cross(radial);
      const Vec3 generator =
          (frustum.height * n + (frustum.radius1 - frustum.radius0) * radial).normalized();
      const double angle = rng.uniform(-1.2, 1.2);  // at least 0.37 rad from the generator
      const Vec3 direction = std::cos(angle) * around + std::sin(angle) * generator;
      const double length = rng.uniform(0.1, 10.0);
      const double t = rng.uniform(-5.0, 5.0);
      const Ray ray{contact - t * direction, length * direction};
      const Interval hit = intersect(ray, frustum);
      ASSERT_FALSE(hit.is_empty()) << describe(ray);
      EXPECT_EQ(hit.lo, hit.hi) << describe(ray) << " r0 " << frustum.radius0 << " r1 "
                                << frustum.radius1;
      // The double root's position along the ray is good to √(allowance)·size ≈ 1e-7·size.
      EXPECT_NEAR(hit.lo, t / length, 1e-6 * (15.0 + 2.0 * placement) / length);
    }
  }
}

// --- Torus.

Torus random_torus(test::Random& rng, bool spindle) {
  Torus torus;
  torus.center = rng.point_in_box(5.0);
  torus.axis = rng.unit_vector();
  if (spindle) {
    torus.minor_radius = rng.uniform(0.5, 2.0);
    torus.major_radius = torus.minor_radius * rng.uniform(0.05, 0.95);
  } else {
    torus.major_radius = rng.uniform(1.0, 3.0);
    torus.minor_radius = torus.major_radius * rng.uniform(0.1, 0.9);
  }
  return torus;
}

// `minimum_two_intervals`: how many rays at least must cross the tube twice, so that the test
// is known to exercise that case.
void check_torus_against_sampling(test::Random& rng, bool spindle, int trials, double placement,
                                  double distance, int minimum_two_intervals) {
  int two_intervals = 0;
  for (int trial = 0; trial < trials; ++trial) {
    Torus torus = random_torus(rng, spindle);
    torus.center += rng.point_in_box(placement);
    const double bound = torus.major_radius + torus.minor_radius;
    const Ray ray = random_ray(rng, torus.center, bound, distance + 3.0 * bound);
    const IntervalPair pair = intersect(ray, torus);
    const std::vector<Interval> intervals = as_vector(pair);
    expect_well_formed(intervals);
    if (pair.count == 2) ++two_intervals;
    const Interval range = parameter_range(ray, torus.center, bound);
    const double exclusion = kEndExclusion * bound / ray.direction.norm();
    ASSERT_EQ(count_sampling_mismatches(
                  ray, intervals, [&](const Vec3& p) { return contains(torus, p); }, range.lo,
                  range.hi, exclusion),
              0)
        << "R " << torus.major_radius << " r " << torus.minor_radius;
    // End points on the tube. The quartic implicit factors into (distance to the circle)² - r²,
    // with gradient 2r on the tube, times (distance to the opposite point)² - r² ≤ (2R + 2r)²;
    // the end point carries ~1e3 u·size of rounding, so |implicit| ≲ 2e-13·size·r·(2R + 2r)².
    const double size = bound + torus.center.norm() + ray.origin.norm();
    const double tolerance = 1e-12 * size * torus.minor_radius * 4.0 * bound * bound;
    for (const Interval& interval : intervals) {
      for (const double end : {interval.lo, interval.hi}) {
        EXPECT_NEAR(implicit_value(torus, ray.at(end)), 0.0, tolerance) << describe(ray);
      }
    }
  }
  EXPECT_GE(two_intervals, minimum_two_intervals);
}

TEST(IntersectTorus, RandomRingTorusAgainstSampling) {
  test::Random rng(51);
  check_torus_against_sampling(rng, false, 1200, 0.0, 0.0, 60);
}

TEST(IntersectTorus, RandomSpindleTorusAgainstSampling) {
  test::Random rng(52);
  check_torus_against_sampling(rng, true, 600, 0.0, 0.0, 0);
}

TEST(IntersectTorus, RandomRaysAtModelScale) {
  test::Random rng(55);
  check_torus_against_sampling(rng, false, 300, 1000.0, 1000.0, 6);
  check_torus_against_sampling(rng, true, 150, 1000.0, 1000.0, 0);
}

TEST(IntersectTorus, Cases) {
  const Torus torus{Vec3::Zero(), Vec3::UnitZ(), 2.0, 1.0};
  // Along the axis, through the hole: empty.
  EXPECT_TRUE(intersect(Ray{Vec3(0, 0, -5), Vec3(0, 0, 1)}, torus).empty());
  // Through the tube twice, in the equatorial plane: [-3, -1] and [1, 3] (|d| = 2, from x = -5).
  IntervalPair pair = intersect(Ray{Vec3(-5, 0, 0), Vec3(2, 0, 0)}, torus);
  ASSERT_EQ(pair.count, 2);
  EXPECT_NEAR(pair.interval[0].lo, 1.0, 1e-14);
  EXPECT_NEAR(pair.interval[0].hi, 2.0, 1e-14);
  EXPECT_NEAR(pair.interval[1].lo, 3.0, 1e-14);
  EXPECT_NEAR(pair.interval[1].hi, 4.0, 1e-14);
  // Parallel to the axis through the tube's centre circle: z in [-1, 1].
  pair = intersect(Ray{Vec3(2, 0, -5), Vec3(0, 0, 1)}, torus);
  ASSERT_EQ(pair.count, 1);
  EXPECT_NEAR(pair.interval[0].lo, 4.0, 1e-14);
  EXPECT_NEAR(pair.interval[0].hi, 6.0, 1e-14);
  // Tangent to the outer equator, parallel to the axis: [t, t] at z = 0.
  pair = intersect(Ray{Vec3(3, 0, -5), Vec3(0, 0, 1)}, torus);
  ASSERT_EQ(pair.count, 1);
  EXPECT_EQ(pair.interval[0].lo, pair.interval[0].hi);
  EXPECT_NEAR(pair.interval[0].lo, 5.0, 1e-7);
  // Tangent to the inner equator, parallel to the axis.
  pair = intersect(Ray{Vec3(0, 1, -5), Vec3(0, 0, 1)}, torus);
  ASSERT_EQ(pair.count, 1);
  EXPECT_EQ(pair.interval[0].lo, pair.interval[0].hi);
  EXPECT_NEAR(pair.interval[0].lo, 5.0, 1e-7);
  // Across the top (z = r): touches the top circle twice, two degenerate intervals.
  pair = intersect(Ray{Vec3(-5, 0, 1), Vec3(1, 0, 0)}, torus);
  ASSERT_EQ(pair.count, 2);
  EXPECT_EQ(pair.interval[0].lo, pair.interval[0].hi);
  EXPECT_EQ(pair.interval[1].lo, pair.interval[1].hi);
  EXPECT_NEAR(pair.interval[0].lo, 3.0, 1e-7);
  EXPECT_NEAR(pair.interval[1].lo, 7.0, 1e-7);
  // In the equatorial plane, tangent to the outer equator circle (y = 3).
  pair = intersect(Ray{Vec3(-5, 3, 0), Vec3(1, 0, 0)}, torus);
  ASSERT_EQ(pair.count, 1);
  EXPECT_EQ(pair.interval[0].lo, pair.interval[0].hi);
  EXPECT_NEAR(pair.interval[0].lo, 5.0, 1e-7);
  // In the equatorial plane, tangent to the inner equator (y = 1): crosses the tube on both
  // sides and touches the inner circle in between, which lies between the two chords.
  pair = intersect(Ray{Vec3(-5, 1, 0), Vec3(1, 0, 0)}, torus);
  ASSERT_EQ(pair.count, 1);  // the touch point joins the chord [−√8, √8]: one interval
  EXPECT_NEAR(pair.interval[0].lo, 5.0 - std::sqrt(8.0), 1e-12);
  EXPECT_NEAR(pair.interval[0].hi, 5.0 + std::sqrt(8.0), 1e-12);
  // Origin inside the tube; zero direction.
  pair = intersect(Ray{Vec3(2, 0, 0.5), Vec3(1, 1, 1)}, torus);
  ASSERT_EQ(pair.count, 1);
  EXPECT_TRUE(pair.interval[0].contains(0.0));
  pair = intersect(Ray{Vec3(2, 0, 0.5), Vec3::Zero()}, torus);
  ASSERT_EQ(pair.count, 1);
  EXPECT_EQ(pair.interval[0], Interval::full());
  EXPECT_TRUE(intersect(Ray{Vec3(0, 0, 0), Vec3::Zero()}, torus).empty());
}

TEST(IntersectTorus, SpindleAndBall) {
  // Spindle torus (R < r): the inner lemon is inside, so the axis is inside for
  // |z| ≤ √(r² - R²) = 0.8.
  const Torus spindle{Vec3::Zero(), Vec3::UnitZ(), 0.6, 1.0};
  IntervalPair pair = intersect(Ray{Vec3(0, 0, -5), Vec3(0, 0, 1)}, spindle);
  ASSERT_EQ(pair.count, 1);
  EXPECT_NEAR(pair.interval[0].lo, 4.2, 1e-12);
  EXPECT_NEAR(pair.interval[0].hi, 5.8, 1e-12);
  // Across the equator of the spindle: one chord from -1.6 to 1.6 (lemon included).
  pair = intersect(Ray{Vec3(-5, 0, 0), Vec3(1, 0, 0)}, spindle);
  ASSERT_EQ(pair.count, 1);
  EXPECT_NEAR(pair.interval[0].lo, 3.4, 1e-12);
  EXPECT_NEAR(pair.interval[0].hi, 6.6, 1e-12);
  // Major radius 0: the ball of the minor radius.
  const Torus ball{Vec3(1, 1, 1), Vec3::UnitX(), 0.0, 2.0};
  pair = intersect(Ray{Vec3(1, 1, -4), Vec3(0, 0, 1)}, ball);
  ASSERT_EQ(pair.count, 1);
  EXPECT_NEAR(pair.interval[0].lo, 3.0, 1e-14);
  EXPECT_NEAR(pair.interval[0].hi, 7.0, 1e-14);
  pair = intersect(Ray{Vec3(3, 1, -4), Vec3(0, 0, 1)}, ball);  // tangent
  ASSERT_EQ(pair.count, 1);
  EXPECT_EQ(pair.interval[0].lo, pair.interval[0].hi);
  EXPECT_NEAR(pair.interval[0].lo, 5.0, 1e-14);
}

TEST(IntersectTorus, RandomTangentRaysAtTheOuterEquator) {
  test::Random rng(53);
  // Near the origin, and at model scale (coordinates ~1e3, whose rounding the allowances scale
  // with).
  for (const double placement : {0.0, 1000.0}) {
    for (int trial = 0; trial < 1000; ++trial) {
      Torus torus = random_torus(rng, false);
      torus.center += rng.point_in_box(placement);
      const Vec3& n = torus.axis;
      const Vec3 radial = random_perpendicular(rng, n);
      const Vec3 contact = torus.center + (torus.major_radius + torus.minor_radius) * radial;
      // The plane through the outer equator point perpendicular to `radial` supports the whole
      // torus (every point has (p - c)·radial ≤ R + r): a line in it touches only the contact.
      const double angle = rng.uniform(0.0, kTwoPi);
      const Vec3 direction = std::cos(angle) * n + std::sin(angle) * n.cross(radial);
      const double length = rng.uniform(0.1, 10.0);
      const double t = rng.uniform(-5.0, 5.0);
      const Ray ray{contact - t * direction, length * direction};
      const IntervalPair pair = intersect(ray, torus);
      ASSERT_EQ(pair.count, 1) << describe(ray) << " R " << torus.major_radius << " r "
                               << torus.minor_radius;
      EXPECT_EQ(pair.interval[0].lo, pair.interval[0].hi) << describe(ray);
      // The double root's position along the ray: √(allowance)·size ≈ 1e-7·size.
      EXPECT_NEAR(pair.interval[0].lo, t / length, 1e-6 * (15.0 + 2.0 * placement) / length);
    }
  }
}

TEST(IntersectTorus, RandomLinesInTheTopPlane) {
  // The plane z = r supports the torus along its whole top circle: a line in it touches the
  // circle twice (two degenerate intervals) when it passes within R of the axis.
  test::Random rng(54);
  // Near the origin, and at model scale (coordinates ~1e3, whose rounding the allowances scale
  // with).
  for (const double placement : {0.0, 1000.0}) {
    for (int trial = 0; trial < 500; ++trial) {
      Torus torus = random_torus(rng, false);
      torus.center += rng.point_in_box(placement);
      const Vec3& n = torus.axis;
      const Vec3 x = random_perpendicular(rng, n);
      const Vec3 y = n.cross(x);
      const double offset = rng.uniform(-0.9, 0.9) * torus.major_radius;  // distance from axis
      const double half = std::sqrt(torus.major_radius * torus.major_radius - offset * offset);
      const Vec3 origin = torus.center + torus.minor_radius * n + offset * y - 4.0 * x;
      const Ray ray{origin, x};
      const IntervalPair pair = intersect(ray, torus);
      ASSERT_EQ(pair.count, 2) << describe(ray) << " R " << torus.major_radius << " r "
                               << torus.minor_radius << " offset " << offset;
      for (int i = 0; i < 2; ++i) {
        const Interval& interval = pair.interval[static_cast<std::size_t>(i)];
        EXPECT_EQ(interval.lo, interval.hi) << describe(ray);
        EXPECT_NEAR(interval.lo, 4.0 + (i == 0 ? -half : half), 1e-6 * (15.0 + 2.0 * placement));
      }
    }
  }
}

}  // namespace
}  // namespace cwe

namespace cwe {
namespace {

// Rays along a torus's axis or square to it take the closed forms (a vertical line at constant ρ,
// a line across the annulus of its plane): their chords agree with point membership.
TEST(IntersectTorus, AxisAlignedRaysInClosedForm) {
  test::Random rng(55);
  int hits = 0, twos = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const Torus torus{rng.point_in_box(3.0), Vec3::UnitZ(), rng.uniform(0.5, 4.0),
                      rng.uniform(0.2, 2.0)};
    const double angle = rng.uniform(0.0, kTwoPi);
    const Vec3 direction = trial % 3 == 0 ? Vec3(0, 0, trial % 2 ? 1.0 : -1.0)
                                          : Vec3(std::cos(angle), std::sin(angle), 0.0);
    const Vec3 origin =
        torus.center + rng.point_in_box(torus.major_radius + torus.minor_radius) - 8.0 * direction;
    const Ray ray{origin, direction};
    const IntervalPair pair = intersect(ray, torus);
    hits += pair.count > 0 ? 1 : 0;
    twos += pair.count == 2 ? 1 : 0;
    for (int k = 0; k <= 1600; ++k) {
      const double t = k * 0.01;
      bool in = false, near_end = false;
      for (const Interval& i : pair) {
        in = in || i.contains(t);
        near_end = near_end || std::abs(t - i.lo) < 1e-9 || std::abs(t - i.hi) < 1e-9;
      }
      if (near_end) continue;
      ASSERT_EQ(in, contains(torus, ray.at(t))) << describe(ray) << " t " << t;
    }
    for (const Interval& i : pair) {
      for (const double t : {i.lo, i.hi}) {
        const Vec3 q = ray.at(t) - torus.center;
        const double rho = std::hypot(q.x(), q.y());
        EXPECT_NEAR(std::hypot(rho - torus.major_radius, q.z()), torus.minor_radius, 1e-12);
      }
    }
  }
  EXPECT_GT(hits, 150);
  EXPECT_GT(twos, 20);
}

}  // namespace
}  // namespace cwe

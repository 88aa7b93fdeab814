#include "cwe/tool/cutter.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "cwe/tool/tool_spec.hpp"
#include "random.hpp"
#include "tool_testing.hpp"

namespace cwe {
namespace {

using Seg = ProfileSegment;

CutterOptions named(const std::string& name) {
  CutterOptions options;
  options.name = name;
  return options;
}

// A corner-rounding cutter: pilot, concave quarter arc, horizontal step, cylinder. It exercises
// the non-convex paths (concave torus, step) that APT tools never produce.
Cutter corner_rounding() {
  return Cutter(Profile({Seg::line({0, 0}, {2, 0}), Seg::line({2, 0}, {2, 1}),
                         Seg::arc({2, 1}, {5, 4}, {5, 1}, false), Seg::line({5, 4}, {8, 4}),
                         Seg::line({8, 4}, {8, 12})}),
                named("corner rounding"));
}

std::vector<Cutter> all_cutters() {
  std::vector<Cutter> cutters;
  for (const char* spec : {"flat:10,20", "ball:10,20", "bull:10,2,20", "taper-flat:6,5,20",
                           "taper-flat:10,-3,20", "taper-ball:4,3,20", "chamfer:12,90,15",
                           "chamfer:8,118,20", "apt:7.8586,1,3,1.5444,10,5,20"}) {
    cutters.push_back(cutter_from_spec(spec));
  }
  cutters.push_back(corner_rounding());
  return cutters;
}

TEST(Cutter, PatchKinds) {
  const auto kinds = [](const Cutter& c) {
    std::vector<PatchKind> k;
    for (const auto& p : c.patches()) k.push_back(p.kind);
    return k;
  };
  using K = PatchKind;
  EXPECT_EQ(kinds(cutter_from_spec("flat:10")), (std::vector{K::kFlatBottom, K::kCylinder}));
  EXPECT_EQ(kinds(cutter_from_spec("ball:10")), (std::vector{K::kSphere, K::kCylinder}));
  EXPECT_EQ(kinds(cutter_from_spec("bull:10,2")),
            (std::vector{K::kFlatBottom, K::kTorus, K::kCylinder}));
  EXPECT_EQ(kinds(cutter_from_spec("taper-ball:4,3")), (std::vector{K::kSphere, K::kCone}));
  EXPECT_EQ(kinds(cutter_from_spec("chamfer:12,90")), (std::vector{K::kCone, K::kCylinder}));
  EXPECT_EQ(kinds(corner_rounding()),
            (std::vector{K::kFlatBottom, K::kCylinder, K::kTorus, K::kStep, K::kCylinder}));
}

TEST(Cutter, DefaultsAndDimensions) {
  const Cutter flat = cutter_from_spec("flat:10");
  EXPECT_DOUBLE_EQ(flat.diameter(), 10.0);
  EXPECT_DOUBLE_EQ(flat.flute_length(), 30.0);
  EXPECT_EQ(flat.flutes(), 4);
  EXPECT_EQ(cutter_from_spec("ball:10").flutes(), 2);
  EXPECT_NEAR(flat.helix_angle(), degrees_to_radians(30.0), 1e-15);
  EXPECT_DOUBLE_EQ(flat.shank().diameter, 10.0);
  const BoundingCylinder b = cutter_from_spec("taper-flat:6,5,20").bounding_cylinder();
  EXPECT_NEAR(b.radius, 3.0 + 20.0 * std::tan(degrees_to_radians(5.0)), 1e-12);
  EXPECT_DOUBLE_EQ(b.z_max, 20.0);
}

TEST(Cutter, RejectsImpossibleOptions) {
  const Profile p = cutter_from_spec("flat:10").profile();
  CutterOptions options = named("t");
  options.flutes = -1;
  EXPECT_INPUT_ERROR(Cutter(p, options), "flutes = -1");
  options = named("t");
  options.helix_angle_deg = 95;
  EXPECT_INPUT_ERROR(Cutter(p, options), "helix angle = 95°");
  options = named("t");
  options.shank = Shank{0.0, 10.0};
  EXPECT_INPUT_ERROR(Cutter(p, options), "shank diameter 0");
}

// φ convention of docs/architecture.md: φ = 0 along +y, φ = 90° along +x (clockwise seen from the
// shank).
TEST(Cutter, EngagementAngleConvention) {
  const Cutter c = cutter_from_spec("flat:10");
  EXPECT_TRUE(c.point(1, 0.0, 0.5).isApprox(Vec3(0, 5, 15), 1e-12));
  EXPECT_TRUE(c.point(1, kPi / 2, 0.5).isApprox(Vec3(5, 0, 15), 1e-12));
  const EngagementCoordinates e = c.engagement_coordinates(Vec3(5, 0, 15));
  EXPECT_NEAR(e.phi, kPi / 2, 1e-15);
  EXPECT_NEAR(e.depth, 15.0, 1e-12);
  EXPECT_FALSE(e.polar);
  const EngagementCoordinates bottom = c.engagement_coordinates(Vec3(-2, 0, 0));
  EXPECT_TRUE(bottom.polar);
  EXPECT_NEAR(bottom.phi, 3 * kPi / 2, 1e-15);
  EXPECT_NEAR(bottom.radius, 2.0, 1e-15);
}

// Surface points lie on their patch's implicit surface; normals are unit, perpendicular to the
// surface (finite-difference tangents) and point out of the solid.
TEST(Cutter, SurfacePointsNormalsAndImplicitValues) {
  test::Random random(7);
  for (const Cutter& c : all_cutters()) {
    SCOPED_TRACE(c.name());
    for (int patch = 0; patch < static_cast<int>(c.patches().size()); ++patch) {
      for (int k = 0; k < 200; ++k) {
        const double phi = random.uniform(0.0, kTwoPi);
        const double u = random.uniform(0.02, 0.98);
        const Vec3 p = c.point(patch, phi, u);
        const Vec3 n = c.normal(patch, phi, u);
        // Implicit values are polynomials in coordinates of size ≤ 20 mm: degree 2 (mm²) for
        // quadrics, degree 4 (mm⁴) for the torus; rounding stays below 1e-9 of their scale.
        const double scale = c.patches()[static_cast<std::size_t>(patch)].kind == PatchKind::kTorus
                                 ? std::pow(20.0, 4)
                                 : 400.0;
        EXPECT_NEAR(c.implicit_value(patch, p), 0.0, 1e-12 * scale);
        EXPECT_NEAR(n.norm(), 1.0, 1e-12);
        const double h = 1e-6;
        const Vec3 dphi = (c.point(patch, phi + h, u) - c.point(patch, phi - h, u)) / (2 * h);
        const Vec3 du = (c.point(patch, phi, u + h) - c.point(patch, phi, u - h)) / (2 * h);
        // Central differences of a smooth surface: error O(h²·curvature) ≈ 1e-12, plus rounding
        // 1e-16·|p|/h ≈ 2e-9.
        EXPECT_NEAR(dphi.dot(n), 0.0, 1e-8);
        EXPECT_NEAR(du.dot(n), 0.0, 1e-8);
        // A step of 1e-3 mm along ±n leaves or enters the solid (the patches are at least 1 mm
        // from any other part of the cutter surface in these tools).
        EXPECT_FALSE(c.contains(p + 1e-3 * n));
        EXPECT_TRUE(c.contains(p - 1e-3 * n));
        // Round trip through the engagement coordinates.
        const EngagementCoordinates e = c.engagement_coordinates(p);
        EXPECT_EQ(e.patch, patch);
        EXPECT_NEAR(e.distance, 0.0, 1e-9);
        EXPECT_NEAR(e.u, u, 1e-9);
        // u ≥ 0.02 keeps p off the axis, where φ would be undefined.
        EXPECT_NEAR(std::remainder(e.phi - phi, kTwoPi), 0.0, 1e-9);
      }
    }
  }
}

// Oracle: dense sampling of contains() along the ray. Every sample inside a returned chord must
// be inside the solid and every sample outside all chords outside, except within one sample step
// of a chord end (where the sample may fall either side of the true boundary).
void expect_chords_match_sampling(const Cutter& c, const Ray& ray, double t_max, int samples) {
  const std::vector<Interval> chords = c.intersect(ray);
  for (std::size_t i = 1; i < chords.size(); ++i) ASSERT_LT(chords[i - 1].hi, chords[i].lo);
  const double step = 2.0 * t_max / samples;
  for (int k = 0; k <= samples; ++k) {
    const double t = -t_max + k * step;
    bool in_chord = false;
    bool near_end = false;
    for (const Interval& i : chords) {
      in_chord = in_chord || i.contains(t);
      near_end = near_end || std::abs(t - i.lo) <= step || std::abs(t - i.hi) <= step;
    }
    if (near_end) continue;
    ASSERT_EQ(in_chord, c.contains(ray.at(t)))
        << "t = " << t << " point " << ray.at(t).transpose() << " chords " << chords.size();
  }
}

TEST(Cutter, RayChordsAgreeWithPointSampling) {
  test::Random random(11);
  for (const Cutter& c : all_cutters()) {
    SCOPED_TRACE(c.name());
    const double r = c.bounding_cylinder().radius;
    const double h = c.bounding_cylinder().z_max;
    for (int k = 0; k < 300; ++k) {
      // Rays through a random point of the bounding cylinder's box, in random directions,
      // and a share of near-axial and near-horizontal rays (the degenerate directions).
      const Vec3 through(random.uniform(-r, r), random.uniform(-r, r), random.uniform(-1, h + 1));
      Vec3 direction = random.unit_vector();
      if (k % 5 == 0)
        direction = Vec3(random.uniform(-1e-3, 1e-3), random.uniform(-1e-3, 1e-3), 1).normalized();
      if (k % 5 == 1) direction = Vec3(direction.x(), direction.y(), 0.0).normalized();
      expect_chords_match_sampling(c, Ray{through, direction}, 2 * (r + h), 4000);
    }
  }
}

TEST(Profile, HeightsReachingAgreeWithSampledRadii) {
  // Oracle: the lowest and highest of 20,001 sampled heights where the radius reaches r. The
  // answer may extend past a sampled extreme by up to one sample spacing, never fall short.
  constexpr int kSamples = 20000;
  for (const Cutter& c : all_cutters()) {
    SCOPED_TRACE(c.name());
    const Profile& profile = c.profile();
    const double spacing = profile.height() / kSamples;
    for (int j = 0; j <= 40; ++j) {
      const double r = profile.max_radius() * (1.05 * j / 40);
      double lo = std::numeric_limits<double>::infinity(), hi = -lo;
      for (int k = 0; k <= kSamples; ++k) {
        const double z = profile.height() * k / kSamples;
        if (profile.radius_at(z) >= r) lo = std::min(lo, z), hi = std::max(hi, z);
      }
      const Interval heights = profile.heights_reaching(r);
      if (lo > hi) {
        // No sample reaches r: at most a sliver between samples does.
        if (!heights.is_empty()) {
          EXPECT_LE(heights.length(), spacing) << "r = " << r;
        }
        continue;
      }
      ASSERT_FALSE(heights.is_empty()) << "r = " << r;
      EXPECT_LE(heights.lo, lo + 1e-12) << "r = " << r;
      EXPECT_GE(heights.lo, lo - spacing) << "r = " << r;
      EXPECT_GE(heights.hi, hi - 1e-12) << "r = " << r;
      EXPECT_LE(heights.hi, hi + spacing) << "r = " << r;
    }
  }
}

TEST(Cutter, RayAlongTheAxisAndAcrossTheBottom) {
  const Cutter flat = cutter_from_spec("flat:10,20");
  auto chords = flat.intersect(Ray{Vec3(0, 0, -5), Vec3::UnitZ()});
  ASSERT_EQ(chords.size(), 1u);
  EXPECT_NEAR(chords[0].lo, 5.0, 1e-12);
  EXPECT_NEAR(chords[0].hi, 25.0, 1e-12);
  // A ray lying in the bottom plane crosses the whole bottom disc.
  chords = flat.intersect(Ray{Vec3(-10, 1, 0), Vec3::UnitX()});
  ASSERT_EQ(chords.size(), 1u);
  EXPECT_NEAR(chords[0].lo, 10.0 - std::sqrt(24.0), 1e-12);
  EXPECT_NEAR(chords[0].hi, 10.0 + std::sqrt(24.0), 1e-12);
  // A horizontal ray through the concave corner of the corner-rounding tool at z = 2.5 meets
  // the neck ρ ≤ 5 - √(9 - 2.25).
  const Cutter cr = corner_rounding();
  chords = cr.intersect(Ray{Vec3(-10, 0, 2.5), Vec3::UnitX()});
  ASSERT_EQ(chords.size(), 1u);
  EXPECT_NEAR(chords[0].hi - 10.0, 5.0 - std::sqrt(6.75), 1e-9);
  // Tangent to the ball: a single touching point.
  const Cutter ball = cutter_from_spec("ball:10,20");
  chords = ball.intersect(Ray{Vec3(-10, 0, 0), Vec3::UnitX()});
  ASSERT_EQ(chords.size(), 1u);
  EXPECT_NEAR(chords[0].lo, 10.0, 1e-6);
  EXPECT_NEAR(chords[0].length(), 0.0, 1e-6);
}

}  // namespace
}  // namespace cwe

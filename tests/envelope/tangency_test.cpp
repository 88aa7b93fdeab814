#include "cwe/envelope/tangency.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "cwe/tool/tool_spec.hpp"
#include "random.hpp"

namespace cwe {
namespace {

// APT tools (convex), including the generic cutter of Aras 2008 Fig. 5.3: conical bottom
// (alpha = 10°), corner torus (r = 1) and tapered side (beta = 5°).
const char* const kGeneric = "apt:7.8586,1,3,1.5444,10,5,20";
const std::vector<std::string> kConvexTools = {
    "flat:10,20",        "ball:10,20",       "bull:10,2,20", "taper-flat:6,5,20",
    "taper-ball:4,3,20", "chamfer:12,90,15", kGeneric};

// A random instantaneous motion: tilted axis, tip velocity and angular velocity.
ToolState random_state(test::Random& random, bool rotating) {
  const Vec3 axis = random.unit_vector();
  const Vec3 v = random.unit_vector() * random.uniform(1.0, 50.0);
  const Vec3 w = rotating ? Vec3(random.unit_vector() * random.uniform(0.01, 2.0)) : Vec3::Zero();
  return tool_state(random.point_in_box(50), axis, v, w);
}

// The closed form a sin φ + b cos φ + c equals N·V computed from its definition.
TEST(Tangency, ClosedFormEqualsDefinition) {
  test::Random random(21);
  for (const std::string& spec : kConvexTools) {
    const Cutter cutter = cutter_from_spec(spec);
    for (int k = 0; k < 100; ++k) {
      const ToolState s = random_state(random, k % 2 == 0);
      const int patch = random.integer(0, static_cast<int>(cutter.patches().size()) - 1);
      const double phi = random.uniform(0, kTwoPi), u = random.uniform(0, 1);
      const double scale = s.tip_velocity.norm() + s.angular_velocity.norm() * 30.0;
      EXPECT_NEAR(tangency_coefficients(cutter, patch, u, s)(phi),
                  tangency(cutter, patch, phi, u, s), 1e-12 * scale)
          << spec;
    }
  }
}

// Penetration of a world point into the tool placed at `tip` with the state's axes: how far
// inside the solid it is radially (negative outside).
double penetration(const Cutter& cutter, const Frame& tcs, const Vec3& tip, const Vec3& p) {
  Frame at = tcs;
  at.origin = tip;
  const Vec3 local = at.to_local(p);
  // Points within rounding (1e-12 mm) of the tip plane or the top count as at that height.
  const double h = cutter.profile().height();
  if (local.z() < -1e-12 || local.z() > h + 1e-12) return -1.0;
  const double z = std::clamp(local.z(), 0.0, h);
  return cutter.profile().radius_at(z) - std::hypot(local.x(), local.y());
}

// Grazing points satisfy N·V = 0 and, for a translating convex tool, lie on the boundary of the
// union of its positions: on the tool now, inside none of the densely sampled nearby positions.
TEST(Grazing, PointsLieOnTheBoundaryOfTheSweptUnion) {
  test::Random random(22);
  for (const std::string& spec : kConvexTools) {
    const Cutter cutter = cutter_from_spec(spec);
    for (int k = 0; k < 12; ++k) {
      const ToolState s = random_state(random, false);
      const GrazingCurves curves = grazing_points(cutter, s);
      ASSERT_FALSE(curves.points.empty()) << spec;
      const Vec3 direction = s.tip_velocity.normalized();
      for (const GrazingPoint& g : curves.points) {
        EXPECT_NEAR(tangency(cutter, g.patch, g.phi, g.u, s), 0.0, 1e-12 * s.tip_velocity.norm());
        EXPECT_NEAR(penetration(cutter, s.tcs, s.tcs.origin, g.point), 0.0, 1e-9);
        // Positions 0.05 mm apart over ±10 mm of travel. Rounding of the radial distance
        // (~1e-15 · 50 mm) is the only allowed penetration.
        for (int j = -200; j <= 200; ++j) {
          if (j == 0) continue;
          const Vec3 tip = s.tcs.origin + (0.05 * j) * direction;
          ASSERT_LE(penetration(cutter, s.tcs, tip, g.point), 1e-9)
              << spec << " patch " << g.patch << " u " << g.u << " phi " << g.phi << " at "
              << 0.05 * j << " mm";
        }
      }
    }
  }
}

// The converse: a point of the forward set (f > 0) is inside the tool a moment later.
TEST(Grazing, ForwardPointsAreOvertaken) {
  test::Random random(23);
  const Cutter cutter = cutter_from_spec(kGeneric);
  for (int k = 0; k < 200; ++k) {
    const ToolState s = random_state(random, false);
    const int patch = random.integer(0, 2);
    const double phi = random.uniform(0, kTwoPi), u = random.uniform(0.05, 0.95);
    const double f = tangency(cutter, patch, phi, u, s) / s.tip_velocity.norm();
    if (std::abs(f) < 0.05) continue;  // near grazing: second-order effects decide
    const Vec3 p = s.tcs.to_world(cutter.point(patch, phi, u));
    const Vec3 later = s.tcs.origin + 1e-4 * s.tip_velocity.normalized();
    // Moving 1e-4 mm, the surface passes the point by ≈ f·1e-4 mm (first order).
    EXPECT_EQ(penetration(cutter, s.tcs, later, p) > 0.0, f > 0.0) << "f = " << f;
  }
}

// Aras 2008 Property 3.2: on a pipe surface (cylinder, torus) the grazing points are
// P = m ± r (m_t × m_u)/|m_t × m_u| for spine point m, spine tangent m_t and spine velocity m_u.
// An independent construction: every such point must satisfy the closed form.
TEST(Grazing, PipeSurfaceShortcutAgrees) {
  test::Random random(24);
  const Cutter bull = cutter_from_spec("bull:10,2,20");  // torus: ring radius 3 at height 2
  for (int k = 0; k < 50; ++k) {
    const ToolState s = random_state(random, k % 2 == 1);
    for (int j = 0; j < 36; ++j) {
      const double theta = kTwoPi * j / 36;
      const Vec3 e(std::sin(theta), std::cos(theta), 0);
      // Torus spine: the ring of sphere centres; cylinder spine: the axis (sphere radius 5).
      const Vec3 m_torus = s.tcs.to_world(3.0 * e + Vec3(0, 0, 2));
      const Vec3 t_torus = s.tcs.direction_to_world(Vec3(std::cos(theta), -std::sin(theta), 0));
      const Vec3 m_cylinder = s.tcs.to_world(Vec3(0, 0, 2 + 18.0 * j / 36));
      const Vec3 t_cylinder = s.tcs.z();
      for (const auto& [m, t, r] :
           {std::tuple{m_torus, t_torus, 2.0}, std::tuple{m_cylinder, t_cylinder, 5.0}}) {
        const Vec3 binormal = t.cross(s.point_velocity(m));
        if (binormal.norm() < 1e-6) continue;  // the spine moves along itself: no grazing line
        for (const double side : {1.0, -1.0}) {
          const Vec3 p = m + side * r * binormal.normalized();
          const EngagementCoordinates c = bull.engagement_coordinates(s.tcs.to_local(p));
          if (c.distance > 1e-9) continue;  // on the full torus but off the cutter's patch
          const double scale = s.tip_velocity.norm() + s.angular_velocity.norm() * 30.0;
          EXPECT_NEAR(tangency_coefficients(bull, c.patch, c.u, s)(c.phi), 0.0, 1e-9 * scale);
        }
      }
    }
  }
}

TEST(FeasibleContact, FlatBottomByMotionClass) {
  const Cutter flat = cutter_from_spec("flat:10,20");
  const auto at = [&](const Vec3& v) {
    return feasible_contact_surface(flat, tool_state(Vec3::Zero(), Vec3::UnitZ(), v, Vec3::Zero()));
  };
  // Horizontal: the bottom grazes everywhere (f ≡ 0, left behind), the side's front half cuts.
  const FeasibleContactSurface horizontal = at(Vec3(1, 0, 0));
  EXPECT_FALSE(horizontal.front[0]);
  EXPECT_FALSE(horizontal.back[0]);
  EXPECT_TRUE(horizontal.front[1]);
  EXPECT_FALSE(horizontal.back[1]);
  const FcsSection& side = horizontal.sections.back();
  ASSERT_EQ(side.phi.size(), 1u);
  EXPECT_NEAR(side.phi[0].lo, 0.0, 1e-12);
  EXPECT_NEAR(side.phi[0].hi, kPi, 1e-12);
  EXPECT_EQ(
      grazing_points(flat, tool_state(Vec3::Zero(), Vec3::UnitZ(), Vec3(1, 0, 0), Vec3::Zero()))
          .identically_grazing,
      std::vector<int>{0});
  // Plunge: the whole bottom cuts, the side grazes.
  const FeasibleContactSurface plunge = at(Vec3(0, 0, -1));
  EXPECT_TRUE(plunge.front[0]);
  EXPECT_TRUE(plunge.back[0]);
  EXPECT_FALSE(plunge.front[1]);
  // Ascending: the bottom leaves the material.
  EXPECT_FALSE(at(Vec3(1, 0, 0.2)).front[0]);
}

// Aras 2008 Tables 5.1 and 5.2 for the generic cutter (alpha = 10°, beta = 5°): which patches
// can cut, on which face, in each feed-angle region. With outward profile normals at angles θ
// (lower cone -80°, corner torus -80°…-5°, upper cone -5°), a patch has feasible points on the
// front iff sin(ψ + θ) > 0 for one of its θ, and on the back iff its normals point down and the
// motion descends (ψ > 90°). The region boundaries are β, 90° - α, 90°, 90° + α and 180° - β.
TEST(FeasibleContact, GenericCutterTable) {
  const Cutter generic = cutter_from_spec(kGeneric);
  ASSERT_EQ(generic.patches().size(), 3u);
  struct Row {
    double psi_deg;
    bool front_lower, front_torus, front_upper, back;
  };
  const Row rows[] = {
      {2, false, false, false, false},  // nearly axial retract: nothing ahead of the tool
      {40, false, true, true, false},   // ascending above the taper: torus and upper cone
      {85, true, true, true, false},    // F-region between 90° - α and 90°: lower cone too
      {90, true, true, true, false},    // horizontal
      {95, true, true, true, true},     // descending: back face and bottom join
      {120, true, true, true, true},   {178, true, true, true, true},  // near plunge
  };
  for (const Row& row : rows) {
    SCOPED_TRACE("psi = " + std::to_string(row.psi_deg));
    const double psi = degrees_to_radians(row.psi_deg);
    const ToolState s = tool_state(Vec3::Zero(), Vec3::UnitZ(),
                                   Vec3(std::sin(psi), 0, std::cos(psi)), Vec3::Zero());
    const FeasibleContactSurface fcs = feasible_contact_surface(generic, s);
    EXPECT_EQ(fcs.front[0], row.front_lower);
    EXPECT_EQ(fcs.front[1], row.front_torus);
    EXPECT_EQ(fcs.front[2], row.front_upper);
    for (int patch = 0; patch < 3; ++patch) EXPECT_EQ(fcs.back[patch], row.back) << patch;
  }
}

// Every FCS section's intervals are exactly where f ≥ 0 (dense φ sampling).
TEST(FeasibleContact, IntervalsMatchSampling) {
  test::Random random(25);
  for (const std::string& spec : kConvexTools) {
    const Cutter cutter = cutter_from_spec(spec);
    for (int k = 0; k < 10; ++k) {
      const ToolState s = random_state(random, k % 2 == 0);
      EnvelopeOptions options;
      options.samples_per_patch = 9;
      for (const FcsSection& section : feasible_contact_surface(cutter, s, options).sections) {
        const TangencyCoefficients t = tangency_coefficients(cutter, section.patch, section.u, s);
        const double scale = std::abs(t.a) + std::abs(t.b) + std::abs(t.c);
        for (int j = 0; j < 720; ++j) {
          const double phi = kTwoPi * (j + 0.5) / 720;
          bool inside = false;
          for (const Interval& i : section.phi) inside = inside || i.contains(phi);
          // Away from roots (|f| above 1e-9 of its scale) the sign decides membership.
          if (std::abs(t(phi)) > 1e-9 * scale) {
            EXPECT_EQ(inside, t(phi) > 0) << spec;
          }
        }
      }
    }
  }
}

}  // namespace
}  // namespace cwe

// The mechanistic force model against closed forms (flat end mill mean forces, plunge) and a
// brute-force per-element sum written independently in vector form (ball end).
#include "cwe/process/force_model.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>

#include "cwe/core/error.hpp"
#include "cwe/tool/tool_spec.hpp"
#include "process_testing.hpp"

namespace cwe {
namespace {

constexpr double kDeg = kPi / 180.0;

using test::closed_form_mean;
using test::test_coefficients;

// Discs of height dz from the tip to `depth`, each engaged over `phi`.
EngagementMap side_map(double depth, double dz, std::vector<Interval> phi) {
  EngagementMap map;
  const int n = static_cast<int>(std::lround(depth / dz));
  for (int i = 0; i < n; ++i) map.discs.push_back({i * dz, (i + 1) * dz, 0, phi});
  map.engaged = true;
  return map;
}

struct Immersion {
  const char* name;
  double start, exit;
};

// The mean force is the exact integral up to the midpoint rule over each 1° step: the integrands
// are sinusoids of φ and 2φ, so the rule's relative error is at most (2Δ)²/24 = 5.1e-5 of the
// largest element force density N·a·(K_tc·c + K_te)/2π (measured: 1.7e-5).
TEST(ForceModel, FlatEndMillMeanForcesMatchClosedForms) {
  const Cutter cutter = cutter_from_spec("flat:10,30");
  const CuttingCoefficients k = test_coefficients();
  const double a = 2.0, c = 0.1;
  const double quarter = std::acos(1.0 - 2.5 / 5.0);  // radial depth D/4
  const Immersion cases[] = {{"slot", 0.0, kPi},
                             {"half up", 0.0, kPi / 2},
                             {"half down", kPi / 2, kPi},
                             {"quarter up", 0.0, quarter},
                             {"quarter down", kPi - quarter, kPi},
                             {"odd", 0.3, 2.2}};
  for (const int flutes : {1, 2, 3, 4}) {
    ForceModelOptions options;
    options.flutes = flutes;
    const ForceModel model(cutter, k, options);
    for (const Immersion& im : cases) {
      SCOPED_TRACE(fmt::format("{} flutes, {}", flutes, im.name));
      const ClForces f =
          model.evaluate(side_map(a, 0.1, {{im.start, im.exit}}), Vec3::UnitX(), c, 10000.0);
      const Vec3 expected = closed_form_mean(k, flutes, a, c, im.start, im.exit);
      const double tol = 5.1e-5 * flutes * a * (k.ktc * c + k.kte) / (2 * kPi) * 2 * kPi;
      EXPECT_TRUE(f.cutting);
      EXPECT_NEAR(f.mean_force.x(), expected.x(), tol);
      EXPECT_NEAR(f.mean_force.y(), expected.y(), tol);
      EXPECT_NEAR(f.mean_force.z(), expected.z(), tol);
      // Torque: Σ R·dF_t, mean (N a R/2π)[−K_tc c cos φ + K_te φ], N·mm → N·m.
      const double torque =
          flutes * a * 5.0 / (2 * kPi) *
          (k.ktc * c * (std::cos(im.start) - std::cos(im.exit)) + k.kte * (im.exit - im.start)) /
          1000.0;
      EXPECT_NEAR(f.mean_torque, torque, 5.1e-5 * torque);
      EXPECT_NEAR(f.mean_power, torque * 10000.0 * 2 * kPi / 60.0, 5.1e-5 * f.mean_power);
      EXPECT_NEAR(f.max_chip, c * std::sin(std::min(im.exit, std::max(im.start, kPi / 2))),
                  c * 1e-4);
    }
  }
}

TEST(ForceModel, MeanForcesDoNotDependOnTheHelixAngle) {
  const Cutter cutter = cutter_from_spec("flat:10,30");
  const EngagementMap map = side_map(6.0, 0.1, {{0.0, kPi / 2}});
  ForceModelOptions straight;
  straight.helix_angle = 0.0;
  const ClForces base =
      ForceModel(cutter, test_coefficients(), straight).evaluate(map, Vec3::UnitX(), 0.08, 8000.0);
  for (const double helix : {15.0, 30.0, 45.0, 60.0}) {
    SCOPED_TRACE(helix);
    ForceModelOptions options;
    options.helix_angle = helix * kDeg;
    const ClForces f =
        ForceModel(cutter, test_coefficients(), options).evaluate(map, Vec3::UnitX(), 0.08, 8000.0);
    EXPECT_NEAR((f.mean_force - base.mean_force).norm(), 0.0, 1e-3);
    EXPECT_NEAR(f.mean_torque, base.mean_torque, 1e-6);
    // The helix spreads the flute over the immersion: the force varies less around the turn.
    EXPECT_LT(f.peak_resultant, base.peak_resultant);
  }
}

// A plunge: every ring of the bottom engaged all round, feed along −z. Each flute's bottom edge
// cuts a chip of thickness c over radius R: F_z = N(K_rc c + K_re)R, torque N(K_tc c + K_te)R²/2,
// F_x = F_y = 0 by symmetry.
TEST(ForceModel, PlungeLoadsTheBottomEdges) {
  const Cutter cutter = cutter_from_spec("flat:10,30");
  const CuttingCoefficients k = test_coefficients();
  EngagementMap map;
  map.engaged = true;
  for (int i = 0; i < 50; ++i) map.rings.push_back({i * 0.1, (i + 1) * 0.1, {{0.0, 2 * kPi}}});
  for (const int flutes : {2, 3, 4}) {
    ForceModelOptions options;
    options.flutes = flutes;
    const ClForces f =
        ForceModel(cutter, k, options).evaluate(map, -Vec3::UnitZ(), 0.02, 6000.0, true);
    EXPECT_NEAR(f.mean_force.x(), 0.0, 1e-9);
    EXPECT_NEAR(f.mean_force.y(), 0.0, 1e-9);
    EXPECT_NEAR(f.mean_force.z(), flutes * (k.krc * 0.02 + k.kre) * 5.0, 1e-9);
    EXPECT_NEAR(f.mean_torque, flutes * (k.ktc * 0.02 + k.kte) * 12.5 / 1000.0, 1e-12);
    EXPECT_NEAR(f.max_chip, 0.02, 1e-15);
    ASSERT_EQ(f.curve.size(), 360u);
    // Every sample is the same: the plunge force does not vary round the turn.
    for (const ForceSample& s : f.curve) EXPECT_NEAR((s.force - f.mean_force).norm(), 0.0, 1e-9);
  }
}

// An independent brute force for a ball end: the force as a sum over fine sub-elements, written
// with vectors (the edge direction e_t, the sphere's normal n = (P − C)/R, a = e_t × n) and point
// samples of the spindle angle, against the model's disc elements and step averages.
struct BruteForce {
  Vec3 mean = Vec3::Zero();
  double peak = 0.0;
};

BruteForce ball_brute_force(const CuttingCoefficients& k, double radius, int flutes, double helix,
                            double depth, const Interval& phi, const Vec3& feed, double c) {
  constexpr int kAngles = 7200;  // 0.05°
  constexpr double kDz = 0.005;
  const double lead = std::tan(helix) / radius;
  BruteForce out;
  for (int s = 0; s < kAngles; ++s) {
    const double theta = 2 * kPi * s / kAngles;
    Vec3 force = Vec3::Zero();
    for (double z = 0.5 * kDz; z < depth; z += kDz) {
      const double rho = std::sqrt(std::max(0.0, 2 * radius * z - z * z));
      const double z0 = z - 0.5 * kDz, z1 = z + 0.5 * kDz;
      const double r0 = std::sqrt(std::max(0.0, 2 * radius * z0 - z0 * z0));
      const double r1 = std::sqrt(2 * radius * z1 - z1 * z1);
      const double db = std::hypot(r1 - r0, kDz);
      for (int j = 0; j < flutes; ++j) {
        double p = std::fmod(theta + 2 * kPi * j / flutes - lead * z, 2 * kPi);
        if (p < 0) p += 2 * kPi;
        if (!phi.contains(p)) continue;
        const Vec3 er(std::sin(p), std::cos(p), 0.0);
        const Vec3 et(std::cos(p), -std::sin(p), 0.0);
        const Vec3 point = rho * er + Vec3(0, 0, z);
        const Vec3 n = (point - Vec3(0, 0, radius)) / radius;
        const Vec3 a = et.cross(n);
        const double h = c * feed.dot(n);
        if (h <= 0) continue;
        force -= (k.ktc * h + k.kte) * db * et + (k.krc * h + k.kre) * db * n +
                 (k.kac * h + k.kae) * db * a;
      }
    }
    out.mean += force / kAngles;
    out.peak = std::max(out.peak, force.norm());
  }
  return out;
}

TEST(ForceModel, BallEndMatchesABruteForceElementSum) {
  const Cutter cutter = cutter_from_spec("ball:10,30");
  const CuttingCoefficients k = test_coefficients();
  struct Case {
    Vec3 feed;
    Interval phi;
    double depth;
  };
  const Case cases[] = {{Vec3::UnitX(), {0.0, kPi}, 2.0},
                        {Vec3(1, 0, -0.4).normalized(), {0.2, 2.6}, 1.5},
                        {Vec3(1, 0, 0.3).normalized(), {kPi / 2, kPi}, 2.5}};
  for (const Case& cs : cases) {
    SCOPED_TRACE(fmt::format("feed {} {} {}", cs.feed.x(), cs.feed.y(), cs.feed.z()));
    ForceModelOptions options;
    options.flutes = 2;
    options.helix_angle = 30 * kDeg;
    const ClForces f = ForceModel(cutter, k, options)
                           .evaluate(side_map(cs.depth, 0.1, {cs.phi}), cs.feed, 0.05, 12000.0);
    const BruteForce b = ball_brute_force(k, 5.0, 2, 30 * kDeg, cs.depth, cs.phi, cs.feed, 0.05);
    // The model integrates each 0.1 mm disc's profile moments (16 chords) but places the whole
    // disc at the flute's mid-height lag (it spans lead·0.1 mm = 0.66° at a 30° helix) and
    // averages over 1° steps; both are fractions of a degree at the entry and exit edges: 0.5%
    // of the largest mean component (measured up to 0.27%). (The tip disc alone was 40% off when
    // κ was taken at mid-height.)
    const double scale = b.mean.cwiseAbs().maxCoeff();
    EXPECT_NEAR(f.mean_force.x(), b.mean.x(), 5e-3 * scale);
    EXPECT_NEAR(f.mean_force.y(), b.mean.y(), 5e-3 * scale);
    EXPECT_NEAR(f.mean_force.z(), b.mean.z(), 5e-3 * scale);
    // Peaks: the model's are averages over 1° of spindle angle, with each disc entering at once
    // where the brute force's sub-elements enter one by one: 2% (measured up to 1.6%).
    EXPECT_NEAR(f.peak_resultant, b.peak, 0.02 * b.peak);
  }
}

// Ramping down at 5°, a ball's normal points straight into the feed at κ = 85° (z = 4.564 mm,
// inside the disc 4.5–4.6 mm, not at a disc's edge): the thickest chip is the feed per tooth.
TEST(ForceModel, ThickestChipIsFoundInsideADisc) {
  const Cutter cutter = cutter_from_spec("ball:10,30");
  const ForceModel model(cutter, test_coefficients());
  const Vec3 feed(std::cos(5 * kDeg), 0.0, -std::sin(5 * kDeg));
  EXPECT_NEAR(model.evaluate(side_map(4.7, 0.1, {{0.0, kPi}}), feed, 0.05, 1e4).max_chip, 0.05,
              1e-12);
  // Only up to 2 mm (κ ≤ 53.13°): the largest chip is at the top disc's upper edge.
  const double top = 0.05 * (std::cos(5 * kDeg) * 0.8 + std::sin(5 * kDeg) * 0.6);
  EXPECT_NEAR(model.evaluate(side_map(2.0, 0.1, {{0.0, kPi}}), feed, 0.05, 1e4).max_chip, top,
              1e-12);
}

// The steps an element spends wholly inside an engaged interval are summed in closed form (their
// force is a sum of harmonics of φ up to 2φ); under runout every step is evaluated one by one.
// A runout of 1e-12 mm changes a chip by at most 2e-12 mm, so the two must give the same
// revolution, sample for sample, to that (1e-9 of the peak allows for the chips' rounding). A
// step given to the wrong side of a chip's sign change or of an interval's end would move its
// sample by a whole element's force, 1e-3 of the peak or more.
TEST(ForceModel, ClosedFormStepsMatchStepByStep) {
  struct Case {
    const char* tool;
    Vec3 feed;
    std::vector<Interval> phi;  // every disc's
    double depth;
    bool rings;  // the bottom's rings engaged all round too
  };
  const Case cases[] = {
      {"flat:10,30", Vec3::UnitX(), {{0.0, kPi}}, 2.0, false},
      {"flat:10,30", Vec3::UnitX(), {{0.0, 1.0}, {5.5, 2 * kPi}}, 2.0, false},  // across θ = 0
      {"flat:10,30", Vec3(0.6, -0.8, 0.0), {{0.0, 2 * kPi}}, 1.0, false},       // a full ring
      {"flat:10,30", Vec3(0.3, 0.2, -1.0).normalized(), {{0.0, 2 * kPi}}, 0.5, true},
      {"ball:10,30", Vec3(1, 0, -0.4).normalized(), {{0.2, 2.6}}, 1.5, false},
      {"ball:10,30", Vec3(1, 0, 0.3).normalized(), {{0.0, kPi}}, 2.5, false},
      {"bull:10,2,30", Vec3(1, 0.5, -0.2).normalized(), {{1.0, 1.01}, {1.5, 4.0}}, 3.0, true},
  };
  for (const Case& cs : cases) {
    SCOPED_TRACE(fmt::format("{} feed {} {} {}", cs.tool, cs.feed.x(), cs.feed.y(), cs.feed.z()));
    const Cutter cutter = cutter_from_spec(cs.tool);
    EngagementMap map = side_map(cs.depth, 0.1, cs.phi);
    if (cs.rings) {
      for (int i = 0; i < 30; ++i) map.rings.push_back({i * 0.1, (i + 1) * 0.1, {{0.0, 2 * kPi}}});
    }
    ForceModelOptions options;
    options.flutes = 3;
    options.helix_angle = 30 * kDeg;
    const ClForces closed =
        ForceModel(cutter, test_coefficients(), options).evaluate(map, cs.feed, 0.05, 1e4, true);
    options.runout = {1e-12, 0.3};
    const ClForces stepped =
        ForceModel(cutter, test_coefficients(), options).evaluate(map, cs.feed, 0.05, 1e4, true);
    ASSERT_TRUE(closed.cutting);
    ASSERT_EQ(closed.curve.size(), stepped.curve.size());
    const double tolerance = 1e-9 * closed.peak_resultant;
    int zero_steps = 0;
    for (std::size_t k = 0; k < closed.curve.size(); ++k) {
      SCOPED_TRACE(fmt::format("step {}", k));
      EXPECT_NEAR(closed.curve[k].force.x(), stepped.curve[k].force.x(), tolerance);
      EXPECT_NEAR(closed.curve[k].force.y(), stepped.curve[k].force.y(), tolerance);
      EXPECT_NEAR(closed.curve[k].force.z(), stepped.curve[k].force.z(), tolerance);
      EXPECT_NEAR(closed.curve[k].torque, stepped.curve[k].torque, 1e-9 * closed.peak_torque);
      if (closed.curve[k].force == Vec3::Zero()) ++zero_steps;
    }
    EXPECT_NEAR(closed.max_chip, stepped.max_chip, 1e-11);
    // Where nothing cuts, the closed form's sums give exactly zero, not their rounding.
    if (cs.phi.size() == 2 && !cs.rings) {
      EXPECT_GT(zero_steps, 0);
    }
  }
}

// Runout e at angle 0 on two flutes: flute 0 stands out by 2e relative to flute 1 and cuts the
// chip c·sin φ + 2e, flute 1 cuts c·sin φ − 2e; the mean shear load is unchanged.
TEST(ForceModel, RunoutThickensOneFluteAndThinsTheOther) {
  const Cutter cutter = cutter_from_spec("flat:10,30");
  const EngagementMap map = side_map(2.0, 0.1, {{0.0, kPi}});
  ForceModelOptions options;
  options.flutes = 2;
  options.helix_angle = 0.0;
  const double c = 0.1, e = 0.01;
  CuttingCoefficients shear = test_coefficients();
  shear.kte = shear.kre = shear.kae = 0.0;
  const ClForces nominal = ForceModel(cutter, shear, options).evaluate(map, Vec3::UnitX(), c, 1e4);
  options.runout = {e, 0.0};
  const ClForces out = ForceModel(cutter, shear, options).evaluate(map, Vec3::UnitX(), c, 1e4);
  EXPECT_NEAR(out.max_chip, c + 2 * e, 1e-5);
  EXPECT_GT(out.peak_resultant, nominal.peak_resultant * 1.05);
  // Where flute 1's chip would be negative (sin φ < 2e/c) it cuts nothing and flute 0 does not
  // make up for it: the mean differs from the nominal by at most that sliver's share.
  EXPECT_NEAR(out.mean_torque, nominal.mean_torque, 0.05 * nominal.mean_torque);
}

// Feeding along world +Y puts the tool frame's x on world Y and y = z × x on world −X: the
// workpiece-frame figures are the tool frame's turned by that frame.
TEST(ForceModel, WorkpieceFrameFollowsTheToolFrame) {
  const Cutter cutter = cutter_from_spec("flat:10,30");
  const ForceModel model(cutter, test_coefficients());
  const ToolState state = tool_state(Vec3(1, 2, 3), Vec3::UnitZ(), Vec3(0, 600, 0), Vec3::Zero());
  const ClForces f = model.evaluate(side_map(2.0, 0.1, {{0.0, kPi / 2}}), state, 0.05, 8000.0);
  EXPECT_NEAR(f.mean_force_world.x(), -f.mean_force.y(), 1e-12);
  EXPECT_NEAR(f.mean_force_world.y(), f.mean_force.x(), 1e-12);
  EXPECT_NEAR(f.mean_force_world.z(), f.mean_force.z(), 1e-12);
  EXPECT_NEAR(f.peak_force_world.x(), f.peak_force.y(), 1e-12);
  EXPECT_NEAR(f.peak_force_world.y(), f.peak_force.x(), 1e-12);
  EXPECT_NEAR(f.peak_force_world.z(), f.peak_force.z(), 1e-12);
  EXPECT_GT(f.peak_force.norm(), 10.0);
}

TEST(ForceModel, AirAndStoppedFeedCutNothing) {
  const Cutter cutter = cutter_from_spec("flat:10,30");
  const ForceModel model(cutter, test_coefficients());
  EngagementMap air = side_map(2.0, 0.1, {});
  air.engaged = false;
  const ClForces a = model.evaluate(air, Vec3::UnitX(), 0.1, 1e4);
  EXPECT_FALSE(a.cutting);
  EXPECT_EQ(a.peak_resultant, 0.0);
  const ClForces still = model.evaluate(side_map(2.0, 0.1, {{0, kPi}}), Vec3::Zero(), 0.1, 1e4);
  EXPECT_FALSE(still.cutting);
  EXPECT_EQ(still.mean_torque, 0.0);
}

TEST(ForceModel, RefusesBadOptions) {
  const Cutter cutter = cutter_from_spec("flat:10,30");
  ForceModelOptions step;
  step.angle_step = 0.0;
  EXPECT_THROW(ForceModel(cutter, test_coefficients(), step), InputError);
  ForceModelOptions helix;
  helix.helix_angle = kPi / 2;
  EXPECT_THROW(ForceModel(cutter, test_coefficients(), helix), InputError);
  ForceModelOptions flutes;
  flutes.flutes = -1;
  EXPECT_THROW(ForceModel(cutter, test_coefficients(), flutes), InputError);
  ForceModelOptions runout;
  runout.runout.offset = -0.01;
  EXPECT_THROW(ForceModel(cutter, test_coefficients(), runout), InputError);
}

TEST(ForceModel, FeedPerToothFromFeedAndSpindle) {
  EXPECT_DOUBLE_EQ(feed_per_tooth(800.0, 4, 10000.0), 0.02);
  EXPECT_EQ(feed_per_tooth(800.0, 4, 0.0), 0.0);
  EXPECT_EQ(feed_per_tooth(0.0, 4, 10000.0), 0.0);
}

}  // namespace
}  // namespace cwe

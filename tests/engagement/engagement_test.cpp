// Engagement maps against closed forms: slotting, up- and down-milling, half immersion, ball-end
// ramps, a plunge (docs/engagement.md; the conventions of docs/architecture.md).
#include "cwe/engagement/dexel_engagement.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "cwe/envelope/linear_sweep.hpp"
#include "cwe/kinematics/tool_state.hpp"
#include "cwe/simulation/simulation.hpp"
#include "cwe/tool/tool_spec.hpp"
#include "engagement_testing.hpp"

namespace cwe {
namespace {

constexpr double kDeg = kPi / 180.0;
constexpr double kSpacing = 0.1;

using test::line;

// Runs `moves` through a box of stock and returns the map at the CL sample nearest `probe`
// (tip position) among the samples.
struct Probe {
  EngagementMap map;
  ClPoint cl;
};
Probe engagement_near(const char* tool, const Aabb& block, const std::vector<Move>& moves,
                      const Vec3& probe, double cl_step = 0.5) {
  TriDexel stock = TriDexel::from_box(block, kSpacing);
  Toolpath path;
  path.sources = {"test"};
  path.moves = moves;
  const Cutter cutter = cutter_from_spec(tool);
  SimulationOptions options;
  options.resolution = kSpacing;
  SamplingOptions sampling;
  sampling.step = cl_step;
  Probe best;
  double nearest = 1e300;
  simulate_engagement(stock, cutter, path, {options, sampling, {}}, [&](const ClEngagement& e) {
    const double d = (e.cl.position - probe).norm();
    if (d < nearest) {
      nearest = d;
      best = {e.map, e.cl};
    }
  });
  EXPECT_LT(nearest, cl_step);
  return best;
}

// The angular tolerance of a boundary: the test point lies within s/√2 of the cell centre on the
// cutter surface, s/(√2 R) at radius R, plus the bisection's cell/64; 1° is asked for.
double angle_tolerance(double radius) { return kSpacing / (std::sqrt(2.0) * radius) + 0.1 * kDeg; }

// A flat end mill D = 10 at a depth of 3 mm in a block with its top at z = 20, moving +X along
// y = 20; the block's side faces decide the radial immersion.
constexpr double kTop = 20.0;
const std::vector<Move> kPass{line({-10, 20, kTop - 3}, {50, 20, kTop - 3})};
const Vec3 kSteady(25, 20, kTop - 3);

TEST(Engagement, FullSlot) {
  const Probe p = engagement_near("flat:10,20", {{0, 0, 0}, {60, 40, kTop}}, kPass, kSteady);
  ASSERT_TRUE(p.map.engaged);
  test::expect_discs(p.map, 0.0, 2.9, 0.0, kPi, angle_tolerance(5.0));
  EXPECT_NEAR(p.map.phi_entry, 0.0, angle_tolerance(5.0));
  EXPECT_NEAR(p.map.phi_exit, kPi, angle_tolerance(5.0));
  EXPECT_NEAR(p.map.axial_depth, 3.0, kSpacing);
  // A horizontal move: the flat bottom grazes (f = 0) and is not engaged.
  for (const RingEngagement& ring : p.map.rings) EXPECT_TRUE(ring.phi.empty());
  // Engaged area: half the cylinder to 3 mm, π R ap.
  EXPECT_NEAR(p.map.area, kPi * 5.0 * 3.0, kPi * 5.0 * kSpacing + 3.0 * 2 * kSpacing);
}

TEST(Engagement, UpAndDownMillingAndHalfImmersion) {
  const double r = 5.0;
  // Material left of the feed (+y) from y = 20 + R - ae: up-milling, φ ∈ [0, acos(1 - ae/R)].
  for (const double ae : {2.5, 5.0}) {
    SCOPED_TRACE(testing::Message() << "ae " << ae);
    const double edge = 20.0 + r - ae;
    const Probe up = engagement_near("flat:10,20", {{0, edge, 0}, {60, 40, kTop}}, kPass, kSteady);
    test::expect_discs(up.map, 0.0, 2.9, 0.0, std::acos(1.0 - ae / r), angle_tolerance(r));
    EXPECT_NEAR(up.map.axial_depth, 3.0, kSpacing);
    // Material right of the feed (-y) below y = 20 - R + ae: down-milling, [π - acos(1 - ae/R), π].
    const Probe down =
        engagement_near("flat:10,20", {{0, 0, 0}, {60, 20.0 - r + ae, kTop}}, kPass, kSteady);
    test::expect_discs(down.map, 0.0, 2.9, kPi - std::acos(1.0 - ae / r), kPi, angle_tolerance(r));
    EXPECT_NEAR(down.map.phi_entry, kPi - std::acos(1.0 - ae / r), angle_tolerance(r));
    EXPECT_NEAR(down.map.phi_exit, kPi, angle_tolerance(r));
  }
}

// A ball end mill of radius R ramping down into solid stock at angle γ: a disc at height z < R
// engages φ within ψ(z) = acos(-(R - z) tan γ / √(2Rz - z²)) of the feed direction (φ = 90°),
// the whole ring below z = R(1 - cos γ).
TEST(Engagement, BallEndRamp) {
  const double r = 5.0;
  for (const double gamma_deg : {15.0, 30.0}) {
    SCOPED_TRACE(testing::Message() << "ramp " << gamma_deg << "°");
    const double tan_g = std::tan(gamma_deg * kDeg);
    // Only the stock the ball meets: a block around the ramp, the tool buried at x = 18.
    const Vec3 start(-10, 20, 30), end(20, 20, 30 - 30 * tan_g);
    const Vec3 probe = start + (end - start) * (28.0 / 30.0);
    const Probe p =
        engagement_near("ball:10,8", {{0, 12, 5}, {24, 28, 40}}, {line(start, end)}, probe);
    int checked = 0;
    for (const DiscEngagement& disc : p.map.discs) {
      const double z = 0.5 * (disc.z0 + disc.z1);
      if (z < 0.3 || z > r - 0.3) continue;  // ψ(z) is steep at the tip and the equator
      const double rho = std::sqrt(2 * r * z - z * z);
      const double k = (r - z) * tan_g / rho;
      // The interval about φ = 90° (two pieces through φ = 0 when ψ > 90°).
      const double psi = k >= 1.0 ? kPi : std::acos(-k);
      // Within s of the height where k = 1 the disc's circle runs almost along the grazing circle
      // (the ball's lowest contour behind it), so the s/√2 placement on the surface allows a gap
      // at the back as wide as the next disc's, ψ(z + s): the points there are engaged only
      // through a sliver of fresh stock ahead of the grazing circle thinner than 1 µm.
      const double z_next = z + kSpacing;
      const double k_next = (r - z_next) * tan_g / std::sqrt(2 * r * z_next - z_next * z_next);
      if (k >= 1.0 && k_next < 1.0 && disc.phi.size() == 2) {
        const double psi_next = std::acos(-k_next);
        const double tolerance = kSpacing / (std::sqrt(2.0) * rho) + 0.2 * kDeg;
        EXPECT_GE(disc.phi[0].hi, kPi / 2 + psi_next - tolerance) << "z " << z;
        EXPECT_LE(disc.phi[1].lo, 2 * kPi - (psi_next - kPi / 2) + tolerance) << "z " << z;
        ++checked;
        continue;
      }
      ASSERT_EQ(disc.phi.size(), k >= 1.0 ? 1u : 2u) << "z " << z;
      // Tolerance: s/√2 on the surface is s/(√2 ρ) in φ, and the disc's height spread (its ψ
      // changes over s) adds s·|dψ/dz|.
      const double dpsi =
          std::abs(std::acos(-std::min(1.0, (r - z - kSpacing) * tan_g /
                                                std::sqrt(2 * r * (z + kSpacing) -
                                                          (z + kSpacing) * (z + kSpacing)))) -
                   psi);
      const double tolerance = kSpacing / (std::sqrt(2.0) * rho) + dpsi + 0.2 * kDeg;
      if (k >= 1.0) {
        EXPECT_NEAR(disc.phi[0].lo, 0.0, 1e-12);
        EXPECT_NEAR(disc.phi[0].hi, 2 * kPi, 1e-12);
      } else {
        // [0, 90° + ψ] and [270° + (90° - ψ)… 2π]: ψ > 90° here since tan γ > 0.
        EXPECT_NEAR(disc.phi[0].lo, 0.0, 1e-12);
        EXPECT_NEAR(disc.phi[0].hi, kPi / 2 + psi, tolerance) << "z " << z;
        EXPECT_NEAR(disc.phi[1].lo, 2 * kPi - (psi - kPi / 2), tolerance) << "z " << z;
        EXPECT_NEAR(disc.phi[1].hi, 2 * kPi, 1e-12);
      }
      ++checked;
    }
    EXPECT_GT(checked, 30);
  }
}

TEST(Engagement, PlungeEngagesTheWholeBottom) {
  const Probe p =
      engagement_near("flat:10,20", {{0, 0, 0}, {60, 40, kTop}},
                      {line({30, 20, kTop + 2}, {30, 20, kTop - 6})}, Vec3(30, 20, kTop - 4));
  ASSERT_FALSE(p.map.rings.empty());
  for (const RingEngagement& ring : p.map.rings) {
    ASSERT_EQ(ring.phi.size(), 1u) << ring.r0;
    EXPECT_EQ(ring.phi[0].lo, 0.0);
    EXPECT_EQ(ring.phi[0].hi, 2 * kPi);
  }
  // The side moves along itself (f = 0): not engaged.
  for (const DiscEngagement& disc : p.map.discs) EXPECT_TRUE(disc.phi.empty()) << disc.z0;
  EXPECT_EQ(p.map.phi_entry, 0.0);
  EXPECT_EQ(p.map.phi_exit, 2 * kPi);
  EXPECT_EQ(p.map.axial_depth, 0.0);
  EXPECT_NEAR(p.map.area, kPi * 25.0, 1e-9);
}

TEST(Engagement, NothingEngagedInAir) {
  const Probe p =
      engagement_near("bull:10,2,20", {{0, 0, 0}, {60, 40, kTop}},
                      {line({-10, 20, kTop + 1}, {50, 20, kTop + 1})}, Vec3(25, 20, kTop + 1));
  EXPECT_FALSE(p.map.engaged);
  EXPECT_EQ(p.map.area, 0.0);
  EXPECT_EQ(p.map.phi_entry, 0.0);
  EXPECT_EQ(p.map.phi_exit, 0.0);
}

// A side disc of an upright tool takes the intervals of the disc below when the rays it reads
// lost the same in the step and its front is the same (DexelEngagement, reuse_alike_discs). In
// the slot every disc's rays lose alike: on a translation every disc has the same intervals,
// while a turn about X tilts the front from height to height (ω × h·z adds -hω along Y to the
// velocity) and each disc has its own. Either way, the map is the one every disc's own scan finds.
TEST(Engagement, DiscsTakeTheIntervalsBelowOnlyWhereTheyWouldFindThem) {
  const Cutter cutter = cutter_from_spec("flat:10,20");
  TriDexel stock = TriDexel::from_box({{0, 0, 0}, {60, 40, kTop}}, kSpacing);
  const Vec3 tip(25, 20, kTop - 3), next(25.5, 20, kTop - 3);
  const LinearSweep slot(cutter, {-10, 20, kTop - 3}, tip, Vec3::UnitZ());
  stock.remove(slot.bounds(), [&slot](const Ray& ray) { return slot.chord(ray); });
  const LinearSweep step(cutter, tip, next, Vec3::UnitZ());
  RemovalRecord record;
  stock.remove({{step.bounds(), [&step](const Ray& ray) { return step.chord(ray); }, {}, {}}},
               &record);
  EngagementOptions scan_each;
  scan_each.reuse_alike_discs = false;
  const DexelEngagement fast(cutter, kSpacing), full(cutter, kSpacing, scan_each);
  for (const double turn : {0.0, 0.3}) {
    SCOPED_TRACE(testing::Message() << "turn " << turn);
    const ToolState state = tool_state(tip, Vec3::UnitZ(), Vec3::UnitX(), Vec3(turn, 0, 0));
    const EngagementMap reused = fast.at(stock, record, state);
    const EngagementMap own = full.at(stock, record, state);
    ASSERT_EQ(reused.discs.size(), own.discs.size());
    std::vector<std::vector<Interval>> kinds;  // the engaged discs' different interval sets
    for (std::size_t d = 0; d < own.discs.size(); ++d) {
      const std::vector<Interval>& mine = reused.discs[d].phi;
      const std::vector<Interval>& theirs = own.discs[d].phi;
      ASSERT_EQ(mine.size(), theirs.size()) << "disc " << d;
      for (std::size_t i = 0; i < mine.size(); ++i) {
        EXPECT_EQ(mine[i].lo, theirs[i].lo) << "disc " << d;
        EXPECT_EQ(mine[i].hi, theirs[i].hi) << "disc " << d;
      }
      const auto same = [&theirs](const std::vector<Interval>& k) {
        return std::equal(
            k.begin(), k.end(), theirs.begin(), theirs.end(),
            [](const Interval& a, const Interval& b) { return a.lo == b.lo && a.hi == b.hi; });
      };
      if (!theirs.empty() && std::none_of(kinds.begin(), kinds.end(), same)) {
        kinds.push_back(theirs);
      }
    }
    EXPECT_NEAR(own.axial_depth, 3.0, kSpacing);
    if (turn == 0.0) {
      EXPECT_EQ(kinds.size(), 1u);
    } else {
      EXPECT_GT(kinds.size(), 10u);
    }
  }
}

}  // namespace
}  // namespace cwe

// The solid-model CWE on the B-rep workpiece (BrepWorkpiece, Aras 2008 §6.1): slotting, up- and
// down-milling, a bull-nose slot, a ball end on ramps, a plunge and a helix against their closed
// forms within 0.1°, and a tilted 3+2 pass and a simultaneous 5-axis one against the dexel
// method within its bound.
//
// What the tolerances cover: the B-rep method reads each disc's circle exactly (its boundaries
// are crossings of that circle with the removal volume's exact faces, or roots of f), a hair
// (contact/1000 = 1e-5 mm) outside the cutter; so against a closed form evaluated at the same
// circle, a boundary is off by OpenCASCADE's tolerances only (the booleans' fuzzy value, 1e-6
// of the stock's size, 1e-4 mm here: 1e-3° at R = 5). The 0.1° the tests ask is the issue's.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "cwe/core/computation_error.hpp"
#include "cwe/engagement/brep_workpiece.hpp"
#include "cwe/engagement/engagement_grid.hpp"
#include "cwe/simulation/simulation.hpp"
#include "cwe/tool/tool_spec.hpp"
#include "cwe/workpiece/brep/brep_stock.hpp"
#include "engagement_testing.hpp"

namespace cwe {
namespace {

constexpr double kDeg = kPi / 180.0;
constexpr double kSpacing = 0.1;  // the grid's disc height
constexpr double kAngle = 0.1 * kDeg;
constexpr double kTop = 20.0;

// The map at the CL sample nearest `probe` of `moves` cut through `block` on the B-rep
// workpiece (on move `on_move` when it is not negative), sampled every `step` mm; arcs and
// 5-axis moves cut into pieces within `subdivision` (0: s/10).
EngagementMap brep_engagement_near(const char* tool, const Aabb& block,
                                   const std::vector<Move>& moves, const Vec3& probe,
                                   int on_move = -1, double step = 0.5, double subdivision = 0.0) {
  BrepStock stock = BrepStock::from_box(block);
  BrepWorkpiece workpiece(stock, kSpacing);
  Toolpath path;
  path.sources = {"test"};
  path.moves = moves;
  const Cutter cutter = cutter_from_spec(tool);
  SamplingOptions sampling;
  sampling.step = step;
  EngagementMap best;
  double nearest = 1e300;
  simulate_engagement(workpiece, cutter, path, {{kSpacing, subdivision}, sampling, {}},
                      [&](const ClEngagement& e) {
                        if (on_move >= 0 && e.cl.move != on_move) return;
                        const double d = (e.cl.position - probe).norm();
                        if (d < nearest) {
                          nearest = d;
                          best = e.map;
                        }
                      });
  EXPECT_LT(nearest, step);
  return best;
}

// The heights of the circles the grid reads on `tool`'s discs, in the map's order.
std::vector<double> circle_heights(const char* tool) {
  const Cutter cutter = cutter_from_spec(tool);
  const EngagementGrid grid(cutter, kSpacing, {});
  std::vector<double> z;
  for (const EngagementGrid::Band& band : grid.discs()) z.push_back(band.z);
  return z;
}

const std::vector<Move> kPass{test::line({-10, 20, kTop - 3}, {50, 20, kTop - 3})};
const Vec3 kSteady(25, 20, kTop - 3);

TEST(BrepEngagement, FullSlot) {
  const EngagementMap map =
      brep_engagement_near("flat:10,20", {{0, 0, 0}, {60, 40, kTop}}, kPass, kSteady);
  ASSERT_TRUE(map.engaged);
  test::expect_discs(map, 0.0, 2.95, 0.0, kPi, kAngle);
  EXPECT_NEAR(map.axial_depth, 3.0, 1e-9);
  for (const RingEngagement& ring : map.rings) EXPECT_TRUE(ring.phi.empty());
  // The front half of the cylinder up to 3 mm, which the discs tile, less the grazing strips
  // at both sides (each √(2·3e-7/5) rad wide: the circle read lies 2e-7 mm outside the cutter and
  // must be 1e-7 inside the wall to count): 2e-4 of it.
  EXPECT_NEAR(map.area, kPi * 5.0 * 3.0, 2e-4 * kPi * 5.0 * 3.0);
}

TEST(BrepEngagement, UpAndDownMillingAndHalfImmersion) {
  const double r = 5.0;
  for (const double ae : {1.0, 2.5, 5.0}) {
    SCOPED_TRACE(testing::Message() << "ae " << ae);
    const double edge = 20.0 + r - ae;
    const EngagementMap up =
        brep_engagement_near("flat:10,20", {{0, edge, 0}, {60, 40, kTop}}, kPass, kSteady);
    test::expect_discs(up, 0.0, 2.95, 0.0, std::acos(1.0 - ae / r), kAngle);
    EXPECT_NEAR(up.axial_depth, 3.0, 1e-9);
    const EngagementMap down =
        brep_engagement_near("flat:10,20", {{0, 0, 0}, {60, 20.0 - r + ae, kTop}}, kPass, kSteady);
    test::expect_discs(down, 0.0, 2.95, kPi - std::acos(1.0 - ae / r), kPi, kAngle);
    EXPECT_NEAR(down.phi_entry, kPi - std::acos(1.0 - ae / r), kAngle);
    EXPECT_NEAR(down.phi_exit, kPi, kAngle);
  }
}

// A bull-nose end mill (corner radius 2) slotting 3 mm deep: the torus and the cylinder engage
// the front half, each disc from its grazing line on one side to the other's; the flat bottom
// grazes.
TEST(BrepEngagement, BullNoseSlot) {
  const EngagementMap map =
      brep_engagement_near("bull:10,2,20", {{0, 0, 0}, {60, 40, kTop}}, kPass, kSteady);
  int checked = 0;
  for (const DiscEngagement& disc : map.discs) {
    if (disc.z1 > 2.95) continue;
    SCOPED_TRACE(testing::Message() << "disc " << disc.z0);
    ASSERT_EQ(disc.phi.size(), 1u);
    EXPECT_NEAR(disc.phi[0].lo, 0.0, kAngle);
    EXPECT_NEAR(disc.phi[0].hi, kPi, kAngle);
    ++checked;
  }
  EXPECT_GT(checked, 25);
  EXPECT_NEAR(map.axial_depth, 3.0, 1e-9);
  for (const RingEngagement& ring : map.rings) EXPECT_TRUE(ring.phi.empty());
  // π ∫ρ ds over the profile up to 3 mm: the corner arc from (3, 0) to (5, 2), then the
  // cylinder; the discs sample the corner's ρ at one height each, s = 0.1 apart, which moves
  // the area by about s²/2 per unit of ρ's second derivative: well within 1 %.
  EXPECT_NEAR(map.area, kPi * (2.0 * (1.5 * kPi + 2.0) + 5.0), 0.01 * map.area);
}

// A ball end mill of radius R ramping down into solid stock at angle γ: a circle at height z < R
// engages φ within ψ(z) = acos(-(R - z) tan γ / √(2Rz - z²)) of the feed direction (φ = 90°),
// the whole circle below z = R(1 - cos γ) (engagement_test.cpp, BallEndRamp). Here ψ is taken at
// the height of the circle the grid reads, so the 0.1° holds on every disc.
TEST(BrepEngagement, BallEndRamp) {
  const double r = 5.0;
  const std::vector<double> heights = circle_heights("ball:10,8");
  for (const double gamma_deg : {15.0, 30.0}) {
    SCOPED_TRACE(testing::Message() << "ramp " << gamma_deg << "°");
    const double tan_g = std::tan(gamma_deg * kDeg);
    const Vec3 start(-10, 20, 30), end(20, 20, 30 - 30 * tan_g);
    const EngagementMap map =
        brep_engagement_near("ball:10,8", {{0, 12, 5}, {24, 28, 40}}, {test::line(start, end)},
                             start + (end - start) * (28.0 / 30.0));
    ASSERT_EQ(map.discs.size(), heights.size());
    int checked = 0;
    for (std::size_t k = 0; k < map.discs.size(); ++k) {
      const double z = heights[k];
      if (z > r - 0.05) continue;
      const double rho = std::sqrt(2 * r * z - z * z);
      const double c = (r - z) * tan_g / rho;
      const DiscEngagement& disc = map.discs[k];
      SCOPED_TRACE(testing::Message() << "z " << z);
      if (c >= 1.0) {
        ASSERT_EQ(disc.phi.size(), 1u);
        EXPECT_EQ(disc.phi[0].lo, 0.0);
        EXPECT_EQ(disc.phi[0].hi, 2 * kPi);
      } else {
        const double psi = std::acos(-c);
        ASSERT_EQ(disc.phi.size(), 2u);
        EXPECT_EQ(disc.phi[0].lo, 0.0);
        EXPECT_NEAR(disc.phi[0].hi, kPi / 2 + psi, kAngle);
        EXPECT_NEAR(disc.phi[1].lo, 2 * kPi - (psi - kPi / 2), kAngle);
        EXPECT_EQ(disc.phi[1].hi, 2 * kPi);
      }
      ++checked;
    }
    EXPECT_GT(checked, 45);
  }
}

// The thesis's figure 6.11 (a flat end mill on a linear descending 3-axis move; its dimensions are
// not given, these are ours): the side engages its front half, 0 to π, down to the tip; the
// bottom, a front face all over (the tool moves down), engages every ring whole, 0 to 2π (the
// material under it was not taken by the higher positions before; the lower ones after take it).
TEST(BrepEngagement, ThesisFlatEndMillDescendingRamp) {
  const double tan_g = std::tan(15.0 * kDeg);
  const Vec3 start(12, 20, 21), end(40, 20, 21 - 28 * tan_g);
  const Vec3 probe(30, 20, 21 - 18 * tan_g);  // 3.8 mm deep, the tool's back 9 mm in
  const EngagementMap map = brep_engagement_near("flat:10,20", {{0, 0, 0}, {60, 40, kTop}},
                                                 {test::line(start, end)}, probe, -1, 1.0);
  ASSERT_TRUE(map.engaged);
  // Sampled every 1 mm: the CL read is within 0.5 mm of the probe, its depth within 0.5 tan γ.
  EXPECT_NEAR(map.axial_depth, kTop - probe.z(), 0.5 * tan_g + 1e-6);
  test::expect_discs(map, 0.0, map.axial_depth - kSpacing, 0.0, kPi, kAngle);
  ASSERT_FALSE(map.rings.empty());
  for (const RingEngagement& ring : map.rings) {
    ASSERT_EQ(ring.phi.size(), 1u) << ring.r0;
    EXPECT_EQ(ring.phi[0].lo, 0.0);
    EXPECT_EQ(ring.phi[0].hi, 2 * kPi);
  }
}

// The thesis's figure 6.12 (a tapered end mill ramping up; dimensions ours): only the front of
// the cone engages. A cone of half-angle β moving at γ upwards has n·v > 0 where cos θ >
// tan β tan γ (θ from the feed), and there only: the positions before, lower and behind, are
// wider at each height by d tan γ tan β, which covers the points with cos θ < tan β tan γ and no
// others. So each disc engages φ within ψ = acos(tan β tan γ) of the feed (φ = 90°), narrower
// than the flat end's half (87.3° at β = 10°, γ = 15°), and the bottom, a back face, nothing.
TEST(BrepEngagement, ThesisTaperedEndMillAscendingRamp) {
  const double tan_g = std::tan(15.0 * kDeg);
  const Vec3 start(5, 20, 10), end(45, 20, 10 + 40 * tan_g);
  const Vec3 probe = start + (end - start) * 0.5;  // x = 25, 4.6 mm deep
  const double depth = kTop - probe.z();
  const EngagementMap map = brep_engagement_near("taper-flat:8,10,20", {{0, 0, 0}, {60, 40, kTop}},
                                                 {test::line(start, end)}, probe);
  ASSERT_TRUE(map.engaged);
  const double psi = std::acos(std::tan(10.0 * kDeg) * tan_g);
  test::expect_discs(map, 0.0, depth - 0.5, kPi / 2 - psi, kPi / 2 + psi, kAngle);
  for (const RingEngagement& ring : map.rings) EXPECT_TRUE(ring.phi.empty()) << ring.r0;
}

// A helix passes over its own path: at a location on its second turn, the RV in front of the
// tool above the first turn's floor (1 mm pitch higher) was taken a turn before, and is not
// engaged. Only the bore's wall at radius R_helix + r touches the side there, along a grazing
// line; below, the ramp engages the front half. (A turn and a quarter, sampled every 2 mm: the
// helix's RV has pipe-shell faces, whose crossings with the circles are OpenCASCADE's slowest.)
TEST(BrepEngagement, HelixDoesNotEngageWhatItsLastTurnTook) {
  Move helix;
  helix.shape = MoveShape::kArc;
  helix.feed_rate = 400.0;
  helix.normal = Vec3::UnitZ();             // G3
  helix.center = Vec3(30, 20, kTop - 1.5);  // starting in the material
  helix.start = helix.center + Vec3(6, 0, 0);
  helix.sweep = 1.25 * kTwoPi;
  helix.axial = -1.25;  // 1 mm a turn
  helix.end = helix.position(1.0);
  const Vec3 probe = helix.position(0.96);  // 2.7 mm deep, 1 mm below the turn before
  const EngagementMap map =
      brep_engagement_near("flat:10,20", {{0, 0, 0}, {60, 40, kTop}}, {helix}, probe, -1, 2.0);
  ASSERT_TRUE(map.engaged);
  int above = 0, below = 0;
  for (const DiscEngagement& disc : map.discs) {
    double width = 0.0;
    for (const Interval& phi : disc.phi) width += phi.hi - phi.lo;
    if (disc.z0 > 1.0 + 2 * kSpacing) {
      // The wall's grazing line, widened by the band where the point read lies less than the
      // contact tolerance (0.01 mm) inside the turn before's tool and so is not known to be
      // taken: about 2·acos(1 - 0.01/5).
      EXPECT_LE(width, 2.0 * std::acos(1.0 - 0.01 / 5.0) + kAngle) << "disc " << disc.z0;
      ++above;
    } else if (disc.z1 < 0.5) {
      EXPECT_EQ(disc.phi.size(), 1u) << "disc " << disc.z0;
      EXPECT_GE(width, kPi / 2) << "disc " << disc.z0;
      ++below;
    }
  }
  EXPECT_GT(above, 0);
  EXPECT_GT(below, 0);
}

TEST(BrepEngagement, PlungeEngagesTheWholeBottom) {
  const EngagementMap map = brep_engagement_near(
      "flat:10,20", {{0, 0, 0}, {60, 40, kTop}},
      {test::line({30, 20, kTop + 2}, {30, 20, kTop - 6})}, Vec3(30, 20, kTop - 4));
  ASSERT_FALSE(map.rings.empty());
  for (const RingEngagement& ring : map.rings) {
    ASSERT_EQ(ring.phi.size(), 1u) << ring.r0;
    EXPECT_EQ(ring.phi[0].lo, 0.0);
    EXPECT_EQ(ring.phi[0].hi, 2 * kPi);
  }
  for (const DiscEngagement& disc : map.discs) EXPECT_TRUE(disc.phi.empty()) << disc.z0;
  EXPECT_EQ(map.axial_depth, 0.0);
  EXPECT_NEAR(map.area, kPi * 25.0, 1e-6);
}

TEST(BrepEngagement, NothingEngagedInAir) {
  const EngagementMap map = brep_engagement_near(
      "bull:10,2,20", {{0, 0, 0}, {60, 40, kTop}},
      {test::line({-10, 20, kTop + 1}, {50, 20, kTop + 1})}, Vec3(25, 20, kTop + 1));
  EXPECT_FALSE(map.engaged);
}

// The maps of the B-rep and the dexel workpieces at the location nearest `probe` agree within
// `tolerance` on every disc both engage; the disc at the top of the cut may be engaged by one
// method only (depth within 2s).
void expect_agrees_with_dexel(const char* tool, const Aabb& block, const Move& pass,
                              const Vec3& probe, double subdivision, double tolerance) {
  const EngagementMap brep = brep_engagement_near(tool, block, {pass}, probe, -1, 0.5, subdivision);
  test::expect_agrees_with_dexel(
      brep, test::dexel_map_near({pass}, tool, block, kSpacing, subdivision, probe), tolerance,
      kSpacing);
}

// A flat end mill D = 8 tilted 20° sideways (3+2), 3 mm deep along the block's edge: the same
// map as the dexel method's at the same location, within the dexel's own bound (a cell's
// s/(√2·R) and 0.1° of its bisection) plus the 0.1° asked of the B-rep method.
TEST(BrepEngagement, TiltedThreePlusTwoAgreesWithTheDexelMethod) {
  const double r = 4.0;
  Move pass = test::line({28, -10, kTop - 3}, {28, 50, kTop - 3});
  pass.start_axis = pass.end_axis = Vec3(std::sin(20 * kDeg), 0.0, std::cos(20 * kDeg));
  expect_agrees_with_dexel("flat:8,20", {{0, 0, 0}, {30, 40, kTop}}, pass, Vec3(28, 20, kTop - 3),
                           0.0, kSpacing / (std::sqrt(2.0) * r) + 0.1 * kDeg + kAngle);
}

// The same pass with the tilt swinging from 10° to 30° along it (simultaneous 5-axis): the dexel
// workpiece cuts the move in linear pieces within the subdivision tolerance t (38 for this tool
// at t = 0.1 mm), the B-rep one lofts it within t (lofted_sweep_solid), and
// each reads the tool at a location in its true pose: a boundary moves by up to t/R more, on top
// of the 3+2 bound.
TEST(BrepEngagement, SimultaneousFiveAxisAgreesWithTheDexelMethod) {
  const double r = 4.0, t = 0.1;
  Move pass = test::line({28, -10, kTop - 3}, {28, 50, kTop - 3});
  pass.start_axis = Vec3(std::sin(10 * kDeg), 0.0, std::cos(10 * kDeg));
  pass.end_axis = Vec3(std::sin(30 * kDeg), 0.0, std::cos(30 * kDeg));
  expect_agrees_with_dexel("flat:8,10", {{0, 0, 0}, {30, 40, kTop}}, pass, Vec3(28, 20, kTop - 3),
                           t, kSpacing / (std::sqrt(2.0) * r) + 0.1 * kDeg + kAngle + t / r);
}

// The bundled example's helical entry (3 turns of 1 mm pitch on a 6 mm radius from 1 mm above
// the block, a 10 mm end mill), cut exactly: as its last turn with the tool lengthened by the two
// turns over it (helix_sweep_solids). Cut in half turns along the whole helix, the booleans
// refused it from the fifth on (the floors' B-spline tubes under the turn before's). Against the
// dexel workpiece at s = 0.1: within s/2 over the cavity's surface, the dexel's own bound (the
// floor π(11² − 1²) = 377 mm² and walls of radius 11 and 1 at most 2 mm high: under 530 mm²).
TEST(BrepEngagement, HelixOfSeveralTurnsIsCutExactly) {
  Move helix;
  helix.shape = MoveShape::kArc;
  helix.feed_rate = 400.0;
  helix.normal = Vec3::UnitZ();
  helix.center = Vec3(74, 30, 1);
  helix.start = Vec3(80, 30, 1);
  helix.sweep = 3 * kTwoPi;
  helix.axial = -3.0;
  helix.end = helix.position(1.0);
  const Aabb block{{0, 0, -30}, {100, 60, 0}};
  const Cutter cutter = cutter_from_spec("flat:10,30");
  Toolpath path;
  path.sources = {"test"};
  path.moves = {helix};
  const double t = 0.1;
  BrepStock stock = BrepStock::from_box(block);
  BrepWorkpiece workpiece(stock, kSpacing);
  double exact = 0.0;
  for (const double v : remove_toolpath(workpiece, cutter, path, {kSpacing, t}).removed_by_move) {
    exact += v;
  }
  EXPECT_EQ(stock.moves_in_lines(), 0);
  TriDexel rays = TriDexel::from_box(block, kSpacing);
  double dexel = 0.0;
  for (const double v : remove_toolpath(rays, cutter, path, {kSpacing, t}).removed_by_move) {
    dexel += v;
  }
  EXPECT_NEAR(exact, dexel, 0.5 * kSpacing * 530.0);  // measured: 0.1 mm³
}

// What each move of `path` takes from `block` on the B-rep workpiece (exact) and on the dexel one,
// at spacing s and sweep tolerance t, with the B-rep stock's counts of lofted moves and of moves
// cut as linear pieces.
struct Removals {
  std::vector<double> exact, dexel;
  int lofted = 0, in_lines = 0;
};
Removals removed_on_both(const Aabb& block, const Cutter& cutter, const Toolpath& path, double s,
                         double t) {
  Removals r;
  BrepStock stock = BrepStock::from_box(block);
  BrepWorkpiece workpiece(stock, s);
  r.exact = remove_toolpath(workpiece, cutter, path, {s, t}).removed_by_move;
  r.lofted = stock.moves_lofted();
  r.in_lines = stock.moves_in_lines();
  TriDexel rays = TriDexel::from_box(block, s);
  r.dexel = remove_toolpath(rays, cutter, path, {s, t}).removed_by_move;
  return r;
}

// A tilt in place at the end of a slot (a 6 mm end mill 2 mm deep, tilting 30° sideways, then
// across, then back upright: BrepShapes.TiltInPlaceIsTheUnionOfItsPoses holds its solids to the
// union of the poses) is cut exactly, not as linear pieces, and removes what the dexel workpiece
// removes at s = 0.05 (its linear pieces within 0.005 mm): the three tilts take 36.0 mm³; the
// dexel's error, s/2 over the wedges' new faces (some 40 mm²), bounds the difference.
TEST(BrepEngagement, TiltInPlaceIsCutExactly) {
  const Aabb block{{0, 0, -8}, {30, 20, 0}};
  const Cutter cutter = cutter_from_spec("flat:6,20");
  const Vec3 at(10, 10, -2), up = Vec3::UnitZ();
  Toolpath path;
  path.sources = {"test"};
  // A move of the tip from `from` to `to` with the axis turning from `a0` to `a1`.
  const auto tilt = [](const Vec3& from, const Vec3& to, const Vec3& a0, const Vec3& a1) {
    Move move = test::line(from, to);
    move.start_axis = a0.normalized();
    move.end_axis = a1.normalized();
    return move;
  };
  const Vec3 side(0, -0.5, 0.866025), across(0.5, 0, 0.866025);
  path.moves = {test::line({-5, 10, -2}, at), tilt(at, at, up, side), tilt(at, at, side, across),
                tilt(at, at, across, up), test::line(at, {25, 10, -2})};
  const double s = 0.05, t = 0.005;
  const Removals r = removed_on_both(block, cutter, path, s, t);
  const std::vector<double>& exact = r.exact;
  const std::vector<double>& dexel = r.dexel;
  EXPECT_EQ(r.in_lines, 0);
  ASSERT_EQ(exact.size(), 5u);
  ASSERT_EQ(dexel.size(), 5u);
  const double tilts = exact[1] + exact[2] + exact[3];
  EXPECT_GT(tilts, 20.0);
  EXPECT_NEAR(tilts, dexel[1] + dexel[2] + dexel[3], 0.5 * s * 40.0);  // measured: 0.05 mm³
  double total = 0.0, total_dexel = 0.0;
  for (std::size_t k = 0; k < 5; ++k) {
    total += exact[k];
    total_dexel += dexel[k];
  }
  EXPECT_NEAR(total, total_dexel, 0.5 * s * 200.0);  // the slot's surface under 200 mm²
}

// A 5-axis retract from a slot's end (a 6 mm end mill 2 mm deep), 60 mm up and 10 mm on while
// its axis tilts 30° forward: it shaves a wedge off the slot's end wall as it leaves. Only the
// stretch of the move whose pieces can come near the block is lofted (most of its pieces are
// far above it); that stretch must hold all the move takes: against the dexel workpiece at
// s = 0.05, within its error of s/2 over the wedge's new faces (under 40 mm²). Measured: 2.04
// against 2.05 mm³; a loft of the move's other end takes nothing. The same move backwards (an
// approach that plunges into the block, its stretch at its end) takes a pocket of 58.6 mm³
// (58.589 against 58.587): within s/2 over its floor, wall and wedge (under 120 mm²).
TEST(BrepEngagement, FiveAxisMovesAreLoftedWhereTheyMeetTheBlock) {
  const Aabb block{{0, 0, -8}, {30, 20, 0}};
  const Cutter cutter = cutter_from_spec("flat:6,20");
  const Vec3 end(15, 10, -2), above(25, 10, 58), slot_start(-5, 10, -2);
  const Vec3 tilted = Vec3(0.5, 0, 0.866025).normalized();
  const double s = 0.05, t = 0.005;
  // The 5-axis move from `from` to `to` (axis `a0` to `a1`) and the slot, in that order or the
  // other: what each takes on both workpieces, the 5-axis move lofted.
  const auto cut = [&](const Vec3& from, const Vec3& to, const Vec3& a0, const Vec3& a1,
                       bool slot_first) {
    Toolpath path;
    path.sources = {"test"};
    Move move = test::line(from, to);
    move.start_axis = a0;
    move.end_axis = a1;
    const Move slot = slot_first ? test::line(slot_start, end) : test::line(end, slot_start);
    path.moves = slot_first ? std::vector<Move>{slot, move} : std::vector<Move>{move, slot};
    Removals r = removed_on_both(block, cutter, path, s, t);
    EXPECT_EQ(r.lofted, 1);
    EXPECT_EQ(r.in_lines, 0);
    EXPECT_EQ(r.exact.size(), 2u);
    EXPECT_EQ(r.dexel.size(), 2u);
    r.exact.resize(2, 0.0);
    r.dexel.resize(2, 0.0);
    return r;
  };
  const Removals retract = cut(end, above, Vec3::UnitZ(), tilted, true);
  EXPECT_GT(retract.dexel[1], 1.0);
  EXPECT_NEAR(retract.exact[1], retract.dexel[1], 0.5 * s * 40.0);   // measured: 0.01 mm³
  EXPECT_NEAR(retract.exact[0], retract.dexel[0], 0.5 * s * 200.0);  // the slot's surface
  const Removals approach = cut(above, end, tilted, Vec3::UnitZ(), false);
  EXPECT_GT(approach.dexel[0], 50.0);
  EXPECT_NEAR(approach.exact[0], approach.dexel[0], 0.5 * s * 120.0);  // measured: 0.002 mm³
  EXPECT_NEAR(approach.exact[1], approach.dexel[1], 0.5 * s * 200.0);
}

// Where no attempt gives a removal volume that holds what the stock lost, the engagement reads
// the stock before the cut (BrepStock::cut): at the points it tests, just outside the cutter
// where it moves into the material and so inside the swept volume, W ∩ SV and W are the same.
// Read so at every location of a flat end mill's slot, a pass back along the wall the slot left
// (3 mm of radial depth) and a ramp, the maps are those the removal volumes give. Both read the
// same faces of the stock; what parts them is where f is so small that the tool does not reach
// the circle read, 2e-7 mm outside it, before the move ends: at a grazing line (f = 0), within
// √(2·2e-7/ρ) of it (2.8e-4 rad on the 5 mm radius), the stock counts the material there and
// the removal volume does not. That, plus 1e-4 rad for OpenCASCADE's tolerances (the fuzzy
// value, 1e-6 of the stock's size, is 1.5e-5 rad at 5 mm), is what every interval is held to.
TEST(BrepEngagement, ReadingTheStockBeforeTheCutGivesTheRemovalVolumesMaps) {
  const Aabb block{{0, 0, 0}, {60, 40, kTop}};
  Toolpath path;
  path.sources = {"test"};
  path.moves = {test::line({-10, 20, kTop - 3}, {50, 20, kTop - 3}),
                test::line({50, 20, kTop - 3}, {50, 23, kTop - 3}),
                test::line({50, 23, kTop - 3}, {-10, 23, kTop - 3}),
                test::line({-10, 23, kTop - 3}, {30, 12, kTop - 5})};
  const Cutter cutter = cutter_from_spec("flat:10,20");
  SamplingOptions sampling;
  sampling.step = 1.0;
  const auto maps = [&](bool reads_stock) {
    BrepStock stock = BrepStock::from_box(block);
    stock.refuse_removal_volumes(reads_stock);
    BrepWorkpiece workpiece(stock, kSpacing);
    std::vector<EngagementMap> out;
    simulate_engagement(workpiece, cutter, path, {{kSpacing, 0.0}, sampling, {}},
                        [&](const ClEngagement& e) { out.push_back(e.map); });
    // Every move's cut read from the stock before it, or none.
    EXPECT_EQ(stock.removal_volumes_replaced(), reads_stock ? 4 : 0);
    return out;
  };
  const std::vector<EngagementMap> from_rv = maps(false), from_stock = maps(true);
  ASSERT_EQ(from_rv.size(), from_stock.size());
  int engaged = 0;
  // Intervals on a circle of radius rho.
  const auto same = [](const std::vector<Interval>& a, const std::vector<Interval>& b, double rho) {
    const double tolerance = std::sqrt(2.0 * 2e-7 / rho) + 1e-4;
    if (a.size() != b.size()) return false;
    for (std::size_t k = 0; k < a.size(); ++k) {
      if (std::abs(a[k].lo - b[k].lo) > tolerance || std::abs(a[k].hi - b[k].hi) > tolerance) {
        return false;
      }
    }
    return true;
  };
  for (std::size_t cl = 0; cl < from_rv.size(); ++cl) {
    const EngagementMap &a = from_rv[cl], &b = from_stock[cl];
    engaged += a.engaged ? 1 : 0;
    ASSERT_EQ(a.engaged, b.engaged) << "CL " << cl;
    ASSERT_EQ(a.discs.size(), b.discs.size());
    for (std::size_t k = 0; k < a.discs.size(); ++k) {
      EXPECT_TRUE(same(a.discs[k].phi, b.discs[k].phi, 5.0)) << "CL " << cl << ", disc " << k;
    }
    ASSERT_EQ(a.rings.size(), b.rings.size());
    for (std::size_t k = 0; k < a.rings.size(); ++k) {
      EXPECT_TRUE(same(a.rings[k].phi, b.rings[k].phi, 0.5 * (a.rings[k].r0 + a.rings[k].r1)))
          << "CL " << cl << ", ring " << k;
    }
  }
  // The slot, the pass back and the ramp are cut: most of the 60 + 60 + 42 locations engage.
  EXPECT_GT(engaged, 140);
}

}  // namespace
}  // namespace cwe

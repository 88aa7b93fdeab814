// Engagement where earlier passes left walls and floors exactly where the cutter runs: step-downs,
// repeated passes, ring grooves, stepovers, contour finishing, a tool edge along a stock face and
// ball-end rasters, each against its closed form (CWE = FCS ∩ (W ∩ SV), docs/engagement.md).
// The programs are G-code, as a user writes them.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "cwe/engagement/dexel_engagement.hpp"
#include "cwe/process/force_model.hpp"
#include "cwe/simulation/simulation.hpp"
#include "cwe/tool/tool_spec.hpp"
#include "cwe/toolpath/cldata_reader.hpp"
#include "cwe/toolpath/gcode_reader.hpp"
#include "engagement/engagement_testing.hpp"
#include "process/process_testing.hpp"
#include "source_dir.hpp"

namespace cwe {
namespace {

constexpr double kDeg = kPi / 180.0;
constexpr double kSpacing = 0.1;
// The stock of the examples: tip coordinates, top face at z = 0.
const Aabb kBlock{{0, 0, -20}, {100, 60, 0}};

using test::Sample;

// Every cutter location of `path` cut by `tool` through `block`.
std::vector<Sample> simulate(const Toolpath& path, const char* tool, const Aabb& block = kBlock) {
  return test::simulate_samples(path, tool, block, kSpacing, 0.5);
}

// The same for a G-code program.
std::vector<Sample> simulate(const std::string& program, const char* tool,
                             const Aabb& block = kBlock) {
  return simulate(read_gcode(program, "test.ngc"), tool, block);
}

// The samples on source line `line` whose tip lies within [x0, x1] (the steady part of a pass).
std::vector<const Sample*> on_line(const std::vector<Sample>& samples, int line, double x0,
                                   double x1) {
  std::vector<const Sample*> found;
  for (const Sample& s : samples) {
    if (s.cl.line == line && s.cl.position.x() >= x0 && s.cl.position.x() <= x1) {
      found.push_back(&s);
    }
  }
  EXPECT_GT(found.size(), 5u) << "line " << line;
  return found;
}

// The angular tolerance of a boundary on a radius ρ: Q lies within s/√2 of the cell's point
// across the ray, s/(√2 ρ) in φ, plus the bisection's cell/64 (docs/engagement.md).
double angle_tolerance(double rho) { return kSpacing / (std::sqrt(2.0) * rho) + 0.1 * kDeg; }

// Every disc below `depth` engaged over [entry, exit] alone, none above; `margin` leaves out the
// discs that close to the depth.
void expect_side(const EngagementMap& map, double depth, double entry, double exit, double rho,
                 double margin = 0.0) {
  for (const DiscEngagement& disc : map.discs) {
    SCOPED_TRACE(testing::Message() << "disc " << disc.z0 << "–" << disc.z1);
    if (disc.z1 <= depth - margin + 1e-9) {
      ASSERT_EQ(disc.phi.size(), 1u);
      EXPECT_NEAR(disc.phi[0].lo, entry, angle_tolerance(rho));
      EXPECT_NEAR(disc.phi[0].hi, exit, angle_tolerance(rho));
    } else if (disc.z0 >= depth + margin - 1e-9) {
      EXPECT_TRUE(disc.phi.empty());
    }
  }
}

constexpr const char* kHeader = "G21 G90 G17 G94\nS10000 M3\nG0 Z5\n";

// A slot along X at Y30, at Z-3 (line 6), then again at Z-6 (line 10).
const std::string kStepDownSlot = std::string(kHeader) +
                                  "G0 X-10 Y30\n"
                                  "G1 Z-3 F600\n"
                                  "G1 X110\n"
                                  "G0 Z5\n"
                                  "G0 X-10\n"
                                  "G1 Z-6\n"
                                  "G1 X110\n";

// A slot at Z-3, then the same line at Z-6: the second level cuts 3 mm, not 6; its walls above
// are the first level's, left at exactly the tool's radius.
TEST(EngagementFidelity, StepDownSlotCutsOnlyTheNewLevel) {
  const std::vector<Sample> samples = simulate(kStepDownSlot, "flat:10,20");
  for (const int line : {6, 10}) {
    SCOPED_TRACE(testing::Message() << "level on line " << line);
    for (const Sample* s : on_line(samples, line, 20, 80)) {
      ASSERT_TRUE(s->map.engaged);
      EXPECT_NEAR(s->map.axial_depth, 3.0, kSpacing);
      // Half the cylinder over 3 mm: π·R·3 = 47.12 mm² (within 2 %).
      EXPECT_NEAR(s->map.area, kPi * 5.0 * 3.0, 0.02 * kPi * 5.0 * 3.0);
      expect_side(s->map, 3.0, 0.0, kPi, 5.0);
      EXPECT_NEAR(s->map.phi_entry, 0.0, angle_tolerance(5.0));
      EXPECT_NEAR(s->map.phi_exit, kPi, angle_tolerance(5.0));
    }
  }
}

// The same slot twice at Z-5: the second pass cuts air.
TEST(EngagementFidelity, RepeatedPassIsNotEngaged) {
  const std::string program = std::string(kHeader) +
                              "G0 X-10 Y30\n"
                              "G1 Z-5 F600\n"
                              "G1 X110\n"  // line 6
                              "G0 Z5\n"
                              "G0 X-10\n"
                              "G1 Z-5\n"
                              "G1 X110\n";  // line 10
  const std::vector<Sample> samples = simulate(program, "flat:10,20");
  for (const Sample* s : on_line(samples, 6, 20, 80)) {
    EXPECT_NEAR(s->map.axial_depth, 5.0, kSpacing);
  }
  for (const Sample& s : samples) {
    if (s.cl.line < 9) continue;  // the second plunge and pass
    EXPECT_LT(s.map.area, 0.1) << "x " << s.cl.position.x() << " line " << s.cl.line;
    EXPECT_FALSE(s.map.engaged) << "x " << s.cl.position.x() << " line " << s.cl.line;
  }
}

// A ring groove by two full circles at Z-3 and Z-6: the second circle cuts 3 mm; its walls above
// are the first circle's.
TEST(EngagementFidelity, SecondRingLevelCutsOnlyTheNewLevel) {
  const std::string program = std::string(kHeader) +
                              "G0 X65 Y30\n"
                              "G1 Z-3 F600\n"
                              "G2 X65 Y30 I-15 J0\n"  // line 6
                              "G1 Z-6\n"
                              "G2 X65 Y30 I-15 J0\n";  // line 8
  const std::vector<Sample> samples = simulate(program, "flat:10,20");
  for (const int line : {6, 8}) {
    SCOPED_TRACE(testing::Message() << "circle on line " << line);
    int checked = 0;
    for (const Sample& s : samples) {
      // Past the plunge's crater and before the cutter reaches it again (10 mm of 94 mm):
      // the groove ahead is fresh, the walls beside it are not.
      if (s.cl.line != line || s.cl.u < 0.1 || s.cl.u > 0.85) continue;
      ASSERT_TRUE(s.map.engaged);
      EXPECT_NEAR(s.map.axial_depth, 3.0, kSpacing) << "u " << s.cl.u;
      // A translating cutter (no spin about the arc's centre): the front half cuts the fresh
      // groove ahead, whatever the curvature of the path.
      EXPECT_NEAR(s.map.area, kPi * 5.0 * 3.0, 0.02 * kPi * 5.0 * 3.0) << "u " << s.cl.u;
      ++checked;
    }
    EXPECT_GT(checked, 100);
  }
}

// A ring groove by two helical turns, 3 mm each: the second turn cuts the 3 mm between the first
// turn's floor and its own; the groove's walls beside it are the first turn's.
TEST(EngagementFidelity, SecondHelicalTurnCutsOnePitch) {
  const std::string program = std::string(kHeader) +
                              "G0 X65 Y30\n"
                              "G1 Z0 F600\n"
                              "G2 X65 Y30 Z-3 I-15 J0\n"  // line 6
                              "G2 X65 Y30 Z-6 I-15 J0\n";  // line 7
  const std::vector<Sample> samples = simulate(program, "flat:10,20");
  int checked = 0;
  for (const Sample& s : samples) {
    if (s.cl.line != 7 || s.cl.u < 0.1 || s.cl.u > 0.85) continue;
    ASSERT_TRUE(s.map.engaged);
    EXPECT_NEAR(s.map.axial_depth, 3.0, kSpacing) << "u " << s.cl.u;
    ++checked;
  }
  EXPECT_GT(checked, 100);
}

// A flat end mill tilted 20° (3+2) slots along Y, then again 3 mm further along its own axis: the
// second pass cuts the 3 mm between the first pass's bottom and its own, beside the first pass's
// walls (planes through the axis and the feed, the same for both passes). The rays cross the tilted
// cutter obliquely: the point Q a cell reads lies within s√(3/2) of the cell's point, up to 0.12 mm
// along the axis, so the disc at the new level's top may read either level (depth within s).
TEST(EngagementFidelity, TiltedStepDownCutsOnlyTheNewLevel) {
  const Vec3 axis(std::sin(20 * kDeg), 0.0, std::cos(20 * kDeg));
  const auto pass = [&](double along_axis) {
    Move m;
    m.start = Vec3(50, -10, -4) - along_axis * axis;
    m.end = Vec3(50, 70, -4) - along_axis * axis;
    m.start_axis = m.end_axis = axis;
    m.feed_rate = 600.0;
    return m;
  };
  Toolpath path;
  path.sources = {"test"};
  path.moves = {pass(0.0), pass(3.0)};
  path.moves[1].line = 2;
  const std::vector<Sample> samples = simulate(path, "flat:8,20");
  int checked = 0;
  for (const Sample& s : samples) {
    if (s.cl.move != 1 || s.cl.position.y() < 15 || s.cl.position.y() > 45) continue;
    ASSERT_TRUE(s.map.engaged);
    EXPECT_GE(s.map.axial_depth, 3.0 - 1e-9) << "y " << s.cl.position.y();
    EXPECT_LE(s.map.axial_depth, 3.0 + kSpacing + 1e-9) << "y " << s.cl.position.y();
    expect_side(s.map, 3.0, 0.0, kPi, 4.0, kSpacing);
    ++checked;
  }
  EXPECT_GT(checked, 50);
}

// The bundled simultaneous 5-axis pass (a ball end tilting through 30° and back), run twice: the
// second run's pieces are the first run's, so it removes nothing and engages nothing.
TEST(EngagementFidelity, RepeatedFiveAxisPassIsNotEngaged) {
  Toolpath path = read_cldata_file(
      (test::source_dir() / "examples/programs/five_axis_pass.cls").string());
  const std::size_t once = path.moves.size();
  for (std::size_t k = 0; k < once; ++k) path.moves.push_back(path.moves[k]);
  // A short ball and a thin block keep the test quick: each step of a turning move is swept in
  // pieces that turn by at most 2·tolerance/reach.
  const std::vector<Sample> samples = simulate(path, "ball:6,8", Aabb{{0, 0, -6}, {100, 60, 0}});
  double first = 0.0;
  for (const Sample& s : samples) {
    if (static_cast<std::size_t>(s.cl.move) < once) {
      first = std::max(first, s.map.area);
    } else {
      EXPECT_LT(s.map.area, 0.1) << "move " << s.cl.move << " u " << s.cl.u;
    }
  }
  EXPECT_GT(first, 5.0);  // the first run does cut
}

// A 2 mm stepover to the left (+Y) of a slot at the same depth: up-milling, φ ∈ [0, acos(1 -
// 2/5)] = [0, 53.13°], area 5·5·0.9273 = 23.18 mm².
TEST(EngagementFidelity, StepoverBesideASlot) {
  const std::string program = std::string(kHeader) +
                              "G0 X-10 Y30\n"
                              "G1 Z-5 F600\n"
                              "G1 X110\n"
                              "G0 Z5\n"
                              "G0 X-10 Y32\n"
                              "G1 Z-5\n"
                              "G1 X110\n";  // line 10
  const std::vector<Sample> samples = simulate(program, "flat:10,20");
  const double exit = std::acos(1.0 - 2.0 / 5.0);
  for (const Sample* s : on_line(samples, 10, 20, 80)) {
    EXPECT_NEAR(s->map.axial_depth, 5.0, kSpacing);
    expect_side(s->map, 5.0, 0.0, exit, 5.0);
    EXPECT_NEAR(s->map.area, 25.0 * exit, 0.02 * 25.0 * exit);
  }
}

// A contour finishing pass along a wall roughed by the same tool in two levels, 0.5 mm left:
// radial depth 0.5 mm, φ ∈ [0, acos(0.9)] = [0, 25.84°], over the finishing depth only.
TEST(EngagementFidelity, ContourFinishingTakesTheStockLeftOnTheWall) {
  const std::string rough = kStepDownSlot + "G0 Z5\nG0 X-10 Y30.5\n";  // lines 11, 12
  const double exit = std::acos(1.0 - 0.5 / 5.0);
  for (const double depth : {6.0, 3.0}) {
    SCOPED_TRACE(testing::Message() << "finishing at Z-" << depth);
    const std::vector<Sample> samples =
        simulate(rough + "G1 Z-" + std::to_string(depth) + "\nG1 X110\n", "flat:10,20");
    for (const Sample* s : on_line(samples, 14, 20, 80)) {
      EXPECT_NEAR(s->map.axial_depth, depth, kSpacing);
      expect_side(s->map, depth, 0.0, exit, 5.0);
      EXPECT_NEAR(s->map.area, 5.0 * depth * exit, 0.02 * 5.0 * depth * exit);
    }
  }
}

// A 12 mm face mill whose edge runs exactly along the stock's side face (Y = 0): the thin stock
// between the cutter and the face is engaged up to φ = 180°. Run just outside the face instead,
// the cutter only touches it and nothing is engaged.
TEST(EngagementFidelity, ToolEdgeAlongTheStockFace) {
  const auto run = [](const char* y) {
    return simulate(std::string(kHeader) + "G0 X-10 Y" + y + "\nG1 Z-2 F600\nG1 X110\n",
                    "flat:12,10");
  };
  const std::vector<Sample> along = run("6");
  for (const Sample* s : on_line(along, 6, 20, 80)) {
    expect_side(s->map, 2.0, 0.0, kPi, 6.0);
    EXPECT_NEAR(s->map.phi_exit, kPi, angle_tolerance(6.0));
  }
  for (const Sample& s : run("-6")) EXPECT_FALSE(s.map.engaged) << s.cl.position.x();
}

// The step-down slot's second level loads the cutter like a 3 mm slot (docs/forces.md's
// closed form), not like a 6 mm one.
TEST(EngagementFidelity, StepDownForcesAreThoseOfTheNewLevel) {
  const std::vector<Sample> samples = simulate(kStepDownSlot, "flat:10,20");
  const Cutter cutter = cutter_from_spec("flat:10,20");
  const CuttingCoefficients k = test::test_coefficients();
  const ForceModel model(cutter, k);
  const double c = 0.05;
  const Vec3 expected = test::closed_form_mean(k, model.flutes(), 3.0, c, 0.0, kPi);
  for (const Sample* s : on_line(samples, 10, 20, 80)) {
    const ClForces forces = model.evaluate(s->map, s->state, c, 10000.0);
    // Within 2 %: the map's ends are within angle_tolerance of 0° and 180° and its depth
    // within s of 3 mm (3 %, but the top disc's error is a fraction of it).
    EXPECT_NEAR(forces.mean_force.x(), expected.x(), 0.02 * expected.norm());
    EXPECT_NEAR(forces.mean_force.y(), expected.y(), 0.02 * expected.norm());
    EXPECT_NEAR(forces.mean_force.z(), expected.z(), 0.02 * expected.norm());
  }
}

// A ball end mill (D 10) rasters a flat floor with 1 mm stepovers, zig-zag along X, then rasters
// it again 1 mm deeper. Each pass of the first raster cuts only the crescent its neighbour left:
// a disc of radius ρ(z) engages the side towards the stepover up to acos(1 - w/ρ) from it (the
// earlier groove is the cylinder of the ball's radius along the neighbour's path). The second
// raster's engaged area is the closed-form region of the front hemisphere, below the top and
// outside every groove cut before it (its own earlier passes and the whole first raster),
// integrated on the sphere (dA = R² d(cos θ) dφ).
TEST(EngagementFidelity, BallRastersCutOnlyTheirCrescents) {
  constexpr double kRadius = 5.0, kStep = 1.0;
  constexpr int kPasses = 7;
  std::string program = std::string(kHeader) + "G0 X-10 Y20\n";
  std::vector<int> pass_lines;  // the line of each pass, first raster then second
  int line = 4;
  for (const double depth : {2.0, 3.0}) {
    program += "G1 Z-" + std::to_string(depth) + " F600\n";
    ++line;
    for (int k = 0; k < kPasses; ++k) {
      if (k > 0) {
        program += "G1 Y" + std::to_string(20 + k * kStep) + "\n";
        ++line;
      }
      program += k % 2 == 0 ? "G1 X110\n" : "G1 X-10\n";
      pass_lines.push_back(++line);
    }
    program += "G0 Z5\nG0 X-10 Y20\n";
    line += 2;
  }
  const std::vector<Sample> samples = simulate(program, "ball:10,20");

  // Closed-form engagement of pass k of raster r at a surface point of the ball (centre height
  // c above the tip at z_tip) with unit normal n = (sin φ x + cos φ y) sin θ - cos θ z.
  const auto engaged = [&](int r, int k, const Vec3& n) {
    const double direction = k % 2 == 0 ? 1.0 : -1.0;  // +X on even passes
    const double z_tip = r == 0 ? -2.0 : -3.0;
    const Vec3 p = Vec3(0, 20 + k * kStep, z_tip + kRadius) + kRadius * n;
    if (n.x() * direction <= 0.0 || p.z() >= 0.0) return false;
    for (int rr = 0; rr <= r; ++rr) {
      const double centre = (rr == 0 ? -2.0 : -3.0) + kRadius;
      for (int j = 0; j < (rr < r ? kPasses : k); ++j) {
        const double dy = p.y() - (20 + j * kStep), dz = p.z() - centre;
        if (dy * dy + dz * dz < kRadius * kRadius) return false;
      }
    }
    return true;
  };
  // The engaged area and the height above the tip of its highest point.
  struct Region {
    double area = 0.0, depth = 0.0;
  };
  const auto closed_form = [&](int r, int k) {
    constexpr int kU = 600, kPhi = 1200;  // cells of 0.017 mm × 0.026 mm on the ball
    Region region;
    for (int a = 0; a < kU; ++a) {
      const double cos_theta = -1.0 + (a + 0.5) * 2.0 / kU;  // n_z
      const double sin_theta = std::sqrt(1.0 - cos_theta * cos_theta);
      for (int b = 0; b < kPhi; ++b) {
        const double phi = (b + 0.5) * 2 * kPi / kPhi;
        const Vec3 n(sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta);
        if (!engaged(r, k, n)) continue;
        region.area += 1.0;
        region.depth = std::max(region.depth, kRadius * (1.0 + cos_theta));
      }
    }
    region.area *= kRadius * kRadius * (2.0 / kU) * (2 * kPi / kPhi);
    return region;
  };

  for (int r = 0; r < 2; ++r) {
    for (int k = 1; k < kPasses; ++k) {
      SCOPED_TRACE(testing::Message() << "raster " << r + 1 << " pass " << k + 1);
      const std::vector<const Sample*> steady =
          on_line(samples, pass_lines[static_cast<std::size_t>(r * kPasses + k)], 30, 70);
      const Region expected = closed_form(r, k);
      double boundary = 0.0;  // the bound: each engaged disc's two ends within angle_tolerance
      for (const Sample* s : steady) {
        boundary = 0.0;
        for (const DiscEngagement& disc : s->map.discs) {
          if (disc.phi.empty()) continue;
          const double rho = std::sqrt(kRadius * kRadius -
                                       std::pow(kRadius - 0.5 * (disc.z0 + disc.z1), 2));
          boundary += 2.0 * angle_tolerance(rho) * rho * (disc.z1 - disc.z0);
        }
        EXPECT_NEAR(s->map.area, expected.area, boundary) << "x " << s->cl.position.x();
        // The top of the highest engaged disc: at or above the deepest engaged point, by < s.
        EXPECT_GE(s->map.axial_depth, expected.depth - 1e-9) << "x " << s->cl.position.x();
        EXPECT_LT(s->map.axial_depth, expected.depth + kSpacing) << "x " << s->cl.position.x();
        if (r > 0) continue;
        // First raster: disc by disc, the crescent on the stepover side (+Y: φ = 0 on passes
        // along +X, φ = 180° along -X).
        for (const DiscEngagement& disc : s->map.discs) {
          const double z = 0.5 * (disc.z0 + disc.z1);
          if (z > 2.0 || z < 0.5) continue;  // above the top; near the tip the crescent is steep
          const double rho = std::sqrt(kRadius * kRadius - (kRadius - z) * (kRadius - z));
          const double width = std::acos(std::max(-1.0, 1.0 - kStep / rho));
          // The disc's height spread moves its end by up to s·|dφ/dz| as well.
          const double rho_low = std::sqrt(kRadius * kRadius - std::pow(kRadius - disc.z0, 2));
          const double spread = std::abs(std::acos(std::max(-1.0, 1.0 - kStep / rho_low)) - width);
          ASSERT_EQ(disc.phi.size(), 1u) << "z " << z;
          const Interval expected_phi =
              k % 2 == 0 ? Interval{0.0, width} : Interval{kPi - width, kPi};
          EXPECT_NEAR(disc.phi[0].lo, expected_phi.lo, angle_tolerance(rho) + spread) << "z " << z;
          EXPECT_NEAR(disc.phi[0].hi, expected_phi.hi, angle_tolerance(rho) + spread) << "z " << z;
        }
      }
    }
  }
}

// Every map of every location the same, interval for interval, with DexelEngagement's default
// options and with `off` applied to them, on the families above: a step-down and its contour
// finishing along the wall, a ring groove in two levels, a ball raster in two depths, a tilted
// step-down with a 5-axis repeat.
void expect_same_maps_without(void (*off)(EngagementOptions&)) {
  const auto maps = [off](const Toolpath& path, const char* tool, bool fast) {
    TriDexel stock = TriDexel::from_box(kBlock, kSpacing);
    SimulationOptions options;
    options.resolution = kSpacing;
    SamplingOptions sampling;
    sampling.step = 0.5;
    EngagementOptions engagement;
    if (!fast) off(engagement);
    std::vector<EngagementMap> found;
    simulate_engagement(stock, cutter_from_spec(tool), path, {options, sampling, engagement},
                        [&](const ClEngagement& e) { found.push_back(e.map); });
    return found;
  };
  std::string raster = std::string(kHeader) + "G0 X-10 Y20\n";
  for (const double depth : {2.0, 3.0}) {
    raster += "G1 Z-" + std::to_string(depth) + " F600\n";
    for (int k = 0; k < 4; ++k) {
      if (k > 0) raster += "G1 Y" + std::to_string(20 + k) + "\n";
      raster += k % 2 == 0 ? "G1 X110\n" : "G1 X-10\n";
    }
    raster += "G0 Z5\nG0 X-10 Y20\n";
  }
  const Vec3 axis(std::sin(20 * kDeg), 0.0, std::cos(20 * kDeg));
  Toolpath tilted;
  tilted.sources = {"test"};
  for (const double back : {0.0, 3.0, 3.0}) {
    Move m;
    m.start = Vec3(50, -10, -4) - back * axis;
    m.end = Vec3(50, 70, -4) - back * axis;
    m.start_axis = m.end_axis = axis;
    m.feed_rate = 600.0;
    tilted.moves.push_back(m);
  }
  tilted.moves[2].end_axis = Vec3(0.0, std::sin(10 * kDeg), std::cos(10 * kDeg));
  const std::vector<std::pair<Toolpath, const char*>> cases = {
      {read_gcode(kStepDownSlot + "G0 Z5\nG0 X-10 Y30.5\nG1 Z-6\nG1 X110\n", "finish.ngc"),
       "flat:10,20"},
      {read_gcode(std::string(kHeader) + "G0 X65 Y30\nG1 Z-3 F600\nG2 X65 Y30 I-15 J0\n"
                                         "G1 Z-6\nG2 X65 Y30 I-15 J0\n",
                  "ring.ngc"),
       "bull:10,2,20"},
      {read_gcode(raster, "raster.ngc"), "ball:10,20"},
      {tilted, "flat:8,20"}};
  for (const auto& [path, tool] : cases) {
    SCOPED_TRACE(tool);
    const std::vector<EngagementMap> fast = maps(path, tool, true);
    const std::vector<EngagementMap> full = maps(path, tool, false);
    ASSERT_EQ(fast.size(), full.size());
    std::size_t engaged = 0;
    for (std::size_t k = 0; k < fast.size(); ++k) {
      SCOPED_TRACE(testing::Message() << "CL " << k);
      engaged += full[k].engaged ? 1 : 0;
      ASSERT_EQ(fast[k].discs.size(), full[k].discs.size());
      ASSERT_EQ(fast[k].rings.size(), full[k].rings.size());
      for (std::size_t d = 0; d < full[k].discs.size(); ++d) {
        ASSERT_EQ(fast[k].discs[d].phi.size(), full[k].discs[d].phi.size()) << "disc " << d;
        for (std::size_t i = 0; i < full[k].discs[d].phi.size(); ++i) {
          EXPECT_EQ(fast[k].discs[d].phi[i].lo, full[k].discs[d].phi[i].lo);
          EXPECT_EQ(fast[k].discs[d].phi[i].hi, full[k].discs[d].phi[i].hi);
        }
      }
      for (std::size_t r = 0; r < full[k].rings.size(); ++r) {
        ASSERT_EQ(fast[k].rings[r].phi.size(), full[k].rings[r].phi.size()) << "ring " << r;
        for (std::size_t i = 0; i < full[k].rings[r].phi.size(); ++i) {
          EXPECT_EQ(fast[k].rings[r].phi[i].lo, full[k].rings[r].phi[i].lo);
          EXPECT_EQ(fast[k].rings[r].phi[i].hi, full[k].rings[r].phi[i].hi);
        }
      }
    }
    EXPECT_GT(engaged, fast.size() / 2);  // the comparison is about engaged maps
  }
}

// The per-cell skip (a cell farther from the step's removal box than any stretch its test can
// touch) is exact.
TEST(EngagementFidelity, SkippingFarCellsChangesNoMap) {
  expect_same_maps_without([](EngagementOptions& o) { o.skip_far_cells = false; });
}

// An upright tool's side discs above or below the step's removal box, beyond the far-cell
// test's margin, are left unscanned: exact. The step-down's and the raster's steps remove
// material over a few millimetres of the tool's height, with discs above and below them.
TEST(EngagementFidelity, SkippingFarDiscsChangesNoMap) {
  expect_same_maps_without([](EngagementOptions& o) { o.skip_far_discs = false; });
}

// A side disc of an upright tool that takes the intervals of the disc below (the rays it reads
// lost what that disc's rays lost) gets the intervals its own scan finds. In the step-down's
// second level, the discs above the first level's floor (their rays lost nothing) stand over
// discs that cut.
TEST(EngagementFidelity, ReusingAlikeDiscsChangesNoMap) {
  expect_same_maps_without([](EngagementOptions& o) { o.reuse_alike_discs = false; });
}

}  // namespace
}  // namespace cwe

#include "cwe/simulation/simulation.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <unistd.h>

#include <atomic>
#include <cmath>
#include <filesystem>
#include <memory>
#include <span>
#include <string>
#include <tuple>
#include <vector>

#include "cwe/engagement/dexel_workpiece.hpp"
#include "cwe/geometry/triangle_mesh.hpp"
#include "cwe/io/atomic_file.hpp"
#include "cwe/io/mesh_io.hpp"
#include "cwe/tool/tool_spec.hpp"
#include "envelope/sweep_oracle.hpp"
#include "random.hpp"

namespace cwe {
namespace {

// Removed volumes against closed forms. Each ray's chord is exact (envelope tests), so a
// family's measure Σ length × s² errs only where the cut's boundary passes between ray centres:
// at most the boundary's area times s (each boundary cell of s² misattributes at most a length
// of about s across the surface). Cases whose faces lie on cell boundaries are exact to float
// rounding. Stock: a 40 × 30 × 20 mm block, top at z = 20, s = 0.1 mm.
constexpr double kSpacing = 0.1;
const Aabb kBlock{{0, 0, 0}, {40, 30, 20}};

Move line(const Vec3& a, const Vec3& b, const Vec3& axis = Vec3::UnitZ()) {
  Move m;
  m.start = a;
  m.end = b;
  m.start_axis = m.end_axis = axis.normalized();
  return m;
}

Move circle(const Vec3& start, const Vec3& center, double turns, double axial) {
  Move m;
  m.shape = MoveShape::kArc;
  m.start = start;
  m.center = center;
  m.normal = -Vec3::UnitZ();  // clockwise (G2) seen from above
  m.sweep = turns * kTwoPi;
  m.axial = -axial;  // along -normal: the height changes by `axial`
  m.end = m.position(1.0);
  return m;
}

struct Cut {
  TriDexel::Volume removed;
  RemovalSummary summary;
};

Cut cut(const char* tool, const std::vector<Move>& moves, double spacing = kSpacing) {
  TriDexel stock = TriDexel::from_box(kBlock, spacing);
  const TriDexel::Volume before = stock.volume();
  Toolpath path;
  path.sources = {"test"};
  path.moves = moves;
  const Cutter cutter = cutter_from_spec(tool);
  SimulationOptions options;
  options.resolution = spacing;
  Cut result;
  result.summary = remove_toolpath(stock, cutter, path, options);
  const TriDexel::Volume after = stock.volume();
  for (std::size_t a = 0; a < 3; ++a) {
    result.removed.by_family[a] = before.by_family[a] - after.by_family[a];
  }
  return result;
}

void expect_volume(const Cut& c, double exact, double bound) {
  for (const double v : c.removed.by_family) EXPECT_NEAR(v, exact, bound);
  EXPECT_NEAR(c.removed.mean(), exact, bound);
}

// The per-ray check behind the volumes: what one family must measure when every ray carries
// the exact length of the true removed region. `length(p, q)` gives, for the ray through cross
// coordinates (p, q) (family 2: p = x, q = y; family 0: p = y, q = z), the least and the most
// length the true region allows there (they differ only within a subdivision tolerance of its
// boundary). The family's measure must fall between the sums, up to float rounding of ray ends.
template <typename Length>
void expect_family_between(const Cut& c, int family, Length length) {
  const Vec3 size = kBlock.size();
  const int b = (family + 1) % 3, cc = (family + 2) % 3;
  const int nb = static_cast<int>(std::lround(size[b] / kSpacing));
  const int nc = static_cast<int>(std::lround(size[cc] / kSpacing));
  double least = 0.0, most = 0.0;
  for (int j = 0; j < nc; ++j) {
    for (int i = 0; i < nb; ++i) {
      const double p = (i + 0.5) * kSpacing, q = (j + 0.5) * kSpacing;
      const auto [lo, hi] = length(p, q);
      least += lo;
      most += hi;
    }
  }
  const double cell = kSpacing * kSpacing;
  const double rounding = 2e-5 * nb * nc * cell;  // float ends, 1e-5 mm each
  EXPECT_GE(c.removed.by_family[static_cast<std::size_t>(family)], least * cell - rounding);
  EXPECT_LE(c.removed.by_family[static_cast<std::size_t>(family)], most * cell + rounding);
}

// Lengths of Z rays through a flat-bottomed region of `depth` between radii r0 and r1 about
// `centre`, uncertain within `band` of either radius.
std::pair<double, double> in_annulus(double x, double y, const Vec2& centre, double r0, double r1,
                                     double depth, double band) {
  const double r = (Vec2(x, y) - centre).norm();
  const bool surely = r >= r0 + band && r <= r1 - band;
  const bool maybe = r >= r0 - band && r <= r1 + band;
  return {surely ? depth : 0.0, maybe ? depth : 0.0};
}

TEST(RemovedVolume, PartialWidthSideCut) {
  // Radial depth 3, axial depth 4 along the y = 0 face: 3 × 4 × 40. Faces on cell boundaries.
  const Cut c = cut("flat:10,30", {line({-10, -2, 16}, {50, -2, 16})});
  expect_volume(c, 480.0, 0.05);
}

TEST(RemovedVolume, Ramp) {
  // Flat D = 10 ramping from the top at x = 0 to 4 mm deep at x = 40, centred at y = 15. At
  // (x, y) the depth is 0.1·min(x + w, 40), w = √(25 - (y - 15)²); integrating over the block,
  // V = ∫ (80 + 4w - w²/20) dy = 800 + 4·(25π/2) - 500/3/20.
  const Cut c = cut("flat:10,30", {line({0, 15, 20}, {40, 15, 16})});
  const double exact = 800.0 + 50.0 * kPi - 500.0 / 60.0;
  // Boundary: floor ~ 400, sides 2 × 80, front half-cylinder π·5·4: about 625 mm².
  expect_volume(c, exact, kSpacing * 625.0);
  // Each Z ray carries the depth at its (x, y).
  expect_family_between(c, 2, [](double x, double y) {
    const double dy = y - 15.0;
    if (std::abs(dy) > 5.0) return std::pair{0.0, 0.0};
    const double depth = 0.1 * std::min(x + std::sqrt(25.0 - dy * dy), 40.0);
    return std::pair{depth, depth};
  });
}

TEST(RemovedVolume, Plunge) {
  // A flat end mill plunging 5 mm: the cylinder π·5²·5.
  const Cut c = cut("flat:10,30", {line({20.03, 15.02, 25}, {20.03, 15.02, 15})});
  expect_volume(c, kPi * 25.0 * 5.0, kSpacing * (2 * kPi * 5.0 * 5.0 + kPi * 25.0));
  expect_family_between(c, 2, [](double x, double y) {
    return in_annulus(x, y, {20.03, 15.02}, -1.0, 5.0, 5.0, 1e-9);
  });
}

TEST(RemovedVolume, CircularPocket) {
  // A full circle of radius 10 at 3 mm depth: the annulus π(15² - 5²) × 3. Arcs are cut into
  // linear pieces within s/10, which adds at most that times the wall area.
  const Cut c = cut("flat:10,30", {circle({30, 15, 17}, {20, 15, 17}, 1.0, 0.0)});
  const double area = kPi * 200.0 * 3.0 + 2 * kPi * 20.0 * 3.0 + kPi * 200.0;
  expect_volume(c, kPi * 200.0 * 3.0, kSpacing * area);
  expect_family_between(c, 2, [](double x, double y) {
    return in_annulus(x, y, {20, 15}, 5.0, 15.0, 3.0, kSpacing / 10.0);
  });
  EXPECT_GT(c.summary.linear_pieces, 50);
  EXPECT_DOUBLE_EQ(c.summary.deviation_bound, kSpacing / 10.0);
}

TEST(RemovedVolume, HelicalBore) {
  // Three turns of radius 3 from the top down to 3 mm, then a full circle at the bottom: a bore
  // of radius 8, π·8²·3.
  const Cut c = cut("flat:10,30", {circle({23, 15, 20}, {20, 15, 20}, 3.0, -3.0),
                                   circle({23, 15, 17}, {20, 15, 17}, 1.0, 0.0)});
  expect_volume(c, kPi * 64.0 * 3.0, kSpacing * (kPi * 64.0 + 2 * kPi * 8.0 * 3.0));
  expect_family_between(c, 2, [](double x, double y) {
    return in_annulus(x, y, {20, 15}, -1.0, 8.0, 3.0, kSpacing / 10.0);
  });
}

TEST(RemovedVolume, BullNoseSlot) {
  // Bull nose D = 10, r = 2, 3 mm deep along x: cross-section ∫₀³ 2ρ(z) dz with ρ = 3 + √(4 -
  // (2 - z)²) below z = 2 and 5 above: 2(6 + π) + 10.
  const Cut c = cut("bull:10,2,30", {line({-10, 15.01, 17}, {50, 15.01, 17})});
  const double section = 2.0 * (6.0 + kPi) + 10.0;
  expect_volume(c, section * 40.0, kSpacing * (40.0 * 12.0 + 2 * section));
  // X rays run along the slot: each inside the section carries all 40 mm.
  expect_family_between(c, 0, [](double y, double z) {
    const double h = z - 17.0, dy = std::abs(y - 15.01);
    if (h < 0.0 || z > 20.0) return std::pair{0.0, 0.0};
    const double rho = h >= 2.0 ? 5.0 : 3.0 + std::sqrt(4.0 - (2.0 - h) * (2.0 - h));
    return std::pair{dy <= rho ? 40.0 : 0.0, dy <= rho ? 40.0 : 0.0};
  });
}

TEST(RemovedVolume, TiltedThreePlusTwoSlot) {
  // A flat end mill tilted 30° about x, moved along x: its silhouette in the y-z plane (a
  // 10 × 30 rectangle turned by 30°) swept along x. The part below the top, clipped exactly as
  // a polygon, times the length.
  const double theta = kPi / 6.0;
  const Vec3 axis(0, std::sin(theta), std::cos(theta));
  const Vec2 tip(15.0, 17.0), along(axis.y(), axis.z()), across(axis.z(), -axis.y());
  std::vector<Vec2> polygon = {tip - 5.0 * across, tip + 5.0 * across,
                               tip + 5.0 * across + 30.0 * along,
                               tip - 5.0 * across + 30.0 * along};
  // Clip to z ≤ 20 (Sutherland–Hodgman against one half-plane).
  std::vector<Vec2> clipped;
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const Vec2& p = polygon[i];
    const Vec2& q = polygon[(i + 1) % polygon.size()];
    if (p.y() <= 20.0) clipped.push_back(p);
    if ((p.y() < 20.0) != (q.y() < 20.0)) {
      clipped.push_back(p + (q - p) * ((20.0 - p.y()) / (q.y() - p.y())));
    }
  }
  double area = 0.0;
  for (std::size_t i = 0; i < clipped.size(); ++i) {
    const Vec2& p = clipped[i];
    const Vec2& q = clipped[(i + 1) % clipped.size()];
    area += 0.5 * (p.x() * q.y() - q.x() * p.y());
  }
  const Cut c = cut("flat:10,30", {line({-10, tip.x(), tip.y()}, {50, tip.x(), tip.y()}, axis)});
  expect_volume(c, std::abs(area) * 40.0, kSpacing * (40.0 * 20.0 + 2 * std::abs(area)));
  EXPECT_EQ(c.summary.deviation_bound, 0.0);  // 3+2 linear moves are exact
  expect_family_between(c, 0, [&](double y, double z) {
    const Vec2 d = Vec2(y, z) - tip;
    const double s = d.dot(along), t = d.dot(across);
    const bool in = z <= 20.0 && s >= 0.0 && s <= 30.0 && std::abs(t) <= 5.0;
    return std::pair{in ? 40.0 : 0.0, in ? 40.0 : 0.0};
  });
}

TEST(Simulation, RapidsThatCutAreReported) {
  Move rapid = line({-10, 15, 18}, {50, 15, 18});
  rapid.mode = MotionMode::kRapid;
  rapid.line = 7;
  Move retract = line({50, 15, 18}, {50, 15, 40});  // through the air: not a cut
  retract.mode = MotionMode::kRapid;
  const Cut c = cut("flat:10,30", {rapid, retract});
  ASSERT_EQ(c.summary.rapid_cuts.size(), 1u);
  EXPECT_EQ(c.summary.rapid_cuts[0].move, 0);
  EXPECT_EQ(c.summary.rapid_cuts[0].location.line, 7);
  EXPECT_NEAR(c.summary.rapid_cuts[0].volume, 10.0 * 2.0 * 40.0, 0.05);
  EXPECT_EQ(c.summary.rapid_moves, 2);
  EXPECT_EQ(c.summary.cutting_moves, 1);
}

// Retracing a cut removes nothing more (float rounding of ray ends is not a cut).
TEST(Simulation, RetracingACutRemovesNothing) {
  const Cut c =
      cut("ball:10,30", {line({-10, 15, 16}, {50, 15, 16}), line({50, 15, 16}, {-10, 15, 16}),
                         line({-10, 15, 16}, {-10, 15, 40})});
  EXPECT_EQ(c.summary.cutting_moves, 1);
  EXPECT_LT(c.summary.removed_by_move[1], std::pow(kSpacing, 3));
}

// The same job with one thread and with several gives bit-identical rays.
// Twelve random lines (every third one tilted) and a helical arc through kBlock.
std::vector<Move> random_job() {
  test::Random random(81);
  std::vector<Move> moves;
  Vec3 at(5, 5, 18);
  for (int k = 0; k < 12; ++k) {
    const Vec3 to(random.uniform(0, 40), random.uniform(0, 30), random.uniform(12, 21));
    const Vec3 axis =
        k % 3 == 0 ? Vec3(random.uniform(-0.3, 0.3), random.uniform(-0.3, 0.3), 1) : Vec3::UnitZ();
    moves.push_back(line(at, to, axis));
    at = to;
  }
  moves.push_back(circle(at, at + Vec3(4, 0, 0), 1.25, -2.0));
  return moves;
}

void cut_random_job(TriDexel& stock) {
  Toolpath path;
  path.moves = random_job();
  const Cutter cutter = cutter_from_spec("bull:8,1.5,25");
  SimulationOptions options;
  options.resolution = stock.spacing();
  remove_toolpath(stock, cutter, path, options);
}

void expect_identical(const TriDexel& one, const TriDexel& other) {
  ASSERT_EQ(one.ray_count(), other.ray_count());
  for (int a = 0; a < 3; ++a) {
    ASSERT_EQ(one.grid(a), other.grid(a));
    for (int j = 0; j < one.grid(a)[1]; ++j) {
      for (int i = 0; i < one.grid(a)[0]; ++i) {
        const auto x = one.at(a, i, j).intervals(), y = other.at(a, i, j).intervals();
        ASSERT_EQ(x.size(), y.size());
        for (std::size_t k = 0; k < x.size(); ++k) {
          ASSERT_EQ(x[k].lo, y[k].lo);  // bit for bit
          ASSERT_EQ(x[k].hi, y[k].hi);
        }
      }
    }
  }
}

TEST(Simulation, IdenticalForAnyThreadCount) {
  const auto run = [&](int threads) {
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                                    static_cast<std::size_t>(threads));
    TriDexel stock = TriDexel::from_box(kBlock, 0.25);
    cut_random_job(stock);
    return stock;
  };
  const TriDexel one = run(1), four = run(4);
  expect_identical(one, four);
  EXPECT_LT(one.volume().mean(), 0.99 * 24000.0);  // the job did cut
}

// A sweep's pieces cut by their boxes cut down to the tool's part that can reach the stock
// (MoveSweep::reach_bounds) remove exactly what their whole boxes remove, ray by ray: a tilted
// corner-rounding tool (parts offset along the axis), a long bull nose tilting in and out of a
// block, and a vertical ball end, as the engagement's steps sweep them (the whole tool's
// pieces).
TEST(Simulation, ReachBoundsRemoveWhatWholeBoxesRemove) {
  const Cutter bull = cutter_from_spec("bull:10,1,30");
  const Cutter ball = cutter_from_spec("ball:6,40");
  // A corner-rounding tool (a concave arc): convex parts stacked along the axis.
  using Seg = ProfileSegment;
  const Cutter rounding(Profile({Seg::line({0, 0}, {2, 0}), Seg::line({2, 0}, {2, 1}),
                                 Seg::arc({2, 1}, {5, 4}, {5, 1}, false), Seg::line({5, 4}, {8, 4}),
                                 Seg::line({8, 4}, {8, 30})}),
                        CutterOptions{});
  std::vector<std::pair<const Cutter*, Move>> moves = {
      {&rounding, line({-9, 8, 19}, {20, 12, 18}, Vec3(0.2, 0, 1))},
      {&bull, line({-6, 15, 22}, {12, 15, 17}, Vec3::UnitZ())},
      {&bull, line({12, 15, 17}, {30, 10, 16.5}, Vec3::UnitZ())},
      {&ball, line({2, 2, 18}, {38, 27, 17})},
      {&bull, line({30, 10, 16.5}, {38, 25, 19}, Vec3::UnitZ())}};
  moves[1].second.end_axis = Vec3(0.3, 0.1, 0.95).normalized();
  moves[3].second.start_axis = moves[1].second.end_axis;
  moves[3].second.end_axis = Vec3(-0.2, 0.05, 0.98).normalized();
  TriDexel whole = TriDexel::from_box(kBlock, 0.4);
  TriDexel clipped = whole;
  DexelWorkpiece whole_workpiece(whole), clipped_workpiece(clipped);
  int narrower = 0;
  for (const auto& [cutter, move] : moves) {
    const ConvexParts parts(*cutter, 0.1);
    const MoveSweep everywhere(parts, move, Aabb(), MoveSweep::PieceReach::kWholeTool);
    const MoveSweep within(parts, move, kBlock, MoveSweep::PieceReach::kWholeTool);
    ASSERT_EQ(within.pieces().size(), everywhere.pieces().size());
    for (std::size_t k = 0; k < within.pieces().size(); ++k) {
      const Aabb& box = within.reach_bounds(k);
      narrower += box.size().z() < everywhere.reach_bounds(k).size().z() - 1.0 ? 1 : 0;
    }
    const std::vector<double> a = whole_workpiece.remove(std::span(&everywhere, 1));
    const std::vector<double> b = clipped_workpiece.remove(std::span(&within, 1));
    EXPECT_EQ(a, b);
    EXPECT_GT(a.front(), 1.0);
  }
  EXPECT_GT(narrower, 20);
  expect_identical(whole, clipped);
}

TEST(Simulation, StlStockOfABoxEqualsTheBoxStock) {
  std::vector<Vec3> corners;
  for (int k = 0; k < 8; ++k) {
    corners.emplace_back(k & 1 ? kBlock.max.x() : kBlock.min.x(),
                         k & 2 ? kBlock.max.y() : kBlock.min.y(),
                         k & 4 ? kBlock.max.z() : kBlock.min.z());
  }
  const auto file = std::filesystem::temp_directory_path() /
                    ("cwe-simulation-box-" + std::to_string(::getpid()) + ".stl");
  write_file_atomically(file, stl_binary(convex_hull(corners), "box stock"));
  SimulationOptions options;
  options.resolution = 0.25;
  TriDexel from_file = make_stock(parse_stock_spec(file.string(), {"--stock"}), options);
  std::filesystem::remove(file);
  TriDexel box = make_stock(parse_stock_spec("box:0,0,0,40,30,20", {"--stock"}), options);
  expect_identical(from_file, box);
  cut_random_job(from_file);
  cut_random_job(box);
  expect_identical(from_file, box);
}

// Every checked ray against the brute-force oracle: points along the ray are material exactly
// when they lie in the block and outside the union of the true tool positions of every move
// (test::union_side, sampling the motion as densely as each point needs), except within the
// subdivision tolerance of a sweep's boundary. Moves of every kind: 3-axis lines, a plunge, a
// tilted 3+2 line, a simultaneous 5-axis line, an arc and a helix. Also the invariants: intervals
// sorted and disjoint, and no material outside the original block.
TEST(Simulation, RaysAgreeWithDenseToolPositions) {
  const Aabb block{{0, 0, 0}, {30, 24, 16}};
  const double s = 0.4;
  const Cutter cutter = cutter_from_spec("bull:6,1.5,20");
  const std::vector<Move> moves{
      line({-4, 6, 13}, {34, 8, 11}),                       // slot descending gently
      line({15, 12, 20}, {15, 12, 9}),                      // plunge
      line({2, 18, 12}, {26, 20, 14}, Vec3(0.3, -0.2, 1)),  // tilted 3+2, climbing
      [] {                                                  // simultaneous 5-axis
        Move m = line({5, 3, 10}, {25, 16, 12});
        m.start_axis = Vec3(-0.3, 0, 1).normalized();
        m.end_axis = Vec3(0.2, 0.3, 1).normalized();
        return m;
      }(),
      circle({22, 12, 10}, {15, 12, 10}, 0.4, 0.0),  // arc
      circle({12, 12, 9}, {15, 12, 9}, 1.5, -3.0),   // helix downwards
  };
  TriDexel stock = TriDexel::from_box(block, s);
  Toolpath path;
  path.sources = {"test"};
  path.moves = moves;
  SimulationOptions options;
  options.resolution = s;
  options.tolerance = 0.02;
  const RemovalSummary summary = remove_toolpath(stock, cutter, path, options);
  EXPECT_EQ(summary.cutting_moves, 6);

  const BoundingCylinder cylinder = cutter.bounding_cylinder();
  const double reach = std::hypot(cylinder.radius, cylinder.z_max);
  // Subdivision puts the removed sweep within the tolerance of the true one; 1e-4 more covers
  // float ray ends and the oracle's own rounding.
  const double band = options.tolerance + 1e-4;
  std::vector<Aabb> near;  // where a move's sweep and its band can be
  for (const Move& m : moves) {
    Aabb box;
    for (int k = 0; k <= 50; ++k) box.extend(m.position(k / 50.0));
    box.inflate(reach + band + m.length() / 50);
    near.push_back(box);
  }
  // -1: surely removed, +1: surely material, 0: within the band of some sweep's boundary.
  const auto oracle = [&](const Vec3& p) {
    int verdict = 1;
    for (std::size_t k = 0; k < moves.size(); ++k) {
      if (!near[k].contains(p)) continue;
      const int side = test::union_side(cutter, moves[k], p, band, reach);
      if (side < 0) return -1;
      verdict = std::min(verdict, side);
    }
    return verdict;
  };

  test::Random random(404);
  int agreed_removed = 0, agreed_material = 0;
  for (int a = 0; a < 3; ++a) {
    for (int j = 0; j < stock.grid(a)[1]; ++j) {
      for (int i = 0; i < stock.grid(a)[0]; ++i) {
        const DexelRay& ray = stock.at(a, i, j);
        const auto intervals = ray.intervals();
        const double lo = block.min[a] - stock.domain().min[a];
        const double hi = block.max[a] - stock.domain().min[a];
        for (std::size_t k = 0; k < intervals.size(); ++k) {
          ASSERT_LT(intervals[k].lo, intervals[k].hi);
          if (k > 0) {
            ASSERT_LT(intervals[k - 1].hi, intervals[k].lo);
          }
          ASSERT_GE(intervals[k].lo, lo - 1e-5);
          ASSERT_LE(intervals[k].hi, hi + 1e-5);
        }
        if (random.integer(0, 19) != 0) continue;  // the oracle on one ray in twenty
        const Ray r = stock.ray(a, i, j);
        for (double t = lo + 0.0371; t < hi; t += 0.13) {
          const int expected = oracle(r.at(t));
          if (expected == 0) continue;
          ASSERT_EQ(ray.contains(t), expected > 0)
              << "family " << a << " ray " << i << ", " << j << " at " << r.at(t).transpose();
          (expected > 0 ? agreed_material : agreed_removed) += 1;
        }
      }
    }
  }
  EXPECT_GT(agreed_removed, 2000);
  EXPECT_GT(agreed_material, 2000);
}

TEST(StockSpec, ParsesBoxesAndNamesErrors) {
  const StockSpec box = parse_stock_spec("box:0,0,-30,100,60,0", SourceLocation{"--stock"});
  EXPECT_TRUE(box.is_box);
  EXPECT_EQ(box.box.min, Vec3(0, 0, -30));
  EXPECT_EQ(box.box.max, Vec3(100, 60, 0));
  const StockSpec file = parse_stock_spec("part.stl", SourceLocation{"--stock"});
  EXPECT_FALSE(file.is_box);
  EXPECT_EQ(file.path, "part.stl");
  // Inches with a trailing ":in" (":mm" is the default spelled out).
  const StockSpec inch = parse_stock_spec("box:0,0,-1,4,2.5,0:in", SourceLocation{"--stock"});
  EXPECT_EQ(inch.box.min, Vec3(0, 0, -25.4));
  EXPECT_EQ(inch.box.max, Vec3(101.6, 63.5, 0));
  EXPECT_EQ(parse_stock_spec("box:0,0,-30,100,60,0:mm", SourceLocation{"--stock"}).box.max,
            Vec3(100, 60, 0));
  for (const char* bad : {"box:0,0,0,1,1", "box:0,0,0,1,1,x", "box:0,0,0,1,0,1", "box:", "",
                          "box:0,0,0,1,1,1:ft", "box::in"}) {
    EXPECT_THROW(parse_stock_spec(bad, SourceLocation{"--stock"}), InputError) << bad;
  }
}

// The workpiece seam (cwe/engagement/workpiece.hpp): the main loop asks a backend for nothing
// but removal, steps and engagement. A backend that forwards to the tri-dexel one and counts its
// calls gives the same results as the tri-dexel overload, with one recorded step and one
// engagement query per cutter location.
class CountingWorkpiece : public Workpiece {
 public:
  explicit CountingWorkpiece(TriDexel& stock) : inner_(stock) {}
  double cell_volume() const override { return inner_.cell_volume(); }
  std::vector<double> remove(std::span<const MoveSweep> sweeps) override {
    batches += 1;
    return inner_.remove(sweeps);
  }
  std::unique_ptr<StepEngagement> engagement(const Cutter& cutter,
                                             const EngagementOptions& options) override {
    struct Counting : StepEngagement {
      Counting(std::unique_ptr<StepEngagement> wrapped, CountingWorkpiece& counter)
          : inner(std::move(wrapped)), owner(counter) {}
      std::unique_ptr<Step> new_step() const override { return inner->new_step(); }
      double remove(const MoveSweep& sweep, Step* step) override {
        ++(step != nullptr ? owner.recorded : owner.unrecorded);
        return inner->remove(sweep, step);
      }
      void finish(Step& step) const override { inner->finish(step); }
      // Called from several threads at once.
      EngagementMap at(const ToolState& state, const Step& step) const override {
        ++owner.queries;
        return inner->at(state, step);
      }
      std::unique_ptr<StepEngagement> inner;
      CountingWorkpiece& owner;
    };
    contact = options.contact;
    return std::make_unique<Counting>(inner_.engagement(cutter, options), *this);
  }
  int batches = 0, recorded = 0, unrecorded = 0;
  std::atomic<int> queries = 0;
  double contact = -1.0;

 private:
  DexelWorkpiece inner_;
};

TEST(WorkpieceSeam, TheMainLoopGoesThroughTheBackend) {
  Toolpath path;
  path.sources = {"test"};
  Move rapid;
  rapid.mode = MotionMode::kRapid;
  rapid.start = Vec3(-10, 15, 5);
  rapid.end = Vec3(-10, 15, -2);
  Move slot;
  slot.start = rapid.end;
  slot.end = Vec3(50, 15, -2);
  slot.feed_rate = 600;
  path.moves = {rapid, slot};
  const Cutter cutter = cutter_from_spec("flat:10,20");
  SimulationOptions options;
  options.resolution = 0.25;
  SamplingOptions sampling;
  TriDexel a = TriDexel::from_box(kBlock, options.resolution);
  TriDexel b = TriDexel::from_box(kBlock, options.resolution);
  std::vector<EngagementMap> direct, through;
  const auto keep = [](std::vector<EngagementMap>& maps) {
    return [&maps](const ClEngagement& e) { maps.push_back(e.map); };
  };
  const RemovalSummary sa =
      simulate_engagement(a, cutter, path, {options, sampling, {}}, keep(direct));
  CountingWorkpiece counting(b);
  const RemovalSummary sb =
      simulate_engagement(counting, cutter, path, {options, sampling, {}}, keep(through));
  // 60 mm at 0.5 mm: 120 locations at the start of each step (cl_sampling.hpp), each with its
  // recorded step and its query; the rapid, without locations, is removed whole.
  ASSERT_EQ(direct.size(), 120u);
  ASSERT_EQ(through.size(), direct.size());
  EXPECT_EQ(counting.recorded, 120);
  EXPECT_EQ(counting.queries, 120);
  EXPECT_EQ(counting.unrecorded, 1);
  EXPECT_EQ(counting.contact, options.effective_tolerance());  // the loop sets the default
  for (std::size_t k = 0; k < direct.size(); ++k) {
    EXPECT_EQ(direct[k].phi_entry, through[k].phi_entry) << k;
    EXPECT_EQ(direct[k].phi_exit, through[k].phi_exit) << k;
    EXPECT_EQ(direct[k].axial_depth, through[k].axial_depth) << k;
  }
  EXPECT_EQ(sa.removed_by_move, sb.removed_by_move);
  EXPECT_EQ(a.volume().by_family, b.volume().by_family);
  // Removal only: batched through the backend.
  TriDexel c = TriDexel::from_box(kBlock, options.resolution);
  CountingWorkpiece batched(c);
  const RemovalSummary sc = remove_toolpath(batched, cutter, path, options);
  EXPECT_EQ(batched.batches, 1);
  EXPECT_NEAR(sc.removed_by_move[1] + sc.removed_by_move[0],
              sa.removed_by_move[0] + sa.removed_by_move[1], 0.05);
}

// EngagementRun's prepare: called once for every location, beside the engagement search (on
// any thread), and what it returns reaches the sink with that same location, in order, for
// one thread and for several. The probe records the location's index and area.
TEST(EngagementRun, PreparedWorkReachesTheSinkWithItsLocation) {
  struct Probe : ClExtra {
    std::size_t index = 0;
    double area = 0.0;
  };
  Move slot;
  slot.start = Vec3(-10, 15, -2);
  slot.end = Vec3(50, 15, -2);
  slot.feed_rate = 600;
  const Cutter cutter = cutter_from_spec("flat:10,20");
  SimulationOptions options;
  options.resolution = 0.25;
  for (const int threads : {1, 4}) {
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                                    static_cast<std::size_t>(threads));
    TriDexel stock = TriDexel::from_box(kBlock, options.resolution);
    DexelWorkpiece workpiece(stock);
    std::atomic<int> prepared = 0;
    std::vector<std::size_t> seen;
    int engaged = 0;
    const auto prepare = [&](const ClEngagement& e) -> std::unique_ptr<ClExtra> {
      EXPECT_EQ(e.extra, nullptr);
      ++prepared;
      auto probe = std::make_unique<Probe>();
      probe->index = e.index;
      probe->area = e.map.area;
      return probe;
    };
    const auto sink = [&](const ClEngagement& e) {
      const auto* probe = dynamic_cast<const Probe*>(e.extra);
      ASSERT_NE(probe, nullptr);
      EXPECT_EQ(probe->index, e.index);
      EXPECT_EQ(probe->area, e.map.area);
      engaged += e.map.engaged ? 1 : 0;
      seen.push_back(e.index);
    };
    EngagementRun run(workpiece, cutter, {options, {}, {}}, sink, {}, prepare);
    run.add(slot, {"test"});
    run.finish();
    // 60 mm at 0.5 mm: 120 locations; the tool's front meets the 40 mm block from x = -5 to 40,
    // 90 of them (one either way for the locations at the block's faces).
    ASSERT_EQ(seen.size(), 120u) << threads;
    EXPECT_EQ(prepared, 120) << threads;
    for (std::size_t k = 0; k < seen.size(); ++k) EXPECT_EQ(seen[k], k) << threads;
    EXPECT_NEAR(engaged, 90, 1) << threads;
  }
}

// The batches EngagementRun holds its locations and moves in change no result: a zig-zag of
// two levels (passes over earlier ones, a rapid and ramps between them)
// gives every location's map and every move's volume the same, bit for bit, in one batch, in
// batches of a few locations or moves (groups cut short by a batch's end), one location at a
// time, on one thread and on two.
TEST(EngagementRun, BatchesChangeNoResult) {
  std::vector<Move> moves{line({-8, 5, 25}, {-8, 5, 18.5})};
  for (const double z : {18.5, 17.0}) {
    for (int row = 0; row < 4; ++row) {
      const double y = 5.0 + 6.0 * row;
      const bool forward = row % 2 == 0;
      moves.push_back(line({forward ? -8.0 : 48.0, y, z}, {forward ? 48.0 : -8.0, y, z}));
      moves.push_back(line(moves.back().end, moves.back().end + Vec3(0, 6, 0)));
    }
    moves.push_back(line(moves.back().end, {-8, 5, z - 1.5}));
  }
  for (Move& m : moves) m.feed_rate = 600;
  moves[0].mode = MotionMode::kRapid;
  moves[0].feed_rate = 0.0;
  const Cutter cutter = cutter_from_spec("flat:8,20");
  SimulationOptions options;
  options.resolution = 0.25;
  struct Seen {
    std::vector<std::size_t> index;
    std::vector<EngagementMap> maps;
    std::vector<double> volumes;
  };
  const auto simulate = [&](int threads, std::size_t locations, std::size_t batch_moves) {
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism,
                                    static_cast<std::size_t>(threads));
    TriDexel stock = TriDexel::from_box(kBlock, options.resolution);
    DexelWorkpiece workpiece(stock);
    Seen seen;
    EngagementRunOptions run_options{options, {}, {}};
    run_options.batch_locations = locations;
    run_options.batch_moves = batch_moves;
    EngagementRun run(
        workpiece, cutter, run_options,
        [&](const ClEngagement& e) {
          seen.index.push_back(e.index);
          seen.maps.push_back(e.map);
        },
        [&](std::size_t, double volume) { seen.volumes.push_back(volume); });
    for (const Move& m : moves) run.add(m, {"test"});
    run.finish();
    return seen;
  };
  const Seen whole = simulate(1, 1 << 20, 1 << 20);
  ASSERT_GT(whole.maps.size(), 400u);  // two levels of 4 rows of 56 mm at 0.5 mm
  ASSERT_EQ(whole.volumes.size(), moves.size());
  int engaged = 0;
  for (const EngagementMap& map : whole.maps) engaged += map.engaged ? 1 : 0;
  EXPECT_GT(engaged, 300);
  for (const auto& [threads, locations, batch_moves] :
       std::vector<std::tuple<int, std::size_t, std::size_t>>{
           {2, 1 << 20, 1 << 20}, {1, 7, 1 << 20}, {2, 7, 1 << 20}, {2, 1, 1}, {1, 1 << 20, 3}}) {
    const Seen batched = simulate(threads, locations, batch_moves);
    const std::string label = fmt::format("{} threads, batches of {} locations, {} moves", threads,
                                          locations, batch_moves);
    ASSERT_EQ(batched.index, whole.index) << label;
    EXPECT_EQ(batched.volumes, whole.volumes) << label;
    for (std::size_t k = 0; k < whole.maps.size(); ++k) {
      const EngagementMap &a = whole.maps[k], &b = batched.maps[k];
      ASSERT_EQ(a.discs.size(), b.discs.size());
      ASSERT_EQ(a.rings.size(), b.rings.size());
      bool same = a.engaged == b.engaged && a.phi_entry == b.phi_entry &&
                  a.phi_exit == b.phi_exit && a.axial_depth == b.axial_depth && a.area == b.area;
      for (std::size_t d = 0; d < a.discs.size(); ++d) {
        same = same && a.discs[d].phi == b.discs[d].phi;
      }
      for (std::size_t r = 0; r < a.rings.size(); ++r) {
        same = same && a.rings[r].phi == b.rings[r].phi;
      }
      ASSERT_TRUE(same) << label << ", location " << k;
    }
  }
}

}  // namespace
}  // namespace cwe

#include "cwe/envelope/linear_sweep.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "cwe/envelope/swept_volume.hpp"
#include "cwe/tool/tool_spec.hpp"
#include "random.hpp"
#include "sweep_oracle.hpp"

namespace cwe {
namespace {

Move linear(const Vec3& a, const Vec3& b, const Vec3& axis) {
  Move m;
  m.start = a;
  m.end = b;
  m.start_axis = m.end_axis = axis.normalized();
  return m;
}

// Oracle: along the ray, points well inside the chord are in the union of densely sampled tool
// positions, points well outside are not. "Well" is the band the sampling can resolve: moving the
// tool by at most half the gap between sampled positions changes any distance by at most that
// much, so the gap itself is a safe band.
void expect_chord_matches_union(const Cutter& cutter, const Move& move, const Ray& ray) {
  const LinearSweep sweep(cutter, move.start, move.end, move.start_axis);
  const Interval chord = sweep.chord(ray);
  constexpr int kPositions = 200;
  const double gap = move.length() / kPositions;
  // Dense samples around the chord (where errors would show) and sparse ones along the rest.
  std::vector<double> ts;
  for (int k = -60; k <= 60; ++k) ts.push_back(k * 0.25);
  if (!chord.is_empty()) {
    for (int k = 0; k <= 160; ++k) ts.push_back(chord.lo - 1.0 + (chord.length() + 2.0) * k / 160);
  }
  const double band = gap;
  for (const double t : ts) {
    const double d = test::union_signed_distance(cutter, move, ray.at(t), kPositions);
    if (std::abs(d) <= band) continue;
    const bool inside = !chord.is_empty() && chord.contains(t);
    ASSERT_EQ(inside, d < 0.0) << "t = " << t << " distance " << d << " chord [" << chord.lo << ", "
                               << chord.hi << "]";
  }
  // The chord's ends lie on the swept volume's boundary.
  if (!chord.is_empty()) {
    for (const double t : {chord.lo, chord.hi}) {
      EXPECT_LT(std::abs(test::union_signed_distance(cutter, move, ray.at(t), kPositions)), band);
    }
  }
}

TEST(LinearSweep, ChordsAgreeWithTheUnionOfToolPositions) {
  test::Random random(61);
  for (const char* spec :
       {"flat:10,20", "ball:10,20", "bull:10,2,20", "taper-flat:6,5,20", "taper-flat:10,-3,20",
        "taper-ball:4,3,20", "chamfer:12,90,15", "apt:7.8586,1,3,1.5444,10,5,20"}) {
    SCOPED_TRACE(spec);
    const Cutter cutter = cutter_from_spec(spec);
    const std::vector<Move> moves = {
        linear({0, 0, 0}, {15, 0, 0}, Vec3::UnitZ()),        // horizontal slot
        linear({0, 0, 0}, {12, 4, -4.4}, Vec3::UnitZ()),     // ramp down
        linear({0, 0, 0}, {8, -3, 5}, Vec3::UnitZ()),        // ascending
        linear({0, 0, 0}, {0, 0, -8}, Vec3::UnitZ()),        // plunge
        linear({0, 0, 0}, {10, 6, -2}, Vec3(0.3, -0.2, 1)),  // tilted 3+2
    };
    for (const Move& move : moves) {
      for (int k = 0; k < 4; ++k) {
        // Rays through random points near the sweep: axis-aligned (as dexels are) and random.
        const Vec3 through =
            0.5 * (move.start + move.end) + random.point_in_box(8.0) + Vec3(0, 0, 6);
        Vec3 direction = random.unit_vector();
        if (k < 3) direction = Vec3::Unit(k);
        expect_chord_matches_union(cutter, move, Ray{through, direction});
      }
    }
  }
}

// The chord agrees with the hull mesh of swept_volume(): both contain each other's points up to
// the hull's tessellation tolerance.
// A barrel's arc whose normal turns through horizontal, on a nearly axial move: its grazing curve
// exists only within 1.15° of the horizontal normal, narrower than the 3.8° between the arc's
// samples, and neither sample about it sees the curve. The chord search must still look between
// them (the normal's z component changes sign there): at heights that neither end of the tool
// covers, the swept barrel's width comes from that stretch of the curve alone.
TEST(LinearSweep, GrazingCurveNarrowerThanItsSamplesIsFound) {
  using Seg = ProfileSegment;
  const Cutter barrel(
      Profile({Seg::line({0, 0}, {3, 0}), Seg::arc({3, 0}, {4, 9}, {1, 86.0 / 18.0}, true)}),
      CutterOptions{});
  const Move move = linear({0, 0, 0}, {0.4, 0, -20}, Vec3::UnitZ());
  for (const double z : {-5.0, -7.0, -12.0}) {
    for (const double x : {0.0, 0.2, 0.4}) {
      SCOPED_TRACE("z " + std::to_string(z) + " x " + std::to_string(x));
      const Ray ray{{x, -20, z}, Vec3::UnitY()};
      expect_chord_matches_union(barrel, move, ray);
      // Wider than the barrel's foot: its bulge (about 6.2 mm) passes every such height.
      const LinearSweep sweep(barrel, move.start, move.end, move.start_axis);
      EXPECT_GT(sweep.chord(ray).length(), 2.0 * 6.0);
    }
  }
}

TEST(LinearSweep, AgreesWithTheSweptVolumeMesh) {
  test::Random random(62);
  const Cutter cutter = cutter_from_spec("bull:10,2,20");
  const Move move = linear({1, 2, 3}, {20, -4, -1}, Vec3::UnitZ());
  SweptVolumeOptions options;
  options.tolerance = 0.005;
  const TriangleMesh hull = swept_volume(cutter, move, options).pieces.front();
  const LinearSweep sweep(cutter, move.start, move.end, move.start_axis);
  int crossings = 0;
  for (int k = 0; k < 400; ++k) {
    const Ray ray{sweep.bounds().center() + random.point_in_box(6.0), random.unit_vector()};
    const Interval chord = sweep.chord(ray);
    // Mesh chord: the parameter range where the ray is behind every face plane.
    double lo = -1e9, hi = 1e9;
    for (const auto& t : hull.triangles) {
      const Vec3& a = hull.vertices[static_cast<std::size_t>(t[0])];
      const Vec3 n = (hull.vertices[static_cast<std::size_t>(t[1])] - a)
                         .cross(hull.vertices[static_cast<std::size_t>(t[2])] - a)
                         .normalized();
      const double num = n.dot(a - ray.origin), den = n.dot(ray.direction);
      if (den > 0) hi = std::min(hi, num / den);
      if (den < 0) lo = std::max(lo, num / den);
      if (den == 0 && num < 0) lo = 1e9;
    }
    if (lo > hi) {
      // Missed the inscribed mesh: the exact chord is at most a sliver of the tolerance.
      EXPECT_TRUE(chord.is_empty() || chord.length() < 2.0) << chord.length();
      continue;
    }
    ++crossings;
    ASSERT_FALSE(chord.is_empty());
    // The mesh is inscribed: its chord lies inside the exact one (minus rounding), and falls
    // short of it by no more than a grazing angle allows for a 0.005 mm deviation.
    EXPECT_LE(chord.lo, lo + 1e-9);
    EXPECT_GE(chord.hi, hi - 1e-9);
  }
  EXPECT_GT(crossings, 100);
}

// The closed forms for a vertical tool (level and axial moves, axis-aligned rays), and the culls
// of rays that miss a climbing or descending vertical tool's sweep, against the general
// construction, which the oracle tests above prove. Both are exact, so they agree to
// rounding (measured: about 1e-13 mm; asserted: 1e-9 mm). Only a ray that grazes a curved face
// can see more, the square root of the discriminant amplifying rounding: chords shorter than
// 1e-3 mm may differ by that much.
TEST(LinearSweep, ClosedFormsAgreeWithTheGeneralConstruction) {
  test::Random random(63);
  for (const char* spec :
       {"flat:10,20", "ball:10,20", "bull:10,2,20", "taper-flat:6,5,20", "taper-flat:10,-3,20",
        "taper-ball:4,3,20", "chamfer:12,90,15", "apt:7.8586,1,3,1.5444,10,5,20"}) {
    SCOPED_TRACE(spec);
    const Cutter cutter = cutter_from_spec(spec);
    int compared = 0;
    for (int m = 0; m < 30; ++m) {
      const Vec3 start = random.point_in_box(5.0);
      Vec3 end = start + random.point_in_box(12.0);
      if (m % 3 == 0) {
        end.z() = start.z();  // level
        // Every other level move runs along X or Y (most of a pocket's moves), which the level
        // chords take in closed form of their own.
        if (m % 6 == 0) end[(m / 6) % 2] = start[(m / 6) % 2];
      } else if (m % 3 == 1) {
        end.head<2>() = start.head<2>();  // axial
      }  // else climbing or descending: the general construction behind the culls
      const LinearSweep sweep(cutter, start, end, Vec3::UnitZ());
      for (int k = 0; k < 300; ++k) {
        const Vec3 through = sweep.bounds().center() + random.point_in_box(10.0);
        const int axis = k % 3;
        const Ray ray{through, (k % 2 == 0 ? 1.0 : -1.0) * Vec3::Unit(axis)};
        const Interval fast = sweep.chord(ray), general = sweep.generic_chord(ray);
        // The reach holds the chord (it is all that dexel removal looks at before the chord).
        const Interval reach = sweep.reach(ray);
        if (!general.is_empty() && general.length() >= 1e-3) {
          ASSERT_LE(reach.lo, general.lo + 1e-9) << "move " << m << " ray " << k;
          ASSERT_GE(reach.hi, general.hi - 1e-9) << "move " << m << " ray " << k;
        }
        if (fast.is_empty() || general.is_empty()) {
          EXPECT_LT(std::max(fast.length(), general.length()), 1e-3)
              << "move " << m << " ray " << k;
          continue;
        }
        ++compared;
        const double tolerance = std::min(fast.length(), general.length()) < 1e-3 ? 1e-3 : 1e-9;
        ASSERT_NEAR(fast.lo, general.lo, tolerance) << "move " << m << " ray " << k;
        ASSERT_NEAR(fast.hi, general.hi, tolerance) << "move " << m << " ray " << k;
      }
    }
    EXPECT_GT(compared, 1000);
  }
}

// The chords of a row of rays are the chords of its rays one by one, to the last bit: removal
// takes them a row at a time, and its results must not depend on which way it asked. Rows of
// all three dexel families (horizontal rays in rows across in plan and in rows up the height;
// vertical rays), both directions, on level, axial, climbing and tilted moves.
TEST(LinearSweep, RowChordsAreTheRaysChords) {
  test::Random random(64);
  for (const char* spec : {"flat:10,20", "ball:10,20", "bull:10,2,20", "taper-flat:10,-3,20"}) {
    SCOPED_TRACE(spec);
    const Cutter cutter = cutter_from_spec(spec);
    int nonempty = 0;
    for (int m = 0; m < 24; ++m) {
      const Vec3 start = random.point_in_box(5.0);
      Vec3 end = start + random.point_in_box(12.0);
      if (m % 4 == 0) {
        end.z() = start.z();
        if (m % 8 == 0) end[(m / 8) % 2] = start[(m / 8) % 2];  // level along X or Y
      } else if (m % 4 == 1) {
        end.head<2>() = start.head<2>();  // axial
      } else if (m % 8 == 2) {
        end[(m / 8) % 2] = start[(m / 8) % 2];  // climbing along Y or X
      }
      const Vec3 axis = m % 4 == 3 ? Vec3(0.3, -0.2, 1.0).normalized() : Vec3::UnitZ();
      const LinearSweep sweep(cutter, start, end, axis);
      const Vec3 low_tip = start.z() < end.z() ? start : end;
      for (int a = 0; a < 3; ++a) {
        for (int across = 0; across < 3; ++across) {
          if (across == a) continue;
          const Vec3 d = (m % 2 == 0 ? 1.0 : -1.0) * Vec3::Unit(a);
          // A row about the sweep's middle, and rows just above its lowest tip, across it from
          // far beside the path to far beyond it (each ray's lowest reach its own).
          std::vector<Ray> rows{{sweep.bounds().center() + random.point_in_box(6.0), d}};
          for (const double lift : {0.05, 0.5, 2.0}) rows.push_back({low_tip + lift * axis, d});
          for (const Ray& row : rows) {
            std::vector<double> at(32);
            for (std::size_t k = 0; k < at.size(); ++k) {
              at[k] = row.origin[across] - 8.0 + 0.5 * static_cast<double>(k);
            }
            std::vector<Interval> chords(at.size());
            sweep.chords(row, across, at, chords);
            for (std::size_t k = 0; k < at.size(); ++k) {
              Ray ray = row;
              ray.origin[across] = at[k];
              const Interval one = sweep.chord(ray);
              nonempty += one.is_empty() ? 0 : 1;
              ASSERT_EQ(chords[k].is_empty(), one.is_empty()) << m << " " << a << " " << k;
              if (!one.is_empty()) {
                // Bit for bit (a zero's sign too).
                ASSERT_EQ(std::bit_cast<std::uint64_t>(chords[k].lo),
                          std::bit_cast<std::uint64_t>(one.lo))
                    << "move " << m << " family " << a << " ray " << k;
                ASSERT_EQ(std::bit_cast<std::uint64_t>(chords[k].hi),
                          std::bit_cast<std::uint64_t>(one.hi))
                    << "move " << m << " family " << a << " ray " << k;
              }
            }
          }
        }
      }
    }
    EXPECT_GT(nonempty, 1000);
  }
}

TEST(LinearSweep, RowSpansHoldEveryRayTheSweepMeets) {
  // Removal visits only the rays of a row within row_span(): any ray outside it with a chord
  // would keep material the sweep takes. Dense rows of vertical rays on moves of an upright tool
  // in every direction (level, along X or Y, climbing, plunging, of no length), rays just
  // outside each span's ends, and other rows, which must get the whole line.
  test::Random random(65);
  for (const char* spec :
       {"flat:10,20", "ball:10,20", "bull:10,2,20", "taper-flat:10,-3,20", "taper-flat:6,5,20"}) {
    SCOPED_TRACE(spec);
    const Cutter cutter = cutter_from_spec(spec);
    int narrowed = 0, inside = 0;
    for (int m = 0; m < 24; ++m) {
      const Vec3 start = random.point_in_box(5.0);
      Vec3 end = start + random.point_in_box(12.0);
      if (m % 3 != 2) end.z() = start.z();                    // level, or climbing
      if (m % 6 == 0) end[(m / 6) % 2] = start[(m / 6) % 2];  // along X or Y
      if (m == 5) end = start;
      if (m == 7) end.head<2>() = start.head<2>();  // plunging
      const LinearSweep sweep(cutter, start, end, Vec3::UnitZ());
      for (const int across : {0, 1}) {
        for (const double dz : {1.0, -1.0}) {
          Ray row{sweep.bounds().center() + random.point_in_box(8.0), Vec3(0.0, 0.0, dz)};
          const Interval span = sweep.row_span(row, across);
          narrowed += span == Interval::full() ? 0 : 1;
          const auto chord_at = [&](double x) {
            Ray ray = row;
            ray.origin[across] = x;
            return sweep.chord(ray);
          };
          for (int k = 0; k <= 400; ++k) {
            const double x = row.origin[across] - 20.0 + 0.1 * k;
            if (chord_at(x).is_empty()) continue;
            ++inside;
            ASSERT_TRUE(span.contains(x)) << "move " << m << " across " << across << " at " << x;
          }
          if (span.is_empty() || span == Interval::full()) continue;
          const double inf = std::numeric_limits<double>::infinity();
          EXPECT_TRUE(chord_at(std::nextafter(span.lo, -inf)).is_empty()) << m;
          EXPECT_TRUE(chord_at(std::nextafter(span.hi, inf)).is_empty()) << m;
        }
      }
      // Rows of level rays, and vertical rays of a tilted tool: no span.
      const Ray level{start, Vec3::UnitX()};
      EXPECT_EQ(sweep.row_span(level, 1), Interval::full());
      const LinearSweep tilted(cutter, start, end, Vec3(0.3, -0.2, 1.0).normalized());
      EXPECT_EQ(tilted.row_span(Ray{start, Vec3::UnitZ()}, 0), Interval::full());
    }
    EXPECT_GT(narrowed, 80);
    EXPECT_GT(inside, 5000);
  }
}

// chord() takes a ball end's chord on a ray along X or Y above both ball centres from the
// swept cylinder's section alone (LinearSweep::kBallClearance): exact only while the ball's
// capsule stays well inside the section, by g = R − √(R² − m²), m = kBallClearance·R, far more
// than rounding. Rays just above that clearance, on climbing and descending moves along X, Y and
// diagonals: the ray's interval through the ball's capsule (points within R of the centres'
// segment, found by dense steps and bisection) lies at least g/2 inside the chord.
TEST(LinearSweep, BallCapsuleLiesInsideTheSectionAboveTheClearance) {
  test::Random random(66);
  for (const char* spec : {"ball:6,20", "ball:10,30", "ball:3.175,12"}) {
    SCOPED_TRACE(spec);
    const Cutter cutter = cutter_from_spec(spec);
    const double r = cutter.profile().max_radius();
    const double m = LinearSweep::kBallClearance * r, g = r - std::sqrt(r * r - m * m);
    // A thousand times the rounding of the chords at a tangent (≈ 5e-8·R).
    EXPECT_GT(g, 1000.0 * 5e-8 * r);
    int checked = 0;
    for (int k = 0; k < 60; ++k) {
      const Vec3 start = random.point_in_box(20.0);
      Vec3 feed(random.uniform(-2.0, 2.0), random.uniform(-2.0, 2.0), random.uniform(-0.6, 0.6));
      if (k % 3 == 0) feed.y() = 0.0;  // along X
      if (k % 3 == 1) feed.x() = 0.0;  // along Y
      const LinearSweep sweep(cutter, start, start + feed, Vec3::UnitZ());
      const Vec3 c0 = start + Vec3(0.0, 0.0, r), c1 = c0 + feed;
      const double lowest = std::max(c0.z(), c1.z()) + m;
      for (int a = 0; a < 2; ++a) {
        for (int n = 0; n < 20; ++n) {
          // Just above the clearance, or anywhere up to the cylinder's top; beside the path.
          const double z =
              lowest + (n % 2 == 0 ? random.uniform(0.0, 0.01 * r) : random.uniform(0.0, 2.0 * r));
          Vec3 o = 0.5 * (c0 + c1) + random.point_in_box(r);
          o.z() = z;
          o[a] -= 30.0;
          const Ray ray{o, Vec3::Unit(a)};
          const auto inside = [&](double t) {
            const Vec3 p = o + t * ray.direction, f = c1 - c0;
            const double u = std::clamp((p - c0).dot(f) / f.squaredNorm(), 0.0, 1.0);
            return (p - c0 - u * f).norm() <= r;
          };
          // The capsule's interval: the first and last steps inside, refined to 1e-12.
          double first = -1.0, last = -1.0;
          for (double t = 20.0; t <= 40.0; t += 1e-3) {
            if (!inside(t)) continue;
            if (first < 0.0) first = t;
            last = t;
          }
          if (first < 0.0) continue;
          const auto edge = [&](double in, double out) {
            for (int i = 0; i < 60; ++i) {
              const double mid = 0.5 * (in + out);
              (inside(mid) ? in : out) = mid;
            }
            return in;
          };
          first = edge(first, first - 1e-3);
          last = edge(last, last + 1e-3);
          const Interval chord = sweep.chord(ray);
          ASSERT_FALSE(chord.is_empty()) << k;
          EXPECT_LE(chord.lo, first - 0.5 * g) << "move " << k << " ray " << n;
          EXPECT_GE(chord.hi, last + 0.5 * g) << "move " << k << " ray " << n;
          ++checked;
        }
      }
    }
    EXPECT_GT(checked, 1500);
  }
}

TEST(LinearSweep, StraightSlotChordsInClosedForm) {
  // Flat end mill D = 10 from (0, 0, 0) to (30, 0, 0): an X-ray at height 5, offset y = 3, meets
  // the stadium from -4 to 34; a Z-ray at (12, 4) from the tip plane up to the top, 20.
  const Cutter flat = cutter_from_spec("flat:10,20");
  const LinearSweep sweep(flat, Vec3(0, 0, 0), Vec3(30, 0, 0), Vec3::UnitZ());
  Interval c = sweep.chord(Ray{Vec3(-50, 3, 5), Vec3::UnitX()});
  EXPECT_NEAR(c.lo, 50 - 4, 1e-12);
  EXPECT_NEAR(c.hi, 50 + 34, 1e-12);
  c = sweep.chord(Ray{Vec3(12, 4, -10), Vec3::UnitZ()});
  EXPECT_NEAR(c.lo, 10, 1e-12);
  EXPECT_NEAR(c.hi, 30, 1e-12);
  EXPECT_TRUE(sweep.chord(Ray{Vec3(12, 5.5, -10), Vec3::UnitZ()}).is_empty());
  // Along the feed: the two tool chords.
  c = sweep.chord(Ray{Vec3(-20, 0, 1), Vec3::UnitX()});
  EXPECT_NEAR(c.lo, 15, 1e-12);
  EXPECT_NEAR(c.hi, 55, 1e-12);
}

}  // namespace
}  // namespace cwe

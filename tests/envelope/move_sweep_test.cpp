#include "cwe/envelope/move_sweep.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "cwe/core/error.hpp"
#include "cwe/geometry/tolerance.hpp"
#include "cwe/tool/tool_spec.hpp"
#include "random.hpp"
#include "sweep_oracle.hpp"

namespace cwe {
namespace {

using Seg = ProfileSegment;

using test::line;

Move arc(const Vec3& start, const Vec3& center, double sweep, double axial) {
  Move m;
  m.shape = MoveShape::kArc;
  m.start = start;
  m.center = center;
  m.normal = Vec3::UnitZ();
  m.sweep = sweep;
  m.axial = axial;
  m.end = m.position(1.0);
  return m;
}

// A corner-rounding cutter (concave arc, step): not convex.
Cutter corner_rounding() {
  CutterOptions options;
  options.name = "corner rounding";
  return Cutter(Profile({Seg::line({0, 0}, {2, 0}), Seg::line({2, 0}, {2, 1}),
                         Seg::arc({2, 1}, {5, 4}, {5, 1}, false), Seg::line({5, 4}, {8, 4}),
                         Seg::line({8, 4}, {8, 12})}),
                options);
}

bool inside(const MoveSweep& sweep, const Vec3& p, const Vec3& direction) {
  for (const LinearSweep& piece : sweep.pieces()) {
    if (piece.chord(Ray{p, direction}).contains(0.0)) return true;
  }
  return false;
}

// Points near the move: inside the union of the pieces exactly when inside the union of densely
// sampled true tool positions, outside a band of the deviation bound plus the sampling gap (the
// farthest any tool point travels between two samples).
// With `within`, the points are drawn in that box only.
void expect_matches_true_sweep(const Cutter& cutter, const MoveSweep& sweep, const Move& move,
                               test::Random& random, int points = 600,
                               const Aabb& within = Aabb()) {
  constexpr int kPositions = 400;
  const BoundingCylinder b = cutter.bounding_cylinder();
  const double reach = std::hypot(b.radius, b.z_max);
  const double gap = (move.length() + reach * move.axis_angle()) / kPositions;
  const double band = sweep.deviation_bound() + gap + 1e-9;
  Aabb box = sweep.bounds();
  if (!within.is_empty()) {
    box.min = box.min.cwiseMax(within.min);
    box.max = box.max.cwiseMin(within.max);
  }
  int in = 0, out = 0;
  for (int k = 0; k < points; ++k) {
    const Vec3 p = box.center() +
                   0.5 * box.size().cwiseProduct(Vec3(random.uniform(-1, 1), random.uniform(-1, 1),
                                                      random.uniform(-1, 1)));
    const double d = test::union_signed_distance(cutter, move, p, kPositions);
    if (std::abs(d) <= band) continue;
    const Vec3 direction = k % 2 == 0 ? Vec3::Unit(k % 3) : random.unit_vector();
    ASSERT_EQ(inside(sweep, p, direction), d < 0.0)
        << "point " << p.transpose() << " distance " << d;
    (d < 0.0 ? in : out) += 1;
  }
  EXPECT_GT(in, points / 20);
  EXPECT_GT(out, points / 20);
}

TEST(ConvexParts, AnAptCutterIsItsOwnPart) {
  const Cutter bull = cutter_from_spec("bull:10,2,20");
  const ConvexParts parts(bull, 0.01);
  ASSERT_EQ(parts.parts().size(), 1u);
  EXPECT_EQ(parts.parts()[0].cutter, &bull);
  EXPECT_EQ(parts.deviation(), 0.0);
  EXPECT_THROW(ConvexParts(bull, 0.0), InputError);
  EXPECT_THROW(ConvexParts(bull, std::nan("")), InputError);
}

TEST(ConvexParts, ANonConvexToolIsCutIntoSlabs) {
  const Cutter tool = corner_rounding();
  const ConvexParts parts(tool, 0.01);
  // Pilot line, the concave arc as chords (sagitta ≤ 0.01 on r = 3: 2·acos(1 - 0.01/3) per step
  // over a quarter circle gives 10 chords), the cylinder; the step and the bottom add none.
  const int arc_steps =
      static_cast<int>(std::ceil((kPi / 2) / (2.0 * std::acos(1.0 - 0.01 / 3.0))));
  EXPECT_EQ(static_cast<int>(parts.parts().size()), 1 + arc_steps + 1);
  EXPECT_GT(parts.deviation(), 0.0);
  EXPECT_LE(parts.deviation(), 0.01);
  // The parts stack up: each starts where the previous one ends, and their union is the tool
  // within the deviation, outside it never below.
  test::Random random(71);
  for (int k = 0; k < 4000; ++k) {
    const Vec3 p(random.uniform(-9, 9), random.uniform(-9, 9), random.uniform(-1, 13));
    bool in_parts = false;
    for (const auto& part : parts.parts()) {
      in_parts = in_parts || part.cutter->contains(p - part.offset * Vec3::UnitZ());
    }
    const double d = test::signed_distance(tool, p);
    if (d < 0.0) {
      ASSERT_TRUE(in_parts) << p.transpose();
    }
    if (d > parts.deviation() + 1e-12) {
      ASSERT_FALSE(in_parts) << p.transpose();
    }
  }
}

TEST(MoveSweep, NonConvexToolAlongLinearMoves) {
  test::Random random(72);
  const Cutter tool = corner_rounding();
  const ConvexParts parts(tool, 0.01);
  for (const Move& move : {line({0, 0, 0}, {15, 4, 0}, Vec3::UnitZ(), Vec3::UnitZ()),
                           line({0, 0, 0}, {10, 0, -5}, Vec3::UnitZ(), Vec3::UnitZ()),
                           line({0, 0, 0}, {8, 6, -2}, Vec3(0.3, 0, 1), Vec3(0.3, 0, 1))}) {
    const MoveSweep sweep(parts, move);
    EXPECT_EQ(sweep.path_pieces(), 1);
    EXPECT_DOUBLE_EQ(sweep.deviation_bound(), parts.deviation());
    expect_matches_true_sweep(tool, sweep, move, random);
  }
}

TEST(MoveSweep, ArcsHelicesAndFiveAxisBySubdivision) {
  test::Random random(73);
  for (const char* spec : {"flat:10,20", "ball:10,20", "bull:10,2,20"}) {
    SCOPED_TRACE(spec);
    const Cutter cutter = cutter_from_spec(spec);
    const ConvexParts parts(cutter, 0.02);
    const Move quarter = arc({20, 0, 0}, {0, 0, 0}, kPi / 2, 0.0);
    const Move helix = arc({6, 0, 0}, {0, 0, 0}, 1.5 * kPi, -4.0);
    const Move five_axis = line({0, 0, 0}, {20, 5, -2}, Vec3(0, 0, 1), Vec3(0.4, 0.1, 1));
    for (const Move& move : {quarter, helix, five_axis}) {
      const MoveSweep sweep(parts, move);
      EXPECT_GT(sweep.path_pieces(), 1);
      EXPECT_DOUBLE_EQ(sweep.deviation_bound(), 0.02);
      expect_matches_true_sweep(cutter, sweep, move, random);
    }
    // The quarter circle of radius 20 at sagitta ≤ 0.02: steps of 2·acos(1 - 0.02/20).
    EXPECT_EQ(MoveSweep(parts, quarter).path_pieces(),
              static_cast<int>(std::ceil((kPi / 2) / (2.0 * std::acos(1.0 - 0.001)))));
  }
}

// A long tool tilting a few millimetres into the material: only the part of it that can enter
// the region holding the material sets the pieces. Within the region the sweep is the true one
// to the same bound with far fewer pieces; a region the whole tool can reach changes nothing.
// From above (the axis up, the block's top face) and from below (the axis down, its bottom).
TEST(MoveSweep, FiveAxisPiecesReachOnlyIntoTheRegion) {
  test::Random random(74);
  for (const char* spec : {"flat:10,50", "ball:8,60", "bull:10,2,50"}) {
    for (const double up : {1.0, -1.0}) {
      SCOPED_TRACE(std::string(spec) + (up > 0.0 ? " from above" : " from below"));
      const Cutter cutter = cutter_from_spec(spec);
      const ConvexParts parts(cutter, 0.02);
      // From along ±Z to 30° over the +X side, the tip 3 mm inside a 40 × 40 × 10 block.
      const Move tilt = line({0, 0, -3 * up}, {15, 6, -3 * up}, up * Vec3::UnitZ(),
                             Vec3(std::sin(kPi / 6), 0, up * std::cos(kPi / 6)));
      const Aabb block =
          up > 0.0 ? Aabb{{-20, -20, -10}, {20, 20, 0}} : Aabb{{-20, -20, 0}, {20, 20, 10}};
      const MoveSweep everywhere(parts, tilt);
      const MoveSweep within(parts, tilt, block);
      // The tool's part within reach: (3 + R) / cos 30° above the tip, R the largest radius.
      const double radius = cutter.bounding_cylinder().radius;
      const double height = (3.0 + radius) / std::cos(kPi / 6);
      const double turn = tilt.axis_angle();
      EXPECT_EQ(within.path_pieces(),
                static_cast<int>(std::ceil(turn * std::hypot(radius, height) / (2.0 * 0.02))));
      EXPECT_LT(3 * within.path_pieces(), everywhere.path_pieces());
      // What that rests on: no tool point higher than that, at any pose of the move or of a
      // piece (its middle axis, its tip anywhere on its chord), lies in the block.
      const Profile& profile = cutter.profile();
      const auto clear_above = [&](const Vec3& tip, const Vec3& axis) {
        const Vec3 e1 = axis.cross(Vec3::UnitY()).normalized(), e2 = axis.cross(e1);
        for (double h = height + 1e-9; h <= profile.height(); h += 0.25) {
          for (int k = 0; k < 72; ++k) {
            const double phi = kTwoPi * k / 72;
            const Vec3 point =
                tip + h * axis + profile.radius_at(h) * (std::cos(phi) * e1 + std::sin(phi) * e2);
            if (block.contains(point)) return false;
          }
        }
        return true;
      };
      for (int k = 0; k <= 100; ++k) {
        ASSERT_TRUE(clear_above(tilt.position(k / 100.0), tilt.axis(k / 100.0))) << k;
      }
      for (const LinearSweep& piece : within.pieces()) {
        for (const double u : {0.0, 0.5, 1.0}) {
          ASSERT_TRUE(clear_above(piece.start() + u * (piece.end() - piece.start()), piece.axis()));
        }
      }
      expect_matches_true_sweep(cutter, within, tilt, random, 1500, block);
      // A block as tall as the tool: no fewer pieces.
      const Aabb tall{{-20, -20, -80}, {20, 20, 80}};
      EXPECT_EQ(MoveSweep(parts, tilt, tall).path_pieces(), everywhere.path_pieces());
    }
  }
}

// A tolerance far below any machining need would cut a move into millions of pieces (44 s to
// bad_alloc once): an error at --tolerance that names the move, before anything is allocated.
TEST(MoveSweep, TooManyPiecesIsAnErrorAtTheTolerance) {
  const Cutter cutter = cutter_from_spec("flat:10,20");
  Move full = arc({20, 0, 0}, {0, 0, 0}, 2 * kPi, 0.0);
  full.line = 31;
  const ConvexParts fine(cutter, 1e-12);
  try {
    MoveSweep sweep(fine, full);
    ADD_FAILURE() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.location().source, "--tolerance");
    EXPECT_NE(e.message().find("would cut the move at line 31 into"), std::string::npos)
        << e.what();
  }
  // A full circle of radius 20 at 1e-9 mm: 2π / (2·acos(1 - 1e-9/20)) ≈ π·1e5 steps, within it.
  EXPECT_NEAR(MoveSweep(ConvexParts(cutter, 1e-9), full).path_pieces(), kPi * 1e5, 2.0);
}

}  // namespace
}  // namespace cwe

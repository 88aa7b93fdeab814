// Cutter radius compensation (G41, G42, G41.1, G42.1). LinuxCNC's own results are in the golden
// program tests/toolpath/golden/compensation.ngc (gcode_reader_test.cpp); here the geometry is
// proven without LinuxCNC: along a contour of lines, arcs, convex and concave corners, every point
// of the compensated path (once on the contour) is exactly one tool radius from the programmed
// contour, on the side asked for, and passes each element of it.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "cwe/toolpath/gcode_reader.hpp"
#include "reader_testing.hpp"

namespace cwe {
namespace {

// Distances below come from a handful of operations (atan2, cos, hypot) on coordinates below
// 100 mm: rounding stays below 1e-12 mm; 1e-9 mm leaves margin.
constexpr double kTight = 1e-9;

Toolpath read(std::string_view text, const GcodeOptions& options = {}) {
  return read_gcode(text, "test.ngc", options);
}

// A programmed contour element: a segment, or a counter-clockwise arc about `center`.
struct Element {
  Vec2 a, b;
  bool arc = false;
  Vec2 center = Vec2::Zero();
};

// Exact distance from p to an element.
double distance(const Vec2& p, const Element& e) {
  if (!e.arc) {
    const Vec2 d = e.b - e.a;
    const double t = std::clamp((p - e.a).dot(d) / d.squaredNorm(), 0.0, 1.0);
    return (p - (e.a + t * d)).norm();
  }
  const double r = (e.a - e.center).norm();
  const double from = std::atan2(e.a.y() - e.center.y(), e.a.x() - e.center.x());
  double sweep = std::atan2(e.b.y() - e.center.y(), e.b.x() - e.center.x()) - from;
  if (sweep <= 0.0) sweep += kTwoPi;
  double angle = std::atan2(p.y() - e.center.y(), p.x() - e.center.x()) - from;
  while (angle < 0.0) angle += kTwoPi;
  if (angle <= sweep) return std::abs((p - e.center).norm() - r);
  return std::min((p - e.a).norm(), (p - e.b).norm());
}

double distance(const Vec2& p, const std::vector<Element>& contour) {
  double best = std::numeric_limits<double>::infinity();
  for (const Element& e : contour) best = std::min(best, distance(p, e));
  return best;
}

// Inside the region the counter-clockwise contour bounds (crossing number on a fine polygon).
bool inside(const Vec2& p, const std::vector<Element>& contour) {
  std::vector<Vec2> polygon;
  for (const Element& e : contour) {
    if (!e.arc) {
      polygon.push_back(e.a);
      continue;
    }
    const double r = (e.a - e.center).norm();
    const double from = std::atan2(e.a.y() - e.center.y(), e.a.x() - e.center.x());
    double sweep = std::atan2(e.b.y() - e.center.y(), e.b.x() - e.center.x()) - from;
    if (sweep <= 0.0) sweep += kTwoPi;
    for (int k = 0; k < 1000; ++k) {
      const double t = from + sweep * k / 1000.0;
      polygon.emplace_back(e.center.x() + r * std::cos(t), e.center.y() + r * std::sin(t));
    }
  }
  bool in = false;
  for (std::size_t i = 0, j = polygon.size() - 1; i < polygon.size(); j = i++) {
    const Vec2 &u = polygon[i], &v = polygon[j];
    if ((u.y() > p.y()) != (v.y() > p.y()) &&
        p.x() < (v.x() - u.x()) * (p.y() - u.y()) / (v.y() - u.y()) + u.x()) {
      in = !in;
    }
  }
  return in;
}

// A plate with a rounded corner and a notch, counter-clockwise from the origin: convex corners,
// concave corners (the notch), a line-to-arc and an arc-to-line joint.
const std::vector<Element> kPlate = {
    {{0, 0}, {40, 0}},    {{40, 0}, {50, 10}, true, {40, 10}},
    {{50, 10}, {50, 30}}, {{50, 30}, {35, 30}},
    {{35, 30}, {35, 20}}, {{35, 20}, {25, 20}},
    {{25, 20}, {25, 30}}, {{25, 30}, {0, 30}},
    {{0, 30}, {0, 0}},
};

// The plate compensated on `side` (G41.1 or G42.1) with a tool of diameter 4: in from the left
// of the origin, once round, along the first edge again (so that the origin's corner is made),
// out with G40.
std::string plate_program(const std::string& side) {
  return "G21 G17 G90 F500\nG0 X-10 Y-10 Z-1\n" + side +
         " D4 G1 X0 Y0\n"
         "X40\nG3 X50 Y10 R10\nG1 Y30\nX35\nY20\nX25\nY30\nX0\nY0\nX20\n"
         "G40 G1 X20 Y-10\nM2\n";
}

void expect_offset_by_radius(const std::string& side, bool tool_inside) {
  SCOPED_TRACE(side);
  const double r = 2.0;
  const Toolpath path = read(plate_program(side));
  // The moves after the entry and before the exit. The entry (after the rapid) ends square to
  // its own direction; from outside, the next move is on the offset. From inside, the entry
  // turns round the origin's corner (an arc about it) onto the first edge's offset line, whose
  // start still touches the left edge: the move after that is on the offset.
  ASSERT_GT(path.moves.size(), 4u);
  const auto on_offset = [&](const Vec2& q) {
    return std::abs(distance(q, kPlate) - r) < kTight && inside(q, kPlate) == tool_inside;
  };
  std::size_t first = 2;
  while (first < 5 && !on_offset(path.moves[first].start.head<2>())) ++first;
  EXPECT_EQ(first, tool_inside ? 4u : 2u);
  std::vector<Vec2> tool;
  for (std::size_t i = first; i + 1 < path.moves.size(); ++i) {
    const Move& m = path.moves[i];
    EXPECT_FALSE(m.is_rapid());
    for (int k = 0; k <= 200; ++k) {
      const Vec3 p = m.position(k / 200.0);
      EXPECT_NEAR(p.z(), -1.0, kTight);
      const Vec2 q = p.head<2>();
      // On the tool's side of the contour, touching it, never into it.
      EXPECT_NEAR(distance(q, kPlate), r, kTight) << "move " << i << " at " << q.transpose();
      EXPECT_EQ(inside(q, kPlate), tool_inside) << q.transpose();
      tool.push_back(q);
    }
  }
  // The tool passes every element: its middle is one radius from the path (within the path's
  // sampling: points 0.25 mm apart at most pass within 0.25²/(8·2) mm ≈ 0.004 mm of it).
  for (const Element& e : kPlate) {
    Vec2 middle = (e.a + e.b) / 2.0;
    if (e.arc) middle = e.center + (middle - e.center).normalized() * (e.a - e.center).norm();
    double nearest = std::numeric_limits<double>::infinity();
    for (const Vec2& q : tool) nearest = std::min(nearest, (q - middle).norm());
    EXPECT_GE(nearest, r - kTight) << middle.transpose();
    EXPECT_LE(nearest, r + 0.004) << middle.transpose();
  }
}

// Reading `text` throws an InputError at line:column whose message contains `fragment`.
void expect_error(std::string_view text, int line, int column, const std::string& fragment,
                  const GcodeOptions& options = {}) {
  test::expect_input_error([&](std::string_view t) { return read(t, options); }, "test.ngc", text,
                           line, column, fragment);
}

TEST(GcodeCompensation, ThePathIsOneRadiusFromTheContourOnTheSideAskedFor) {
  expect_offset_by_radius("G41.1", true);   // left of a counter-clockwise contour: inside
  expect_offset_by_radius("G42.1", false);  // right: outside
}

TEST(GcodeCompensation, CornersTheToolGoesRoundGetArcs) {
  // Arcs of the tool radius about each corner the tool passes outside: from outside the plate,
  // its five convex corners (50,30), (35,30), (25,30), (0,30), (0,0); from inside, the origin on
  // the way in, and the notch's two floor corners. The tangent joints of the R10 arc get none;
  // the arc itself grows to R12 outside and shrinks to R8 inside.
  const auto radii = [](const Toolpath& p) {
    std::vector<double> r;
    for (const Move& m : p.moves) {
      if (m.is_arc()) r.push_back(m.radius());
    }
    return r;
  };
  const std::vector<double> out = radii(read(plate_program("G42.1")));
  ASSERT_EQ(out.size(), 6u);
  EXPECT_NEAR(out[0], 12.0, kTight);
  for (std::size_t i = 1; i < out.size(); ++i) EXPECT_NEAR(out[i], 2.0, kTight);
  const std::vector<double> in = radii(read(plate_program("G41.1")));
  ASSERT_EQ(in.size(), 4u);
  EXPECT_NEAR(in[0], 2.0, kTight);
  EXPECT_NEAR(in[1], 8.0, kTight);
  EXPECT_NEAR(in[2], 2.0, kTight);
  EXPECT_NEAR(in[3], 2.0, kTight);
}

TEST(GcodeCompensation, ToolTableDiameterAsTheDiameterGiven) {
  GcodeOptions options;
  options.tool_diameter = [](int tool) -> std::optional<double> {
    if (tool == 3) return 4.0;
    return std::nullopt;
  };
  const Toolpath given = read(plate_program("G41.1"), options);
  const auto same = [&](const std::string& text, const GcodeOptions& o) {
    SCOPED_TRACE(text);
    const Toolpath p = read(text, o);
    ASSERT_EQ(p.moves.size(), given.moves.size());
    for (std::size_t i = 0; i < p.moves.size(); ++i) {
      EXPECT_LT((p.moves[i].end - given.moves[i].end).norm(), kTight);
    }
  };
  std::string text = plate_program("G41");
  text.replace(text.find("G41 D4"), 6, "G41");
  same("T3 M6\n" + text, options);  // the tool in the spindle
  text.replace(text.find("G41"), 3, "G41 D3");
  same(text, options);  // tool D
  text.replace(text.find("G41 D3"), 6, "G41 D0");
  same("T3 M6\n" + text, options);  // D0: the tool in the spindle
  // An inch program: the table's millimetres become inches.
  GcodeOptions inch = options;
  inch.tool_diameter = [](int) -> std::optional<double> { return 2 * 25.4; };
  const Toolpath a = read("G20 F10\nG0 X-1 Y-1\nG41 D7 G1 X0 Y0\nX5\nY5\nG40 X6\nM2\n", inch);
  const Toolpath b = read("G20 F10\nG0 X-1 Y-1\nG41.1 D2 G1 X0 Y0\nX5\nY5\nG40 X6\nM2\n");
  ASSERT_EQ(a.moves.size(), b.moves.size());
  for (std::size_t i = 0; i < a.moves.size(); ++i) {
    EXPECT_LT((a.moves[i].end - b.moves[i].end).norm(), kTight);
  }
  // After the entry and an arc round the origin, the first edge ends one inch inside the
  // corner it makes with the second: X4 Y1 in, in mm.
  ASSERT_GT(a.moves.size(), 3u);
  EXPECT_TRUE(a.moves[2].is_arc());
  EXPECT_LT((a.moves[3].end - Vec3(4, 1, 0) * 25.4).norm(), kTight);
}

TEST(GcodeCompensation, NoToolInTheSpindleOffsetsNothingWithAWarning) {
  const Toolpath p = read("F100\nG41 G1 X10\nY10\nG40 X0\nM2\n");
  ASSERT_EQ(p.moves.size(), 3u);
  EXPECT_EQ(p.moves[0].end, Vec3(10, 0, 0));
  EXPECT_EQ(p.moves[1].end, Vec3(10, 10, 0));
  ASSERT_EQ(p.warnings.size(), 1u);
  EXPECT_NE(p.warnings[0].message.find("no tool in the spindle"), std::string::npos);
}

TEST(GcodeCompensation, MovesHeldAtTheEndOfAProgramWithoutM2AreNotMade) {
  // As in LinuxCNC: only G40, M0, M1, M2 and M30 release the move held for the next corner.
  const Toolpath p = read("%\nF100\nG41.1 D2 G1 X10\nY10\nX0\n%\n");
  ASSERT_EQ(p.moves.size(), 2u);
  bool warned = false;
  for (const Diagnostic& w : p.warnings) {
    if (w.message.find("never made") != std::string::npos) {
      warned = true;
      EXPECT_EQ(w.location.line, 5);
    }
  }
  EXPECT_TRUE(warned);
  EXPECT_EQ(read("%\nF100\nG41.1 D2 G1 X10\nY10\nX0\nM2\n%\n").moves.size(), 3u);
  // M0 releases it and compensation goes on.
  EXPECT_EQ(read("%\nF100\nG41.1 D2 G1 X10\nY10\nM0\nX0\n%\n").moves.size(), 2u);
}

TEST(GcodeCompensation, AfterG40TheNextMoveStartsWhereTheToolIs) {
  // G40 makes the programmed point current (X10 Y10), but the tool is one radius to the left of
  // it; the next move starts from the tool. A tool change takes the position from the machine.
  const Toolpath p = read("F100\nG41.1 D2 G1 X10\nY10\nG40\nG0 Z5\nT1 M6\nG0 Z6\nM2\n");
  ASSERT_EQ(p.moves.size(), 4u);
  const Vec3 tool(9, 10, 0);
  EXPECT_LT((p.moves[1].end - tool).norm(), kTight);
  EXPECT_LT((p.moves[2].start - tool).norm(), kTight);
  EXPECT_LT((p.moves[2].end - Vec3(10, 10, 5)).norm(), kTight);  // X Y from the program
  EXPECT_LT((p.moves[3].end - Vec3(10, 10, 6)).norm(), kTight);
  const Toolpath q = read("F100\nG41.1 D2 G1 X10\nY10\nG40\nT1 M6\nG0 Z6\nM2\n");
  ASSERT_EQ(q.moves.size(), 3u);
  EXPECT_LT((q.moves[2].end - Vec3(9, 10, 6)).norm(), kTight);  // resynchronised by M6
}

TEST(GcodeCompensation, M72RestoresCompensationOffAsLinuxCncDoes) {
  // M72 runs the G40 that the saved state had: the held move is released as it stands, and the
  // next move is not compensated (checked with rs274: (10, 1), then (10, 10)).
  const Toolpath p = read("G21 G17 G90\nG0 X0 Y-5 Z0 F100\nM70\nG41.1 D2\nG1 X0 Y0\nG1 X10\nM72\n"
                          "G1 Y10\nM2\n");
  ASSERT_EQ(p.moves.size(), 5u);
  EXPECT_LT((p.moves[3].end - Vec3(10, 1, 0)).norm(), kTight);
  EXPECT_LT((p.moves[4].end - Vec3(10, 10, 0)).norm(), kTight);
}

TEST(GcodeCompensation, LastBitsAsLinuxCnc) {
  // LinuxCNC adds its long double π/2 to the entry's direction, and compares lengths from hypot:
  // the entry ends at LinuxCNC's X 0.097139481176069631 (not …069853 of a double sum), and the
  // two entries below fall on the same sides of "longer than the radius" as in rs274.
  const Toolpath p = read("G21 F100\nG41.1 D2 G1 X1 Y2.1\nX5\nM2\n");
  EXPECT_EQ(p.moves[0].end.x(), 0.097139481176069631);
  expect_error("G21 F100\nG41.1 D0.58 G1 X0.2 Y0.21\nX1\nM2\n", 2, 13,
                    "length of cutter compensation entry move is not greater than the tool radius");
  EXPECT_NO_THROW(read("G21 F100\nG41.1 D0.7 G1 X0.21 Y0.28\nX1\nM2\n"));
}

TEST(GcodeCompensation, LinuxCncsErrors) {
  const std::string on = "F100\nG41.1 D4 G1 X10\n";  // compensation on, a move made
  expect_error("F100\nT2 M6\nG41 G1 X10\n", 3, 1, "needs the diameter of tool 2");
  expect_error("F100\nG41 D5 G1 X10\n", 2, 5, "needs the diameter of tool 5");
  expect_error("G41 D1.5\n", 1, 5, "G41 requires D word to be a whole number");
  // LinuxCNC rounds D by truncating D + 0.5, so a negative D is never a whole number to it.
  expect_error("G42 D-1\n", 1, 5, "G42 requires D word to be a whole number");
  expect_error("G41.1\n", 1, 1, "G41.1 with no D word");
  expect_error("G18\nG42.1 D2 L3\n", 2, 10, "lathe tool orientation");
  expect_error("G0 X1 D1\n", 1, 7, "D word with no G41, G41.1, G42 or G42.1 to use it");
  expect_error("G19\nG41.1 D2\n", 2, 1, "allowed only in XY, XZ planes");
  expect_error(on + "G42.1 D2\n", 3, 1, "cannot turn cutter radius comp on when on");
  expect_error(on + "G18\n", 3, 1, "cannot change planes with cutter radius compensation on");
  expect_error(on + "G55\n", 3, 1, "cannot change coordinate systems");
  expect_error(on + "G92 X0\n", 3, 1, "cannot change axis offsets with cutter radius comp");
  expect_error(on + "G28\n", 3, 1, "cannot use G28 or G30 with cutter radius comp");
  expect_error(on + "G30.1\n", 3, 1, "cannot set reference point");
  expect_error(on + "G53 G1 X0\n", 3, 1, "cannot use G53 with cutter radius comp");
  expect_error(on + "G81 X0 Y0 Z-1 R1\n", 3, 1, "cannot use canned cycles");
  expect_error(on + "G64 P0.01\n", 3, 1, "cannot change control mode");
  expect_error(on + "G98\n", 3, 1, "cannot change retract mode");
  expect_error(on + "T1 M6\n", 3, 4, "cannot change tools with cutter radius compensation on");
  expect_error(on + "G10 L2 P1 X1\n", 3, 8, "cannot change the active coordinate system");
  expect_error("F100\nG41.1 D4 G1 X1\n", 2, 10,
               "length of cutter compensation entry move is not greater than the tool radius");
  expect_error(on + "G40\nG2 X30 Y10 R10\n", 4, 1,
               "the move just after exiting cutter compensation mode must be straight");
  // A notch narrower than the tool: the pulled-back line would run backwards.
  expect_error(on + "Y10\nX9\nY0\nX0\nM2\n", 5, 1,
               "straight feed in concave corner cannot be reached by the tool without gouging");
  expect_error(on + "#1 = #5420\n", 3, 6,
               "cannot read current position with cutter radius compensation on");
  expect_error("F100\nG41.1 D2 L9 G1 X10\n", 2, 10, "G41.1 with L word, but plane is not G18");
  expect_error("F100 G18\nG41.1 D2 L3 G1 Z10\n", 2, 10, "lathe tool orientations");
  expect_error(on + "G40\nG5.1 X25 Y5 I2 J0\nG2 X30 Y0 R5\n", 5, 1,
               "the move just after exiting cutter compensation mode must be straight");
  expect_error(on + "S100 M3\nG33 X20 K1\n", 4, 1, "cannot use G33 or G33.1 with cutter radius");
  // An inside arc smaller than the tool.
  expect_error(on + "G3 X10 Y2 R1\n", 3, 1, "tool radius not less than arc radius with comp");
}

}  // namespace
}  // namespace cwe

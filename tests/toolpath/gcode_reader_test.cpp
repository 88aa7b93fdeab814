#include "cwe/toolpath/gcode_reader.hpp"
#include "reader_testing.hpp"
#include "source_dir.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cwe/geometry/tolerance.hpp"
#include "random.hpp"

namespace cwe {
namespace {

// Coordinates in these tests are below 1e5 mm and come from a handful of operations on the
// program's numbers (a unit conversion, a hypot, an atan2, a rotation), each correct to a few
// ulps: the rounding is below 1e-10 mm. 1e-9 mm leaves margin and is still a million times finer
// than machining resolution (1e-3 mm), so any real mistake (a wrong axis, sign or unit) shows.
constexpr double kTight = 1e-9;
// Same for angles (rad): a few ulps of 2π·turns.
constexpr double kAngleTight = 1e-12;

const Vec3 kX = Vec3::UnitX(), kY = Vec3::UnitY(), kZ = Vec3::UnitZ();

std::filesystem::path golden_dir() { return test::source_dir() / "tests" / "toolpath" / "golden"; }

std::string read_text(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

Toolpath read(std::string_view text, const GcodeOptions& options = {}) {
  return read_gcode(text, "test.ngc", options);
}
const auto read_program = [](std::string_view text) { return read(text); };

// Reading `text` throws an InputError at line:column whose message contains `fragment`.
void expect_error(std::string_view text, int line, int column, const std::string& fragment) {
  test::expect_input_error(read_program, "test.ngc", text, line, column, fragment);
}

// Reading `text` succeeds with moves.
void expect_accepted(std::string_view text) {
  SCOPED_TRACE(std::string(text));
  EXPECT_NO_THROW(read(text));
}

// ---------------------------------------------------------------------------------------------
// Golden move lists from LinuxCNC's interpreter (tests/toolpath/golden/*.golden, written by
// golden/linuxcnc_oracle.py; see docs/gcode.md).

struct GoldenMove {
  std::string kind;  // rapid, feed, arc
  int line = 0;
  Vec3 end = Vec3::Zero();
  std::string plane;  // arcs: XY, XZ, YZ
  double center1 = 0.0, center2 = 0.0;
  int rotation = 0;
};

std::vector<GoldenMove> read_golden(const std::filesystem::path& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in.good()) << path;
  std::vector<GoldenMove> moves;
  std::string text;
  while (std::getline(in, text)) {
    if (text.empty() || text[0] == '#') continue;
    std::istringstream s(text);
    GoldenMove m;
    s >> m.kind >> m.line;
    if (m.kind == "arc") s >> m.plane;
    s >> m.end.x() >> m.end.y() >> m.end.z();
    if (m.kind == "arc") s >> m.center1 >> m.center2 >> m.rotation;
    EXPECT_FALSE(s.fail()) << text;
    moves.push_back(m);
  }
  return moves;
}

// (first, second, normal) axes of a golden plane, LinuxCNC's canonical order.
std::array<int, 3> plane_axes(const std::string& plane) {
  if (plane == "XY") return {0, 1, 2};
  if (plane == "XZ") return {2, 0, 1};
  return {1, 2, 0};
}

void expect_matches_golden(const std::string& name) {
  SCOPED_TRACE(name);
  const Toolpath path = read_gcode_file((golden_dir() / (name + ".ngc")).string());
  const std::vector<GoldenMove> golden = read_golden(golden_dir() / (name + ".golden"));
  ASSERT_EQ(path.moves.size(), golden.size());
  ASSERT_EQ(path.sources.size(), 1u);
  Vec3 previous = Vec3::Zero();
  for (std::size_t i = 0; i < golden.size(); ++i) {
    const Move& m = path.moves[i];
    const GoldenMove& g = golden[i];
    SCOPED_TRACE("move " + std::to_string(i) + ", line " + std::to_string(g.line));
    EXPECT_EQ(m.line, g.line);
    EXPECT_EQ(m.source, 0);
    EXPECT_LT((m.start - previous).norm(), kTight);  // moves chain
    EXPECT_LT((m.end - g.end).norm(), kTight);
    EXPECT_EQ(m.start_axis, kZ);
    EXPECT_EQ(m.end_axis, kZ);
    if (g.kind != "arc") {
      EXPECT_FALSE(m.is_arc());
      EXPECT_EQ(m.is_rapid(), g.kind == "rapid");
    } else {
      ASSERT_TRUE(m.is_arc());
      EXPECT_FALSE(m.is_rapid());
      const auto [a1, a2, a3] = plane_axes(g.plane);
      // Direction and turns: LinuxCNC's rotation is ±(extra turns + 1) about the normal axis.
      EXPECT_EQ(m.normal[a3], g.rotation > 0 ? 1.0 : -1.0);
      EXPECT_EQ(m.extra_turns() + 1, std::abs(g.rotation));
      EXPECT_LT((m.position(1.0) - g.end).norm(), kTight);
      EXPECT_NEAR((m.center - m.start).dot(m.normal), 0.0, kTight);
      // The centre is LinuxCNC's, except that the reader moves it onto the bisector of the
      // chord when the programmed radii to start and end differ: by |r1² − r2²| / (2 chord).
      const double r1 = std::hypot(previous[a1] - g.center1, previous[a2] - g.center2);
      const double r2 = std::hypot(g.end[a1] - g.center1, g.end[a2] - g.center2);
      const double chord = std::hypot(g.end[a1] - previous[a1], g.end[a2] - previous[a2]);
      const double shift = chord > tol::kLength ? std::abs(r1 * r1 - r2 * r2) / (2.0 * chord) : 0;
      EXPECT_NEAR(m.center[a1], g.center1, shift + kTight);
      EXPECT_NEAR(m.center[a2], g.center2, shift + kTight);
    }
    previous = g.end;
  }
}

TEST(GcodeGolden, StraightMovesAndLexicalForms) { expect_matches_golden("basic"); }
TEST(GcodeGolden, ArcsInThreePlanes) { expect_matches_golden("arcs"); }
TEST(GcodeGolden, InchProgramSwitchingUnits) { expect_matches_golden("units"); }
TEST(GcodeGolden, DrillingCycles) { expect_matches_golden("drilling"); }
TEST(GcodeGolden, PeckCyclesInInches) { expect_matches_golden("drilling_inch"); }
TEST(GcodeGolden, ParametersAndExpressions) { expect_matches_golden("parameters"); }
TEST(GcodeGolden, SubroutinesConditionsAndLoops) { expect_matches_golden("owords"); }
TEST(GcodeGolden, CoordinateSystems) { expect_matches_golden("offsets"); }
TEST(GcodeGolden, PolarCoordinates) { expect_matches_golden("polar"); }
TEST(GcodeGolden, SavingAndRestoringTheModalState) { expect_matches_golden("modal"); }
TEST(GcodeGolden, FanucStyleSubprograms) { expect_matches_golden("fanuc"); }
TEST(GcodeGolden, CutterRadiusCompensation) { expect_matches_golden("compensation"); }
TEST(GcodeGolden, Splines) { expect_matches_golden("splines"); }
TEST(GcodeGolden, SpindleSynchronisedMotion) { expect_matches_golden("synchronised"); }

// Streaming: the moves handed to a sink are the moves the Toolpath would hold, in order, with
// their files; the Toolpath returned holds none.
TEST(GcodeStreaming, TheSinkGetsEveryMoveInOrder) {
  for (const char* name : {"owords", "compensation", "splines", "offsets"}) {
    SCOPED_TRACE(name);
    const std::string path = (golden_dir() / (std::string(name) + ".ngc")).string();
    const Toolpath whole = read_gcode_file(path);
    std::vector<Move> streamed;
    const Toolpath rest = read_gcode_file(
        path, {}, [&](const Move& m, const std::vector<std::string>& sources) {
          EXPECT_LT(static_cast<std::size_t>(m.source), sources.size());
          streamed.push_back(m);
        });
    EXPECT_TRUE(rest.moves.empty());
    EXPECT_EQ(rest.sources, whole.sources);
    EXPECT_EQ(rest.warnings.size(), whole.warnings.size());
    ASSERT_EQ(streamed.size(), whole.moves.size());
    for (std::size_t i = 0; i < streamed.size(); ++i) {
      EXPECT_EQ(streamed[i].start, whole.moves[i].start);
      EXPECT_EQ(streamed[i].end, whole.moves[i].end);
      EXPECT_EQ(streamed[i].line, whole.moves[i].line);
    }
  }
}

TEST(GcodeStreaming, WarningsAreCappedWithACount) {
  // Every arc here needs a connector (a warning each): 1000 are kept, then one counts the rest.
  // (As GcodeArcs.NearlyFullCircleWithMismatchedRadiiGetsAConnector.)
  std::string text = "G21 F100\n";
  for (int k = 0; k < 1500; ++k) text += "G0 X0 Y0\nG3 X-0.01 Y0.001 I5\n";
  const Toolpath p = read(text + "M2\n");
  ASSERT_EQ(p.warnings.size(), 1001u);
  EXPECT_NE(p.warnings.back().message.find("and 500 more warnings"), std::string::npos);
}

TEST(GcodeStreaming, ADeviceThatNeverEndsIsNotText) {
  // Read whole (it cannot be mapped) in blocks, it stops at its first block: a NUL byte.
  try {
    read_gcode_file("/dev/zero");
    ADD_FAILURE() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.location().source, "/dev/zero");
    EXPECT_EQ(e.location().line, 1);
    EXPECT_NE(e.message().find("holds a NUL byte: not a text file"), std::string::npos) << e.what();
  }
}

TEST(GcodeStreaming, ADirectoryIsAnErrorNamingIt) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / "cwe_dir.ngc";
  std::filesystem::create_directories(dir);
  try {
    read_gcode_file(dir.string());
    ADD_FAILURE() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.location().source, dir.string());
    EXPECT_NE(e.message().find("is a directory"), std::string::npos) << e.what();
  }
  std::filesystem::remove(dir);
}

// ---------------------------------------------------------------------------------------------
// Straight moves, modal state, words

TEST(GcodeReader, RapidAndFeedMoves) {
  const Toolpath p = read("G21 F600\nG0 X1 Y2 Z3\nG1 X4\nM2\n");
  ASSERT_EQ(p.moves.size(), 2u);
  EXPECT_EQ(p.sources, std::vector<std::string>{"test.ngc"});
  EXPECT_EQ(p.units, ProgramUnits::kMillimetres);
  EXPECT_TRUE(p.warnings.empty());
  const Move& rapid = p.moves[0];
  EXPECT_EQ(rapid.shape, MoveShape::kLine);
  EXPECT_TRUE(rapid.is_rapid());
  EXPECT_EQ(rapid.start, Vec3::Zero());
  EXPECT_EQ(rapid.end, Vec3(1, 2, 3));
  EXPECT_EQ(rapid.feed_rate, 0.0);
  EXPECT_EQ(rapid.line, 2);
  const Move& feed = p.moves[1];
  EXPECT_FALSE(feed.is_rapid());
  EXPECT_EQ(feed.start, Vec3(1, 2, 3));
  EXPECT_EQ(feed.end, Vec3(4, 2, 3));
  EXPECT_EQ(feed.feed_rate, 600.0);
  EXPECT_EQ(feed.start_axis, kZ);
  EXPECT_EQ(feed.end_axis, kZ);
  EXPECT_EQ(feed.line, 3);
}

TEST(GcodeReader, InitialPositionAndIncrementalMoves) {
  GcodeOptions options;
  options.initial_position = {10, 20, 30};
  const Toolpath p = read("G91 G0 X1 Y-2\nZ-30\nG90 X0\nM2", options);
  ASSERT_EQ(p.moves.size(), 3u);
  EXPECT_EQ(p.moves[0].start, Vec3(10, 20, 30));
  EXPECT_EQ(p.moves[0].end, Vec3(11, 18, 30));
  EXPECT_EQ(p.moves[1].end, Vec3(11, 18, 0));
  EXPECT_EQ(p.moves[2].end, Vec3(0, 18, 0));
}

TEST(GcodeReader, MotionWithoutAxisWordsIsAZeroLengthMove) {
  // LinuxCNC emits STRAIGHT_FEED / STRAIGHT_TRAVERSE to the current point: kept.
  const Toolpath p = read("F100 G1 X5\nG1\nG0\nM2");
  ASSERT_EQ(p.moves.size(), 3u);
  EXPECT_EQ(p.moves[1].start, p.moves[1].end);
  EXPECT_FALSE(p.moves[1].is_rapid());
  EXPECT_EQ(p.moves[2].start, p.moves[2].end);
  EXPECT_TRUE(p.moves[2].is_rapid());
  EXPECT_EQ(p.moves[2].length(), 0.0);
}

TEST(GcodeReader, FeedSpindleAndTool) {
  // rs274: T3 M6 gives SELECT_TOOL(3), STOP_SPINDLE_TURNING, CHANGE_TOOL(3); a later M6 without
  // T changes to the last selected tool; T alone only selects.
  const Toolpath p = read(
      "T3 M6\n"
      "S1000 M3 F250 G1 X1\n"
      "M4 X2\n"
      "M5 X3\n"
      "T4 M3 X4\n"
      "M6 X5\n"
      "S2000 M3 X6\n"
      "M30\n");
  ASSERT_EQ(p.moves.size(), 6u);
  const SpindleDirection expected_spindle[] = {
      SpindleDirection::kClockwise, SpindleDirection::kCounterClockwise,
      SpindleDirection::kStopped,   SpindleDirection::kClockwise,
      SpindleDirection::kStopped,  // M6 stops the spindle
      SpindleDirection::kClockwise};
  const int expected_tool[] = {3, 3, 3, 3, 4, 4};
  const double expected_speed[] = {1000, 1000, 1000, 1000, 1000, 2000};
  for (std::size_t i = 0; i < 6; ++i) {
    SCOPED_TRACE(i);
    EXPECT_EQ(p.moves[i].spindle, expected_spindle[i]);
    EXPECT_EQ(p.moves[i].tool, expected_tool[i]);
    EXPECT_EQ(p.moves[i].spindle_speed, expected_speed[i]);
    EXPECT_EQ(p.moves[i].feed_rate, 250.0);
  }
  // Before any M6 no tool is loaded.
  EXPECT_EQ(read("T7\nG0 X1\nM2").moves[0].tool, 0);
}

TEST(GcodeReader, ModalCodesThatDoNotChangeThePathAreAccepted) {
  // rs274 prints only SET_MOTION_CONTROL_MODE, USE_TOOL_LENGTH_OFFSET, coolant and comments for
  // these: the moves are those of the same program without them.
  const Toolpath p = read(
      "G40 G49 G54 G94 G97 G61 M7\n"
      "G64 P0.01 Q0.005 M8\n"
      "G61.1 G43 H1 M9\n"
      "G64 G0 X1 M0\n"
      "G43 G0 X2 M1\n"
      "G4 P0.5\n"
      "G0 X3 G4 P1\n"
      "M2");
  ASSERT_EQ(p.moves.size(), 3u);
  EXPECT_EQ(p.moves[2].end, Vec3(3, 0, 0));
}

TEST(GcodeReader, LexicalForms) {
  // Lower case, spaces inside numbers, comments of both kinds, line numbers, tabs, CRLF, a
  // leading '/' (block delete, executed as with LinuxCNC's switch off, its default).
  const Toolpath p = read(
      "%\r\n"
      "(a comment line)\r\n"
      "n10 g0 x 1 0.5 y-.5 z+2.\r\n"
      "N20\tG1 F1 0 0 X1(mid-line comment)Y2 ; X99\r\n"
      "/N30 G0 X0\r\n"
      "N40 (MSG, a message) Y7\r\n"
      "%\r\n");
  ASSERT_EQ(p.moves.size(), 4u);
  EXPECT_EQ(p.moves[0].end, Vec3(10.5, -0.5, 2));
  EXPECT_EQ(p.moves[1].end, Vec3(1, 2, 2));
  EXPECT_EQ(p.moves[1].feed_rate, 100.0);
  EXPECT_EQ(p.moves[2].end, Vec3(0, 2, 2));
  EXPECT_EQ(p.moves[3].end, Vec3(0, 7, 2));
  EXPECT_EQ(p.moves[3].line, 6);
  EXPECT_TRUE(p.warnings.empty());
}

TEST(GcodeReader, G80WithAnotherMotionCodeIsIgnored) {
  // LinuxCNC's read_g: "This allows G80 on the same line as one other g_code with the same mode.
  // If this happens, the G80 is simply ignored." (rs274: G80 G0 X1 and G0 G80 X1 both traverse.)
  EXPECT_EQ(read("G80 G0 X1\nM2").moves.size(), 1u);
  EXPECT_EQ(read("G0 G80 X1\nM2").moves.size(), 1u);
}

// ---------------------------------------------------------------------------------------------
// Units

TEST(GcodeUnits, InchProgramIsScaledToMillimetres) {
  const Toolpath p = read("G20 G90\nF10\nG1 X1 Y2\nG2 X2 Y2 I0.5\nM2");
  EXPECT_EQ(p.units, ProgramUnits::kInches);
  ASSERT_EQ(p.moves.size(), 2u);
  EXPECT_LT((p.moves[0].end - Vec3(25.4, 50.8, 0)).norm(), kTight);
  EXPECT_NEAR(p.moves[0].feed_rate, 254.0, kTight);  // 10 in/min
  const Move& arc = p.moves[1];
  EXPECT_NEAR(arc.radius(), 12.7, kTight);
  EXPECT_LT((arc.center - Vec3(38.1, 50.8, 0)).norm(), kTight);
  EXPECT_NEAR(arc.feed_rate, 254.0, kTight);
}

TEST(GcodeUnits, InitialUnitsOption) {
  GcodeOptions options;
  options.initial_units = ProgramUnits::kInches;
  options.initial_position = {25.4, 0, 0};
  const Toolpath p = read("F1 G91 G1 X1\nM2", options);
  EXPECT_EQ(p.units, ProgramUnits::kInches);
  EXPECT_LT((p.moves[0].end - Vec3(50.8, 0, 0)).norm(), kTight);
  EXPECT_NEAR(p.moves[0].feed_rate, 25.4, kTight);
}

TEST(GcodeUnits, ReportedUnitsAreTheFirstSelected) {
  EXPECT_EQ(read("G21\nG20\nG0 X1\nM2").units, ProgramUnits::kMillimetres);
  EXPECT_EQ(read("G20\nG21\nG0 X1\nM2").units, ProgramUnits::kInches);
  EXPECT_EQ(read("G0 X1\nM2").units, ProgramUnits::kMillimetres);  // the initial units
}

TEST(GcodeUnits, FeedRateIsPhysicalAcrossUnitChanges) {
  // LinuxCNC's canon converts F when it is set (SET_FEED_RATE), and convert_length_units keeps
  // that physical rate. F comes before G20/G21 in a line's order of execution (rs274 prints
  // SET_FEED_RATE(10) before USE_LENGTH_UNITS(CANON_UNITS_INCHES) for "G20 F10 G1 X1").
  const Toolpath p = read("G21 F254 G1 X1\nG20 G1 X1\nF10 X2\nG21 F10 G1 X3\nM2");
  ASSERT_EQ(p.moves.size(), 4u);
  EXPECT_NEAR(p.moves[0].feed_rate, 254.0, kTight);
  EXPECT_NEAR(p.moves[1].feed_rate, 254.0, kTight);
  EXPECT_NEAR(p.moves[2].feed_rate, 254.0, kTight);
  EXPECT_NEAR(p.moves[3].feed_rate, 254.0, kTight);  // F10 read while still in inches
  EXPECT_LT((p.moves[1].end - Vec3(25.4, 0, 0)).norm(), kTight);
  EXPECT_LT((p.moves[3].end - Vec3(3, 0, 0)).norm(), kTight);
}

// ---------------------------------------------------------------------------------------------
// Arcs

// The arc of a one-arc program after "F100".
Move only_arc(const std::string& words) {
  const Toolpath p = read("F100\n" + words + "\nM2");
  EXPECT_EQ(p.moves.size(), 1u);
  EXPECT_TRUE(p.moves.at(0).is_arc());
  return p.moves.at(0);
}

TEST(GcodeArcs, NormalFollowsTheRightHandRule) {
  // G2 is clockwise seen from the normal axis of the plane: in LinuxCNC's canonical order
  // (XY, ZX, YZ) ARC_FEED's rotation is -1, i.e. the normal is -Z, -Y, -X. The mid points
  // agree with gcode.arc_to_segments: G18 G2 from X0 to X10 passes through Z-5.
  struct Case {
    std::string words;
    Vec3 normal, middle;
  };
  const Case cases[] = {
      {"G17 G2 X10 I5", -kZ, {5, 5, 0}},  {"G17 G3 X10 I5", kZ, {5, -5, 0}},
      {"G18 G2 X10 I5", -kY, {5, 0, -5}}, {"G18 G3 X10 I5", kY, {5, 0, 5}},
      {"G19 G2 Y10 J5", -kX, {0, 5, 5}},  {"G19 G3 Y10 J5", kX, {0, 5, -5}},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.words);
    const Move arc = only_arc(c.words);
    EXPECT_EQ(arc.normal, c.normal);
    EXPECT_NEAR(arc.sweep, kPi, kAngleTight);
    EXPECT_LT((arc.position(0.5) - c.middle).norm(), kTight);
    EXPECT_LT((arc.position(1.0) - arc.end).norm(), kTight);
  }
}

TEST(GcodeArcs, RFormat) {
  EXPECT_NEAR(only_arc("G2 X10 R5").sweep, kPi, kAngleTight);
  const Move quarter = only_arc("G2 X10 Y10 R10");
  EXPECT_NEAR(quarter.sweep, kPi / 2, kAngleTight);
  EXPECT_LT((quarter.center - Vec3(10, 0, 0)).norm(), kTight);
  const Move large = only_arc("G2 X10 Y10 R-10");  // negative R: the long way round
  EXPECT_NEAR(large.sweep, 1.5 * kPi, kAngleTight);
  EXPECT_LT((large.center - Vec3(0, 10, 0)).norm(), kTight);
  EXPECT_LT((large.position(1.0) - Vec3(10, 10, 0)).norm(), kTight);
  const Move ccw = only_arc("G3 X10 Y10 R10");
  EXPECT_LT((ccw.center - Vec3(0, 10, 0)).norm(), kTight);
  // R with a full circle: LinuxCNC "Current point same as end point of arc".
  expect_error("F100\nG2 X0 Y0 R5\nM2", 2, 1, "current point same as end point of arc");
  expect_error("F100\nG2 R5 Z-1\nM2", 2, 1, "X and Y words missing for arc in XY plane");
  expect_error("F100\nG18 G2 R5 Y1\nM2", 2, 5, "X and Z words missing for arc in XZ plane");
  expect_error("F100\nG19 G2 R5 X1\nM2", 2, 5, "Y and Z words missing for arc in YZ plane");
}

TEST(GcodeArcs, FullCirclesTurnsAndHelices) {
  const Move circle = only_arc("G2 I5");
  EXPECT_NEAR(circle.sweep, kTwoPi, kAngleTight);
  EXPECT_EQ(circle.extra_turns(), 0);
  EXPECT_EQ(circle.end, circle.start);

  const Move two = only_arc("G2 X0 I5 P2");  // P2: one extra full turn
  EXPECT_NEAR(two.sweep, 2 * kTwoPi, kAngleTight);
  EXPECT_EQ(two.extra_turns(), 1);

  const Move half_and_turn = only_arc("G3 X10 I5 P2");
  EXPECT_NEAR(half_and_turn.sweep, kPi + kTwoPi, kAngleTight);
  EXPECT_EQ(half_and_turn.extra_turns(), 1);

  const Move helix = only_arc("G3 X0 Y0 Z-6 I5 P3");
  EXPECT_NEAR(helix.sweep, 3 * kTwoPi, kAngleTight);
  EXPECT_EQ(helix.extra_turns(), 2);
  EXPECT_EQ(helix.normal, kZ);
  EXPECT_NEAR(helix.axial, -6.0, kTight);  // along +Z normal
  EXPECT_NEAR(helix.length(), std::hypot(5 * 3 * kTwoPi, 6.0), kTight);
  EXPECT_LT((helix.position(1.0) - Vec3(0, 0, -6)).norm(), kTight);
  EXPECT_LT((helix.position(0.5) - Vec3(10, 0, -3)).norm(), kTight);

  const Move cw_helix = only_arc("G2 X10 Z4 I5");  // normal -Z: axial is -4
  EXPECT_NEAR(cw_helix.axial, -4.0, kTight);
  EXPECT_LT((cw_helix.position(1.0) - Vec3(10, 0, 4)).norm(), kTight);

  const Move xz_helix = only_arc("G18 G3 X10 Y-4 I5");  // helix along Y
  EXPECT_EQ(xz_helix.normal, kY);
  EXPECT_NEAR(xz_helix.axial, -4.0, kTight);
  EXPECT_LT((xz_helix.position(1.0) - Vec3(10, -4, 0)).norm(), kTight);

  expect_error("F100\nG2 X10 I5 P0\nM2", 2, 11, "P value should be 1 or greater");
  expect_error("F100\nG2 X10 I5 P1.5\nM2", 2, 11, "P value not an integer");
  EXPECT_EQ(only_arc("G2 X10 I5 P2.0009").extra_turns(), 1);  // within 0.001, as LinuxCNC
}

TEST(GcodeArcs, CentreFormats) {
  // G91.1 (default): I, J relative to the start, a missing one is 0; G90.1: absolute, both
  // required ("J word missing in absolute center arc").
  const Toolpath relative = read("F100 G0 X2 Y3\nG2 X12 I5\nM2");
  EXPECT_LT((relative.moves.at(1).center - Vec3(7, 3, 0)).norm(), kTight);
  const Toolpath absolute = read("F100 G0 X2 Y3\nG90.1 G2 X12 I7 J3\nM2");
  EXPECT_LT((absolute.moves.at(1).center - Vec3(7, 3, 0)).norm(), kTight);
  expect_error("F100\nG90.1 G2 X10 I5\nM2", 2, 7, "J word missing in absolute center arc");
  expect_error("F100\nG2 X10 I5 K1\nM2", 2, 11, "K word given for arc in XY plane");
  expect_error("F100\nG18 G2 X10 I5 J1\nM2", 2, 15, "J word given for arc in XZ plane");
  expect_error("F100\nG19 G2 Y10 J5 I1\nM2", 2, 15, "I word given for arc in YZ plane");
  expect_error("F100\nG2 X10 I5 R5\nM2", 2, 1, "mixed radius and IJK format");
  expect_error("F100\nG2 X10\nM2", 2, 1, "R, I, J and K words all missing for arc");
}

// LinuxCNC's arc tolerances, at their boundaries; each case was run through rs274.
TEST(GcodeArcs, RadiusToleranceMatchesLinuxcnc) {
  // mm: |r1 - r2| up to 0.02·√2 = 0.02828 mm always; beyond only while within 0.1 % of the
  // radius, up to 100 times that (2.828 mm).
  expect_accepted("F100 G2 X10.028 I5\nM2");
  expect_error("F100 G2 X10.029 I5\nM2", 1, 6,
               "radius to end of arc differs from radius to start: start=(X0.0000,Y0.0000) "
               "center=(X5.0000,Y0.0000) end=(X10.0290,Y0.0000) r1=5.0000 r2=5.0290 "
               "abs_err=0.029 rel_err=0.5767%");
  expect_accepted("F100 G2 X200.05 I100\nM2");  // 0.05 mm but 0.05 % of the radius
  expect_error("F100 G2 X2002.82 I1000\nM2", 1, 6, "rel_err=0.2812%");
  expect_accepted("F100 G2 X20002.8 I10000\nM2");                    // 2.8 mm, 0.028 %
  expect_error("F100 G2 X20002.9 I10000\nM2", 1, 6, "abs_err=2.9");  // beyond 2.828 mm
  // inch: 0.002·√2 in.
  expect_accepted("G20 F100 G2 X2.0028 I1\nM2");
  expect_error("G20 F100 G2 X2.0029 I1\nM2", 1, 10, "abs_err=0.0029 rel_err=0.2892%");
  // Zero radius: below 0.00005 in (0.00127 mm).
  expect_accepted("F1 G2 X0.0026 I0.0013\nM2");
  expect_error("F1 G2 X1 I0.0012\nM2", 1, 4, "zero-radius arc: start=(X0.0000,Y0.0000)");
  expect_error("G20 F1 G2 X0.00008 I0.00004\nM2", 1, 8, "zero-radius arc");
  // R form: |R| may fall short of half the chord by 0.00005 in (0.00127 mm).
  expect_accepted("F100 G2 X1.0025 R0.5\nM2");
  expect_error("F100 G2 X1.0026 R0.5\nM2", 1, 17, "arc radius too small to reach end point");
  expect_accepted("G20 F1 G2 X1.0001 R0.5\nM2");
  expect_error("G20 F1 G2 X1.0002 R0.5\nM2", 1, 19, "arc radius too small to reach end point");
}

TEST(GcodeArcs, ArcEndsAtTheProgrammedEndWithinTolerance) {
  // Radii differ by 0.02 mm (accepted): the centre moves onto the chord's bisector, by
  // |r1² − r2²| / (2 chord) = (5.02² − 5²) / 20.02 ≈ 0.01 mm, and the arc ends at X10.02.
  const Move arc = only_arc("G2 X10.02 I5");
  EXPECT_LT((arc.position(1.0) - Vec3(10.02, 0, 0)).norm(), kTight);
  EXPECT_NEAR(arc.center.x(), 5.01, kTight);
  EXPECT_NEAR(arc.sweep, kPi, kAngleTight);
  const Toolpath p = read("F100 G2 X10.02 I5\nM2");
  EXPECT_TRUE(p.warnings.empty());
}

TEST(GcodeArcs, NearlyFullCircleWithMismatchedRadiiGetsAConnector) {
  // Start (0,0), centre (5,0), counter-clockwise to an end 0.01 mm from the start, just short of
  // it and 0.01 mm outside the circle: no circle through both ends is near the programmed one,
  // so the arc keeps its centre and radius and a 0.01 mm feed joins it to the programmed end.
  const Toolpath p = read("F100 G3 X-0.01 Y0.001 I5\nM2");
  ASSERT_EQ(p.moves.size(), 2u);
  const Move& arc = p.moves[0];
  const Move& join = p.moves[1];
  EXPECT_TRUE(arc.is_arc());
  EXPECT_LT((arc.center - Vec3(5, 0, 0)).norm(), kTight);
  EXPECT_NEAR(arc.radius(), 5.0, kTight);
  // The end is about 0.001 / 5 = 2e-4 rad short of a full turn.
  EXPECT_NEAR(arc.sweep, kTwoPi - 2e-4, 1e-5);
  EXPECT_LT((arc.position(1.0) - arc.end).norm(), kTight);
  EXPECT_FALSE(join.is_arc());
  EXPECT_EQ(join.start, arc.end);
  EXPECT_LT((join.end - Vec3(-0.01, 0.001, 0)).norm(), kTight);
  EXPECT_NEAR(join.length(), std::hypot(5.01, 0.001) - 5.0, kTight);
  EXPECT_EQ(join.line, 1);
  ASSERT_EQ(p.warnings.size(), 1u);
  EXPECT_EQ(p.warnings[0].location.line, 1);
}

// Seeded property test: IJK arcs written with 4 decimals, as CAM systems do, in all planes and
// units. Every accepted arc ends at its programmed end, and its centre moves by no more than the
// spiral tolerance (LinuxCNC's bound on |r1 − r2|) or joins with a connector.
TEST(GcodeArcs, RoundedIjkArcsEndAtTheirProgrammedEnd) {
  test::Random random(20240611);
  const char* planes[] = {"G17", "G18", "G19"};
  const std::array<std::array<int, 3>, 3> axes = {{{0, 1, 2}, {2, 0, 1}, {1, 2, 0}}};
  const char offsets[3][2] = {{'I', 'J'}, {'K', 'I'}, {'J', 'K'}};
  const char letters[3] = {'X', 'Y', 'Z'};
  int checked = 0;
  for (int trial = 0; trial < 2000; ++trial) {
    const int plane = random.integer(0, 2);
    const bool inch = random.integer(0, 1) == 1;
    const double scale = inch ? 25.4 : 1.0;
    const auto [a1, a2, a3] = axes[static_cast<std::size_t>(plane)];
    const Vec3 start = random.point_in_box(100.0) / scale;
    const double radius = random.uniform(0.01, 200.0) / scale;
    const double phi0 = random.uniform(0, kTwoPi), phi1 = random.uniform(0, kTwoPi);
    const double c1 = start[a1] - radius * std::cos(phi0), c2 = start[a2] - radius * std::sin(phi0);
    Vec3 end = start;
    end[a1] = c1 + radius * std::cos(phi1);
    end[a2] = c2 + radius * std::sin(phi1);
    end[a3] += random.uniform(-10, 10) / scale;
    std::ostringstream program;
    program.setf(std::ios::fixed);
    program.precision(4);
    program << (inch ? "G20" : "G21") << " G90 F100\nG0 X" << start.x() << " Y" << start.y() << " Z"
            << start.z() << "\n"
            << planes[plane] << (random.integer(0, 1) ? " G2" : " G3");
    for (int axis = 0; axis < 3; ++axis) program << ' ' << letters[axis] << end[axis];
    program << ' ' << offsets[plane][0] << c1 - start[a1] << ' ' << offsets[plane][1]
            << c2 - start[a2] << "\nM2\n";
    SCOPED_TRACE(program.str());
    Toolpath p;
    try {
      p = read(program.str());
    } catch (const InputError& e) {
      // Only tiny radii can fail: 4-decimal rounding is within the tolerances otherwise.
      // 4-decimal rounding moves the radii by at most ~1.5e-4 (mm or in), well inside the
      // spiral tolerance (0.028 mm, 0.0028 in): only radii near the zero-radius limit
      // (0.00127 mm) can be refused.
      EXPECT_LT(radius * scale, 0.5) << e.what();
      continue;
    }
    ASSERT_GE(p.moves.size(), 2u);
    const Move& arc = p.moves[1];
    // The programmed end as the reader saw it: the printed (rounded) coordinates, in mm.
    Vec3 programmed;
    std::istringstream words(program.str().substr(program.str().find(planes[plane])));
    std::string word;
    while (words >> word) {
      for (int axis = 0; axis < 3; ++axis) {
        if (word[0] == letters[axis]) programmed[axis] = std::stod(word.substr(1)) * scale;
      }
    }
    const Move& last = p.moves.back();
    const double size = std::max(1.0, programmed.norm());
    EXPECT_LT((last.end - programmed).norm(), kTight * size);
    EXPECT_LT((arc.position(1.0) - arc.end).norm(), kTight * size);
    if (p.moves.size() == 2) ++checked;  // no connector
  }
  EXPECT_GT(checked, 1500);  // connectors are rare: only short chords of rounded arcs
}

// Seeded property test: R arcs hit their end, with |R| as radius and the sweep on the side R's
// sign asks for.
TEST(GcodeArcs, RArcsHitTheirEnd) {
  test::Random random(7);
  for (int trial = 0; trial < 1000; ++trial) {
    const Vec3 start = random.point_in_box(100.0);
    Vec3 end = random.point_in_box(100.0);
    const double half = std::hypot(end.x() - start.x(), end.y() - start.y()) / 2;
    const double radius = half * random.uniform(1.0, 3.0) * (random.integer(0, 1) ? 1 : -1);
    std::ostringstream program;
    program.setf(std::ios::fixed);
    program.precision(12);
    program << "F100 G0 X" << start.x() << " Y" << start.y() << " Z" << start.z() << "\n"
            << (random.integer(0, 1) ? "G2" : "G3") << " X" << end.x() << " Y" << end.y() << " Z"
            << end.z() << " R" << radius << "\nM2";
    SCOPED_TRACE(program.str());
    const Toolpath p = read(program.str());
    ASSERT_EQ(p.moves.size(), 2u);
    const Move& arc = p.moves[1];
    // The program carries 12 decimals, so the reader sees start, end and R to 5e-13 mm; near a
    // semicircle the centre is ill-conditioned along the bisector, but the end (on the
    // bisector's circle) and the radius are not: 1e-7 mm bounds their rounding with margin.
    EXPECT_LT((arc.position(1.0) - end).norm(), kTight * 100);
    EXPECT_NEAR(arc.radius(), std::abs(radius), kTight * 100);
    if (radius > 0) {
      EXPECT_LE(arc.sweep, kPi + kAngleTight);
    } else {
      EXPECT_GE(arc.sweep, kPi - kAngleTight);
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Drilling cycles (expansions in drilling.golden and drilling_inch.golden; these pin the
// numbers that matter)

std::vector<Vec3> ends(const Toolpath& p) {
  std::vector<Vec3> out;
  for (const Move& m : p.moves) out.push_back(m.end);
  return out;
}

TEST(GcodeCycles, G81RetractsToROrToTheInitialLevel) {
  // Default retract mode is G99 (LinuxCNC's initial R_PLANE).
  const Toolpath r = read("G0 Z10\nF100 G81 X1 Y1 Z-5 R2\nM2");
  const std::vector<Vec3> expected_r = {{0, 0, 10}, {1, 1, 10}, {1, 1, 2}, {1, 1, -5}, {1, 1, 2}};
  EXPECT_EQ(ends(r), expected_r);
  EXPECT_TRUE(r.moves[2].is_rapid());
  EXPECT_FALSE(r.moves[3].is_rapid());
  EXPECT_EQ(r.moves[3].feed_rate, 100.0);
  EXPECT_TRUE(r.moves[4].is_rapid());
  // G98: back to the level where this run of cycles started, even after a hole at R.
  const Toolpath initial = read("G0 Z10\nF100 G99 G81 X1 Z-5 R2\nG98 X2\nM2");
  EXPECT_EQ(initial.moves.back().end, Vec3(2, 0, 10));
}

TEST(GcodeCycles, PecksMatchLinuxcnc) {
  // G83: feed a peck, rapid to R, rapid back to 0.254 mm (0.010 in) above the last depth.
  const Toolpath g83 = read("G0 Z5\nF100 G83 X1 Z-3 R1 Q1.1\nM2");
  const std::vector<double> g83_z = {5, 5,      1,    -0.1, 1,      0.154, -1.2,
                                     1, -0.946, -2.3, 1,    -2.046, -3,    1};
  ASSERT_EQ(g83.moves.size(), g83_z.size());
  for (std::size_t i = 0; i < g83_z.size(); ++i)
    EXPECT_NEAR(g83.moves[i].end.z(), g83_z[i], kTight);
  // G73: feed a peck, rapid up 0.254 mm.
  const Toolpath g73 = read("G0 Z5\nF100 G73 X1 Z-3 R1 Q1.1\nM2");
  const std::vector<double> g73_z = {5, 5, 1, -0.1, 0.154, -1.2, -0.946, -2.3, -2.046, -3, 1};
  ASSERT_EQ(g73.moves.size(), g73_z.size());
  for (std::size_t i = 0; i < g73_z.size(); ++i)
    EXPECT_NEAR(g73.moves[i].end.z(), g73_z[i], kTight);
  // G82: the dwell does not move.
  EXPECT_EQ(read("G0 Z5\nF100 G82 X1 Z-3 R1 P2\nM2").moves.size(), 5u);
}

TEST(GcodeCycles, IncrementalWithRepeats) {
  // rs274 for G91 G81 X1 Y2 Z-3 R-1 L3 from Z5: R is 4, the bottom 1, holes at (1,2), (2,4),
  // (3,6).
  const Toolpath p = read("G0 Z5 G91\nF100 G81 X1 Y2 Z-3 R-1 L3\nM2");
  const std::vector<Vec3> expected = {{0, 0, 5}, {1, 2, 5}, {1, 2, 4}, {1, 2, 1},
                                      {1, 2, 4}, {2, 4, 4}, {2, 4, 1}, {2, 4, 4},
                                      {3, 6, 4}, {3, 6, 1}, {3, 6, 4}};
  EXPECT_EQ(ends(p), expected);
}

TEST(GcodeCycles, Errors) {
  expect_error("G0 Z5\nF100 G81 X1 Z-8\nM2", 2, 6, "R clearance plane unspecified");
  expect_error("G0 Z5\nF100 G81 X1 R2\nM2", 2, 6, "Z value unspecified in XY plane canned cycle");
  expect_error("G0 Z5\nF100 G81 X1 Z-8 R-10\nM2", 2, 17, "R less than Z in canned cycle");
  expect_error("G0 Z5\nF100 G73 X1 Z-3 R1\nM2", 2, 6, "Q word missing with G73");
  expect_error("G0 Z5\nF100 G83 X1 Z-3 R1 Q0\nM2", 2, 20, "negative or zero Q value used");
  expect_error("G0 Z5\nF100 G82 X1 Z-3 R1\nM2", 2, 6, "dwell time P word missing with G82");
  expect_error("G0 Z5\nF100 G81 X1 Z-3 R1 L0\nM2", 2, 20, "cannot do zero repeats");
  expect_error("G0 Z5\nG81 X1 Z-3 R1\nM2", 2, 1, "cannot feed with zero feed rate");
  expect_error("F1 G81 Z-1 R2\nG81\nM2", 2, 1, "all axes missing with motion code G81");
  expect_error("F1 G81 Z-1 R2\nR3\nM2", 2, 1, "R word with no G2, G3 or canned cycle to use it");
  expect_error("F1 G18 G81 X1 Z-1 R2\nM2", 1, 8, "canned cycles in the XZ plane are not supported");
  expect_error("F1 G81 X1 Z-1 R2 P1\nM2", 1, 18, "P word with no G2, G3, G4, G5, G64 or G82");
  expect_error("F1 G81 X1 Z-100 R2 L1000\nG83 X1 Z-100 R2 Q0.0001\nM2", 2, 1,
               "would expand to more than");
}

// ---------------------------------------------------------------------------------------------
// Program delimiters and end

TEST(GcodeProgram, LinesAfterM2OrM30AreIgnored) {
  for (const char* end : {"M2", "M30"}) {
    SCOPED_TRACE(end);
    const Toolpath p = read(std::string("G0 X1\n") + end + "\nG0 X2\nfoo bar\n");
    EXPECT_EQ(p.moves.size(), 1u);
    ASSERT_EQ(p.warnings.size(), 1u);  // the ignored lines, not silently dropped
    EXPECT_EQ(p.warnings[0].location.line, 3);
  }
  // Motion on the line of the M2 happens first.
  EXPECT_EQ(read("G0 X1 M2\nG0 X2").moves.size(), 1u);
}

TEST(GcodeProgram, PercentDelimiters) {
  EXPECT_EQ(read("%\nG0 X1\n%\nG0 X2\n").moves.size(), 1u);
  EXPECT_TRUE(read("\n%\nG0 X1\n%\n").warnings.empty());  // blank lines before the opening %
  // LinuxCNC refuses a file without a program end or closing %; cwe reads it and warns.
  const Toolpath open = read("%\nG0 X1\n");
  EXPECT_EQ(open.moves.size(), 1u);
  ASSERT_EQ(open.warnings.size(), 1u);
  EXPECT_NE(open.warnings[0].message.find("percent"), std::string::npos);
  const Toolpath no_end = read("G0 X1\n\n");
  ASSERT_EQ(no_end.warnings.size(), 1u);
  EXPECT_EQ(no_end.warnings[0].location.line, 1);
  // A % that neither opens (first line) nor closes (after an opening one) is a bad character.
  expect_error("G0 X1\n%\nG0 X2\nM2\n", 2, 1, "bad character '%'");
  expect_error("(c)\n%\nG0 X1\n%\n", 2, 1, "bad character '%'");
  expect_error("% abc\nG0 X1\nM2\n", 1, 1, "bad character '%'");
}

// ---------------------------------------------------------------------------------------------
// Errors: message text and line:column (LinuxCNC's message for each, from rs274, in comments)

TEST(GcodeErrors, ModalGroupsAndCodes) {
  expect_error("G0 G1 X1\nM2", 1, 4, "two G codes used from the same modal group: G0 and G1");
  expect_error("G17 G18\nM2", 1, 5, "two G codes used from the same modal group");
  expect_error("G20 G21\nM2", 1, 5, "two G codes used from the same modal group");
  expect_error("G90.1 G91.1\nM2", 1, 7, "two G codes used from the same modal group");
  expect_error("G98 G99\nM2", 1, 5, "two G codes used from the same modal group");
  expect_error("M3 S1000 M4\nM2", 1, 10, "two M codes used from the same modal group: M3 and M4");
  expect_error("M7 M8\nM2", 1, 4, "two M codes used from the same modal group");
  expect_error("G0 X1 M2 M30", 1, 10, "two M codes used from the same modal group");
  expect_error("G6 X1\nM2", 1, 1, "unknown G code: G6");       // Unknown g code used
  expect_error("G1.002 X1\nM2", 1, 1, "G code out of range");  // G-code out of range
  expect_error("G100\nM2", 1, 1, "G code out of range");
  expect_error("G-1\nM2", 1, 1, "negative G code used");
  expect_error("M10\nM2", 1, 1, "unknown M code: M10");  // Unknown m code used: M10
  expect_error("M200\nM2", 1, 1, "M code greater than 199");
  expect_error("M-1\nM2", 1, 1, "negative M code used");
  expect_error("M3.5\nM2", 1, 1, "non-integer value for M");  // Non integer value for integer
  EXPECT_NO_THROW(read("G1.0001 F1 X1\nM2"));  // within a thousandth of a tenth of G1
  expect_error("G1.0009 F1 X1\nM2", 1, 1, "G code out of range");
}

TEST(GcodeErrors, WordsWithoutACodeToUseThem) {
  expect_error("X10\nM2", 1, 1, "cannot use axis values without a G code that uses them");
  expect_error("G4 P1 X1\nM2", 1, 7, "cannot use axis values without a G code that uses them");
  expect_error("G0 X1\nG80 X1\nM2", 2, 5, "cannot use axis values with G80");
  expect_error("G0 X1 I1\nM2", 1, 7, "I word with no G2, G3");
  expect_error("F1 G1 X1 R1\nM2", 1, 10, "R word with no G2, G3 or canned cycle to use it");
  expect_error("G0 X1 P1\nM2", 1, 7, "P word with no G2, G3, G4, G5, G64 or G82 to use it");
  expect_error("G61 P1\nM2", 1, 5, "P word with no");
  expect_error("G0 X1 Q1\nM2", 1, 7, "Q word with no G5, G64, G73, G83 or M61 to use it");
  expect_error("G0 X1 L1\nM2", 1, 7, "L word with no canned cycle to use it");
  expect_error("G0 X1 H1\nM2", 1, 7, "H word with no G43 to use it");
  expect_error("G4\nM2", 1, 1, "dwell time missing with G4");
}

TEST(GcodeErrors, FeedRate) {
  expect_error("G1 X10\nM2", 1, 1, "cannot do G1 with zero feed rate");
  expect_error("G1 F0 X1\nM2", 1, 1, "cannot do G1 with zero feed rate");
  expect_error("F100 G1 X1\nF0\nX2\nM2", 3, 1, "cannot do G1 with zero feed rate");  // modal G1
  expect_error("G2 X10 I5\nM2", 1, 1, "cannot make arc with zero feed rate");
  expect_error("F-1\nM2", 1, 1, "negative F word used");
  expect_error("S-1\nM2", 1, 1, "negative spindle speed used");
  expect_error("T-1\nM2", 1, 1, "negative tool number used");
  expect_error("T1.5\nM2", 1, 1, "non-integer value for T");
}

TEST(GcodeErrors, LexicalErrors) {
  expect_error("G0 X1 *2\nM2", 1, 7, "bad character '*' used");
  expect_error("G0 X1 /Y2\nM2", 1, 7, "bad character '/' used");
  expect_error("G0 X1 )\nM2", 1, 7, "bad character ')' used");
  expect_error("G0 X1 (abc (def) Y2\nM2", 1, 12, "nested comment found");
  expect_error("G0 X1 (abc\nM2", 1, 7, "unclosed comment found");
  expect_error("G0 X1 X2\nM2", 1, 7, "multiple X words on one line");
  expect_error("N10 N20 G0 X1\nM2", 1, 5, "bad character 'N'");
  expect_error("G1 N10 X1\nM2", 1, 4, "bad character 'N'");
  expect_error("(c) N10 G0 X1\nM2", 1, 5, "bad character 'N'");  // N must be first
  expect_error("G0 X\nM2", 1, 4, "bad number format: X needs a number");
  expect_error("G0 X-\nM2", 1, 4, "bad number format: X needs a number");
  expect_error("G0 X.\nM2", 1, 4, "bad number format: X needs a number");
  expect_error("G0 X1.2.3\nM2", 1, 4, "more than one decimal point");
  expect_error("G0 X1e3\nM2", 1, 6, "E word is not supported");  // no exponents: E is a word
  expect_error("G0 Xsinh[0]\nM2", 1, 8, "left bracket missing after unary operation name");
  expect_error("G0 Xy1\nM2", 1, 5, "unknown word starting with 'Y' where a unary operation");
  expect_error("G0 X1 \x01\nM2", 1, 7, "bad character 0x01 used");
  expect_error(std::string("G0 X1 \0 Y2\nM2", 13), 1, 7, "bad character 0x00 used");
  expect_error("G0 X1 \xC3\xA9\nM2", 1, 7, "bad character 0xC3 used");
}

TEST(GcodeErrors, NotSupported) {
  struct Case {
    const char* program;
    int column;
    const char* fragment;
  };
  const Case cases[] = {
      {"G0 A1", 4, "rotary axis words (A, B, C) are not supported: A"},
      {"G0 B1", 4, "rotary axis words"},
      {"G0 C1", 4, "rotary axis words"},
      {"G0 U1", 4, "U, V and W axis words are not supported"},
      {"G93", 1, "inverse time feed (G93) is not supported"},
      {"G95", 1, "feed per revolution (G95) is not supported"},
      {"G96 S100", 1, "constant surface speed (G96) is not supported"},
      {"G84 X1 Z-1 R1", 1, "canned cycles other than G73, G81, G82 and G83 are not supported"},
      {"G85 X1 Z-1 R1", 1, "canned cycles other than"},
      {"G89 X1 Z-1 R1 P1", 1, "canned cycles other than"},
      {"G74 X1 Z-1 R1", 1, "canned cycles other than"},
      {"G76 Z-1", 1, "threading (G76) is not supported"},
      {"G38.2 Z-1", 1, "probing (G38.2 to G38.5) is not supported"},
      {"G5.2 X1 Y1 P1 L3", 1, "NURBS (G5.2, G5.3) are"},
      {"G10 L2 P1 R45", 11, "coordinate system rotation (G10 L2 R) is not supported"},
      {"G43.1 Z1", 1, "dynamic tool length offsets"},
      {"G7", 1, "lathe diameter mode (G7) is not supported"},
      {"G17.1", 1, "UVW planes"},
      {"M60", 1, "pallet changes (M60) are not supported"},
      {"M19", 1, "spindle orientation (M19) is not supported"},
      {"M48", 1, "override switches"},
      {"M62 P1", 1, "digital and analog I/O"},
      {"M100", 1, "user-defined M codes (M100 to M199) are not supported"},
      {"G0 X1 E1", 7, "E word is not supported"},
      {"M3 $1", 4, "spindle selection ($) is not supported"},
  };
  for (const Case& c : cases) {
    expect_error(std::string("F100\n") + c.program + "\nM2", 2, c.column, c.fragment);
  }
}

// LinuxCNC's refusals of spindle-synchronised moves and splines (its words, checked with rs274).
TEST(GcodeErrors, SynchronisedMovesAndSplines) {
  expect_error("F100\nG33 Z-1 K1\nM2", 2, 1, "spindle not turning in G33");
  expect_error("F100 S100\nG33.1 Z-1 K1\nM2", 2, 1, "spindle not turning in G33.1");
  expect_error("S100 M3\nG33 Z-1\nM2", 2, 1, "K word missing with G33/G33.1");
  expect_error("S100 M3\nG33 Z-1 K1 F10\nM2", 2, 12, "F word used with a G33/G33.1");
  expect_error("S100 M3\nG1 Z-1 K1 F10\nM2", 2, 8, "K word with no G2, G3, G33 or G33.1");
  expect_error("F100\nG5.1 X1 I1\nM2", 2, 1, "must specify both I and J with G5.1");
  expect_error("F100\nG5 X1 I1 P1 Q1\nM2", 2, 1, "must specify both I and J, or neither");
  expect_error("F100\nG5 X1 I1 J1 P1\nM2", 2, 1, "must specify both P and Q with G5");
  expect_error("F100\nG5.1 X1 Z1 I1 J1\nM2", 2, 9, "splines may not have motion in Z");
  expect_error("F100 G18\nG5.1 X1 I1 J1\nM2", 2, 1, "splines must be in the XY plane");
  expect_error("G5.1 X1 I1 J1\nM2", 1, 1, "cannot make arc with zero feed rate");
}

TEST(GcodeErrors, EmptyAndMissingFiles) {
  for (const char* empty : {"", "\n", "  \n\t\n", "\r\n"}) {
    SCOPED_TRACE(empty);
    try {
      read(empty);
      ADD_FAILURE() << "expected an InputError";
    } catch (const InputError& e) {
      EXPECT_NE(e.message().find("empty program"), std::string::npos);
      EXPECT_EQ(e.location().line, 0);
    }
  }
  const std::string missing = (golden_dir() / "no_such_file.ngc").string();
  try {
    read_gcode_file(missing);
    ADD_FAILURE() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.location().source, missing);
    EXPECT_NE(e.message().find("cannot open"), std::string::npos);
  }
}

TEST(GcodeErrors, HugeNumbers) {
  expect_error("G0 X" + std::string(400, '9') + "\nM2", 1, 4, "X value out of range");
  expect_error("G0 X1" + std::string(12, '0') + "\nM2", 1, 4, "X value out of range");
  expect_error("G" + std::string(30, '9') + "\nM2", 1, 1, "G value out of range");
  expect_error("M" + std::string(30, '9') + "\nM2", 1, 1, "M value out of range");
  EXPECT_NO_THROW(read("G0 X100000000.5\nM2"));  // 1e8 mm: legal, if absurd
}

// ---------------------------------------------------------------------------------------------
// Robustness: malformed input ends in an InputError or a toolpath, never anything else.

TEST(GcodeRobustness, TruncatedPrograms) {
  // Every prefix of every golden program: truncated numbers, comments, words and lines.
  for (const char* name : {"basic", "arcs", "units", "drilling", "drilling_inch"}) {
    const std::string text = read_text(golden_dir() / (std::string(name) + ".ngc"));
    ASSERT_FALSE(text.empty()) << name;
    for (std::size_t n = 0; n <= text.size(); ++n)
      test::read_or_input_error(read_program, text.substr(0, n));
  }
}

TEST(GcodeRobustness, RandomGarbage) {
  test::Random random(1979);
  const std::string alphabet = "GMXYZIJKRPQFSTLHNgmxyz0123456789.-+ ()%;/#[]*ABCEOUD\t";
  int read_ok = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    std::string text = "G21 F100\n";
    const int lines = random.integer(1, 6);
    for (int l = 0; l < lines; ++l) {
      const int length = random.integer(0, 30);
      for (int c = 0; c < length; ++c) {
        if (random.integer(0, 50) == 0) {
          text.push_back(static_cast<char>(random.integer(0, 255)));  // any byte
        } else {
          text.push_back(alphabet[static_cast<std::size_t>(
              random.integer(0, static_cast<int>(alphabet.size()) - 1))]);
        }
      }
      text.push_back('\n');
    }
    if (test::read_or_input_error(read_program, text)) ++read_ok;
  }
  EXPECT_GT(read_ok, 0);  // the generator does produce valid programs too
}

TEST(GcodeRobustness, RandomValidWords) {
  // Well-formed words in random order and values: valid programs and semantic errors mixed.
  test::Random random(31337);
  const char* words[] = {"G0",  "G1",  "G2",  "G3",  "G17", "G18", "G19",  "G20",   "G21",
                         "G80", "G81", "G82", "G83", "G73", "G90", "G91",  "G90.1", "G91.1",
                         "G98", "G99", "M3",  "M5",  "M6",  "T1",  "S100", "F50"};
  const char letters[] = {'X', 'Y', 'Z', 'I', 'J', 'K', 'R', 'P', 'Q', 'L'};
  int read_ok = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    std::ostringstream text;
    text << "F100\n";
    for (int l = random.integer(1, 8); l > 0; --l) {
      for (int w = random.integer(0, 4); w > 0; --w) {
        if (random.integer(0, 2) == 0) {
          text << words[random.integer(0, 25)] << ' ';
        } else {
          text << letters[random.integer(0, 9)] << random.integer(-20, 20) / 2.0 << ' ';
        }
      }
      text << '\n';
    }
    if (test::read_or_input_error(read_program, text.str())) ++read_ok;
  }
  EXPECT_GT(read_ok, 100);
}

}  // namespace
}  // namespace cwe

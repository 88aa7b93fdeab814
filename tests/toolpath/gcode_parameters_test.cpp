// Parameters and expressions in G-code, with LinuxCNC 2.9's semantics (docs/gcode.md,
// "Parameters and expressions"). Expected values are worked out by hand from LinuxCNC's rules
// (interp_read.cc, interp_execute.cc): precedence levels evaluated left to right, degrees,
// EQ and NE within 0.0001, MOD always positive, parameters set in parallel within a line; the
// golden program tests/toolpath/golden/parameters.ngc holds them to LinuxCNC's own interpreter.

#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <string_view>

#include "cwe/core/error.hpp"
#include "cwe/toolpath/gcode_reader.hpp"

namespace cwe {
namespace {

// Values below 1e3 from a few libm calls: correct to a few ulps, far inside 1e-12.
constexpr double kTight = 1e-12;

Toolpath read(std::string_view text) { return read_gcode(text, "p.ngc"); }

// The X of the rapid that `G0 X<expression>` makes after the lines `before`.
double value_of(const std::string& expression, const std::string& before = "") {
  const Toolpath path = read(before + "\nG0 X" + expression + "\nM2\n");
  EXPECT_FALSE(path.moves.empty()) << expression;
  return path.moves.empty() ? NAN : path.moves.back().end.x();
}

void expect_error(std::string_view text, int line, int column, const std::string& fragment) {
  SCOPED_TRACE(std::string(text));
  try {
    read(text);
    ADD_FAILURE() << "expected an InputError containing: " << fragment;
  } catch (const InputError& e) {
    EXPECT_EQ(e.location().line, line) << e.what();
    EXPECT_EQ(e.location().column, column) << e.what();
    EXPECT_NE(e.message().find(fragment), std::string::npos) << e.what();
  }
}

TEST(GcodeExpressions, PrecedenceAndLeftToRight) {
  EXPECT_EQ(value_of("[1+2*3]"), 7.0);
  EXPECT_EQ(value_of("[[1+2]*3]"), 9.0);
  EXPECT_EQ(value_of("[2*3**2]"), 18.0);
  EXPECT_EQ(value_of("[2**3**2]"), 64.0);  // left to right: (2**3)**2
  EXPECT_EQ(value_of("[8/4/2]"), 1.0);
  EXPECT_EQ(value_of("[1-2-3]"), -4.0);
  EXPECT_EQ(value_of("[1+2 EQ 3]"), 1.0);  // relational below additive
  EXPECT_EQ(value_of("[1 EQ 1 AND 0]"), 0.0);
  EXPECT_EQ(value_of("[3 LT 2 OR 1]"), 1.0);
  EXPECT_EQ(value_of("[1 XOR 1]"), 0.0);
  EXPECT_EQ(value_of("[0 XOR 2]"), 1.0);
  EXPECT_EQ(value_of("[7 MOD 3]"), 1.0);
  EXPECT_EQ(value_of("[-7 MOD 3]"), 2.0);  // LinuxCNC's MOD is never negative
  EXPECT_EQ(value_of("[2 + 3 * 4 - 6 / 2]"), 11.0);
  EXPECT_EQ(value_of("-[2]"), -2.0);
  EXPECT_EQ(value_of("+[2]"), 2.0);
  EXPECT_EQ(value_of("-[-[2]]"), 2.0);
}

TEST(GcodeExpressions, ComparisonsWithinTheTolerance) {
  EXPECT_EQ(value_of("[1 EQ 1.00005]"), 1.0);
  EXPECT_EQ(value_of("[1 EQ 1.0002]"), 0.0);
  EXPECT_EQ(value_of("[1 NE 1.00005]"), 0.0);
  EXPECT_EQ(value_of("[1 LE 0.99995]"), 0.0);  // exact in 2.9 (later versions: within 0.0001)
  EXPECT_EQ(value_of("[1 GE 1.00005]"), 0.0);
  EXPECT_EQ(value_of("[1 LE 1]"), 1.0);
  EXPECT_EQ(value_of("[1 LT 1.00005]"), 1.0);  // LT and GT are exact
  EXPECT_EQ(value_of("[1 GT 1]"), 0.0);
}

TEST(GcodeExpressions, FunctionsInDegrees) {
  EXPECT_NEAR(value_of("SIN[30]"), 0.5, kTight);  // a function directly after the letter
  EXPECT_NEAR(value_of("[COS[60]]"), 0.5, kTight);
  EXPECT_NEAR(value_of("TAN[45]"), 1.0, kTight);
  EXPECT_NEAR(value_of("ASIN[1]"), 90.0, kTight);
  EXPECT_NEAR(value_of("ACOS[0.5]"), 60.0, kTight);
  EXPECT_NEAR(value_of("ATAN[1]/[1]"), 45.0, kTight);
  EXPECT_NEAR(value_of("ATAN[1]/[-1]"), 135.0, kTight);  // atan2: the quadrant of y/x
  EXPECT_NEAR(value_of("SQRT[16]"), 4.0, kTight);
  EXPECT_NEAR(value_of("LN[EXP[2]]"), 2.0, kTight);
  EXPECT_EQ(value_of("ABS[-2.5]"), 2.5);
  EXPECT_EQ(value_of("FIX[-1.5]"), -2.0);
  EXPECT_EQ(value_of("FUP[-1.5]"), -1.0);
  EXPECT_EQ(value_of("ROUND[2.5]"), 3.0);
  EXPECT_EQ(value_of("ROUND[-2.5]"), -3.0);
  EXPECT_EQ(value_of("-SIN[90]"), -1.0);
  EXPECT_EQ(value_of("[EXISTS[#<a>]]"), 0.0);
  EXPECT_EQ(value_of("[EXISTS[#<a>]]", "#<a>=1"), 1.0);
  EXPECT_EQ(value_of("EXISTS[#5]"), 1.0);  // numbered: within range
}

TEST(GcodeParameters, NumberedNamedAndIndirect) {
  EXPECT_EQ(value_of("#1", "#1=2.5"), 2.5);
  EXPECT_EQ(value_of("#3", ""), 0.0);  // never set: 0
  EXPECT_EQ(value_of("##2", "#2=7\n#7=3"), 3.0);
  EXPECT_EQ(value_of("#[1+1]", "#2=4"), 4.0);
  EXPECT_EQ(value_of("#<depth>", "#<depth>=-2"), -2.0);
  // Blanks are removed and case is folded, in names as everywhere outside comments.
  EXPECT_EQ(value_of("#<tooldia>", "#<Tool Dia> = 6"), 6.0);
  EXPECT_EQ(value_of("#<_global>", "#<_global>=[2*2]"), 4.0);
  // A G or M number may be a value too.
  const Toolpath g = read("#1=1 F100\nG#1 X5\nM[1+1]\nG0 X9\n");
  ASSERT_EQ(g.moves.size(), 1u);  // M2 ended the program
  EXPECT_FALSE(g.moves[0].is_rapid());
}

TEST(GcodeParameters, SetInParallelWithinALine) {
  // LinuxCNC's example: #3 is 15, then "#3=6 G1 X#3" moves to X15 and leaves #3 = 6.
  const Toolpath path = read("#3=15 F100\n#3=6 G1 X#3\nG1 Y#3\n#1=5\n#1=10 #2=#1\nG0 X#1 Y#2\nM2\n");
  ASSERT_EQ(path.moves.size(), 3u);
  EXPECT_EQ(path.moves[0].end.x(), 15.0);
  EXPECT_EQ(path.moves[1].end.y(), 6.0);
  EXPECT_EQ(path.moves[2].end.x(), 10.0);
  EXPECT_EQ(path.moves[2].end.y(), 5.0);
}

TEST(GcodeParameters, PredefinedFollowTheState) {
  // The position in program units (#5420-#5422, #<_x>…), the units, the distance mode, the tool.
  EXPECT_EQ(value_of("#5420", "G21 G0 X3"), 3.0);
  EXPECT_EQ(value_of("#<_x>", "G21 G0 X3 Y4"), 3.0);
  EXPECT_EQ(value_of("[#<_y> + #5422]", "G21 G0 X3 Y4 Z5"), 9.0);
  EXPECT_EQ(value_of("#<_metric>", "G21"), 1.0);
  EXPECT_EQ(value_of("#<_imperial>", "G21"), 0.0);
  EXPECT_EQ(value_of("#<_incremental>", "G21"), 0.0);
  EXPECT_EQ(value_of("#<_current_tool>", "T4 M6"), 4.0);
  EXPECT_EQ(value_of("#5400", "T4 M6"), 4.0);
  EXPECT_EQ(value_of("#<_vmajor>"), 2.0);
  // Under G20 the position is in inches: X2 in is 50.8 mm, and #<_x> reads 2.
  const Toolpath inch = read("G20 G0 X2\nG0 Y#<_x>\nM2\n");
  EXPECT_NEAR(inch.moves.back().end.y(), 50.8, kTight);
}

TEST(GcodeParameters, Errors) {
  expect_error("G0 X#<nope>\nM2", 1, 5, "named parameter #<nope> not defined");
  expect_error("#<_x>=1\nM2", 1, 1, "#<_x> is a read-only parameter");
  expect_error("#5420=1\nM2", 1, 1, "parameter #5420 is read-only");
  expect_error("#6000=1\nM2", 1, 1, "parameter number out of range: #6000");
  expect_error("G0 X#0\nM2", 1, 5, "parameter number out of range");
  expect_error("#1 X2\nM2", 1, 4, "equal sign missing in parameter setting");
  expect_error("#1.5=2\nM2", 1, 2, "non-integer value for integer");
  expect_error("#<a=2\nM2", 1, 2, "named parameter not terminated");
  expect_error("G0 X[1+2\nM2", 1, 5, "unclosed expression");
  expect_error("G0 X[1/0]\nM2", 1, 7, "attempt to divide by zero");
  expect_error("G0 X[1 FOO 2]\nM2", 1, 8, "unknown operation: 'F'");
  expect_error("G0 X[1 $ 2]\nM2", 1, 8, "unknown operation: '$'");
  expect_error("G0 XSQRT[-1]\nM2", 1, 5, "negative argument to SQRT");
  expect_error("G0 XLN[0]\nM2", 1, 5, "zero or negative argument to LN");
  expect_error("G0 XACOS[2]\nM2", 1, 5, "argument to ACOS out of range");
  expect_error("G0 X[[-8]**0.5]\nM2", 1, 10, "negative number to a non-integer power");
  expect_error("G0 XATAN[1]\nM2", 1, 12, "slash missing after first ATAN argument");
  expect_error("G0 XATAN[1]/2\nM2", 1, 13, "left bracket missing after slash with ATAN");
  expect_error("G0 XEXISTS[1]\nM2", 1, 12, "expected # reading parameter");
  expect_error("G0 X[10**400]\nM2", 1, 5, "calculation resulted in 'infinity'");
  expect_error("G0 X[2*1e9]\nM2", 1, 9, "unknown operation name starting with E");
  expect_error("G0 X[1000000*10000]\nM2", 1, 4, "X value out of range");
  // The error names the line even after many good ones.
  expect_error("#1=1\n#2=2\nG0 X[#1/[#2-2]]\nM2", 3, 8, "attempt to divide by zero");
}

}  // namespace
}  // namespace cwe

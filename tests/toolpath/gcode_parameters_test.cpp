// Parameters and expressions in G-code, with LinuxCNC 2.9's semantics (docs/gcode.md,
// "Parameters and expressions"). Expected values are worked out by hand from LinuxCNC's rules
// (interp_read.cc, interp_execute.cc): precedence levels evaluated left to right, degrees,
// EQ and NE within 0.0001, MOD always positive, parameters set in parallel within a line; the
// golden program tests/toolpath/golden/parameters.ngc holds them to LinuxCNC's own interpreter.

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

#include "cwe/core/error.hpp"
#include "cwe/toolpath/gcode_reader.hpp"
#include "reader_testing.hpp"
#include "source_dir.hpp"

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
  test::expect_input_error([](std::string_view t) { return read(t); }, "p.ngc", text, line,
                           column, fragment);
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


// A folder of G-code files for subroutine calls by name.
class GcodeSubroutineFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    folder_ = std::filesystem::temp_directory_path() /
              ("cwe_gcode_subs_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
               "_" + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    std::filesystem::create_directories(folder_ / "lib");
  }
  void TearDown() override { std::filesystem::remove_all(folder_); }
  std::string write(const std::string& name, const std::string& text) {
    const std::filesystem::path path = folder_ / name;
    std::ofstream(path) << text;
    return path.string();
  }
  std::filesystem::path folder_;
};

TEST_F(GcodeSubroutineFiles, CalledByNameBesideTheProgramOrOnThePath) {
  write("peck.ngc", "o<peck> sub\nG1 Z#1\nG0 Z2\no<peck> endsub [#1 * 2]\nM2\n");
  write("lib/corner.ngc", "(a library sub)\no<corner> sub\nG1 X#1 Y#2\no<corner> endsub\n");
  const std::string main = write("main.ngc",
                                 "G21 F100\nG0 X1 Z2\no<peck> call [-3]\nG0 X#<_value>\n"
                                 "o<corner> call [4] [5]\no<peck> call [-1]\nM2\n");
  GcodeOptions options;
  options.subroutine_path = {(folder_ / "lib").string()};
  const Toolpath path = read_gcode_file(main, options);
  ASSERT_EQ(path.sources.size(), 3u);
  EXPECT_EQ(path.sources[1], (folder_ / "peck.ngc").string());
  EXPECT_EQ(path.sources[2], (folder_ / "lib" / "corner.ngc").string());
  ASSERT_EQ(path.moves.size(), 7u);
  // Each move names its file and line there.
  EXPECT_EQ(path.moves[1].source, 1);
  EXPECT_EQ(path.moves[1].line, 2);
  EXPECT_EQ(path.moves[1].end, Vec3(1, 0, -3));
  EXPECT_EQ(path.moves[3].source, 0);  // back in the main program: X = the returned -6
  EXPECT_EQ(path.moves[3].end.x(), -6.0);
  EXPECT_EQ(path.moves[4].source, 2);
  EXPECT_EQ(path.moves[4].line, 3);
  EXPECT_EQ(path.moves[4].end, Vec3(4, 5, 2));
  EXPECT_EQ(path.moves[5].source, 1);  // the second call reuses the file read once
  EXPECT_EQ(path.moves[5].end.z(), -1.0);
  EXPECT_EQ(path.moves[6].source, 1);
  // Without the path the library sub is not found: the error names the call's line.
  try {
    read_gcode_file(main);
    ADD_FAILURE() << "no error without the subroutine path";
  } catch (const InputError& e) {
    EXPECT_EQ(e.location().source, main);
    EXPECT_EQ(e.location().line, 5);
    EXPECT_NE(e.message().find("subroutine o<corner> is not defined"), std::string::npos)
        << e.what();
  }
}

TEST_F(GcodeSubroutineFiles, ErrorsInASubroutineFileNameThatFile) {
  const std::string sub = write("bad.ngc", "o<bad> sub\nG1 X[1/0]\no<bad> endsub\n");
  const std::string main = write("main.ngc", "G21 F100\no<bad> call\nM2\n");
  try {
    read_gcode_file(main);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.location().source, sub);
    EXPECT_EQ(e.location().line, 2);
    EXPECT_NE(e.message().find("divide by zero"), std::string::npos) << e.what();
  }
  write("open.ngc", "o<open> sub\nG1 X1\n");
  const std::string caller = write("caller.ngc", "G21 F100\no<open> call\nM2\n");
  EXPECT_THROW(read_gcode_file(caller), InputError);  // endsub missing
}

TEST(GcodeTools, M61SetsTheLoadedToolWithoutAChange) {
  const Toolpath path = read("G21 T3 M6 M3 S1000\nG0 X1\nM61 Q5\nG0 X2\nM2\n");
  ASSERT_EQ(path.moves.size(), 2u);
  EXPECT_EQ(path.moves[0].tool, 3);
  EXPECT_EQ(path.moves[1].tool, 5);
  EXPECT_EQ(path.moves[1].spindle, SpindleDirection::kClockwise);  // no change: it keeps turning
  ASSERT_EQ(path.tool_changes.size(), 2u);
  EXPECT_EQ(path.tool_changes[1].tool, 5);
  EXPECT_EQ(path.tool_changes[1].location.line, 3);
  expect_error("M61\nM2", 1, 1, "need Q parameter with M61");
  expect_error("M61 Q-1\nM2", 1, 5, "must be a tool number");
}

TEST(GcodeOWords, Errors) {
  expect_error("o100 endif\nM2", 1, 1, "o100 endif: undefined O-word label");
  expect_error("o1 if [1]\no2 endif\nM2", 2, 1, "o2 endif: undefined O-word label");
  expect_error("o1 while [0]\no1 endif\nM2", 2, 1, "no matching 'if'");
  expect_error("o1 if [1]\no1 endwhile\nM2", 2, 1, "no matching 'while'");
  expect_error("o1 sub\no2 sub\nM2", 2, 1, "nested subroutine definition");
  expect_error("o1 sub\nG0 X1\nM2\n", 1, 0, "'o<1> sub' has no 'o<1> endsub'");
  expect_error("o1 endsub\nM2", 1, 1, "not in a subroutine definition");
  expect_error("o1 if\nM2", 1, 6, "o1 if: a bracketed expression must follow");
  expect_error("o1 if [1] G0 X1\nM2", 1, 11, "unexpected character after O-word");
  expect_error("o1 foo\nM2", 1, 4, "unknown O-word command");
  expect_error("G0 X1 o1 call\nM2", 1, 7, "an O-word must be the first word of its line");
  expect_error("G21\no<nowhere> call\nM2", 2, 0, "subroutine o<nowhere> is not defined");
  expect_error("o1 if [0]\no1 endif\no1 if [1]\no1 endif\nM2", 3, 1,
               "o1 is already defined at line 1");
  // Eleven levels of calls: LinuxCNC allows ten.
  expect_error("o1 sub\no1 call\no1 endsub\no1 call\nM2", 2, 1, "too many subroutine levels");
}

TEST(GcodeOWords, AnEndlessLoopIsAnErrorNotAHang) {
  // LinuxCNC runs this forever; cwe stops after ten million iterations without a move.
  expect_error("G21\no1 while [1]\no1 endwhile\nM2", 3, 1, "the program never ends");
  // Loops that move are not limited by that count.
  const Toolpath path = read("G21 #1=0\no1 while [#1 LT 20000]\nG0 X#1\n#1=[#1+1]\no1 endwhile\nM2");
  EXPECT_EQ(path.moves.size(), 20000u);
}

TEST(GcodeOWords, TheEndlessLoopLimitIsAnOption) {
  // A caller may lower the count (the fuzz target does, to stay fast).
  GcodeOptions options;
  options.max_idle_iterations = 100;
  try {
    (void)read_gcode("G21\n#1=0\no1 while [1]\n#1=[#1+1]\no1 endwhile\nM2", "p.ngc", options);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.location().line, 5);
    EXPECT_NE(e.message().find("100 loop iterations"), std::string::npos) << e.message();
  }
  // Below the limit, the loop runs.
  const Toolpath path = read_gcode(
      "G21\n#1=0\no1 while [#1 LT 50]\n#1=[#1+1]\no1 endwhile\nG0 X#1\nM2", "p.ngc", options);
  ASSERT_EQ(path.moves.size(), 1u);
  EXPECT_EQ(path.moves.back().end.x(), 50.0);
}

TEST(GcodeOWords, AnEndlessLoopEndsTheReading) {
  // Found by the fuzz target: an endless loop nested in a loop that moves, beside a line in
  // error. Reading on after the first "never ends" went round the outer loop again, each pass
  // another full count of idle iterations, for a thousand errors (minutes). Now that error is
  // the last one.
  GcodeOptions options;
  options.max_idle_iterations = 100;
  try {
    (void)read_gcode("G21 F100\no2 while [1]\nG1 X1\nM221\no1 while [1]\no1 endwhile\n"
                     "o2 endwhile\nM2",
                     "p.ngc", options);
    ADD_FAILURE() << "no error";
  } catch (const InputErrors& e) {
    ASSERT_EQ(e.errors().size(), 2u);
    EXPECT_EQ(e.errors()[0].location().line, 4);  // M221
    EXPECT_EQ(e.errors()[1].location().line, 6);
    EXPECT_NE(e.errors()[1].message().find("never ends"), std::string::npos);
  }
}

TEST(GcodeOWords, TheLinesReadCanBeLimited) {
  // A loop that moves ten thousand times reads 30,000 lines; a limit of 1,000 stops it at the
  // 1,001st line, located at the last line read.
  GcodeOptions options;
  options.max_lines_read = 1000;
  try {
    (void)read_gcode("G21 #1=0\no1 while [#1 LT 10000]\nG0 X#1\n#1=[#1+1]\no1 endwhile\nM2",
                     "p.ngc", options);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_GE(e.location().line, 2);
    EXPECT_LE(e.location().line, 5);
    EXPECT_NE(e.message().find("after 1000 lines"), std::string::npos) << e.message();
  }
  options.max_lines_read = 0;  // no limit
  EXPECT_EQ(read_gcode("G21 #1=0\no1 while [#1 LT 10000]\nG0 X#1\n#1=[#1+1]\no1 endwhile\nM2",
                       "p.ngc", options)
                .moves.size(),
            10000u);
}

TEST(GcodeOWords, ArgumentsAndLocalsBelongToTheCall) {
  // #1-#30 are the call's arguments (0 beyond those given) and come back afterwards; a named
  // local of the caller is not visible in the sub; a global is.
  const Toolpath path = read(
      "#1=7 #2=8 #<mine>=1 #<_shared>=4\n"
      "o<s> sub\n"
      "G0 X#1 Y#2 Z[EXISTS[#<mine>] * 10 + #<_shared>]\n"
      "#<mine>=99\n"
      "o<s> endsub\n"
      "o<s> call [3]\n"
      "G0 X#1 Y#2 Z#<mine>\n"
      "M2\n");
  ASSERT_EQ(path.moves.size(), 2u);
  EXPECT_EQ(path.moves[0].end, Vec3(3, 0, 4));
  EXPECT_EQ(path.moves[1].end, Vec3(7, 8, 1));
}


TEST(GcodePosts, AFusionStyleHeaderReadsAsItIs) {
  // The header and footer a Fusion 360 style post writes for LinuxCNC and Fanuc-like controls: a
  // program number, G53 and G28 retracts, a work offset, a tool change.
  const Toolpath path = read(
      "%\n"
      "O1001 (PART)\n"
      "(T1 D=10. CR=0. - ZMIN=-2. - FLAT END MILL)\n"
      "G90 G94 G17\n"
      "G21\n"
      "G53 G0 Z0.\n"
      "T1 M6\n"
      "S8000 M3\n"
      "G55\n"
      "G0 X10. Y5.\n"
      "G43 Z15. H1\n"
      "G1 Z-2. F300.\n"
      "X40.\n"
      "G0 Z15.\n"
      "G28 G91 Z0.\n"
      "G90\n"
      "M5\n"
      "M30\n"
      "%\n");
  ASSERT_EQ(path.moves.size(), 8u);
  // G53 Z0: machine Z0 (no machine definition: the program's frame with zero offsets).
  EXPECT_EQ(path.moves[0].end.z(), 0.0);
  EXPECT_EQ(path.moves[1].end, Vec3(10, 5, 0));  // G55 with zero offsets is the same frame
  EXPECT_EQ(path.moves[3].end, Vec3(10, 5, -2));
  EXPECT_EQ(path.moves[4].end, Vec3(40, 5, -2));
  EXPECT_EQ(path.moves[6].end, Vec3(40, 5, 15));  // G28 G91 Z0: through the current point…
  EXPECT_EQ(path.moves[7].end, Vec3(40, 5, 0));   // …to the stored home's Z, machine 0
  ASSERT_FALSE(path.warnings.empty());
  EXPECT_NE(path.warnings[0].message.find("G53"), std::string::npos);
}

TEST(GcodeMachine, WorkOffsetsStoredPositionsAndTravel) {
  // The Fusion-style program on a machine whose G55 zero is at X-300 Y-200 Z-300 (machine
  // coordinates, home at 0), moves reported in G55's frame (the stock's).
  const std::string program =
      "G90 G94 G17 G21\nG53 G0 Z0.\nT1 M6\nS8000 M3\nG55\nG0 X10. Y5.\nG43 Z15. H1\n"
      "G1 Z-2. F300.\nX40.\nG0 Z15.\nG28 G91 Z0.\nG90\nM30\n";
  GcodeOptions options;
  MachineDefinition machine;
  machine.work_offsets[0] = Vec3(-400, -200, -300);
  machine.work_offsets[1] = Vec3(-300, -200, -300);
  machine.g28 = Vec3(0, 0, 0);
  machine.travel = Aabb{Vec3(-800, -500, -400), Vec3(0, 0, 0)};
  machine.frame = 2;
  options.machine = machine;
  const Toolpath path = read_gcode(program, "test.ngc", options);
  ASSERT_EQ(path.moves.size(), 8u);
  EXPECT_EQ(path.moves[0].start, Vec3(0, 0, 0));
  EXPECT_EQ(path.moves[0].end, Vec3(0, 0, 300));  // G53 Z0: the machine's top, 300 above
  EXPECT_EQ(path.moves[1].end, Vec3(10, 5, 300));
  EXPECT_EQ(path.moves[3].end, Vec3(10, 5, -2));
  EXPECT_EQ(path.moves[6].end, Vec3(40, 5, 15));
  EXPECT_EQ(path.moves[7].end, Vec3(40, 5, 300));  // G28 Z: home, machine Z0
  // Nothing is assumed about the machine; only G43 is said to change nothing.
  ASSERT_EQ(path.warnings.size(), 1u);
  EXPECT_NE(path.warnings[0].message.find("tool length offsets (G43 H, G49)"), std::string::npos);
  // The work offsets are LinuxCNC's parameters; G54 is selected first.
  const Toolpath p = read_gcode("G0 X#5221 Y#5242 Z#5163\nM2\n", "test.ngc", options);
  // In G54, X-400 Y-200 Z0 is machine X-800 Y-400 Z-300: in G55's frame X-500 Y-200 Z0.
  EXPECT_EQ(p.moves[0].end, Vec3(-500, -200, 0));
  // Beyond the travel: an error at the move's line.
  const auto beyond = [&](std::string_view text) {
    return read_gcode(text, "test.ngc", options);
  };
  test::expect_input_error(beyond, "test.ngc", "G55 G0 X10\nG0 X301\nM2\n", 2, 0,
                           "beyond the machine's travel: X 1.000 mm, its limit 0.000 mm");
  test::expect_input_error(beyond, "test.ngc", "G0 Z-101\nM2\n", 1, 0,
                           "beyond the machine's travel: Z -401.000 mm, its limit -400.000 mm");
}

TEST(GcodeModalState, RestoredAsLinuxcncWritesIt) {
  // M72 restores a changed feed as LinuxCNC's "F%.1f" does: rounded to 0.1; S to 1.
  const Toolpath path = read("G21 F123.456 S1000.4 M3\nM70\nF50 S20 M5\nM72\nG1 X1\nM2\n");
  ASSERT_EQ(path.moves.size(), 1u);
  EXPECT_NEAR(path.moves[0].feed_rate, 123.5, 1e-12);
  EXPECT_EQ(path.moves[0].spindle_speed, 1000.0);
  EXPECT_EQ(path.moves[0].spindle, SpindleDirection::kClockwise);
  // Unchanged values are not rewritten.
  EXPECT_NEAR(read("G21 F123.456\nM70\nM72\nG1 X1\nM2\n").moves[0].feed_rate, 123.456, 1e-12);
  expect_error("M72\nM2", 1, 1, "missing M70/M73");
  expect_error("M70\nM71\nM72\nM2", 3, 1, "missing M70/M73");
}

TEST(GcodeFanuc, M98AndM99) {
  expect_error("M98\nM2", 1, 1, "found 'M98' code with no P-word");
  expect_error("G0 X1 M98 P1\nM2", 1, 7, "M98 must be the first word of its line");
  expect_error("M98 P7\nM2", 1, 0, "subroutine o<7> is not defined");
  expect_error("M98 P5\nM30\nO5\nG0 X1\no5 endsub\n", 5, 1, "must end with 'M99'");
  expect_error("o5 call\nM30\nO5\nM99\n", 3, 1, "must be called with 'M98'");
  expect_error("M98 P5\nM30\no5 sub\nM99\n", 3, 1, "must be called with 'O.... call'");
  // M99 in the main program: LinuxCNC runs the program forever; cwe reads it once and says so.
  const Toolpath path = read("G0 X1\nM99\nG0 X2\n");
  ASSERT_EQ(path.moves.size(), 1u);
  ASSERT_FALSE(path.warnings.empty());
  EXPECT_NE(path.warnings[0].message.find("M99 in the main program"), std::string::npos);
  // L0 calls nothing.
  EXPECT_EQ(read("G0 X1\nM98 P5 L0\nM30\nO5\nG0 X9\nM99\n").moves.size(), 1u);
}

TEST(GcodeTools, ToolTableDataChangesNothingOnTheTipPath) {
  const Toolpath path = read("G21\nG10 L1 P1 R3 Z50\nG0 X1\nG10 L10 P2 Z0\nG10 L11 P3 X0\nM2\n");
  ASSERT_EQ(path.moves.size(), 1u);
  EXPECT_EQ(path.moves[0].end, Vec3(1, 0, 0));
  ASSERT_EQ(path.warnings.size(), 1u);  // once
  EXPECT_EQ(path.warnings[0].location.line, 2);
  EXPECT_NE(path.warnings[0].message.find("G10 L1 (tool table data)"), std::string::npos);
  expect_error("G10 L1 P0 R1\nM2", 1, 8, "needs a tool number P of 1 or more");
}

TEST(GcodePolar, Errors) {
  expect_error("G21 G18\nG0 @1 ^90\nM2", 2, 4, "cannot use polar coordinate except in G17 plane");
  expect_error("G0 X1 @1\nM2", 1, 7, "cannot specify both polar coordinate and X word");
  expect_error("G53 G0 @1\nM2", 1, 8, "cannot use polar coordinates with G53");
  expect_error("G92 @1\nM2", 1, 5, "polar coordinates can only be used for motion");
  expect_error("G0 @1\nM2", 1, 4, "must specify angle in polar coordinate if at the origin");
  expect_error("G91 G0 ^10\nM2", 1, 8, "indeterminate when at the origin");
  expect_error("G0 @1 @2\nM2", 1, 7, "multiple @ words on one line");
}

// tests/toolpath/malformed: one program per kind of error, each naming the errors it must give.
TEST(GcodeMalformed, EveryProgramGivesItsErrors) {
  const std::filesystem::path folder = test::source_dir() / "tests" / "toolpath" / "malformed";
  int programs = 0;
  for (const auto& entry : std::filesystem::directory_iterator(folder)) {
    if (entry.path().extension() != ".ngc") continue;
    ++programs;
    SCOPED_TRACE(entry.path().filename().string());
    struct Expected {
      int line, column;
      std::string text;
    };
    std::vector<Expected> expected;
    std::ifstream in(entry.path());
    std::string line;
    while (std::getline(in, line) && line.rfind("(expect ", 0) == 0) {
      Expected e;
      const std::size_t colon = line.find(':'), space = line.find(' ', 8);
      e.line = std::stoi(line.substr(8, colon - 8));
      e.column = std::stoi(line.substr(colon + 1, space - colon - 1));
      e.text = line.substr(space + 1, line.size() - space - 2);
      expected.push_back(e);
    }
    ASSERT_FALSE(expected.empty()) << "no (expect …) line";
    std::vector<InputError> errors;
    try {
      read_gcode_file(entry.path().string());
    } catch (const InputErrors& e) {
      errors = e.errors();
    } catch (const InputError& e) {
      errors = {e};
    }
    ASSERT_EQ(errors.size(), expected.size());
    for (std::size_t k = 0; k < errors.size(); ++k) {
      EXPECT_EQ(errors[k].location().source, entry.path().string());
      EXPECT_EQ(errors[k].location().line, expected[k].line) << errors[k].what();
      EXPECT_EQ(errors[k].location().column, expected[k].column) << errors[k].what();
      EXPECT_NE(errors[k].message().find(expected[k].text), std::string::npos) << errors[k].what();
    }
  }
  EXPECT_GE(programs, 28);
}

TEST(GcodeErrors, EveryErrorOfTheFileNotOnlyTheFirst) {
  // Three bad lines among good ones: all three, in order, each at its line and column; the
  // exception's own location is the first.
  try {
    read("G21 F100\nG1 X1 G7\nG1 X2\nG1 X[1/0]\nG1 X3 Y#<nope>\nG1 X4\nM2\n");
    ADD_FAILURE() << "no error";
  } catch (const InputErrors& e) {
    ASSERT_EQ(e.errors().size(), 3u) << e.what();
    EXPECT_EQ(e.more(), 0u);
    EXPECT_EQ(e.location().line, 2);
    EXPECT_EQ(e.errors()[1].location().line, 4);
    EXPECT_EQ(e.errors()[1].location().column, 7);
    EXPECT_EQ(e.errors()[2].location().line, 5);
    const std::string text = e.what();
    EXPECT_NE(text.find("p.ngc:2:7: error: G7"), std::string::npos) << text;
    EXPECT_NE(text.find("\np.ngc:4:7: error: attempt to divide by zero"), std::string::npos);
    EXPECT_NE(text.find("\np.ngc:5:8: error: named parameter #<nope> not defined"),
              std::string::npos);
  }
  // A single error is a plain InputError, as before.
  try {
    read("G21\nG1 X1 F0\nM2\n");
    ADD_FAILURE() << "no error";
  } catch (const InputErrors&) {
    ADD_FAILURE() << "one error came as several";
  } catch (const InputError& e) {
    EXPECT_EQ(e.location().line, 2);
  }
  // Twenty are listed, then a count.
  std::string many = "G21 F100\n";
  for (int k = 0; k < 25; ++k) many += "G1 X[1/0]\n";
  try {
    read(many + "M2\n");
    ADD_FAILURE() << "no error";
  } catch (const InputErrors& e) {
    EXPECT_EQ(e.errors().size(), 20u);
    EXPECT_EQ(e.more(), 5u);
    EXPECT_NE(std::string(e.what()).find("\n… and 5 more errors"), std::string::npos);
  }
  // An erroring line inside an endless loop: reading stops at a thousand errors.
  try {
    read("G21\no1 while [1]\nG1 X[1/0]\no1 endwhile\nM2\n");
    ADD_FAILURE() << "no error";
  } catch (const InputErrors& e) {
    EXPECT_EQ(e.errors().size(), 21u);
    EXPECT_EQ(e.more(), 980u);
    EXPECT_NE(e.errors().back().message().find("reading stopped after 1000 errors"),
              std::string::npos);
  }
}

}  // namespace
}  // namespace cwe

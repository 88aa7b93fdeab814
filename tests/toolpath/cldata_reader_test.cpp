#include "cwe/toolpath/cldata_reader.hpp"
#include "reader_testing.hpp"
#include "source_dir.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "random.hpp"
#include "tool/tool_testing.hpp"

namespace cwe {
namespace {

// Tolerances. Coordinates are parsed exactly as the nearest doubles; arcs are then built with a
// few rotations and products of values up to ~200 mm, which err by a few ulps of that size
// (~1e-13 mm): kTight leaves three orders of margin. Unit vectors are normalised once (~1e-16).
constexpr double kTight = 1e-10;
constexpr double kUnit = 1e-15;

Toolpath read(std::string_view text) { return read_cldata(text, "t.cl"); }
const auto read_program = [](std::string_view text) { return read(text); };

std::string source_dir() { return test::source_dir().string(); }

void expect_point(const Vec3& actual, const Vec3& expected, double tolerance) {
  EXPECT_LT((actual - expected).norm(), tolerance)
      << "actual (" << actual.transpose() << "), expected (" << expected.transpose() << ")";
}

// ------------------------------------------------------------------------------------------------
// Lexing: case, blanks, numbers, continuation lines, comments, literal records.

TEST(CldataLexing, RecordsAreCaseAndBlankInsensitive) {
  const Toolpath p = read("goto / 1., -.5 , 1.0e-3\n  GoTo/+2,3E1,-4.25E+0\n");
  ASSERT_EQ(p.moves.size(), 2u);
  EXPECT_EQ(p.moves[0].end, Vec3(1.0, -0.5, 1.0e-3));
  EXPECT_EQ(p.moves[1].start, Vec3(1.0, -0.5, 1.0e-3));
  EXPECT_EQ(p.moves[1].end, Vec3(2.0, 30.0, -4.25));
  EXPECT_EQ(p.moves[0].line, 1);
  EXPECT_EQ(p.moves[1].line, 2);
  EXPECT_EQ(p.sources, std::vector<std::string>{"t.cl"});
  EXPECT_EQ(p.moves[1].source, 0);
}

TEST(CldataLexing, ContinuationLinesAndComments) {
  const Toolpath p = read(
      "$$ header comment\n"
      "FEDRAT/ 100 $$ feed\n"
      "GOTO/ 1.0, $\n"
      "      2.0, $   $$ still the same record\n"
      "$$ a comment line inside the record\n"
      "\n"
      "      3.0\n"
      "GOTO/4,5,6 $$ trailing comment\n");
  ASSERT_EQ(p.moves.size(), 2u);
  EXPECT_EQ(p.moves[0].end, Vec3(1, 2, 3));
  EXPECT_EQ(p.moves[0].line, 3);  // the first line of the continued record
  EXPECT_EQ(p.moves[1].end, Vec3(4, 5, 6));
  EXPECT_EQ(p.moves[1].line, 8);
  EXPECT_EQ(p.moves[1].feed_rate, 100.0);
  EXPECT_TRUE(p.warnings.empty());
}

TEST(CldataLexing, CrLfLoneCrAndByteOrderMark) {
  const Toolpath p = read("\xEF\xBB\xBFGOTO/1,2,3\r\nGOTO/4,5,6\rGOTO/7,8,9");
  ASSERT_EQ(p.moves.size(), 3u);
  EXPECT_EQ(p.moves[2].line, 3);
  EXPECT_EQ(p.moves[2].end, Vec3(7, 8, 9));
}

TEST(CldataLexing, LiteralRecordsKeepTheirText) {
  // PARTNO, PPRINT, INSERT and TPRINT take the rest of the line as text: commas, slashes and
  // dollars there are not syntax.
  const Toolpath p = read(
      "PARTNO BRACKET-01 / OP10, $ not a continuation\n"
      "PPRINT/ TOOL: D10, R0 $$ not a comment either\n"
      "INSERT/G91 G28 Z0\n"
      "TPRINT/T1 End Mill D 10\n"
      "pprint lower case works too\n"
      "RAPID\n"
      "GOTO/1,2,3\n");
  ASSERT_EQ(p.moves.size(), 1u);
  EXPECT_EQ(p.moves[0].line, 7);
  EXPECT_TRUE(p.warnings.empty());
}

TEST(CldataLexing, TextAfterTheContinuationMarkIsAnError) {
  EXPECT_INPUT_ERROR(read("GOTO/1,$ 2,3\n4\n"),
                     "t.cl:1:10: error: unexpected text after the continuation mark '$'");
}

TEST(CldataLexing, FileEndingInsideAContinuedRecordIsAnError) {
  EXPECT_INPUT_ERROR(read("GOTO/0,0,0\nGOTO/1,2,$\n$$ comment\n"),
                     "t.cl:2:1: error: the record is continued with '$' but the file ends");
}

TEST(CldataLexing, NumbersAndFieldsAreCheckedWithTheirColumn) {
  EXPECT_INPUT_ERROR(read("GOTO/1,x,3"),
                     "t.cl:1:8: error: GOTO takes x,y,z or x,y,z,i,j,k: expected a number, "
                     "found 'X'");
  EXPECT_INPUT_ERROR(read("GOTO/1,,3"), "t.cl:1:8: error: expected a number");
  EXPECT_INPUT_ERROR(read("GOTO/1,2,"), "t.cl:1:10: error: expected a number");
  EXPECT_INPUT_ERROR(read("\n  GOTO / 1, 2"),
                     "t.cl:2:3: error: GOTO takes x,y,z or x,y,z,i,j,k (2 values given)");
  EXPECT_INPUT_ERROR(read("GOTO/1,2,3,4"), "(4 values given)");
  EXPECT_INPUT_ERROR(read("GOTO/1.2.3,0,0"), "t.cl:1:6: error: expected a number, found '1.2.3'");
  EXPECT_INPUT_ERROR(read("GOTO/1E,0,0"), "expected a number, found '1E'");
  EXPECT_INPUT_ERROR(read("GOTO/-,0,0"), "expected a number, found '-'");
  EXPECT_INPUT_ERROR(read("GOTO/INF,0,0"), "expected a number, found 'INF'");
  EXPECT_INPUT_ERROR(read("GOTO/1 2,0,0"), "expected a number, found '1 2'");
  EXPECT_INPUT_ERROR(read("GOTO"), "t.cl:1:1: error: GOTO takes x,y,z");
  EXPECT_INPUT_ERROR(read("/1,2,3"), "t.cl:1:1: error: expected a major word before '/'");
  EXPECT_INPUT_ERROR(read("1,2,3"), "t.cl:1:1: error: numbers without a major word");
  EXPECT_INPUT_ERROR(read("  G%TO/1,2,3"),
                     "t.cl:1:3: error: expected a record such as GOTO/x,y,z, found 'G%TO'");
}

TEST(CldataLexing, HugeNumbersAreRefused) {
  EXPECT_INPUT_ERROR(read("GOTO/1e999,0,0"), "t.cl:1:6: error: '1E999' is out of range");
  EXPECT_INPUT_ERROR(read("GOTO/0,-1e300,0"), "'-1E300' is out of range");
  EXPECT_INPUT_ERROR(read("FEDRAT/1e10"), "is out of range");
  EXPECT_INPUT_ERROR(read("GOTO/0,0,1e-400"), "is out of range");  // underflows
  // Up to the limit (1e9) is fine, and so are all squares and products formed from it.
  const Toolpath p = read("GOTO/1e9,-1e9,1e9");
  EXPECT_EQ(p.moves[0].end, Vec3(1e9, -1e9, 1e9));
}

// ------------------------------------------------------------------------------------------------
// Units.

TEST(CldataUnits, InchProgramsAreConvertedToMillimetres) {
  const Toolpath p = read(
      "UNITS/INCHES\n"
      "CUTTER/0.5,0.125,0.125,0.125,0,0,1.5\n"
      "FEDRAT/10,IPM\n"
      "GOTO/1,2,3\n"
      "FEDRAT/IPM,20\n"
      "GODLTA/0,0,1\n"
      "FEDRAT/254,MMPM\n"
      "GOTO/1,2,5\n"
      "FEDRAT/30\n"
      "GOTO/1,2,6\n");
  EXPECT_EQ(p.units, ProgramUnits::kInches);
  ASSERT_EQ(p.moves.size(), 4u);
  EXPECT_EQ(p.moves[0].end, Vec3(25.4, 2 * 25.4, 3 * 25.4));
  EXPECT_EQ(p.moves[1].end, Vec3(25.4, 2 * 25.4, 3 * 25.4 + 25.4));
  EXPECT_DOUBLE_EQ(p.moves[0].feed_rate, 10 * 25.4);
  EXPECT_DOUBLE_EQ(p.moves[1].feed_rate, 20 * 25.4);
  EXPECT_DOUBLE_EQ(p.moves[2].feed_rate, 254.0);      // an explicit MMPM stays mm/min
  EXPECT_DOUBLE_EQ(p.moves[3].feed_rate, 30 * 25.4);  // no unit: the program's, per minute
  ASSERT_EQ(p.tool_definitions.count(0), 1u);
  const AptCutter& t = p.tool_definitions.at(0);
  EXPECT_DOUBLE_EQ(t.d, 12.7);
  EXPECT_DOUBLE_EQ(t.r, 3.175);
  EXPECT_DOUBLE_EQ(t.e, 3.175);
  EXPECT_DOUBLE_EQ(t.f, 3.175);
  EXPECT_DOUBLE_EQ(t.h, 38.1);
  EXPECT_TRUE(p.warnings.empty());
}

TEST(CldataUnits, CutterAnglesAreNotScaled) {
  const Toolpath p = read("UNITS/INCHES\nCUTTER/0.25,0,0.125,0,0,5,1\nGOTO/0,0,0");
  const AptCutter& t = p.tool_definitions.at(0);
  EXPECT_DOUBLE_EQ(t.d, 6.35);
  EXPECT_EQ(t.beta_deg, 5.0);
  EXPECT_DOUBLE_EQ(t.h, 25.4);
}

TEST(CldataUnits, InchFeedsInAMillimetreProgramAndBack) {
  const Toolpath p = read("UNITS/MM\nFEDRAT/IPM,10\nGOTO/1,0,0\nUNITS/INCH\nGOTO/1,0,0\n");
  EXPECT_DOUBLE_EQ(p.moves[0].feed_rate, 254.0);
  EXPECT_EQ(p.moves[0].end, Vec3(1, 0, 0));
  EXPECT_EQ(p.moves[1].end, Vec3(25.4, 0, 0));
  EXPECT_EQ(p.units, ProgramUnits::kInches);  // the last UNITS record
  EXPECT_EQ(read("GOTO/1,0,0").units, ProgramUnits::kMillimetres);
}

TEST(CldataUnits, UnknownUnitIsAnError) {
  EXPECT_INPUT_ERROR(read("UNITS/FEET"), "t.cl:1:7: error: UNITS takes MM or INCHES");
  EXPECT_INPUT_ERROR(read("UNITS"), "t.cl:1:1: error: UNITS takes MM or INCHES");
}

// ------------------------------------------------------------------------------------------------
// Tools.

TEST(CldataTools, CutterBelongsToTheToolLoadedNextOrJustBefore) {
  // CATIA writes CUTTER/ before LOADTL/; others after it; NX loads with LOAD/TOOL.
  const Toolpath p = read(
      "FEDRAT/100\n"
      "CUTTER/10\n"
      "LOADTL/1\n"
      "GOTO/0,0,0\n"
      "LOADTL/2,ADJUST,2\n"
      "CUTTER/6,3\n"
      "GOTO/1,0,0\n"
      "CUTTER/8\n"
      "LOAD/TOOL,3,ADJUST,3\n"
      "GOTO/2,0,0\n");
  ASSERT_EQ(p.moves.size(), 3u);
  EXPECT_EQ(p.moves[0].tool, 1);
  EXPECT_EQ(p.moves[1].tool, 2);
  EXPECT_EQ(p.moves[2].tool, 3);
  ASSERT_EQ(p.tool_definitions.size(), 3u);
  EXPECT_EQ(to_string(p.tool_definitions.at(1)), "CUTTER/10,0,5,0,0,0,30");
  EXPECT_EQ(to_string(p.tool_definitions.at(2)), "CUTTER/6,3,0,3,0,0,18");
  EXPECT_EQ(to_string(p.tool_definitions.at(3)), "CUTTER/8,0,4,0,0,0,24");
  EXPECT_TRUE(p.warnings.empty());
}

TEST(CldataTools, CutterWithoutLoadtlIsToolZero) {
  const Toolpath p = read("CUTTER/10,2\nGOTO/1,2,3\n");
  EXPECT_EQ(p.moves[0].tool, 0);
  EXPECT_EQ(to_string(p.tool_definitions.at(0)), "CUTTER/10,2,3,2,0,0,30");
  // Also when the program has no motion at all.
  EXPECT_EQ(read("LOADTL/7\nCUTTER/4\n").tool_definitions.count(7), 1u);
  EXPECT_EQ(read("CUTTER/4\n").tool_definitions.count(0), 1u);
}

TEST(CldataTools, InconsistentCutterIsAWarningNotADefinition) {
  const Toolpath p = read("CUTTER/10,2,3,2.5,0,0,30\nRAPID\nGOTO/0,0,1");
  EXPECT_TRUE(p.tool_definitions.empty());
  ASSERT_EQ(p.warnings.size(), 1u);
  EXPECT_EQ(p.warnings[0].location.line, 1);
  EXPECT_NE(p.warnings[0].message.find("f = 2.5"), std::string::npos) << p.warnings[0].message;
  EXPECT_NE(p.warnings[0].message.find("tool 0 stays undefined"), std::string::npos);
}

TEST(CldataTools, RedefinitionWarnsAndTheLastWins) {
  const Toolpath p =
      read("FEDRAT/100\nLOADTL/1\nCUTTER/10\nGOTO/0,0,0\nLOADTL/1\nCUTTER/12\nGOTO/1,0,0\n");
  EXPECT_EQ(p.tool_definitions.at(1).d, 12.0);
  ASSERT_EQ(p.warnings.size(), 1u);
  EXPECT_EQ(p.warnings[0].location.line, 6);
  EXPECT_NE(p.warnings[0].message.find("tool 1 redefined"), std::string::npos);
  // The same definition again is not a redefinition.
  EXPECT_TRUE(
      read("FEDRAT/9\nLOADTL/1\nCUTTER/10\nGOTO/0,0,0\nLOADTL/1\nCUTTER/10.0\n").warnings.empty());
}

TEST(CldataTools, MalformedToolRecords) {
  EXPECT_INPUT_ERROR(read("CUTTER/10,2,3"), "t.cl:1:1: error: CUTTER with 3 values is ambiguous");
  EXPECT_INPUT_ERROR(read("CUTTER/"), "t.cl:1:8: error: expected a number");
  EXPECT_INPUT_ERROR(read("CUTTER/10,X"), "t.cl:1:11: error: CUTTER takes 1 to 7 numbers");
  EXPECT_INPUT_ERROR(read("CUTTER/1,2,3,4,5,6,7,8"), "CUTTER takes 1 to 7 numbers");
  EXPECT_INPUT_ERROR(read("LOADTL/1.5"), "t.cl:1:8: error: tool number: expected a whole number");
  EXPECT_INPUT_ERROR(read("LOADTL/-1"), "expected a whole number from 0 to");
  EXPECT_INPUT_ERROR(read("LOADTL/"), "LOADTL takes the tool number");
  EXPECT_INPUT_ERROR(read("LOADTL/T1"), "t.cl:1:8: error: LOADTL takes the tool number");
  EXPECT_INPUT_ERROR(read("LOAD/TOOL"), "LOAD/TOOL takes the tool number");
}

// ------------------------------------------------------------------------------------------------
// Motion records.

TEST(CldataMotion, TheFirstGotoStartsAtTheOrigin) {
  const Toolpath p = read("GOTO/1,2,3");
  EXPECT_EQ(p.moves[0].start, Vec3::Zero());
  EXPECT_EQ(p.moves[0].start_axis, Vec3::UnitZ());
  // Or where the reader is told the tool is.
  EXPECT_EQ(read_cldata("GOTO/1,2,3", "t.cl", Vec3(1, 2, 8)).moves[0].start, Vec3(1, 2, 8));
  EXPECT_EQ(read_cldata("FROM/0,0,9\nGOTO/1,2,3", "t.cl", Vec3(1, 2, 8)).moves[0].start,
            Vec3(0, 0, 9));
}

// A program that states no axis before its first GOTO starts in that GOTO's orientation: no
// simultaneous 5-axis turn from an invented +Z pose.
TEST(CldataMotion, TheFirstGotoStartsInItsOwnOrientation) {
  const Vec3 tilted = Vec3(0, 3, 4) / 5.0;
  for (const char* program : {"RAPID\nGOTO/10,0,20,0,3,4\nGOTO/10,0,5,0,0,1\n",
                              "FEDRAT/300\nMULTAX/ON\nGOTO/10,0,20,0,0.6,0.8\nGOTO/10,0,5,0,0,1\n",
                              "FROM/0,0,50\nGOTO/10,0,20,0,3,4\nGOTO/10,0,5,0,0,1\n"}) {
    const Toolpath p = read(program);
    ASSERT_EQ(p.moves.size(), 2u) << program;
    expect_point(p.moves[0].start_axis, tilted, kUnit);
    expect_point(p.moves[0].end_axis, tilted, kUnit);
    EXPECT_EQ(p.moves[0].axis_angle(), 0.0) << program;
    EXPECT_GT(p.moves[1].axis_angle(), 0.6) << program;  // the later turn is programmed
  }
  // An axis stated before the first GOTO is where the tool starts.
  for (const char* program : {"TLAXIS/0,0,1\nGOTO/10,0,20,0,3,4\n",
                              "FROM/0,0,50,0,0,1\nGOTO/10,0,20,0,3,4\n"}) {
    const Toolpath p = read(program);
    EXPECT_EQ(p.moves[0].start_axis, Vec3::UnitZ()) << program;
    expect_point(p.moves[0].end_axis, tilted, kUnit);
  }
}

TEST(CldataMotion, FromSetsThePositionWithoutMoving) {
  const Toolpath p = read("FROM/5,5,5\nGOTO/6,5,5\nFROM/0,0,10,0,1,1\nGOTO/0,0,0\n");
  ASSERT_EQ(p.moves.size(), 2u);
  EXPECT_EQ(p.moves[0].start, Vec3(5, 5, 5));
  EXPECT_EQ(p.moves[1].start, Vec3(0, 0, 10));
  expect_point(p.moves[1].start_axis, Vec3(0, 1, 1) / std::sqrt(2.0), kUnit);
  expect_point(p.moves[1].end_axis, Vec3(0, 1, 1) / std::sqrt(2.0), kUnit);
  EXPECT_INPUT_ERROR(read("FROM/1,2,3,4"), "FROM takes x,y,z or x,y,z,i,j,k (4 values given)");
}

TEST(CldataMotion, RapidAppliesToTheNextMotionOnly) {
  const Toolpath p = read(
      "FEDRAT/500\nRAPID\nGOTO/0,0,10\nGOTO/0,0,0\nRAPID\nFEDRAT/300\nGOTO/1,0,0\n"
      "RAPID\nGODLTA/0,0,5\nGOTO/1,0,0\n");
  ASSERT_EQ(p.moves.size(), 5u);
  EXPECT_TRUE(p.moves[0].is_rapid());
  EXPECT_EQ(p.moves[0].feed_rate, 0.0);
  EXPECT_FALSE(p.moves[1].is_rapid());
  EXPECT_EQ(p.moves[1].feed_rate, 500.0);
  EXPECT_FALSE(p.moves[2].is_rapid());  // FEDRAT replaced the pending RAPID
  EXPECT_EQ(p.moves[2].feed_rate, 300.0);
  EXPECT_TRUE(p.moves[3].is_rapid());
  EXPECT_FALSE(p.moves[4].is_rapid());
  EXPECT_INPUT_ERROR(read("RAPID/5"), "t.cl:1:7: error: RAPID takes no values");
}

TEST(CldataMotion, GodltaIsIncremental) {
  const Toolpath p = read(
      "FROM/1,1,1\nGODLTA/1,2,3\nTLAXIS/0,0,2\nGODLTA/-5\nTLAXIS/1,0,1\nGODLTA/2\n"
      "GODLTA/0,0,0,1,0,0\n");
  ASSERT_EQ(p.moves.size(), 4u);
  EXPECT_EQ(p.moves[0].end, Vec3(2, 3, 4));
  EXPECT_EQ(p.moves[1].end, Vec3(2, 3, -1));  // along the tool axis
  expect_point(p.moves[2].end, Vec3(2 + std::sqrt(2.0), 3, -1 + std::sqrt(2.0)), kTight);
  expect_point(p.moves[3].end, p.moves[2].end, kTight);
  expect_point(p.moves[3].start_axis, Vec3(1, 0, 1) / std::sqrt(2.0), kUnit);
  EXPECT_EQ(p.moves[3].end_axis, Vec3::UnitX());
  EXPECT_INPUT_ERROR(read("GODLTA/1,2"), "GODLTA takes d, dx,dy,dz or dx,dy,dz,i,j,k (2 values");
}

TEST(CldataMotion, TlaxisIsNormalisedAndTheZeroVectorIsAnError) {
  const Toolpath p = read("TLAXIS/0,3,4\nGOTO/1,0,0");
  EXPECT_EQ(p.moves[0].start_axis, Vec3(0, 0.6, 0.8));
  EXPECT_EQ(p.moves[0].end_axis, Vec3(0, 0.6, 0.8));
  EXPECT_INPUT_ERROR(read("TLAXIS/0,0,0"), "t.cl:1:8: error: (0, 0, 0) is not a direction");
  EXPECT_INPUT_ERROR(read("TLAXIS/0,0,0.0001"), "is not a direction: its length is 0.0001");
  EXPECT_INPUT_ERROR(read("TLAXIS/1,2"), "TLAXIS takes i,j,k (2 values given)");
  EXPECT_INPUT_ERROR(read("TLAXIS/NORMPS"), "TLAXIS takes i,j,k: expected a number");
}

TEST(CldataMotion, MultaxGotoCarriesTheAxis) {
  const Toolpath p = read(
      "MULTAX/ON\n"
      "GOTO/0,0,0,0,0,1\n"
      "GOTO/10,0,0,0,3,4\n"
      "MULTAX/OFF\n"
      "GOTO/20,0,0\n"
      "GOTO/30,0,0,1,0,0\n"  // NX and Creo write the axis without MULTAX
      "MULTAX\n"
      "GOTO/30,0,0,0,0,-2\n");
  ASSERT_EQ(p.moves.size(), 5u);
  EXPECT_EQ(p.moves[0].start_axis, Vec3::UnitZ());
  EXPECT_EQ(p.moves[0].end_axis, Vec3::UnitZ());
  // Simultaneous 5-axis: the axis turns from the current one to the new one.
  EXPECT_EQ(p.moves[1].start_axis, Vec3::UnitZ());
  EXPECT_EQ(p.moves[1].end_axis, Vec3(0, 0.6, 0.8));
  EXPECT_NEAR(p.moves[1].axis_angle(), std::atan2(0.6, 0.8), 1e-15);
  EXPECT_EQ(p.moves[2].start_axis, Vec3(0, 0.6, 0.8));
  EXPECT_EQ(p.moves[2].end_axis, Vec3(0, 0.6, 0.8));
  EXPECT_EQ(p.moves[3].end_axis, Vec3::UnitX());
  EXPECT_EQ(p.moves[4].end_axis, -Vec3::UnitZ());
  EXPECT_EQ(p.moves[4].end, Vec3(30, 0, 0));
}

TEST(CldataMotion, MultaxErrors) {
  EXPECT_INPUT_ERROR(read("MULTAX/ON\nGOTO/1,2,3"),
                     "t.cl:2:1: error: GOTO takes x,y,z,i,j,k while MULTAX is on (3 values given)");
  EXPECT_INPUT_ERROR(read("MULTAX/SOMETIMES"), "t.cl:1:8: error: MULTAX takes ON or OFF");
  EXPECT_INPUT_ERROR(read("GOTO/0,0,0,0,0,0"), "t.cl:1:12: error: (0, 0, 0) is not a direction");
}

TEST(CldataMotion, MovesCarryFeedSpindleToolAndLine) {
  const Toolpath p =
      read("LOADTL/5\nSPINDL/2400,CCLW\nFEDRAT/MMPM,$\n$$ the feed follows\n  750\nGOTO/1,2,3\n");
  ASSERT_EQ(p.moves.size(), 1u);
  const Move& m = p.moves[0];
  EXPECT_EQ(m.tool, 5);
  EXPECT_EQ(m.spindle_speed, 2400.0);
  EXPECT_EQ(m.spindle, SpindleDirection::kCounterClockwise);
  EXPECT_EQ(m.feed_rate, 750.0);
  EXPECT_EQ(m.line, 6);
  EXPECT_EQ(m.source, 0);
}

// ------------------------------------------------------------------------------------------------
// Feeds and spindle.

TEST(CldataFeed, BothOrdersAndEveryUnit) {
  const auto feed_of = [](const std::string& records) {
    const Toolpath p = read(records + "\nGOTO/1,0,0\n");
    return p.moves.at(0).feed_rate;
  };
  EXPECT_EQ(feed_of("FEDRAT/250"), 250.0);
  EXPECT_EQ(feed_of("FEDRAT/250,MMPM"), 250.0);
  EXPECT_EQ(feed_of("FEDRAT/MMPM,250"), 250.0);
  EXPECT_DOUBLE_EQ(feed_of("FEDRAT/IPM,10"), 254.0);
  EXPECT_DOUBLE_EQ(feed_of("FEDRAT/10,IPM"), 254.0);
  EXPECT_DOUBLE_EQ(feed_of("UNITS/INCHES\nFEDRAT/10,PERMIN"), 254.0);
  EXPECT_DOUBLE_EQ(feed_of("FEDRAT/250,PERMIN"), 250.0);
  // Per revolution: times the spindle speed at the move.
  EXPECT_DOUBLE_EQ(feed_of("SPINDL/1000\nFEDRAT/0.1,MMPR"), 100.0);
  EXPECT_DOUBLE_EQ(feed_of("FEDRAT/IPR,0.01\nSPINDL/1000"), 254.0);
  EXPECT_DOUBLE_EQ(feed_of("UNITS/INCHES\nSPINDL/500\nFEDRAT/0.002,PERREV"), 25.4);
}

TEST(CldataFeed, MalformedFeeds) {
  EXPECT_INPUT_ERROR(read("FEDRAT/"), "t.cl:1:8: error: FEDRAT takes a feed and an optional unit");
  EXPECT_INPUT_ERROR(read("FEDRAT"), "t.cl:1:1: error: FEDRAT takes a feed");
  EXPECT_INPUT_ERROR(read("FEDRAT/FAST"),
                     "t.cl:1:8: error: FEDRAT takes a feed and an optional "
                     "unit (MMPM, IPM, PERMIN, MMPR, IPR, PERREV); found "
                     "'FAST'");
  EXPECT_INPUT_ERROR(read("FEDRAT/1,2"), "t.cl:1:10: error: FEDRAT takes");
  EXPECT_INPUT_ERROR(read("FEDRAT/MMPM,IPM,3"), "found 'IPM'");
  EXPECT_INPUT_ERROR(read("FEDRAT/-5"), "t.cl:1:8: error: the feed rate cannot be negative");
  EXPECT_INPUT_ERROR(read("FEDRAT/MMPM"), "t.cl:1:1: error: FEDRAT takes");
}

TEST(CldataFeed, FeedWarnings) {
  // A feed move before any FEDRAT: one warning, however many moves.
  const Toolpath a = read("GOTO/1,0,0\nGOTO/2,0,0\n");
  ASSERT_EQ(a.warnings.size(), 1u);
  EXPECT_EQ(a.warnings[0].location.line, 1);
  EXPECT_NE(a.warnings[0].message.find("before any FEDRAT"), std::string::npos);
  EXPECT_EQ(a.moves[1].feed_rate, 0.0);
  // Rapids need no feed.
  EXPECT_TRUE(read("RAPID\nGOTO/1,0,0\n").warnings.empty());
  // Feed per revolution with the spindle stopped.
  const Toolpath b = read("FEDRAT/0.1,MMPR\nGOTO/1,0,0\nGOTO/2,0,0\nSPINDL/100\nGOTO/3,0,0\n");
  ASSERT_EQ(b.warnings.size(), 1u);
  EXPECT_EQ(b.warnings[0].location.line, 2);
  EXPECT_DOUBLE_EQ(b.moves[2].feed_rate, 10.0);
}

TEST(CldataSpindle, SpeedsDirectionsOnAndOff) {
  const Toolpath p = read(
      "FEDRAT/100\nSPINDL/1200,CLW\nGOTO/1,0,0\n"
      "SPINDL/RPM,800,CCLW\nGOTO/2,0,0\n"
      "SPINDL/OFF\nGOTO/3,0,0\n"
      "SPINDL/ON\nGOTO/4,0,0\n"
      "SPINDL/500,RANGE,2\nGOTO/5,0,0\n"  // keeps the last direction
      "LOADTL/2\nCUTTER/10\n"
      "SPINDL/SMM,100,CLW,MAXRPM,8000\nGOTO/6,0,0\n"
      "SPINDL/CLW,SFM,100\nGOTO/7,0,0\n");
  ASSERT_EQ(p.moves.size(), 7u);
  const auto expect_spindle = [&](std::size_t i, double rpm, SpindleDirection direction) {
    SCOPED_TRACE(i);
    EXPECT_NEAR(p.moves[i].spindle_speed, rpm, 1e-9);
    EXPECT_EQ(p.moves[i].spindle, direction);
  };
  expect_spindle(0, 1200, SpindleDirection::kClockwise);
  expect_spindle(1, 800, SpindleDirection::kCounterClockwise);
  expect_spindle(2, 0, SpindleDirection::kStopped);
  expect_spindle(3, 800, SpindleDirection::kCounterClockwise);
  expect_spindle(4, 500, SpindleDirection::kCounterClockwise);
  // Surface speed over the tool's diameter: n = v / (π d).
  expect_spindle(5, 100.0 * 1000.0 / (kPi * 10.0), SpindleDirection::kClockwise);
  expect_spindle(6, 100.0 * 304.8 / (kPi * 10.0), SpindleDirection::kClockwise);
  EXPECT_TRUE(p.warnings.empty()) << p.warnings[0].message;
  // A first SPINDL without a direction turns clockwise (M3).
  EXPECT_EQ(read("SPINDL/900\nGOTO/1,0,0").moves[0].spindle, SpindleDirection::kClockwise);
}

TEST(CldataSpindle, MalformedSpindles) {
  EXPECT_INPUT_ERROR(read("SPINDL/"), "t.cl:1:1: error: SPINDL takes a speed");
  EXPECT_INPUT_ERROR(read("SPINDL/FAST"), "t.cl:1:8: error: SPINDL takes a speed");
  EXPECT_INPUT_ERROR(read("SPINDL/-5"), "the spindle speed cannot be negative");
  EXPECT_INPUT_ERROR(read("SPINDL/CLW"), "t.cl:1:1: error: SPINDL takes a speed");
  EXPECT_INPUT_ERROR(read("SPINDL/100,200"), "t.cl:1:12: error: SPINDL takes");
  // Surface speed without a tool diameter: a warning, speed 0.
  const Toolpath p = read("SPINDL/SFM,300\nGOTO/1,0,0");
  ASSERT_EQ(p.warnings.size(), 2u);  // and the feed move before any FEDRAT
  EXPECT_NE(p.warnings[0].message.find("surface speed cannot be converted"), std::string::npos);
  EXPECT_EQ(p.moves[0].spindle_speed, 0.0);
}

// ------------------------------------------------------------------------------------------------
// CIRCLE: arcs and helices.

TEST(CldataArc, QuarterArcIsCounterClockwiseAboutAPositiveNormal) {
  const Toolpath p = read("FROM/10,0,0\nCIRCLE/0,0,0,0,0,1,10\nGOTO/0,10,0\n");
  ASSERT_EQ(p.moves.size(), 1u);
  const Move& m = p.moves[0];
  ASSERT_TRUE(m.is_arc());
  EXPECT_EQ(m.line, 3);
  EXPECT_EQ(m.start, Vec3(10, 0, 0));
  EXPECT_EQ(m.end, Vec3(0, 10, 0));
  expect_point(m.position(1.0), Vec3(0, 10, 0), kTight);
  expect_point(m.position(0.5), Vec3(1, 1, 0) * (10 / std::sqrt(2.0)), kTight);
  EXPECT_EQ(m.normal, Vec3::UnitZ());
  expect_point(m.center, Vec3::Zero(), kTight);
  EXPECT_NEAR(m.radius(), 10.0, kTight);
  EXPECT_NEAR(m.sweep, kPi / 2, 1e-15);
  EXPECT_EQ(m.axial, 0.0);
  EXPECT_EQ(m.extra_turns(), 0);
}

TEST(CldataArc, NegativeNormalTravelsClockwise) {
  const Toolpath p = read("FROM/10,0,0\nCIRCLE/0,0,0,0,0,-1,10\nGOTO/0,10,0\n");
  const Move& m = p.moves.at(0);
  EXPECT_EQ(m.normal, -Vec3::UnitZ());
  EXPECT_NEAR(m.sweep, 3 * kPi / 2, 1e-15);
  expect_point(m.position(1.0), Vec3(0, 10, 0), kTight);
  expect_point(m.position(1.0 / 3.0), Vec3(0, -10, 0), kTight);  // through -Y: clockwise
  EXPECT_NEAR(m.length(), 15 * kPi, kTight);
}

TEST(CldataArc, ArcInAVerticalPlane) {
  // About +Y, counter-clockwise: +X turns towards -Z.
  const Toolpath p = read(
      "FROM/10,0,0\nCIRCLE/0,0,0,0,1,0,10\nGOTO/0,0,-10\nCIRCLE/0,0,0,0,1,0,10\nGOTO/0,0,10\n");
  ASSERT_EQ(p.moves.size(), 2u);
  EXPECT_NEAR(p.moves[0].sweep, kPi / 2, 1e-15);
  expect_point(p.moves[0].position(0.5), Vec3(1, 0, -1) * (10 / std::sqrt(2.0)), kTight);
  EXPECT_NEAR(p.moves[1].sweep, kPi, 1e-15);
  expect_point(p.moves[1].position(0.5), Vec3(-10, 0, 0), kTight);  // -Z turns towards -X
  expect_point(p.moves[1].position(1.0), Vec3(0, 0, 10), kTight);
}

TEST(CldataArc, StartEqualToEndIsAFullCircle) {
  const Toolpath p = read("FROM/10,0,0\nCIRCLE/0,0,0,0,0,1,10\nGOTO/10,0,0\n");
  const Move& m = p.moves.at(0);
  EXPECT_EQ(m.sweep, kTwoPi);
  EXPECT_EQ(m.extra_turns(), 0);
  expect_point(m.position(0.25), Vec3(0, 10, 0), kTight);
  expect_point(m.position(1.0), Vec3(10, 0, 0), kTight);
  EXPECT_NEAR(m.length(), 20 * kPi, kTight);
}

TEST(CldataArc, HelixAdvancesAlongTheNormal) {
  // The CIRCLE's centre height does not matter: the arc is about its axis line.
  const Toolpath p = read("FROM/10,0,0\nCIRCLE/0,0,5,0,0,1,10\nGOTO/0,10,-2\n");
  const Move& m = p.moves.at(0);
  expect_point(m.center, Vec3::Zero(), kTight);  // at the start's height
  EXPECT_NEAR(m.axial, -2.0, kTight);
  EXPECT_NEAR(m.sweep, kPi / 2, 1e-15);
  expect_point(m.position(1.0), Vec3(0, 10, -2), kTight);
  expect_point(m.position(0.5), Vec3(10 / std::sqrt(2.0), 10 / std::sqrt(2.0), -1), kTight);
}

TEST(CldataArc, CreoThreadMillingExample) {
  // PTC Creo help, "CL Output for Circular Interpolation", helical interpolation sample (inch):
  // two full orbits, each rising one pitch (1/24 in), right-hand rule about +Z.
  const Toolpath p = read(
      "UNITS/INCHES\n"
      "FEDRAT / 12.000000, IPM\n"
      "GOTO / 8.198000, 0.000000, -.625000\n"
      "FEDRAT / 8.000000, IPM\n"
      "CIRCLE / 8.000000, 0.000000, -0.625000, $ $$ 1ST ORBIT\n"
      "0.000000, 0.000000, 1.000000, 0.198000\n"
      "GOTO / 8.198000, 0.000000, -0.583333\n"
      "CIRCLE / 8.000000, 0.000000, -0.583333, $ $$ 2ND ORBIT\n"
      "0.000000, 0.000000, 1.000000, 0.198000\n"
      "GOTO / 8.198000, 0.000000, -0.541667\n"
      "FEDRAT / 12.000000, IPM\n");
  ASSERT_EQ(p.moves.size(), 3u);
  for (int orbit = 1; orbit <= 2; ++orbit) {
    SCOPED_TRACE(orbit);
    const Move& m = p.moves[orbit];
    ASSERT_TRUE(m.is_arc());
    EXPECT_EQ(m.line, orbit == 1 ? 7 : 10);
    EXPECT_EQ(m.sweep, kTwoPi);
    EXPECT_DOUBLE_EQ(m.feed_rate, 8 * 25.4);
    EXPECT_NEAR(m.radius(), 0.198 * 25.4, kTight);
    EXPECT_NEAR(m.axial, (orbit == 1 ? 0.041667 : 0.041666) * 25.4, kTight);
    expect_point(m.position(1.0), m.end, kTight);
    // A quarter orbit later the tool is on the +Y side: counter-clockwise seen from +Z.
    const Vec3 quarter = m.position(0.25);
    EXPECT_NEAR(quarter.x(), 8.0 * 25.4, kTight);
    EXPECT_NEAR(quarter.y(), 0.198 * 25.4, kTight);
  }
  EXPECT_TRUE(p.warnings.empty());
}

TEST(CldataArc, TimesAddsFullTurns) {
  // NX's helix form CIRCLE/x,y,z,i,j,k,r,t,f,d,e,TIMES,n: n turns begun, here 1½ turns.
  const Toolpath p =
      read("FROM/1,0,0\nCIRCLE/0,0,-2.475,0,0,1,1,0.002,0.5,1,0,TIMES,2\nGOTO/-1,0,-2.475\n");
  const Move& m = p.moves.at(0);
  EXPECT_NEAR(m.sweep, 3 * kPi, 1e-14);
  EXPECT_EQ(m.extra_turns(), 1);
  EXPECT_NEAR(m.axial, -2.475, kTight);
  expect_point(m.position(1.0), Vec3(-1, 0, -2.475), kTight);
  // With the start and end at the same angle, n full turns.
  const Toolpath q = read("FROM/1,0,0\nCIRCLE/0,0,0,0,0,1,1,TIMES,3\nGOTO/1,0,-3\n");
  EXPECT_NEAR(q.moves.at(0).sweep, 3 * kTwoPi, 1e-14);
  EXPECT_EQ(q.moves.at(0).extra_turns(), 2);
}

TEST(CldataArc, NxClsfAxisGivesClockwiseTravel) {
  // NX documents its CIRCLE axis "assuming a clockwise direction"; a program is NX CLSF when it
  // has TOOL PATH/ records.
  const std::string body =
      "TLDATA/MILL,10.0000,0.0000,75.0000,0.0000,0.0000\n"
      "MSYS/0.0000,0.0000,0.0000,1.0000000,0.0000000,0.0000000,0.0000000,1.0000000,0.0000000\n"
      "$$ centerline data\n"
      "PAINT/PATH\n"
      "RAPID\n"
      "GOTO/10.0000,0.0000,0.0000\n"
      "PAINT/COLOR,31\n"
      "FEDRAT/MMPM,250.0000\n"
      "CIRCLE/0.0000,0.0000,0.0000,0.0000000,0.0000000,1.0000000,10.0000,0.0600,0.5000,"
      "10.0000,0.0000\n"
      "GOTO/0.0000,10.0000,0.0000\n"
      "END-OF-PATH\n";
  const Toolpath nx = read("TOOL PATH/PLANAR_MILL,TOOL,D10\n" + body);
  ASSERT_EQ(nx.moves.size(), 2u);
  EXPECT_EQ(nx.moves[1].normal, -Vec3::UnitZ());
  EXPECT_NEAR(nx.moves[1].sweep, 3 * kPi / 2, 1e-15);
  expect_point(nx.moves[1].position(1.0 / 3.0), Vec3(0, -10, 0), kTight);
  ASSERT_EQ(nx.warnings.size(), 1u);  // TLDATA only; the identity MSYS is quiet
  EXPECT_EQ(nx.warnings[0].location.line, 2);
  // The same records without TOOL PATH/: the APT right-hand rule.
  const Toolpath apt = read(body);
  EXPECT_EQ(apt.moves.at(1).normal, Vec3::UnitZ());
  EXPECT_NEAR(apt.moves.at(1).sweep, kPi / 2, 1e-15);
}

TEST(CldataArc, EndsMustLieOnTheCircle) {
  EXPECT_INPUT_ERROR(read("FROM/10,0,0\nCIRCLE/0,0,0,0,0,1,10\nGOTO/0,10.01,0"),
                     "t.cl:3:1: error: the arc of the CIRCLE at line 2 ends at (0, 10.01, 0) mm, "
                     "10.01 mm from its axis, not on the circle of radius 10 mm");
  EXPECT_INPUT_ERROR(read("FROM/10.01,0,0\nCIRCLE/0,0,0,0,0,1,10\nGOTO/0,10,0"),
                     "t.cl:2:1: error: the arc starts at (10.01, 0, 0) mm, 10.01 mm from the axis");
  // In inches the tolerance is 2e-4 in: 0.01 in off is refused, 1e-4 in accepted.
  EXPECT_INPUT_ERROR(read("UNITS/INCHES\nFROM/1,0,0\nCIRCLE/0,0,0,0,0,1,1\nGOTO/0,1.01,0"),
                     "t.cl:4:1: error: the arc of the CIRCLE at line 3 ends");
  EXPECT_NO_THROW(read("UNITS/INCHES\nFROM/1,0,0\nCIRCLE/0,0,0,0,0,1,1\nGOTO/0,1.0001,0"));
}

TEST(CldataArc, EndsWithinTheToleranceAreKeptExactly) {
  // Written with rounding: the start is 1e-4 mm outside the circle, the end 1e-4 mm inside. The
  // centre moves onto the chord's bisector so that the move still starts and ends exactly there.
  const Toolpath p = read("FROM/10.0001,0,0\nCIRCLE/0,0,0,0,0,1,10\nGOTO/0,9.9999,0\n");
  const Move& m = p.moves.at(0);
  expect_point(m.position(0.0), Vec3(10.0001, 0, 0), kTight);
  expect_point(m.position(1.0), Vec3(0, 9.9999, 0), kTight);
  EXPECT_NEAR(m.radius(), 10.0, 2e-4);
  EXPECT_NEAR(m.sweep, kPi / 2, 2e-5);  // the bisector turns the chord's ends by ~1e-5 rad
}

TEST(CldataArc, CircleMustBeFollowedByTheGotoThatEndsIt) {
  EXPECT_INPUT_ERROR(read("CIRCLE/0,0,0,0,0,1,10"),
                     "t.cl:1:1: error: CIRCLE is not followed by the GOTO that ends the arc");
  EXPECT_INPUT_ERROR(read("CIRCLE/0,0,0,0,0,1,10\nFINI\n"), "t.cl:1:1: error: CIRCLE is not");
  EXPECT_INPUT_ERROR(read("FROM/10,0,0\nCIRCLE/0,0,0,0,0,1,10\nGODLTA/1,0,0"),
                     "t.cl:3:1: error: GODLTA follows the CIRCLE at line 2, which must be "
                     "followed by the GOTO that ends the arc");
  EXPECT_INPUT_ERROR(read("CIRCLE/0,0,0,0,0,1,10\nCIRCLE/0,0,0,0,0,1,10"),
                     "t.cl:2:1: error: CIRCLE follows the CIRCLE at line 1");
  // Other records may stand between them.
  const Toolpath p =
      read("FROM/10,0,0\nCIRCLE/0,0,0,0,0,1,10\nFEDRAT/100\nPAINT/COLOR,3\nGOTO/0,10,0\n");
  EXPECT_TRUE(p.moves.at(0).is_arc());
  EXPECT_EQ(p.moves.at(0).feed_rate, 100.0);
}

TEST(CldataArc, MalformedCircles) {
  EXPECT_INPUT_ERROR(read("CIRCLE/0,0,0,0,0,1"),
                     "t.cl:1:18: error: CIRCLE takes xc,yc,zc,i,j,k,r and optional values "
                     "(6 given)");
  EXPECT_INPUT_ERROR(read("CIRCLE"), "t.cl:1:1: error: CIRCLE takes xc,yc,zc,i,j,k,r");
  EXPECT_INPUT_ERROR(read("CIRCLE/0,0,0,0,0,0,10"), "t.cl:1:14: error: (0, 0, 0) is not a");
  EXPECT_INPUT_ERROR(read("CIRCLE/0,0,0,0,0,1,0"),
                     "t.cl:1:20: error: the circle radius must be positive, found '0'");
  EXPECT_INPUT_ERROR(read("CIRCLE/0,0,0,0,0,1,-5"), "the circle radius must be positive");
  EXPECT_INPUT_ERROR(read("CIRCLE/0,0,0,0,0,1,5,FOO"), "t.cl:1:22: error: CIRCLE takes");
  EXPECT_INPUT_ERROR(read("CIRCLE/0,0,0,0,0,1,5,TIMES,0"),
                     "CIRCLE TIMES: expected a whole number from 1 to 10000, found '0'");
  EXPECT_INPUT_ERROR(read("CIRCLE/0,0,0,0,0,1,5,TIMES,1.5"), "expected a whole number");
  EXPECT_INPUT_ERROR(read("CIRCLE/0,0,X,0,0,1,5"), "t.cl:1:12: error: expected a number");
}

TEST(CldataArc, PointsOnLinesOfTheirOwnContinueTheGoto) {
  // Creo (POINTS_&_ARC): the GOTO after CIRCLE and the bare points after it lie on the arc.
  const Toolpath p = read(
      "FROM/10,0,0\n"
      "CIRCLE/0,0,0,0,0,1,10\n"
      "GOTO/7.0710678,7.0710678,0\n"
      "0,10,0\n"
      "-10,0,0\n"
      "GOTO/-10,0,5\n");
  ASSERT_EQ(p.moves.size(), 4u);
  const double sweeps[] = {kPi / 4, kPi / 4, kPi / 2};
  for (int i = 0; i < 3; ++i) {
    SCOPED_TRACE(i);
    ASSERT_TRUE(p.moves[i].is_arc());
    EXPECT_EQ(p.moves[i].line, 3 + i);
    // The written point is rounded to 7 decimals: 1e-7 mm off the circle, 1e-8 rad.
    EXPECT_NEAR(p.moves[i].sweep, sweeps[i], 1e-7);
    expect_point(p.moves[i].position(1.0), p.moves[i].end, kTight);
  }
  EXPECT_FALSE(p.moves[3].is_arc());
  // After a line GOTO the points are lines; after anything else they are an error.
  const Toolpath lines = read("RAPID\nGOTO/1,0,0\n2,0,0\n3,0,0,0,1,0\nGOTO/4,0,0\n");
  ASSERT_EQ(lines.moves.size(), 4u);
  EXPECT_TRUE(lines.moves[2].is_rapid());  // the points share their GOTO's RAPID
  EXPECT_FALSE(lines.moves[3].is_rapid());
  EXPECT_EQ(lines.moves[2].end_axis, Vec3::UnitY());
  EXPECT_INPUT_ERROR(read("GOTO/1,0,0\nFEDRAT/10\n2,0,0\n"),
                     "t.cl:3:1: error: numbers without a major word");
}

TEST(CldataArc, FiveAxisArcTurnsTheAxis) {
  const Toolpath p = read("FROM/10,0,0,0,0,1\nCIRCLE/0,0,0,0,0,1,10\nGOTO/0,10,0,0,1,1\n");
  const Move& m = p.moves.at(0);
  EXPECT_TRUE(m.is_arc());
  EXPECT_EQ(m.start_axis, Vec3::UnitZ());
  expect_point(m.end_axis, Vec3(0, 1, 1) / std::sqrt(2.0), kUnit);
  expect_point(m.axis(1.0), Vec3(0, 1, 1) / std::sqrt(2.0), 1e-12);
}

TEST(CldataArc, RapidArc) {
  const Toolpath p = read("FROM/10,0,0\nRAPID\nCIRCLE/0,0,0,0,0,1,10\nGOTO/0,10,0\n");
  EXPECT_TRUE(p.moves.at(0).is_rapid());
  EXPECT_TRUE(p.moves.at(0).is_arc());
}

// Oracle: arcs and helices in random planes, built with Move::position, written with 7
// decimals (as CAM systems write them) and read back.
TEST(CldataArc, RandomArcsRoundTrip) {
  test::Random random(42);
  for (int trial = 0; trial < 300; ++trial) {
    SCOPED_TRACE(trial);
    Move oracle;
    oracle.shape = MoveShape::kArc;
    oracle.normal = random.unit_vector();
    const double radius = random.uniform(1.0, 50.0);
    const Vec3 c = random.point_in_box(100.0);
    const Vec3 any = std::abs(oracle.normal.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
    const Vec3 radial = (any - oracle.normal * oracle.normal.dot(any)).normalized();
    oracle.center = c;
    const Eigen::AngleAxisd turn(random.uniform(0.0, kTwoPi), oracle.normal);
    oracle.start = c + radius * (turn * radial);
    const int turns = random.integer(1, 3);
    oracle.sweep = random.uniform(0.05, kTwoPi - 0.05) + kTwoPi * (turns - 1);
    oracle.axial = random.integer(0, 1) == 0 ? 0.0 : random.uniform(-5.0, 5.0);
    oracle.end = oracle.position(1.0);
    const Vec3& s = oracle.start;
    const Vec3& e = oracle.end;
    const Vec3& n = oracle.normal;
    const std::string text = fmt::format(
        "FROM/{:.7f},{:.7f},{:.7f}\nCIRCLE/{:.7f},{:.7f},{:.7f},{:.9f},{:.9f},{:.9f},{:.7f}"
        ",TIMES,{}\nGOTO/{:.7f},{:.7f},{:.7f}\n",
        s.x(), s.y(), s.z(), c.x(), c.y(), c.z(), n.x(), n.y(), n.z(), radius, turns, e.x(), e.y(),
        e.z());
    const Toolpath p = read(text);
    ASSERT_EQ(p.moves.size(), 1u);
    const Move& m = p.moves[0];
    ASSERT_TRUE(m.is_arc());
    // Written coordinates are off by up to 5e-8 mm per component and the normal by 5e-10: the
    // ends are ~1e-7 mm off the circle, so the sweep and the advance are off by ~1e-7. Moving
    // the centre onto the chord's bisector shifts it by ~1e-7 / θ ≤ 2e-6 mm (θ ≥ 0.05 here),
    // and the arc's points with it (worst seen: sweep 6e-8, axial 1.3e-7, points 1.5e-6 mm).
    EXPECT_NEAR(m.sweep, oracle.sweep, 1e-6);
    EXPECT_NEAR(m.axial, oracle.axial, 1e-6);
    EXPECT_EQ(m.extra_turns(), oracle.extra_turns());
    expect_point(m.position(1.0), m.end, 1e-9);  // exact up to rounding of ~1e2 mm values
    for (double u : {0.0, 0.25, 0.5, 0.75, 1.0})
      expect_point(m.position(u), oracle.position(u), 1e-5);
  }
}

// ------------------------------------------------------------------------------------------------
// Warnings and known records.

TEST(CldataWarnings, UnknownWordsAreReportedOnceEachWithTheirLine) {
  const Toolpath p = read("PARTNO TEST\nFOO/1,2\nGOTO/1,0,0\nBAR\nAUXFUN/3\nFOO/3\n");
  ASSERT_EQ(p.warnings.size(), 5u);  // FOO, feed before FEDRAT, BAR, AUXFUN, FOO
  const std::vector<std::pair<int, std::string>> expected = {
      {2, "unknown record FOO ignored"},
      {3, "feed move before any FEDRAT: its feed rate is 0"},
      {4, "unknown record BAR ignored"},
      {5, "unknown record AUXFUN ignored"},
      {6, "unknown record FOO ignored"}};
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(p.warnings[i].location.source, "t.cl");
    EXPECT_EQ(p.warnings[i].location.line, expected[i].first);
    EXPECT_EQ(p.warnings[i].location.column, 1);
    EXPECT_EQ(p.warnings[i].message, expected[i].second);
  }
  EXPECT_EQ(p.moves.size(), 1u);
}

TEST(CldataWarnings, KnownNonGeometricRecordsAreQuiet) {
  const Toolpath p = read(
      "COOLNT/ON\nINTOL/0.01\nOUTTOL/0.01\nTOLER/0.01\nSELECT/TOOL,2\nOPSKIP/ON\nOPSTOP\n"
      "END\nSTOP\nDISPLY/ON\nCLRSRF/Z,50\nSET/MODE,ABSOL\nCYCLE/OFF\nCUTCOM/OFF\n"
      "MACHIN/UNCX01,1\nDELAY/2\nPAINT/COLOR,186\nTOOL PATH/OP1,TOOL,T1\nEND-OF-PATH\n"
      "FEDRAT/100\nGOTO/1,0,0\nMSYS/0,0,0,1,0,0,0,1,0\n");
  EXPECT_TRUE(p.warnings.empty()) << p.warnings[0].message;
  EXPECT_EQ(p.moves.size(), 1u);
}

TEST(CldataWarnings, RecordsThatWouldChangeTheGeometryWarn) {
  const Toolpath p = read(
      "CUTCOM/LEFT,1\n"
      "CYCLE/DRILL,10,FEDTO,-5\n"
      "RAPID\nGOTO/0,0,0\n"
      "CYCLE/OFF\n"
      "MSYS/10,0,0,1,0,0,0,1,0\n"
      "TLDATA/MILL,10,0,75,0,0\n"
      "LOAD/SPINDLE,1\n");
  ASSERT_EQ(p.warnings.size(), 5u);
  const int lines[] = {1, 2, 6, 7, 8};
  const char* fragments[] = {"CUTCOM: cutter compensation is not applied",
                             "CYCLE/DRILL: canned cycles are not expanded", "MSYS: positions",
                             "TLDATA (NX tool data) is not read", "LOAD/ without TOOL"};
  for (int i = 0; i < 5; ++i) {
    EXPECT_EQ(p.warnings[i].location.line, lines[i]);
    EXPECT_NE(p.warnings[i].message.find(fragments[i]), std::string::npos) << p.warnings[i].message;
  }
}

TEST(CldataWarnings, RecordsAfterFiniAreCountedOnce) {
  const Toolpath p = read("RAPID\nGOTO/1,0,0\nFINI\nGOTO/2,0,0\nFOO\n  garbage ,, \nGOTO/1,$\n");
  EXPECT_EQ(p.moves.size(), 1u);
  ASSERT_EQ(p.warnings.size(), 1u);
  EXPECT_EQ(p.warnings[0].location.line, 4);
  EXPECT_EQ(p.warnings[0].message, "4 records after FINI ignored");
  EXPECT_TRUE(read("RAPID\nGOTO/1,0,0\nFINI\n$$ the end\n").warnings.empty());
}

// ------------------------------------------------------------------------------------------------
// Malformed input: an InputError or warnings, never a crash.

TEST(CldataMalformed, EmptyAndCommentOnlyFiles) {
  for (const char* text : {"", "\n\n", "   \t\n", "$$ only a comment\n$$ and another", "\r\n"}) {
    const Toolpath p = read(text);
    EXPECT_TRUE(p.moves.empty());
    EXPECT_TRUE(p.warnings.empty());
    EXPECT_EQ(p.sources, std::vector<std::string>{"t.cl"});
  }
}

TEST(CldataMalformed, BinaryBytes) {
  EXPECT_INPUT_ERROR(read(std::string("\x00\x01\x02GOTO/1,2,3", 14)),
                     "t.cl:1:1: error: expected a record such as GOTO/x,y,z, found "
                     "'\\x00\\x01\\x02GOTO'");
  EXPECT_INPUT_ERROR(read("GOTO/1,\xff\xfe,3"), "expected a number, found '\\xFF\\xFE'");
}

TEST(CldataMalformed, EveryPrefixOfAProgramReadsOrFailsCleanly) {
  const std::string program =
      "PARTNO T\nUNITS/MM\nCUTTER/10,1,4,1,0,0,50\nLOADTL/1\nSPINDL/3000,CLW\nMULTAX/ON\n"
      "FROM/0,0,50,0,0,1\nRAPID\nGOTO/10,0,5,0,0,1\nFEDRAT/200,MMPM\nGOTO/10,0,-1,0,0,1\n"
      "CIRCLE/0,0,-1,0,0,1,10,$\n0.01,0.5,10,1\nGOTO/0,10,-1,0,0.1,1\nGODLTA/0,0,5\nFINI\n";
  int read_count = 0;
  for (std::size_t n = 0; n <= program.size(); ++n) {
    if (test::read_or_input_error(read_program, program.substr(0, n))) ++read_count;
  }
  EXPECT_GT(read_count, 0);
  EXPECT_TRUE(test::read_or_input_error(read_program, program));
}

TEST(CldataMalformed, RandomBytesAndTokens) {
  test::Random random(7);
  const std::vector<std::string> tokens = {
      "GOTO/",   "CIRCLE/", "FROM/",   "GODLTA/", "TLAXIS/",      "MULTAX", "RAPID",
      "FEDRAT/", "SPINDL/", "CUTTER/", "LOADTL/", "UNITS/INCHES", "FINI",   "TIMES",
      ",",       ",",       ",",       "$",       "$$",           "\n",     "\n",
      " ",       "/",       "0",       "1",       "-1",           "10",     ".5",
      "1e9",     "1e999",   "-0",      "1E-3",    "ON",           "OFF",    "MMPM",
      "IPR",     "CLW",     "\r",      "\x01",    "\xff",         "PARTNO", "TOOL PATH/"};
  int errors = 0;
  for (int trial = 0; trial < 3000; ++trial) {
    std::string text;
    const int length = random.integer(0, 60);
    if (trial % 3 == 0) {
      for (int i = 0; i < length * 3; ++i) text += static_cast<char>(random.integer(0, 255));
    } else {
      for (int i = 0; i < length; ++i)
        text += tokens[random.integer(0, static_cast<int>(tokens.size()) - 1)];
    }
    if (!test::read_or_input_error(read_program, text)) ++errors;
  }
  EXPECT_GT(errors, 0);  // the generator does reach the error paths
}

TEST(CldataMalformed, MutatedSampleProgram) {
  const std::string program =
      "UNITS/MM\nLOADTL/1\nCUTTER/10\nSPINDL/1000\nFEDRAT/100\nFROM/10,0,0\n"
      "CIRCLE/0,0,0,0,0,1,10\nGOTO/0,10,0\nGOTO/0,10,5,0,1,1\nGODLTA/0,0,0,0,0,1\n"
      "CIRCLE/0,0,5,0,0,-1,10\nGOTO/10,0,5\nGODLTA/-2\n";
  ASSERT_TRUE(test::read_or_input_error(read_program, program));
  test::Random random(11);
  const std::string alphabet = "0123456789.,-+/$E \nGOTOCIRCLE";
  for (int trial = 0; trial < 3000; ++trial) {
    std::string text = program;
    for (int k = random.integer(1, 4); k > 0; --k) {
      const auto at =
          static_cast<std::size_t>(random.integer(0, static_cast<int>(text.size()) - 1));
      const char c = alphabet[static_cast<std::size_t>(
          random.integer(0, static_cast<int>(alphabet.size()) - 1))];
      switch (random.integer(0, 2)) {
        case 0:
          text[at] = c;
          break;
        case 1:
          text.insert(at, 1, c);
          break;
        default:
          text.erase(at, 1);
          break;
      }
    }
    test::read_or_input_error(read_program, text);
  }
}

// ------------------------------------------------------------------------------------------------
// Files.

TEST(CldataFile, CatiaStyleContour) {
  const std::string path = source_dir() + "/tests/toolpath/data/contour_catia.aptsource";
  const Toolpath p = read_cldata_file(path);
  EXPECT_EQ(p.sources, std::vector<std::string>{path});
  EXPECT_TRUE(p.warnings.empty()) << p.warnings[0].message;
  ASSERT_EQ(p.moves.size(), 15u);
  EXPECT_EQ(to_string(p.tool_definitions.at(1)), "CUTTER/10,1,4,1,0,0,50");
  int arcs = 0;
  double arc_length = 0.0;
  double line_feed_length = 0.0;
  for (std::size_t i = 0; i < p.moves.size(); ++i) {
    const Move& m = p.moves[i];
    EXPECT_EQ(m.tool, 1);
    EXPECT_EQ(m.spindle_speed, 3000.0);
    if (i > 0) expect_point(m.start, p.moves[i - 1].end, kTight);  // a continuous path
    if (m.is_arc()) {
      ++arcs;
      arc_length += m.length();
      EXPECT_NEAR(m.sweep, kPi / 2, 1e-15);
      EXPECT_NEAR(m.radius(), 10.0, kTight);
      EXPECT_EQ(m.normal, Vec3::UnitZ());
      EXPECT_EQ(m.feed_rate, 1000.0);
    } else if (!m.is_rapid() && m.feed_rate == 1000.0) {
      line_feed_length += m.length();
    }
  }
  EXPECT_EQ(arcs, 4);
  EXPECT_NEAR(arc_length, 20 * kPi, kTight);
  EXPECT_NEAR(line_feed_length, 160.0, kTight);
  EXPECT_TRUE(p.moves[0].is_rapid());
  EXPECT_EQ(p.moves[0].start, Vec3(0, 0, 100));  // from FROM
  EXPECT_EQ(p.moves[2].feed_rate, 300.0);
  // The tilted pass: the axis turns from +Z to 30° about +Y, then stays.
  EXPECT_NEAR(p.moves[12].axis_angle(), kPi / 6, 1e-6);
  EXPECT_NEAR(p.moves[13].axis_angle(), 0.0, 1e-15);
  EXPECT_EQ(p.moves[12].feed_rate, 800.0);
  EXPECT_EQ(p.moves[12].line, 50);
}

TEST(CldataFile, NxStyleHelicalHole) {
  const std::string path = source_dir() + "/tests/toolpath/data/hole_nx.cls";
  const Toolpath p = read_cldata_file(path);
  ASSERT_EQ(p.moves.size(), 5u);
  ASSERT_EQ(p.warnings.size(), 1u);  // TLDATA is not read
  EXPECT_EQ(p.warnings[0].location.line, 2);
  EXPECT_TRUE(p.tool_definitions.empty());
  const Move& ramp = p.moves[2];
  const Move& finish = p.moves[3];
  ASSERT_TRUE(ramp.is_arc());
  // NX axis 0,0,-1: counter-clockwise seen from +Z.
  EXPECT_EQ(ramp.normal, Vec3::UnitZ());
  EXPECT_NEAR(ramp.sweep, 2 * kTwoPi, 1e-14);  // TIMES,2 from and to the same angle
  EXPECT_NEAR(ramp.axial, -4.0, kTight);
  EXPECT_NEAR(ramp.length(), std::hypot(6.0 * 2 * kTwoPi, 4.0), kTight);
  EXPECT_EQ(ramp.feed_rate, 400.0);
  EXPECT_EQ(ramp.line, 22);
  EXPECT_EQ(finish.sweep, kTwoPi);
  EXPECT_EQ(finish.axial, 0.0);
  EXPECT_EQ(finish.feed_rate, 800.0);
  for (const Move& m : p.moves) {
    EXPECT_EQ(m.tool, 4);
    EXPECT_EQ(m.spindle_speed, 6000.0);
    EXPECT_EQ(m.spindle, SpindleDirection::kClockwise);
  }
  EXPECT_TRUE(p.moves[4].is_rapid());
}

TEST(CldataFile, MissingFile) {
  EXPECT_INPUT_ERROR(read_cldata_file("/nonexistent/program.cl"),
                     "/nonexistent/program.cl: error: cannot open the CLDATA file");
}

}  // namespace
}  // namespace cwe

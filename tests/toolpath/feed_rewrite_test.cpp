#include "cwe/toolpath/feed_rewrite.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "cwe/core/error.hpp"
#include "cwe/toolpath/cldata_reader.hpp"
#include "cwe/toolpath/gcode_reader.hpp"
#include "random.hpp"

namespace cwe {
namespace {

// A new feed is rounded down to the program's precision: at worst (F words without decimals in an
// inch program) to 0.1 in/min, 2.54 mm/min, below the feed asked for. A feed restored in other
// units than its F word is within 0.5e-5 in/min = 1.3e-4 mm/min, below 1e-6 relative for the
// feeds ≥ 127 mm/min such tests use.
constexpr double kListedStep = 2.54;
constexpr double kFeedRelative = 1e-6;

std::vector<std::string> split_lines(std::string_view text) {
  std::vector<std::string> lines;
  std::size_t begin = 0;
  while (begin < text.size()) {
    std::size_t end = text.find('\n', begin);
    if (end == std::string_view::npos) end = text.size();
    lines.emplace_back(text.substr(begin, end - begin));
    begin = end + 1;
  }
  return lines;
}

// `rewritten` reads as `original` but for the feeds: the same moves in the same order (shape,
// mode, positions, axes, arc geometry, spindle, tool), the feed moves of a listed line at its new
// feed (never above it, at most kListedStep below), every other move at its old feed (exactly,
// or within `unlisted_relative`). The line of each move is `line_of` of the original one.
void expect_feeds_rewritten(const Toolpath& original, const Toolpath& rewritten,
                            const LineFeeds& feeds, const std::function<int(int)>& line_of,
                            double unlisted_relative = 0.0) {
  ASSERT_EQ(original.moves.size(), rewritten.moves.size());
  for (std::size_t i = 0; i < original.moves.size(); ++i) {
    const Move& a = original.moves[i];
    const Move& b = rewritten.moves[i];
    SCOPED_TRACE(fmt::format("move {} of line {}", i, a.line));
    EXPECT_EQ(b.line, line_of(a.line));
    EXPECT_EQ(a.shape, b.shape);
    EXPECT_EQ(a.mode, b.mode);
    EXPECT_EQ(a.start, b.start);
    EXPECT_EQ(a.end, b.end);
    EXPECT_EQ(a.start_axis, b.start_axis);
    EXPECT_EQ(a.end_axis, b.end_axis);
    EXPECT_EQ(a.center, b.center);
    EXPECT_EQ(a.normal, b.normal);
    EXPECT_EQ(a.sweep, b.sweep);
    EXPECT_EQ(a.axial, b.axial);
    EXPECT_EQ(a.spindle_speed, b.spindle_speed);
    EXPECT_EQ(a.spindle, b.spindle);
    EXPECT_EQ(a.tool, b.tool);
    const auto listed = feeds.find(a.line);
    if (a.is_rapid()) {
      EXPECT_EQ(b.feed_rate, 0.0);
    } else if (listed != feeds.end()) {
      EXPECT_LE(b.feed_rate, listed->second * (1.0 + 1e-12));
      EXPECT_GE(b.feed_rate, listed->second - kListedStep);
    } else {
      EXPECT_NEAR(b.feed_rate, a.feed_rate, unlisted_relative * a.feed_rate);
    }
  }
}

// ---------------------------------------------------------------------------------------------
// G-code

Toolpath gcode(std::string_view text, const GcodeOptions& options = {}) {
  return read_gcode(text, "t.ngc", options);
}

std::string rewrite_gcode(std::string_view text, const LineFeeds& feeds,
                          const GcodeOptions& options = {}) {
  return rewrite_feeds(text, ToolpathFormat::kGcode, feeds, "t.ngc", FeedRewriteOptions{options});
}

// Rewrites, checks the round trip (G-code keeps every line where it was) and returns the text.
std::string rewrite_gcode_checked(std::string_view text, const LineFeeds& feeds,
                                  const GcodeOptions& options = {},
                                  double unlisted_relative = 0.0) {
  const std::string out = rewrite_gcode(text, feeds, options);
  EXPECT_EQ(split_lines(out).size(), split_lines(text).size());
  expect_feeds_rewritten(
      gcode(text, options), gcode(out, options), feeds, [](int line) { return line; },
      unlisted_relative);
  return out;
}

TEST(FeedRewriteGcode, ReplacesTheFWordAndKeepsEverythingElse) {
  const std::string text =
      "%\n"
      "(program F100 header)\n"
      "N10 G21 G90 G17\n"
      "N20 G0 X0 Y0 Z5\n"
      "N30 G1 Z-1 F300 (plunge F300)\n"
      "N40 g1 x10 f 1 2 0 0.0 ; feed F1200\n"
      "N50 X20\n"
      "N60 M2\n"
      "%\n";
  EXPECT_EQ(rewrite_gcode_checked(text, {{5, 150.0}, {6, 812.5}}),
            "%\n"
            "(program F100 header)\n"
            "N10 G21 G90 G17\n"
            "N20 G0 X0 Y0 Z5\n"
            "N30 G1 Z-1 F150 (plunge F300)\n"
            "N40 g1 x10 f 812.5 ; feed F1200\n"
            "N50 X20 F1200.0\n"  // the original F word, restored
            "N60 M2\n"
            "%\n");
}

TEST(FeedRewriteGcode, InsertsAnFWordAndRestoresTheOriginalFeedAfterIt) {
  const std::string text = "G21\nG0 X0 Y0 Z1\nG1 Z0 F300\nG1 X10\nG1 X20\nG1 X30\nM30\n";
  // The program writes whole mm/min: so does the schedule, rounding down.
  EXPECT_EQ(rewrite_gcode_checked(text, {{4, 812.9}}),
            "G21\nG0 X0 Y0 Z1\nG1 Z0 F300\nG1 X10 F812\nG1 X20 F300\nG1 X30\nM30\n");
  // The same feed on consecutive lines is said once.
  EXPECT_EQ(rewrite_gcode_checked(text, {{4, 812.5}, {5, 812.5}}),
            "G21\nG0 X0 Y0 Z1\nG1 Z0 F300\nG1 X10 F812\nG1 X20\nG1 X30 F300\nM30\n");
  // The feed in force already: nothing to write.
  EXPECT_EQ(rewrite_gcode_checked(text, {{4, 300.0}}), text);
  EXPECT_EQ(rewrite_gcode_checked(text, {}), text);
}

TEST(FeedRewriteGcode, CommentsAreNotWordsAndTheFGoesBeforeThem) {
  const std::string text =
      "G21 G1 X0 F300\n"
      "G1 X10 (F500) ; feed F999\n"
      "G1 X20 (F500)\n"
      "G1X30Y5\n"
      "(F700)G1 X40;F800\n";
  EXPECT_EQ(rewrite_gcode_checked(text, {{2, 250.0}, {4, 1200.0}, {5, 95.25}}),
            "G21 G1 X0 F300\n"
            "G1 X10 F250 (F500) ; feed F999\n"
            "G1 X20 F300 (F500)\n"
            "G1X30Y5F1200\n"  // written as the line writes its words
            "(F700)G1 X40 F95;F800\n");
}

TEST(FeedRewriteGcode, InchProgramsGetInchesPerMinute) {
  const std::string text = "G20\nG0 X0 Y0 Z0.1\nG1 Z0 F10\nG1 X1\nG1 X2\nG1 X3\nM2\n";
  // 500 mm/min is 19.685 in/min: 19.6 at the least precision inches get.
  EXPECT_EQ(rewrite_gcode_checked(text, {{4, 635.0}, {5, 500.0}}),
            "G20\nG0 X0 Y0 Z0.1\nG1 Z0 F10\nG1 X1 F25\nG1 X2 F19.6\nG1 X3 F10\nM2\n");
  // The initial units of the reader's options count too.
  const std::string bare = "%\r\n/n1 g1 x1 f10\r\nx2\r\n%\r\n";
  GcodeOptions inches;
  inches.initial_units = ProgramUnits::kInches;
  EXPECT_EQ(rewrite_gcode_checked(bare, {{3, 508.0}}, inches),
            "%\r\n/n1 g1 x1 f10\r\nx2 f20\r\n%\r\n");
}

// A scheduled feed keeps the program's precision, rounded down: never above the feed the limit
// allows, at most one unit of the last decimal below it.
TEST(FeedRewriteGcode, NewFeedsKeepTheProgramsPrecision) {
  // FreeCAD's posts write three decimals.
  const std::string freecad = "G21\nG1 X1 F600.000\nG1 X2\nG1 X3\nM2\n";
  EXPECT_EQ(rewrite_gcode_checked(freecad, {{3, 812.34567}}),
            "G21\nG1 X1 F600.000\nG1 X2 F812.345\nG1 X3 F600.000\nM2\n");
  // 812.3 is not quite 812.3 in binary: still 812.3, not 812.2.
  EXPECT_EQ(rewrite_gcode_checked(freecad, {{3, 812.3}}),
            "G21\nG1 X1 F600.000\nG1 X2 F812.3\nG1 X3 F600.000\nM2\n");
  // An inch post without decimals gets tenths; one with five keeps five.
  EXPECT_EQ(rewrite_gcode_checked("G20\nG1 X1 F15.\nG1 X2\nM2\n", {{3, 578.6}}),
            "G20\nG1 X1 F15.\nG1 X2 F22.7\nM2\n");  // 22.779… in/min
  EXPECT_EQ(rewrite_gcode_checked("G20\nG1 X1 F15.00000\nG1 X2\nM2\n", {{3, 578.6}}),
            "G20\nG1 X1 F15.00000\nG1 X2 F22.77952\nM2\n");
  // A feed that the precision would write as 0 gets the decimals it needs.
  EXPECT_EQ(rewrite_gcode("G21\nG1 X1 F600\nG1 X2\nM2\n", {{3, 0.057}}),
            "G21\nG1 X1 F600\nG1 X2 F0.05\nM2\n");
}

TEST(FeedRewriteGcode, FOnAUnitsLineIsInTheUnitsBeforeIt) {
  // The reader (and LinuxCNC) executes F before G20 on its line: F250 there is 250 mm/min. The
  // restored 100 mm/min under G20 is converted: F3.93701 (100.000054 mm/min).
  const std::string text = "G21\nG1 X1 F100\nG20 G1 X2\nG1 X3\nM2\n";
  EXPECT_EQ(rewrite_gcode_checked(text, {{3, 250.0}}, {}, kFeedRelative),
            "G21\nG1 X1 F100\nG20 G1 X2 F250\nG1 X3 F3.93701\nM2\n");
}

TEST(FeedRewriteGcode, CyclesAndArcs) {
  const std::string text =
      "G21 G0 X0 Y0 Z5 F200\n"
      "G81 X10 Y0 Z-5 R1\n"
      "X20\n"
      "G80\n"
      "G0 X0 Y0 Z0\n"
      "G2 X10 Y0 I5 J0\n"
      "G3 X0 Y0 R5\n"
      "M2\n";
  EXPECT_EQ(rewrite_gcode_checked(text, {{2, 100.0}, {6, 400.0}}),
            "G21 G0 X0 Y0 Z5 F200\n"
            "G81 X10 Y0 Z-5 R1 F100\n"
            "X20 F200\n"
            "G80\n"
            "G0 X0 Y0 Z0\n"
            "G2 X10 Y0 I5 J0 F400\n"
            "G3 X0 Y0 R5 F200\n"
            "M2\n");
}

TEST(FeedRewriteGcode, FWordsThatCannotBeRewrittenAreInputErrors) {
  // The program reads (the feed is 100), but its F words are not numbers to rewrite.
  for (const char* text : {"G21 #1=100\nG1 X1 F#1\nM2\n", "G21\nG1 X1 F[100]\nM2\n",
                           "G21\nG1 X1 F-[-100]\nM2\n"}) {
    try {
      rewrite_gcode(text, {{2, 100.0}});
      ADD_FAILURE() << "no error for " << text;
    } catch (const InputError& e) {
      EXPECT_EQ(e.location().source, "t.ngc");
      EXPECT_EQ(e.location().line, 2);
      EXPECT_EQ(e.location().column, 7);
      EXPECT_NE(e.message().find("cannot be rewritten"), std::string::npos) << e.message();
    }
  }
  // A comment inside the number (the reader joins F1(c)00 into F100).
  try {
    rewrite_gcode("G21\nG1 X1 F1(c)00\nM2\n", {{2, 50.0}});
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_EQ(e.location().line, 2);
    EXPECT_EQ(e.location().column, 7);
    EXPECT_NE(e.message().find("comment"), std::string::npos) << e.message();
  }
  // Unlisted, it stays as it is.
  EXPECT_EQ(rewrite_gcode("G21\nG1 X1 F1(c)00\nX2\nM2\n", {{3, 50.0}}),
            "G21\nG1 X1 F1(c)00\nX2 F50\nM2\n");
}

TEST(FeedRewriteGcode, FeedsThatCannotBeWrittenAreInputErrorsAtTheirLine) {
  const std::string text = "G21\nG0 X0 Z1\nG1 Z0 F100\n(comment)\nM2\n";
  const auto expect_invalid = [&](const LineFeeds& feeds, const std::string& expected) {
    try {
      rewrite_gcode(text, feeds);
      ADD_FAILURE() << "no error for " << expected;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
    }
  };
  expect_invalid({{1, 100.0}}, "t.ngc:1: error: line 1 has no feed move");  // no motion
  expect_invalid({{2, 100.0}}, "t.ngc:2: error: line 2 has no feed move");  // a rapid
  expect_invalid({{4, 100.0}}, "t.ngc:4: error: line 4 has no feed move");  // a comment
  expect_invalid({{9, 100.0}}, "t.ngc:9: error: line 9 has no feed move");  // past the end
  expect_invalid({{0, 100.0}}, "t.ngc: error: line 0 has no feed move");
  expect_invalid({{3, 0.0}}, "t.ngc:3: error: expected a feed rate > 0 mm/min");
  expect_invalid({{3, -5.0}}, "t.ngc:3: error: expected a feed rate > 0 mm/min");
  expect_invalid({{3, std::numeric_limits<double>::infinity()}}, "expected a feed rate > 0");
  expect_invalid({{3, std::numeric_limits<double>::quiet_NaN()}}, "expected a feed rate > 0");
  expect_invalid({{3, 1e-5}}, "is 0 when written with 4 decimals");
  expect_invalid({{3, 2e9}}, "too large to write");
}

// The line without its F word (and the blank before it), for lines written as the random
// programs below write them.
std::string without_f_word(std::string line) {
  const std::size_t code_end = std::min(line.find('('), line.find(';'));
  const std::size_t f = line.find('F');
  if (f == std::string::npos || f > code_end) return line;
  const std::size_t end = line.find_first_not_of("0123456789.", f + 1);
  const std::size_t begin = f > 0 && line[f - 1] == ' ' ? f - 1 : f;
  return line.erase(begin, (end == std::string::npos ? line.size() : end) - begin);
}

// Random programs: moves, arcs, F words or none, unit changes, comments with F in them,
// trailing comments; random lines get random feeds. The rewritten program must read back as
// the original but for the listed feeds, with every line that neither feeds nor is listed kept
// byte for byte, and listed lines changed only by their F word.
TEST(FeedRewriteGcode, RandomProgramsRoundTrip) {
  test::Random random(7);
  int restored = 0;  // unlisted lines given their feed back
  for (int program = 0; program < 150; ++program) {
    SCOPED_TRACE(fmt::format("program {}", program));
    std::string text = random.integer(0, 1) == 0 ? "G21\n" : "G20\n";
    text += "G0 X0 Y0 Z1\nG1 Z0 F" + std::to_string(random.integer(100, 900)) + "\n";
    const int count = random.integer(5, 40);
    for (int i = 0; i < count; ++i) {
      std::string line;
      switch (random.integer(0, 9)) {
        case 0:
          line = random.integer(0, 1) == 0 ? "G20" : "G21";
          break;
        case 1:
          line = fmt::format("(F{})", random.integer(1, 999));
          break;
        case 2:
          line = fmt::format("G0 X{} Y{}", random.integer(-9, 9), random.integer(-9, 9));
          break;
        case 3:
          line = fmt::format("G2 I{} J0", random.integer(1, 5));  // a full circle
          break;
        case 4:
          line = fmt::format("F{}.{}", random.integer(127, 999), random.integer(0, 99));
          break;
        default:
          line = fmt::format("G1 X{} Y{}", random.integer(-9, 9), random.integer(-9, 9));
          break;
      }
      if (line[0] == 'G' && random.integer(0, 2) == 0) {
        line += fmt::format(" F{}", random.integer(127, 999));
      }
      if (random.integer(0, 3) == 0) line += " (F12)";
      if (random.integer(0, 3) == 0) line += " ; F34";
      text += line + "\n";
    }
    text += "M2\n";
    const Toolpath original = gcode(text);
    LineFeeds feeds;
    for (const Move& move : original.moves) {
      if (!move.is_rapid() && random.integer(0, 2) == 0) {
        feeds[move.line] = random.uniform(127.0, 5000.0);
      }
    }
    const std::string out = rewrite_gcode(text, feeds);
    expect_feeds_rewritten(
        original, gcode(out), feeds, [](int line) { return line; }, kFeedRelative);
    const std::vector<std::string> before = split_lines(text), after = split_lines(out);
    ASSERT_EQ(before.size(), after.size());
    std::vector<bool> feeds_on_line(before.size() + 1, false);
    for (const Move& move : original.moves) feeds_on_line[move.line] = !move.is_rapid();
    for (std::size_t i = 0; i < before.size(); ++i) {
      const int line = static_cast<int>(i) + 1;
      if (!feeds_on_line[line]) {
        EXPECT_EQ(before[i], after[i]) << "line " << line;
      }
      if (before[i] != after[i] && feeds.count(line) == 0) ++restored;
      // A changed line differs only by its F word.
      EXPECT_EQ(without_f_word(before[i]), without_f_word(after[i])) << "line " << line;
    }
  }
  EXPECT_GT(restored, 100);  // the programs exercise the restoring
}

// ---------------------------------------------------------------------------------------------
// APT CLDATA

Toolpath cldata(std::string_view text) { return read_cldata(text, "t.cl"); }

std::string rewrite_cldata(std::string_view text, const LineFeeds& feeds) {
  return rewrite_feeds(text, ToolpathFormat::kCldata, feeds, "t.cl");
}

// A line's text without a byte-order mark, the blanks, the line ending and an inserted "GOTO/"
// (what makes a continuation point a GOTO of its own).
std::string record_text(std::string line) {
  if (line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);  // a byte-order mark
  std::string out;
  for (char c : line) {
    if (c != ' ' && c != '\r') out += c;
  }
  if (out.rfind("GOTO/", 0) == 0 && !out.empty() && out.size() > 5 &&
      (std::isdigit(static_cast<unsigned char>(out[5])) || out[5] == '-' || out[5] == '.')) {
    return out.substr(5);
  }
  return out;
}

// Rewrites and checks the round trip: the same moves, each from the same record (lines move down
// by the inserted FEDRAT lines).
std::string rewrite_cldata_checked(std::string_view text, const LineFeeds& feeds) {
  const std::string out = rewrite_cldata(text, feeds);
  const Toolpath original = cldata(text), rewritten = cldata(out);
  const std::vector<std::string> before = split_lines(text), after = split_lines(out);
  expect_feeds_rewritten(original, rewritten, feeds, [&](int line) {
    // The rewritten line that holds the original line's record.
    const std::string wanted = record_text(before.at(static_cast<std::size_t>(line - 1)));
    int skipped = 0;  // lines of the rewritten text before it that are not inserted
    for (std::size_t i = 0; i < after.size(); ++i) {
      const bool inserted = record_text(after[i]) != record_text(before.at(skipped));
      if (!inserted && skipped == line - 1) {
        EXPECT_EQ(record_text(after[i]), wanted);
        return static_cast<int>(i) + 1;
      }
      if (!inserted) ++skipped;
    }
    return 0;
  });
  return out;
}

TEST(FeedRewriteCldata, InsertsFedratLinesInTheFilesStyle) {
  const std::string text =
      "PARTNO/TEST, FEDRAT/999\r\n"
      "$$ FEDRAT/999\r\n"
      "FEDRAT/MMPM,250\r\n"
      "RAPID\r\n"
      "GOTO/0,0,5\r\n"
      "GOTO/0,0,0\r\n"
      "  GOTO/10,0,0\r\n"
      "GOTO/20,0,0\r\n"
      "GOTO/30,0,0\r\n"
      "FINI\r\n";
  EXPECT_EQ(rewrite_cldata_checked(text, {{7, 812.5}}),
            "PARTNO/TEST, FEDRAT/999\r\n"
            "$$ FEDRAT/999\r\n"
            "FEDRAT/MMPM,250\r\n"
            "RAPID\r\n"
            "GOTO/0,0,5\r\n"
            "GOTO/0,0,0\r\n"
            "  FEDRAT/MMPM,812\r\n"
            "  GOTO/10,0,0\r\n"
            "FEDRAT/MMPM,250\r\n"
            "GOTO/20,0,0\r\n"
            "GOTO/30,0,0\r\n"
            "FINI\r\n");
  EXPECT_EQ(rewrite_cldata_checked(text, {{6, 250.0}}), text);
  EXPECT_EQ(rewrite_cldata_checked("fedrat/100\ngoto/1,0,0\ngoto/2,0,0", {{3, 80.0}}),
            "fedrat/100\ngoto/1,0,0\nfedrat/80,mmpm\ngoto/2,0,0");
  // A byte-order mark stays first; lone CR line endings are kept.
  EXPECT_EQ(rewrite_cldata_checked("\xEF\xBB\xBFGOTO/1,0,0\n", {{1, 100.0}}),
            "\xEF\xBB\xBF"
            "FEDRAT/100,MMPM\nGOTO/1,0,0\n");
  // No FEDRAT to take the precision from: one decimal.
  EXPECT_EQ(rewrite_cldata_checked("GOTO/1,0,0\n", {{1, 99.99}}), "FEDRAT/99.9,MMPM\nGOTO/1,0,0\n");
  const std::string lone_cr = "FEDRAT/100\rGOTO/1,0,0\rGOTO/2,0,0\r";
  const std::string out = rewrite_cldata(lone_cr, {{2, 50.0}});
  EXPECT_EQ(out, "FEDRAT/100\rFEDRAT/50,MMPM\rGOTO/1,0,0\rFEDRAT/100,MMPM\rGOTO/2,0,0\r");
  const Toolpath read_back = cldata(out);
  ASSERT_EQ(read_back.moves.size(), 2u);
  EXPECT_EQ(read_back.moves[0].feed_rate, 50.0);
  EXPECT_EQ(read_back.moves[1].feed_rate, 100.0);
}

TEST(FeedRewriteCldata, ContinuedRecordsGetTheFedratBeforeTheirFirstLine) {
  const std::string text =
      "FEDRAT/ 300.0000,MMPM\n"
      "GOTO/0,0,0\n"
      "GOTO/ 10.0, $\n"
      "      0.0, $   $$ same record\n"
      "$$ comment inside\n"
      "      0.0\n"
      "GOTO/20,0,0\n";
  EXPECT_EQ(rewrite_cldata_checked(text, {{3, 150.0}}),
            "FEDRAT/ 300.0000,MMPM\n"
            "GOTO/0,0,0\n"
            "FEDRAT/150,MMPM\n"
            "GOTO/ 10.0, $\n"
            "      0.0, $   $$ same record\n"
            "$$ comment inside\n"
            "      0.0\n"
            "FEDRAT/300.0000,MMPM\n"
            "GOTO/20,0,0\n");
  for (int inside : {4, 5, 6}) {
    EXPECT_THROW(rewrite_cldata(text, {{inside, 150.0}}), InputError) << inside;
  }
}

TEST(FeedRewriteCldata, ArcsKeepTheirCircleNextToTheGoto) {
  // Move::line of an arc is its GOTO's; the FEDRAT goes before the CIRCLE.
  const std::string text =
      "FEDRAT/200\nGOTO/10,0,0\nCIRCLE/0,0,0,0,0,1,10\nGOTO/0,10,0\nGOTO/0,20,0\n";
  EXPECT_EQ(rewrite_cldata_checked(text, {{4, 100.0}}),
            "FEDRAT/200\nGOTO/10,0,0\nFEDRAT/100,MMPM\nCIRCLE/0,0,0,0,0,1,10\nGOTO/0,10,0\n"
            "FEDRAT/200,MMPM\nGOTO/0,20,0\n");
  EXPECT_THROW(rewrite_cldata(text, {{3, 100.0}}), InputError);  // the CIRCLE
  EXPECT_THROW(rewrite_cldata(text, {{1, 100.0}}), InputError);  // the FEDRAT
  // A FEDRAT between the CIRCLE and its GOTO: the new one must come after it.
  const std::string between =
      "FEDRAT/200\nGOTO/10,0,0\nCIRCLE/0,0,0,0,0,1,10\nFEDRAT/300\nGOTO/0,10,0\n";
  EXPECT_EQ(rewrite_cldata_checked(between, {{5, 100.0}}),
            "FEDRAT/200\nGOTO/10,0,0\nCIRCLE/0,0,0,0,0,1,10\nFEDRAT/300\nFEDRAT/100,MMPM\n"
            "GOTO/0,10,0\n");
}

TEST(FeedRewriteCldata, InchUnitsAndFeedsPerRevolutionAreRestoredExactly) {
  const std::string inches = "UNITS/INCHES\nFEDRAT/20\nGOTO/0,0,0\nGOTO/1,0,0\nGOTO/2,0,0\n";
  // In the program's units: 812.5 mm/min is 31.988 in/min.
  EXPECT_EQ(rewrite_cldata_checked(inches, {{4, 812.5}}),
            "UNITS/INCHES\nFEDRAT/20\nGOTO/0,0,0\nFEDRAT/31.9,IPM\nGOTO/1,0,0\nFEDRAT/20,IPM\n"
            "GOTO/2,0,0\n");
  EXPECT_DOUBLE_EQ(cldata(rewrite_cldata(inches, {{4, 812.5}})).moves[2].feed_rate, 508.0);
  const std::string per_revolution =
      "SPINDL/RPM,1000,CLW\nFEDRAT/0.1,MMPR\nGOTO/0,0,0\nGOTO/1,0,0\nGOTO/2,0,0\n";
  EXPECT_EQ(rewrite_cldata_checked(per_revolution, {{4, 50.0}}),
            "SPINDL/RPM,1000,CLW\nFEDRAT/0.1,MMPR\nGOTO/0,0,0\nFEDRAT/50,MMPM\nGOTO/1,0,0\n"
            "FEDRAT/0.1,MMPR\nGOTO/2,0,0\n");
}

TEST(FeedRewriteCldata, PointsThatContinueAGotoBecomeGotos) {
  const std::string text = "FEDRAT/100\nGOTO/0,0,0\n10,0,0\n20,0,0\n30,0,0\n";
  EXPECT_EQ(rewrite_cldata_checked(text, {{4, 50.0}}),
            "FEDRAT/100\nGOTO/0,0,0\n10,0,0\nFEDRAT/50,MMPM\nGOTO/20,0,0\nFEDRAT/100,MMPM\n"
            "GOTO/30,0,0\n");
  // On an arc (Creo's POINTS_&_ARC): the circle is repeated, without TIMES.
  const std::string arc =
      "FEDRAT/100\nGOTO/10,0,0\nCIRCLE/0,0,0,0,0,1,10,0.01,TIMES,2\nGOTO/0,10,0\n  -10,0,0\n"
      "0,-10,0\n";
  EXPECT_EQ(rewrite_cldata_checked(arc, {{5, 50.0}}),
            "FEDRAT/100\nGOTO/10,0,0\nCIRCLE/0,0,0,0,0,1,10,0.01,TIMES,2\nGOTO/0,10,0\n"
            "  FEDRAT/50,MMPM\n  CIRCLE/0,0,0,0,0,1,10\n  GOTO/-10,0,0\nFEDRAT/100,MMPM\n"
            "CIRCLE/0,0,0,0,0,1,10\nGOTO/0,-10,0\n");
}

// Random CLDATA: GOTOs (some continued with `$`, some followed by points), arcs, FEDRATs in
// every unit, UNITS changes, rapids, spindle changes, comments.
TEST(FeedRewriteCldata, RandomProgramsRoundTrip) {
  test::Random random(11);
  int inserted = 0, circles = 0;  // FEDRAT lines, and CIRCLE copies for points on arcs
  for (int program = 0; program < 150; ++program) {
    SCOPED_TRACE(fmt::format("program {}", program));
    std::string text = "FEDRAT/" + std::to_string(random.integer(100, 900)) + "\n";
    int x = 0, y = 0;  // the position, in whole program units
    const int count = random.integer(5, 40);
    for (int i = 0; i < count; ++i) {
      const auto point = [&] { return fmt::format("{},{},0", x, y); };
      switch (random.integer(0, 11)) {
        case 0:
          text += random.integer(0, 1) == 0 ? "UNITS/INCHES\n" : "UNITS/MM\n";
          text += "GOTO/" + point() + "\n";  // the position in the new units
          break;
        case 1: {
          static const char* const kUnits[] = {"", ",MMPM", ",IPM", ",PERMIN", ",MMPR", ",IPR"};
          const char* unit = kUnits[random.integer(0, 5)];
          const bool per_rev = unit[0] != 0 && unit[std::string(unit).size() - 1] == 'R';
          text += fmt::format("FEDRAT/{}{}\n",
                              per_rev ? random.uniform(0.01, 0.3) : random.uniform(100, 900), unit);
          break;
        }
        case 2:
          text += fmt::format("SPINDL/RPM,{},CLW\n", random.integer(1000, 9000));
          break;
        case 3:
          x = random.integer(-9, 9);
          text += "RAPID\nGOTO/" + point() + "\n";
          break;
        case 4: {
          // A quarter circle about a centre one radius to the -x side.
          const int r = random.integer(1, 5);
          text += fmt::format("CIRCLE/{},{},0,0,0,1,{}\n", x - r, y, r);
          if (random.integer(0, 1) == 0) text += "$$ between\n";
          x -= r;
          y += r;
          text += "GOTO/" + point() + "\n";
          if (random.integer(0, 1) == 0) {
            x -= r;
            y -= r;
            text += point() + "\n";  // the next quarter, as a continuation point
          }
          break;
        }
        case 5:
          x = random.integer(-9, 9);
          text += fmt::format("GOTO/ {}, $\n   {}, $ $$ continued\n   0\n", x, y);
          break;
        case 6:
          text += "$$ FEDRAT/1\n";
          break;
        default:
          x = random.integer(-9, 9);
          text += "GOTO/" + point() + "\n";
          while (random.integer(0, 2) == 0) {
            y = random.integer(-9, 9);
            text += point() + "\n";
          }
          break;
      }
    }
    text += "FINI\n";
    const Toolpath original = cldata(text);
    LineFeeds feeds;
    for (const Move& move : original.moves) {
      if (!move.is_rapid() && random.integer(0, 2) == 0) {
        feeds[move.line] = random.uniform(50.0, 5000.0);
      }
    }
    const std::string out = rewrite_cldata_checked(text, feeds);
    const auto occurrences = [](const std::string& s, const char* word) {
      int n = 0;
      for (std::size_t at = s.find(word); at != std::string::npos; at = s.find(word, at + 1)) ++n;
      return n;
    };
    inserted += occurrences(out, "MMPM") - occurrences(text, "MMPM") + occurrences(out, "IPM") -
                occurrences(text, "IPM");
    circles += occurrences(out, "CIRCLE/") - occurrences(text, "CIRCLE/");
  }
  // The programs exercise insertions and continuation points on arcs.
  EXPECT_GT(inserted, 500);
  EXPECT_GT(circles, 10);
}

}  // namespace
}  // namespace cwe

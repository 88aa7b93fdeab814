#include "cwe/tool/tool_spec.hpp"
#include "cwe/core/error.hpp"
#include "source_dir.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <utility>

#include "tool_testing.hpp"

namespace cwe {
namespace {

std::string source_dir() { return test::source_dir().string(); }

TEST(ToolSpec, ParsesEveryType) {
  EXPECT_EQ(to_string(*cutter_from_spec("flat:10").apt()), "CUTTER/10,0,5,0,0,0,30");
  EXPECT_EQ(to_string(*cutter_from_spec("flat:10,25").apt()), "CUTTER/10,0,5,0,0,0,25");
  EXPECT_EQ(to_string(*cutter_from_spec("ball:6").apt()), "CUTTER/6,3,0,3,0,0,18");
  EXPECT_EQ(to_string(*cutter_from_spec("bull: 10 , 2 ,40").apt()), "CUTTER/10,2,3,2,0,0,40");
  EXPECT_EQ(to_string(*cutter_from_spec("taper-flat:6,5,20").apt()), "CUTTER/6,0,3,0,0,5,20");
  EXPECT_EQ(cutter_from_spec("taper-ball:4,3,30").apt()->beta_deg, 3.0);
  EXPECT_EQ(to_string(*cutter_from_spec("chamfer:12,90,15").apt()), "CUTTER/12,0,6,6,45,0,15");
  EXPECT_EQ(to_string(*cutter_from_spec("apt:10,2,3,2,0,0,30").apt()), "CUTTER/10,2,3,2,0,0,30");
  EXPECT_EQ(cutter_from_spec("flat:10").name(), "flat:10");
}

TEST(ToolSpec, ErrorsNameTheColumn) {
  EXPECT_INPUT_ERROR(cutter_from_spec("flatt:10"),
                     "tool spec:1:1: error: unknown tool type 'flatt' (expected flat, ball,");
  EXPECT_INPUT_ERROR(cutter_from_spec("bull:10,x"),
                     "tool spec:1:9: error: expected a number, found 'x'");
  EXPECT_INPUT_ERROR(cutter_from_spec("flat:"), "tool spec:1:6: error: expected a number");
  EXPECT_INPUT_ERROR(cutter_from_spec("flat:10,,3"), "tool spec:1:9: error: expected a number");
  EXPECT_INPUT_ERROR(cutter_from_spec("ball:10,5,3"), "'ball' takes D[,h] (3 values given)");
  EXPECT_INPUT_ERROR(cutter_from_spec("bull:10"), "'bull' takes D,r[,h] (1 value given)");
  EXPECT_INPUT_ERROR(cutter_from_spec("flat:-10"), "tool spec:1:6: error: D = -10");
  EXPECT_INPUT_ERROR(cutter_from_spec("flat:1e999"), "expected a number, found '1e999'");
  // Finite but beyond any tool, and a written height that is not positive (it once silently
  // meant the default).
  EXPECT_INPUT_ERROR(cutter_from_spec("flat:1e308"),
                     "tool spec:1:6: error: '1e308' is beyond the largest value cwe takes");
  EXPECT_INPUT_ERROR(cutter_from_spec("flat:10,-5"),
                     "tool spec:1:9: error: h = -5: the height must be positive");
  EXPECT_INPUT_ERROR(cutter_from_spec("ball:6,0"), "tool spec:1:8: error: h = 0");
  EXPECT_INPUT_ERROR(cutter_from_spec("chamfer:10,90,-1"), "tool spec:1:15: error: h = -1");
  EXPECT_INPUT_ERROR(cutter_from_spec("ten mm"), "is not a tool specification");
  EXPECT_INPUT_ERROR(cutter_from_spec("apt:10,2,3,2.5,0,0,30"), "f = 2.5 does not fit");
}

TEST(ToolSpec, LocationInsideALargerInput) {
  // A specification found at line 3, column 8 of a file reports positions in that file.
  EXPECT_INPUT_ERROR(cutter_from_spec("bull:10,x", {"job.json", 3, 8}),
                     "job.json:3:16: error: expected a number");
}

TEST(ToolFile, ShapeFromSpecAptOrProfile) {
  const Cutter a = cutter_from_json(
      R"({"name": "T1", "spec": "bull:16,2,40", "flutes": 2, "helix_deg": 40,
          "shank": {"diameter": 16, "length": 50}})",
      "t1.json");
  EXPECT_EQ(a.name(), "T1");
  EXPECT_EQ(a.flutes(), 2);
  EXPECT_NEAR(a.helix_angle(), degrees_to_radians(40.0), 1e-15);
  EXPECT_DOUBLE_EQ(a.shank().length, 50.0);
  EXPECT_DOUBLE_EQ(a.diameter(), 16.0);

  const Cutter b = cutter_from_json(R"({"apt": [10, 5, 0, 5, 0, 0, 20]})", "b.json");
  EXPECT_EQ(b.patches().front().kind, PatchKind::kSphere);
  EXPECT_EQ(b.name(), "b.json");

  const Cutter c = cutter_from_json(
      R"({"profile": [{"line": [2, 0]}, {"arc": [4, 2], "center": [2, 2]}, {"line": [4, 10]}]})",
      "c.json");
  EXPECT_EQ(c.patches()[1].kind, PatchKind::kTorus);
  EXPECT_DOUBLE_EQ(c.profile().height(), 10.0);
}

TEST(ToolFile, ErrorsSayWhatWasExpected) {
  EXPECT_INPUT_ERROR(cutter_from_json("{\"spec\": \"flat:10\",\n  \"flutes\": }", "t.json"),
                     "t.json:2:13: error: not valid JSON");
  EXPECT_INPUT_ERROR(cutter_from_json(R"({"spec": "flat:10", "flute": 3})", "t.json"),
                     "unknown key \"flute\"");
  EXPECT_INPUT_ERROR(cutter_from_json(R"({"spec": "flat:10", "apt": [10]})", "t.json"),
                     "exactly one of \"spec\", \"apt\" and \"profile\"");
  EXPECT_INPUT_ERROR(cutter_from_json(R"({"spec": "flat:10", "flutes": 2.5})", "t.json"),
                     "\"flutes\": expected a whole number");
  EXPECT_INPUT_ERROR(cutter_from_json(R"({"spec": "flat:10,q"})", "t.json"),
                     "t.json (\"spec\"):1:9: error: expected a number, found 'q'");
  EXPECT_INPUT_ERROR(
      cutter_from_json(R"({"profile": [{"line": [2, 0]}, {"arc": [4, 2]}]})", "t.json"),
      "an arc needs \"center\"");
  EXPECT_INPUT_ERROR(cutter_from_json(R"({"profile": [{"line": [2]}]})", "t.json"),
                     "expected a point [radius, z]");
  EXPECT_INPUT_ERROR(cutter_from_json("[1, 2]", "t.json"), "must hold a JSON object");
  EXPECT_INPUT_ERROR(cutter_from_file("/nonexistent/tool.json"), "cannot open the tool file");
}

TEST(ToolFile, BundledExamplesLoad) {
  const std::filesystem::path dir = std::filesystem::path(source_dir()) / "examples" / "tools";
  int count = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    SCOPED_TRACE(entry.path().string());
    EXPECT_NO_THROW(cutter_from_spec(entry.path().string()));
    ++count;
  }
  EXPECT_GE(count, 2);
}

// Lengths written in inches are the same cutters as their millimetre equivalents; an angle with
// a length unit is an error at its column.
TEST(ToolSpec, InchLengths) {
  const std::pair<const char*, const char*> same[] = {
      {"flat:0.375in", "flat:9.525"},
      {"ball:0.25in,1in", "ball:6.35,25.4"},
      {"bull:0.5in,0.0625in,1.5in", "bull:12.7,1.5875,38.1"},
      {"taper-flat:0.25in,5,1in", "taper-flat:6.35,5,25.4"},
      {"chamfer:0.5in,90", "chamfer:12.7,90"},
      {"apt:0.25in,0.125in,0,0.125in,0,0,1in", "apt:6.35,3.175,0,3.175,0,0,25.4"},
      {"flat:10mm,30mm", "flat:10,30"}};
  for (const auto& [inch, mm] : same) {
    SCOPED_TRACE(inch);
    const Cutter a = cutter_from_spec(inch), b = cutter_from_spec(mm);
    EXPECT_NEAR(a.diameter(), b.diameter(), 1e-12);
    EXPECT_NEAR(a.flute_length(), b.flute_length(), 1e-12);
    ASSERT_EQ(a.profile().segments().size(), b.profile().segments().size());
    for (std::size_t k = 0; k < a.profile().segments().size(); ++k) {
      EXPECT_LT((a.profile().segments()[k].end - b.profile().segments()[k].end).norm(), 1e-12);
    }
  }
  try {
    (void)cutter_from_spec("taper-flat:0.25in,5in");
    ADD_FAILURE() << "an angle in inches was accepted";
  } catch (const InputError& e) {
    EXPECT_EQ(e.location().column, 19) << e.what();
  }
  EXPECT_THROW((void)cutter_from_spec("flat:0.375ft"), InputError);
}

// Inputs a fuzzer found (tests/data/fuzz-findings): the first line of a tool-crash file is a
// specification, the rest a JSON tool file; each is accepted or refused with an InputError,
// never another exception.
TEST(ToolSpec, FuzzFindingsAreInputErrors) {
  int files = 0;
  for (const auto& entry :
       std::filesystem::directory_iterator(test::source_dir() / "tests/data/fuzz-findings")) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("tool-crash-", 0) != 0) continue;
    std::ifstream in(entry.path(), std::ios::binary);
    const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::size_t newline = std::min(text.find('\n'), text.size());
    const std::string spec = text.substr(0, newline);
    const std::string json = newline < text.size() ? text.substr(newline + 1) : std::string();
    try {
      (void)cutter_from_spec(spec);
    } catch (const InputError&) {
    }
    EXPECT_THROW((void)cutter_from_json(json, name), InputError) << name;
    ++files;
  }
  EXPECT_EQ(files, 3);
}

}  // namespace
}  // namespace cwe

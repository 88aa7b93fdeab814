#include "cwe/toolpath/toolpath_reader.hpp"

#include <gtest/gtest.h>

#include "source_dir.hpp"

namespace cwe {
namespace {

TEST(ToolpathFormat, FromTheExtension) {
  for (const char* name : {"a.ngc", "a.NC", "a.tap", "a.gcode", "a.cnc", "a.g"}) {
    EXPECT_EQ(detect_toolpath_format(name, "GOTO/1,2,3"), ToolpathFormat::kGcode) << name;
  }
  for (const char* name : {"a.cl", "a.CLS", "a.cldata", "a.apt", "a.aps"}) {
    EXPECT_EQ(detect_toolpath_format(name, "G1 X1"), ToolpathFormat::kCldata) << name;
  }
}

TEST(ToolpathFormat, FromTheTextOtherwise) {
  EXPECT_EQ(detect_toolpath_format("prog.txt", "$$ header\nPARTNO demo\n  GOTO/1,2,3\n"),
            ToolpathFormat::kCldata);
  EXPECT_EQ(detect_toolpath_format("prog.txt", "(comment / slash)\nG1 X1 F100\n"),
            ToolpathFormat::kGcode);
  EXPECT_EQ(detect_toolpath_format("prog", ""), ToolpathFormat::kGcode);
}

TEST(ToolpathReader, ReadsTheExamples) {
  const auto dir = test::source_dir() / "examples" / "programs";
  const ReadToolpath g = read_toolpath_file((dir / "pocket.ngc").string());
  EXPECT_EQ(g.format, ToolpathFormat::kGcode);
  EXPECT_EQ(g.toolpath.moves.size(), 53u);
  const ReadToolpath c = read_toolpath_file((dir / "five_axis.cls").string());
  EXPECT_EQ(c.format, ToolpathFormat::kCldata);
  EXPECT_EQ(c.toolpath.moves.size(), 9u);
  EXPECT_THROW(read_toolpath_file((dir / "missing.ngc").string()), InputError);
}

}  // namespace
}  // namespace cwe

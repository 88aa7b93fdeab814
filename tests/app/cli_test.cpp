#include "cwe/app/cli.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace cwe::app {
namespace {

struct Result {
  int status = 0;
  std::string out;
  std::string err;
};

Result run_cwe(std::vector<std::string> args) {
  args.insert(args.begin(), "cwe");
  std::ostringstream out, err;
  const int status = run(args, out, err);
  return {status, out.str(), err.str()};
}

std::filesystem::path scratch_dir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("cwe-cli-test-" + name);
  std::filesystem::remove_all(dir);
  return dir;
}

TEST(CliTool, DescribesACutter) {
  const Result r = run_cwe({"tool", "bull:10,2"});
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("APT form        CUTTER/10,2,3,2,0,0,30"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("diameter        10 mm"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("torus"), std::string::npos) << r.out;
  EXPECT_TRUE(r.err.empty());
}

TEST(CliTool, JsonOutputCarriesTheProfile) {
  const Result r = run_cwe({"tool", "ball:6,20", "flat:8", "--json"});
  ASSERT_EQ(r.status, 0) << r.err;
  std::istringstream lines(r.out);
  std::string line;
  std::vector<nlohmann::json> tools;
  while (std::getline(lines, line)) tools.push_back(nlohmann::json::parse(line));
  ASSERT_EQ(tools.size(), 2u);
  EXPECT_DOUBLE_EQ(tools[0]["diameter_mm"].get<double>(), 6.0);
  EXPECT_EQ(tools[0]["patches"][0]["kind"], "sphere");
  EXPECT_DOUBLE_EQ(tools[0]["profile"][0]["center"][1].get<double>(), 3.0);
  EXPECT_EQ(tools[1]["flutes"], 4);
}

TEST(CliTool, BadSpecificationIsAnInputError) {
  const Result r = run_cwe({"tool", "flat:10", "bull:10,x"});
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.err, "tool spec:1:9: error: expected a number, found 'x'\n");
  EXPECT_TRUE(r.out.empty()) << "nothing is printed when any specification is bad";
}

TEST(CliTool, UsageErrors) {
  EXPECT_EQ(run_cwe({}).status, 2);
  EXPECT_EQ(run_cwe({"tool"}).status, 2);
  EXPECT_EQ(run_cwe({"frobnicate"}).status, 2);
  const Result two = run_cwe({"tool", "flat:10", "ball:10", "--svg", "x.svg"});
  EXPECT_EQ(two.status, 2);
  EXPECT_NE(two.err.find("use --svg-dir"), std::string::npos);
  const Result help = run_cwe({"tool", "--help"});
  EXPECT_EQ(help.status, 0);
  EXPECT_NE(help.out.find("taper-ball"), std::string::npos);
}

TEST(CliTool, WritesDrawings) {
  const auto dir = scratch_dir("svg");
  const Result one = run_cwe({"tool", "chamfer:12,90", "--svg", (dir / "one.svg").string()});
  ASSERT_EQ(one.status, 0) << one.err;
  std::ifstream in(dir / "one.svg");
  std::stringstream content;
  content << in.rdbuf();
  EXPECT_EQ(content.str().rfind("<svg", 0), 0u);
  EXPECT_NE(content.str().find("cone"), std::string::npos);
  EXPECT_NE(content.str().find("</svg>"), std::string::npos);

  const Result many =
      run_cwe({"tool", "flat:10", "bull:10,2", "--svg-dir", (dir / "all").string()});
  ASSERT_EQ(many.status, 0) << many.err;
  EXPECT_TRUE(std::filesystem::exists(dir / "all" / "01-flat-10.svg"));
  EXPECT_TRUE(std::filesystem::exists(dir / "all" / "02-bull-10-2.svg"));
  // No temporary files are left behind.
  int files = 0;
  for ([[maybe_unused]] const auto& e : std::filesystem::directory_iterator(dir / "all")) ++files;
  EXPECT_EQ(files, 2);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace cwe::app

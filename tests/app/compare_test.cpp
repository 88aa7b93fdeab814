// `cwe compare` (compare_command.cpp, cwe/job/compare.hpp): one job on several workpieces, CL by
// CL. A workpiece against itself differs by nothing; the tri-dexel one at s = 0.05 against the
// exact B-rep one on analytic cases engages within 1 % of the same area; and an engagement
// perturbed at one CL is found there.

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "cli_testing.hpp"
#include "cwe/core/computation_error.hpp"
#include "cwe/engagement/engagement_grid.hpp"
#include "cwe/job/compare.hpp"
#include "cwe/job/run.hpp"
#include "source_dir.hpp"

namespace cwe::app {
namespace {

nlohmann::json read_json(const std::filesystem::path& file) {
  std::ifstream in(file);
  return nlohmann::json::parse(in);
}

// A slot (full immersion), a side cut of radial depth 2.5 (quarter immersion, the tool's centre
// on the block's edge 2.5 mm out) and a ramp then a level pass, through a 60 × 40 × 20 block.
const char* const kSlot = "G21 G90\nG0 X-10 Y20 Z25\nG0 Z17\nG1 X70 F600\nG0 Z25\nM2\n";
const char* const kSide = "G21 G90\nG0 X-10 Y-2.5 Z25\nG0 Z17\nG1 X70 F600\nG0 Z25\nM2\n";
const char* const kRamp = "G21 G90\nG0 X-10 Y20 Z25\nG0 Z21\nG1 X20 Z13 F600\nG1 X50\nG0 Z25\nM2\n";

TEST(CliCompare, AWorkpieceAgainstItselfDiffersByNothing) {
  const auto dir = scratch_dir("compare-self");
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "slot.ngc") << kSlot;
  const Result r = run_cwe({"compare", "--stock", "box:0,0,0,60,40,20", "--tool", "flat:10,30",
                            "--path", (dir / "slot.ngc").string(), "--workpieces", "dexel,dexel",
                            "--out", (dir / "out").string(), "--quiet"});
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json c = read_json(dir / "out" / "compare.json");
  EXPECT_EQ(c["reference"], "dexel");
  ASSERT_EQ(c["runs"].size(), 2u);
  EXPECT_EQ(c["runs"][1]["label"], "dexel_2");
  EXPECT_NEAR(c["runs"][0]["removed_volume_mm3"].get<double>(), 1800.0, 1.0);
  EXPECT_EQ(c["runs"][1]["removed_volume_difference_mm3"].get<double>(), 0.0);
  // Each run's own memory: its peak less what the process held when it started (the first
  // run's maps, for the second). It holds at least the run's own rays: at s = 0.1 the block has
  // 400 × 200 + 600 × 200 + 600 × 400 = 440,000, of 16 bytes each (measured: 11.7 and 9.9 MB).
  for (const nlohmann::json& run : c["runs"]) {
    EXPECT_EQ(run["run_memory_bytes"].get<std::size_t>(),
              run["peak_memory_bytes"].get<std::size_t>() -
                  std::min(run["peak_memory_bytes"].get<std::size_t>(),
                           run["memory_held_before_bytes"].get<std::size_t>()));
    EXPECT_GE(run["run_memory_bytes"].get<std::size_t>(), 440000u * 16u);
  }
  const nlohmann::json& d = c["differences"]["dexel_2"];
  for (const char* key : {"entry_deg", "exit_deg", "axial_depth_mm", "area_mm2",
                          "exclusive_area_mm2", "exclusive_relative"}) {
    EXPECT_GT(d[key]["count"].get<int>(), 100) << key;
    EXPECT_EQ(d[key]["max"].get<double>(), 0.0) << key;
  }
  EXPECT_EQ(d["engaged_by_one_only"], 0);
  // No map where nothing differs.
  EXPECT_TRUE(std::filesystem::is_empty(dir / "out" / "maps"));
  // Run again into the same folder: the outputs are replaced.
  const Result again = run_cwe({"compare", "--stock", "box:0,0,0,60,40,20", "--tool", "flat:10,30",
                                "--path", (dir / "slot.ngc").string(), "--workpieces",
                                "dexel,dexel", "--out", (dir / "out").string(), "--quiet"});
  EXPECT_EQ(again.status, 0) << again.err;
  // compare.csv: a header and a row per CL, the methods' columns and the differences'.
  const auto rows = read_csv(dir / "out" / "compare.csv");
  ASSERT_EQ(rows.size(), c["cl_points"].get<std::size_t>() + 1);
  EXPECT_EQ(rows[0].size(), 7u + 2 * 5 + 6);
  EXPECT_EQ(rows[0][7], "dexel_engaged");
  EXPECT_EQ(rows[0][17], "dexel_2_d_entry_deg");
  std::filesystem::remove_all(dir);
}

// The tri-dexel workpiece at s = 0.05 against the B-rep one (the exact reference) on a slot, a
// side cut and a ball end's ramp: the surface engaged by one and not the other is under 1 % of
// the engaged area over each job (measured: 0.04 %, 0.03 %, 0.09 %) and at 95 % of its CLs
// (0.05 %, 0.05 %, 0.30 %), and the entry and exit within 0.05° at 95 % of them (0.015°). Only
// at first contact, where the areas are slivers, does a CL differ by more.
TEST(CliCompare, DexelAtFineResolutionAgreesWithTheBrepReference) {
  const auto dir = scratch_dir("compare-analytic");
  std::filesystem::create_directories(dir);
  struct Case {
    const char* name;
    const char* program;
    const char* tool;
  };
  for (const Case& c : {Case{"slot", kSlot, "flat:10,30"}, Case{"side", kSide, "flat:10,30"},
                        Case{"ramp", kRamp, "ball:10,30"}}) {
    SCOPED_TRACE(c.name);
    const auto program = dir / (std::string(c.name) + ".ngc");
    std::ofstream(program) << c.program;
    const Result r = run_cwe({"compare", "--stock", "box:0,0,0,60,40,20", "--tool", c.tool,
                              "--path", program.string(), "--workpieces", "dexel,brep",
                              "--resolution", "0.05", "--out", (dir / c.name).string(), "--quiet"});
    ASSERT_EQ(r.status, 0) << r.err;
    const nlohmann::json out = read_json(dir / c.name / "compare.json");
    EXPECT_EQ(out["reference"], "brep");
    const nlohmann::json& d = out["differences"]["dexel"];
    EXPECT_LT(d["exclusive_total_relative"].get<double>(), 0.01);
    EXPECT_LT(d["exclusive_relative"]["p95"].get<double>(), 0.01);
    EXPECT_LT(d["entry_deg"]["p95"].get<double>(), 0.05);
    EXPECT_LT(d["exit_deg"]["p95"].get<double>(), 0.05);
    EXPECT_EQ(d["engaged_by_one_only"], 0);
    EXPECT_LT(std::abs(out["runs"][0]["removed_volume_relative"].get<double>()), 1e-3);
  }
  std::filesystem::remove_all(dir);
}

TEST(CliCompare, BadWorkpieceListsAreNamed) {
  const auto dir = scratch_dir("compare-bad");
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "slot.ngc") << kSlot;
  for (const auto& [list, expected] :
       {std::pair{"dexel,octree", "'octree' is not a workpiece; expected dexel, mesh or brep"},
        std::pair{"mesh", "expected at least two workpieces"}}) {
    const Result r = run_cwe({"compare", "--stock", "box:0,0,0,60,40,20", "--tool", "flat:10,30",
                              "--path", (dir / "slot.ngc").string(), "--workpieces", list, "--out",
                              (dir / "out").string()});
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.err.find("--workpieces"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(expected), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir / "out"));
  }
  std::filesystem::remove_all(dir);
}

// Convergence: the tri-dexel workpiece at four resolutions against the B-rep one at the finest,
// on the ball end's ramp. The surface engaged by one only falls with the spacing (measured over
// the job: 4.6 %, 1.3 %, 0.42 %, 0.086 % at s = 0.4, 0.2, 0.1, 0.05), each run is a row of
// convergence.csv, and the figures are written.
TEST(CliCompare, ResolutionSweepConverges) {
  const auto dir = scratch_dir("compare-sweep");
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "ramp.ngc") << kRamp;
  const Result r =
      run_cwe({"compare", "--stock", "box:0,0,0,60,40,20", "--tool", "ball:10,30", "--path",
               (dir / "ramp.ngc").string(), "--workpieces", "dexel,brep", "--sweep-resolution",
               "0.4,0.2,0.1,0.05", "--out", (dir / "out").string(), "--quiet"});
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json c = read_json(dir / "out" / "compare.json");
  EXPECT_EQ(c["reference"], "brep");
  EXPECT_EQ(c["resolution_mm"].get<double>(), 0.05);  // the reference at the finest
  const auto rows = read_csv(dir / "out" / "convergence.csv");
  ASSERT_EQ(rows.size(), 5u);
  EXPECT_EQ(rows[0][0], "workpiece");
  EXPECT_EQ(rows[0][3], "exclusive_total_relative");
  double previous = 1.0;
  for (std::size_t k = 1; k < rows.size(); ++k) {
    SCOPED_TRACE(rows[k][1]);
    EXPECT_EQ(rows[k][0], "dexel");
    const double error = std::stod(rows[k][3]);
    EXPECT_LT(error, previous);
    previous = error;
  }
  EXPECT_LT(previous, 0.002);
  EXPECT_NEAR(c["differences"]["dexel_s0.05"]["exclusive_total_relative"].get<double>(),
              std::stod(rows[4][3]), 1e-5 * previous);  // the table's 6 digits
  for (const char* file : {"convergence.png", "convergence.svg", "convergence_time.png",
                           "convergence_time.svg", "differences.png", "differences.svg"}) {
    EXPECT_TRUE(std::filesystem::exists(dir / "out" / file)) << file;
  }
  // The maps where each run differs most from the reference, named by CL and run.
  for (const char* run : {"dexel_s0.4", "dexel_s0.2", "dexel_s0.1", "dexel_s0.05"}) {
    const std::size_t cl = c["differences"][run]["exclusive_area_mm2"]["max_cl"];
    const auto map = dir / "out" / "maps" / fmt::format("cl_{:06d}_{}.png", cl, run);
    EXPECT_TRUE(std::filesystem::exists(map)) << map;
  }
  std::filesystem::remove_all(dir);
}

TEST(CliCompare, BadSweepsAreNamed) {
  const auto dir = scratch_dir("compare-bad-sweep");
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "slot.ngc") << kSlot;
  const std::vector<std::string> common = {"compare",
                                           "--stock",
                                           "box:0,0,0,60,40,20",
                                           "--tool",
                                           "flat:10,30",
                                           "--path",
                                           (dir / "slot.ngc").string(),
                                           "--out",
                                           (dir / "out").string()};
  struct Case {
    std::vector<std::string> args;
    const char* expected;
  };
  for (const Case& c :
       {Case{{"--sweep-resolution", "0.2,x"},
             "--sweep-resolution: error: 'x' in '0.2,x': expected positive lengths in mm"},
        Case{{"--sweep-resolution", "0.2,-1"}, "'-1' in '0.2,-1': expected positive lengths"},
        Case{{"--sweep-resolution", "0.2", "--sweep-facet", "2"}, "one sweep at a time"},
        Case{{"--workpieces", "dexel,brep", "--sweep-facet", "2,1"},
             "the facet size is the mesh workpiece's; dexel has none"}}) {
    std::vector<std::string> args = common;
    args.insert(args.end(), c.args.begin(), c.args.end());
    const Result r = run_cwe(args);
    EXPECT_EQ(r.status, 2);
    EXPECT_NE(r.err.find(c.expected), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir / "out"));
  }
  std::filesystem::remove_all(dir);
}

// A run that fails (the B-rep workpiece refuses a concave cutter) stops the comparison with
// exit 3, naming the run and the move, and nothing is written.
TEST(CliCompare, AFailingRunIsNamedAndNothingIsWritten) {
  const auto dir = scratch_dir("compare-fails");
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "slot.ngc") << kSlot;
  const Result r = run_cwe({"compare", "--stock", "box:0,0,0,60,40,20", "--tool",
                            (test::source_dir() / "examples/tools/corner-rounding.json").string(),
                            "--path", (dir / "slot.ngc").string(), "--workpieces", "dexel,brep",
                            "--out", (dir / "out").string(), "--quiet"});
  EXPECT_EQ(r.status, 3);
  EXPECT_NE(r.err.find("the brep run: "), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("slot.ngc:2:"), std::string::npos) << r.err;  // its first move
  EXPECT_NE(r.err.find("concave"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "out"));
  std::filesystem::remove_all(dir);
}

// A run's records with one CL's engagement perturbed (a 10° strip cut off one disc's first
// interval): the comparison finds that CL, and only it, with the strip's area.
TEST(CompareRuns, APerturbedEngagementIsFoundAtItsCl) {
  const auto dir = scratch_dir("compare-perturbed");
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "slot.ngc") << kSlot;
  Job job;
  job.stock = "box:0,0,0,60,40,20";
  job.tool = "flat:10,30";
  job.path = (dir / "slot.ngc").string();
  job.resolution = 0.2;
  const PreparedJob prepared = prepare_job(job);
  RecordingSink sink;
  std::vector<ClSink*> sinks = {&sink};
  run_job(prepared, make_job_stock(prepared), RunOptions{true, false}, sinks);
  const std::vector<ClRecord>& reference = sink.records;
  ASSERT_GT(reference.size(), 100u);
  std::vector<ClRecord> perturbed = reference;
  const std::size_t at = 97;
  DiscEngagement& disc = perturbed[at].map.discs[5];
  ASSERT_FALSE(disc.phi.empty());
  const double strip = 10.0 * kPi / 180.0;
  disc.phi[0].lo += strip;
  const std::vector<ClDifference> differences = compare_runs(prepared, reference, perturbed);
  const DifferenceStats area = difference_stats(
      differences, [](const ClDifference& d) { return d.difference.exclusive_area; },
      [](const ClDifference&) { return true; });
  EXPECT_EQ(area.max_cl, at);
  EXPECT_NEAR(
      area.max,
      strip * side_area_per_radian(prepared.operations[0].cutter.profile(), disc.z0, disc.z1),
      1e-9);
  EXPECT_EQ(area.p99, 0.0);  // every other CL agrees
  // Runs whose CLs do not line up are refused.
  perturbed.pop_back();
  EXPECT_THROW(compare_runs(prepared, reference, perturbed), ComputationError);
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace cwe::app

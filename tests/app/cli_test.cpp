#include "cwe/app/cli.hpp"
#include "cli_testing.hpp"
#include "source_dir.hpp"
#include "step_fixtures.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "cwe/core/numbers.hpp"
#include "cwe/geometry/triangle_mesh.hpp"
#include "cwe/geometry/vec.hpp"
#include "cwe/io/atomic_file.hpp"
#include "cwe/io/mesh_io.hpp"
#include "cwe/io/step.hpp"

namespace cwe::app {
namespace {

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

namespace cwe::app {
namespace {

std::filesystem::path write_program(const std::string& name, const std::string& text) {
  const auto dir = std::filesystem::temp_directory_path() / "cwe-cli-test-path";
  std::filesystem::create_directories(dir);
  const auto path = dir / name;
  std::ofstream(path) << text;
  return path;
}

std::vector<nlohmann::json> json_lines(const std::string& text) {
  std::istringstream lines(text);
  std::string line;
  std::vector<nlohmann::json> out;
  while (std::getline(lines, line)) out.push_back(nlohmann::json::parse(line));
  return out;
}

TEST(CliPath, DumpsMovesInMillimetres) {
  const auto file = write_program("dump.ngc",
                                  "G20 G90 G17\n"
                                  "G0 X1 Y0 Z0.5\n"
                                  "G1 Z0 F10\n"
                                  "G2 X0 Y1 I-1 J0\n"  // quarter circle about the origin, clockwise
                                  "M2\n");
  const Result r = run_cwe({"path", file.string(), "--dump"});
  ASSERT_EQ(r.status, 0) << r.err;
  const auto moves = json_lines(r.out);
  ASSERT_EQ(moves.size(), 3u);
  EXPECT_EQ(moves[0]["type"], "rapid");
  EXPECT_EQ(moves[0]["line"], 2);
  EXPECT_DOUBLE_EQ(moves[0]["end"][0].get<double>(), 25.4);
  EXPECT_DOUBLE_EQ(moves[0]["end"][2].get<double>(), 12.7);
  EXPECT_EQ(moves[1]["type"], "feed");
  EXPECT_EQ(moves[2]["type"], "arc");
  EXPECT_EQ(moves[2]["normal"], nlohmann::json({0.0, 0.0, -1.0}));  // G2 in G17: -Z
  EXPECT_EQ(moves[2]["turns"], 0);
  EXPECT_NEAR(moves[2]["center"][0].get<double>(), 0.0, 1e-12);
  EXPECT_NEAR(moves[2]["end"][1].get<double>(), 25.4, 1e-12);
  EXPECT_EQ(moves[2]["axis"], nlohmann::json({0.0, 0.0, 1.0}));
}

TEST(CliPath, SummarisesBothFormats) {
  const std::string root = test::source_dir().string();
  const Result g = run_cwe({"path", root + "/examples/programs/pocket.ngc"});
  ASSERT_EQ(g.status, 0) << g.err;
  EXPECT_NE(g.out.find("(G-code, written in millimetres)"), std::string::npos) << g.out;
  EXPECT_NE(g.out.find("2 arc (1 helical, 2 of a full turn or more)"), std::string::npos) << g.out;
  EXPECT_NE(g.out.find(
                "tip bounds      X -10.000 .. 110.000, Y -2.500 .. 62.500, Z -12.000 .. 50.000 mm"),
            std::string::npos)
      << g.out;
  const Result c = run_cwe({"path", root + "/examples/programs/five_axis.cls"});
  ASSERT_EQ(c.status, 0) << c.err;
  EXPECT_NE(c.out.find("5-axis moves    4"), std::string::npos) << c.out;
  EXPECT_NE(c.out.find("tool T2         9 moves, loaded at line 5  CUTTER/6,3,0,3,0,0,25"),
            std::string::npos)
      << c.out;
}

TEST(CliPath, CutterLocationPoints) {
  // 10 mm along X at 600 mm/min, sampled every 2 mm: 5 CL points, 10 mm/s.
  const auto file = write_program("cl.ngc", "G0 X0 Y0 Z0\nG1 X10 F600\nM2\n");
  const Result r = run_cwe({"path", file.string(), "--cl-dump", "--cl-step", "2"});
  ASSERT_EQ(r.status, 0) << r.err;
  const auto points = json_lines(r.out);
  ASSERT_EQ(points.size(), 5u);
  EXPECT_DOUBLE_EQ(points[3]["position"][0].get<double>(), 6.0);
  EXPECT_DOUBLE_EQ(points[3]["velocity_mm_s"][0].get<double>(), 10.0);
  EXPECT_EQ(points[3]["line"], 2);
  const Result summary = run_cwe({"path", file.string(), "--cl-step", "2"});
  EXPECT_NE(summary.out.find("CL points       5 (every 2 mm"), std::string::npos) << summary.out;
  EXPECT_EQ(run_cwe({"path", file.string(), "--cl-step", "0"}).status, 2);
}

TEST(CliPath, SubroutineFilesFromTheSearchPath) {
  // A program calling a subroutine kept in a library folder, as LinuxCNC's SUBROUTINE_PATH.
  const auto lib = std::filesystem::temp_directory_path() / "cwe-cli-test-path" / "sublib";
  std::filesystem::create_directories(lib);
  std::ofstream(lib / "side.ngc") << "o<side> sub\nG1 X#1 F100\no<side> endsub\n";
  const auto file = write_program("calls.ngc", "G21 G0 Z1\no<side> call [7]\nG0 Z5\nM2\n");
  const Result missing = run_cwe({"path", file.string()});
  EXPECT_EQ(missing.status, 2);
  EXPECT_NE(missing.err.find(file.string() + ":2: error: subroutine o<side> is not defined"),
            std::string::npos)
      << missing.err;
  const Result r = run_cwe({"path", file.string(), "--dump", "--subroutine-path", lib.string()});
  ASSERT_EQ(r.status, 0) << r.err;
  const std::vector<nlohmann::json> moves = json_lines(r.out);
  ASSERT_EQ(moves.size(), 3u);
  EXPECT_FALSE(moves[0].contains("file"));
  EXPECT_EQ(moves[1]["file"], (lib / "side.ngc").string());
  EXPECT_EQ(moves[1]["line"], 2);
  EXPECT_EQ(moves[1]["end"][0], 7.0);
  EXPECT_FALSE(moves[2].contains("file"));
}

TEST(CliPath, EveryErrorOfAProgram) {
  const auto file = write_program("errors.ngc", "G21 F100\nG1 X[1/0]\nG1 X1\nG1 Y#<two>\nM2\n");
  const Result r = run_cwe({"path", file.string()});
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.err.rfind(file.string() + ":2:7: error: attempt to divide by zero\n" +
                            file.string() + ":4:5: error: named parameter #<two> not defined",
                        0),
            0u)
      << r.err;
}

// Each program of the malformed G-code corpus: exit 2, and standard error is its errors, one
// file:line:col line each, the first at the location its first (expect …) comment names.
TEST(CliPath, MalformedProgramsExitTwoWithTheirErrors) {
  const auto folder = test::source_dir() / "tests" / "toolpath" / "malformed";
  int programs = 0;
  for (const auto& entry : std::filesystem::directory_iterator(folder)) {
    if (entry.path().extension() != ".ngc") continue;
    ++programs;
    std::ifstream in(entry.path());
    std::string first;
    std::getline(in, first);  // (expect LINE:COLUMN text)
    const std::string where = first.substr(8, first.find(' ', 8) - 8);
    const Result r = run_cwe({"path", entry.path().string()});
    EXPECT_EQ(r.status, 2) << entry.path();
    const std::string prefix =
        entry.path().string() + ":" + (where.ends_with(":0") ? where.substr(0, where.size() - 2)
                                                              : where) + ": error: ";
    EXPECT_EQ(r.err.rfind(prefix, 0), 0u) << r.err;
    EXPECT_TRUE(r.out.empty()) << r.out;
  }
  EXPECT_GE(programs, 28);
}

TEST(CliPath, ErrorsNameFileLineAndColumn) {
  const auto file = write_program("bad.ngc", "G0 X0\nG1 X1 Y#<two> F100\n");
  const Result r = run_cwe({"path", file.string()});
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.err.rfind(file.string() + ":2:", 0), 0u) << r.err;
  EXPECT_NE(r.err.find("error:"), std::string::npos);
  const Result missing = run_cwe({"path", "/nonexistent/x.ngc"});
  EXPECT_EQ(missing.status, 2);
  EXPECT_NE(missing.err.find("cannot open the toolpath file"), std::string::npos);
}

}  // namespace
}  // namespace cwe::app

namespace cwe::app {
namespace {

TEST(CliEnvelope, WritesClosedVolumesCurvesAndPictures) {
  const auto dir = std::filesystem::temp_directory_path() / "cwe-cli-test-envelope";
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  const auto program = dir / "slot.ngc";
  std::ofstream(program) << "G21 G90\nG0 X0 Y0 Z1\nG1 Z-2 F100\nG1 X30 F600\nG0 Z5\nM2\n";
  const Result r = run_cwe({"envelope", "--tool", "flat:10,20", "--path", program.string(), "--out",
                            (dir / "out").string()});
  ASSERT_EQ(r.status, 0) << r.err;
  std::ifstream in(dir / "out" / "envelope.json");
  const nlohmann::json summary = nlohmann::json::parse(in);
  ASSERT_EQ(summary["moves"].size(), 2u);  // the two feed moves
  const auto& slot = summary["moves"][1];
  EXPECT_EQ(slot["move"], 3);
  EXPECT_EQ(slot["line"], 4);
  EXPECT_EQ(slot["states"][1]["motion"], "horizontal");
  // Stadium prism 20 mm high: (π·25 + 300)·20, inscribed within area × tolerance (≈ 26 mm³).
  const double exact = (cwe::kPi * 25.0 + 300.0) * 20.0;
  EXPECT_LT(slot["volume_mm3"].get<double>(), exact);
  EXPECT_GT(slot["volume_mm3"].get<double>(), exact - 30.0);
  const auto stl = dir / "out" / "move-3.stl";
  ASSERT_TRUE(std::filesystem::exists(stl));
  EXPECT_EQ(std::filesystem::file_size(stl), 84u + 50u * slot["triangles"].get<std::size_t>());
  for (const char* name :
       {"move-3.ply", "move-3-grazing.obj", "move-3-fcs-u0.5.svg", "move-2.stl"}) {
    EXPECT_TRUE(std::filesystem::exists(dir / "out" / name)) << name;
  }

  // FCS pictures at chosen cutter locations along the moves.
  ASSERT_EQ(run_cwe({"envelope", "--tool", "flat:10,20", "--path", program.string(), "--moves", "3",
                     "--fcs-at", "0,1", "--out", (dir / "at").string()})
                .status,
            0);
  EXPECT_TRUE(std::filesystem::exists(dir / "at" / "move-3-fcs-u0.svg"));
  EXPECT_TRUE(std::filesystem::exists(dir / "at" / "move-3-fcs-u1.svg"));

  // Bad selections and tools are input errors, and write nothing.
  EXPECT_EQ(run_cwe({"envelope", "--tool", "flat:10", "--path", program.string(), "--fcs-at", "2",
                     "--out", (dir / "none").string()})
                .status,
            2);
  const auto none = dir / "none";
  EXPECT_EQ(run_cwe({"envelope", "--tool", "flat:10", "--path", program.string(), "--moves", "9-12",
                     "--out", none.string()})
                .status,
            2);
  const Result concave = run_cwe(
      {"envelope", "--tool", (test::source_dir() / "examples/tools/corner-rounding.json").string(),
       "--path", program.string(), "--out", none.string()});
  EXPECT_EQ(concave.status, 2);
  EXPECT_NE(concave.err.find("convex"), std::string::npos) << concave.err;
  EXPECT_EQ(run_cwe({"envelope", "--path", program.string(), "--out", none.string()}).status, 2);
  EXPECT_FALSE(std::filesystem::exists(none));
  std::filesystem::remove_all(dir);
}

TEST(CliSimulate, WritesStockAndSummary) {
  const auto dir = scratch_dir("simulate");
  std::filesystem::create_directories(dir);
  const auto program = dir / "slot.ngc";
  // A 3 mm deep slot of width 10 through a 30 × 20 × 10 block (10 × 30 × 3 = 900 mm³), then a
  // rapid on line 8 that cuts 1 mm into the top beside the slot: x 10..20, y 0..5, z -1..0
  // (50 mm³; its round end lies in the slot). All faces lie on cell boundaries at s = 0.25.
  std::ofstream(program) << "G21 G90\nG0 X-10 Y10 Z1\nG1 Z-3 F100\nG1 X40 F600\nG0 Z5\n"
                            "G0 X15 Y-10\nG0 Z-1\nG0 Y5\nG0 Z5\nM2\n";
  const Result r = run_cwe({"simulate", "--stock", "box:0,0,-10,30,20,0", "--tool", "flat:10,20",
                            "--path", program.string(), "--out", (dir / "out").string(),
                            "--resolution", "0.25", "--threads", "2"});
  ASSERT_EQ(r.status, 0) << r.err;
  std::ifstream in(dir / "out" / "summary.json");
  const nlohmann::json summary = nlohmann::json::parse(in);
  EXPECT_EQ(summary["resolution_mm"], 0.25);
  EXPECT_EQ(summary["moves"], 8);
  EXPECT_NEAR(summary["initial_volume_mm3"].get<double>(), 6000.0, 1e-6);
  // Faces on cell boundaries are exact up to float rounding of the ray ends (~1e-6 mm).
  const double removed = summary["removed_volume_mm3"].get<double>();
  EXPECT_NEAR(summary["final_volume_mm3"].get<double>(), 6000.0 - removed, 1e-6);
  EXPECT_NEAR(removed, 950.0, 0.01);
  EXPECT_EQ(summary["rapid_cuts"]["count"], 1);
  EXPECT_EQ(summary["rapid_cuts"]["first"][0]["line"], 8);
  EXPECT_EQ(summary["rays"], 120u * 80u + 80u * 40u + 40u * 120u);
  EXPECT_GE(summary["peak_memory_bytes"].get<std::size_t>(),
            16u * summary["rays"].get<std::size_t>());
  EXPECT_GT(summary["seconds"].get<double>(), 0.0);
  // The wall time in its three stages, each under way for some time, adding up to it.
  const nlohmann::json& stages = summary["seconds_by_stage"];
  double staged = 0.0;
  for (const char* stage : {"set_up", "simulation", "closing"}) {
    EXPECT_GT(stages[stage].get<double>(), 0.0) << stage;
    staged += stages[stage].get<double>();
  }
  EXPECT_NEAR(staged, summary["seconds"].get<double>(), 1e-9);
  EXPECT_NE(r.out.find(" threads (set-up "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("rapid moves cut material"), std::string::npos) << r.out;
  const auto stl = dir / "out" / "stock.stl";
  ASSERT_TRUE(std::filesystem::exists(stl));
  EXPECT_EQ(std::filesystem::file_size(stl),
            84u + 50u * summary["stock_mesh"]["triangles"].get<std::size_t>());
  EXPECT_NEAR(summary["stock_mesh"]["volume_mm3"].get<double>(),
              summary["final_volume_mm3"].get<double>(), 0.02 * 6000.0);

  // Engagement at every cutter location: the CSV's header and one row per CL, the JSON lines,
  // the maps (about ten by default) and the plot along the path.
  const auto lines_of = [](const std::filesystem::path& file) {
    std::ifstream stream(file);
    std::vector<std::string> lines;
    for (std::string line; std::getline(stream, line);) lines.push_back(line);
    return lines;
  };
  const auto csv = lines_of(dir / "out" / "engagement.csv");
  ASSERT_FALSE(csv.empty());
  EXPECT_EQ(csv[0].rfind("cl,move,line,x,y,z,i,j,k,feed_x,feed_y,feed_z,engaged,phi_entry_deg,"
                         "phi_exit_deg,axial_depth_mm,area_mm2",
                         0),
            0u);
  const std::size_t cls = summary["engagement"]["cl_points"].get<std::size_t>();
  EXPECT_EQ(csv.size(), cls + 1);
  EXPECT_GT(summary["engagement"]["engaged_cl_points"].get<std::size_t>(), 0u);
  // The slot's steady state (x = 15): a full slot 3 mm deep, φ 0–180°.
  bool steady = false;
  for (const std::string& row : csv) {
    if (row.find(",15.0000,10.0000,-3.0000,") == std::string::npos) continue;
    steady = true;
    std::vector<std::string> field;
    std::stringstream fields(row);
    for (std::string f; std::getline(fields, f, ',');) field.push_back(f);
    ASSERT_GE(field.size(), 17u);
    EXPECT_EQ(field[12], "1") << row;
    // Within s/(√2 R) = 0.25/(√2·5) rad ≈ 2° of 0° and 180°, and 3 mm deep within s.
    EXPECT_NEAR(std::stod(field[13]), 0.0, 2.1) << row;
    EXPECT_NEAR(std::stod(field[14]), 180.0, 2.1) << row;
    EXPECT_NEAR(std::stod(field[15]), 3.0, 0.25) << row;
  }
  EXPECT_TRUE(steady);
  const auto jsonl = lines_of(dir / "out" / "engagement.jsonl");
  ASSERT_EQ(jsonl.size(), cls);
  for (std::size_t k = 0; k < jsonl.size(); ++k) {
    const nlohmann::json line = nlohmann::json::parse(jsonl[k]);
    EXPECT_EQ(line["cl"], k);
    EXPECT_TRUE(line["discs"].is_array());
    EXPECT_TRUE(line["bottom"]["rings"].is_array());
  }
  EXPECT_TRUE(std::filesystem::exists(dir / "out" / "maps" / "path.png"));
  EXPECT_TRUE(std::filesystem::exists(dir / "out" / "maps" / "path.svg"));
  std::size_t pngs = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir / "out" / "maps")) {
    pngs += entry.path().extension() == ".png" && entry.path().stem() != "path" ? 1 : 0;
  }
  EXPECT_EQ(pngs, summary["engagement"]["maps"].get<std::size_t>());
  // By default the first engaged CL of each tenth of the path: at most ten maps.
  EXPECT_GE(summary["engagement"]["maps"].get<std::size_t>(), 5u);
  EXPECT_LE(summary["engagement"]["maps"].get<std::size_t>(), 10u);

  // The same job from a JSON job file (paths relative to it); options still override.
  std::ofstream(dir / "job.json") << R"({"stock": "box:0,0,-10,30,20,0", "tool": "flat:10,20",
    "path": "slot.ngc", "out": "from-job", "resolution": 0.5, "mesh_stride": 2, "ply": true})";
  const Result job = run_cwe({"simulate", (dir / "job.json").string(), "--resolution", "0.25"});
  ASSERT_EQ(job.status, 0) << job.err;
  std::ifstream job_in(dir / "from-job" / "summary.json");
  const nlohmann::json job_summary = nlohmann::json::parse(job_in);
  EXPECT_EQ(job_summary["resolution_mm"], 0.25);
  EXPECT_EQ(job_summary["removed_volume_mm3"], summary["removed_volume_mm3"]);
  EXPECT_EQ(job_summary["stock_mesh"]["stride"], 2);
  EXPECT_EQ(job_summary["stock_mesh"]["lattice_mm"], 0.5);
  EXPECT_LT(job_summary["stock_mesh"]["triangles"].get<std::size_t>(),
            summary["stock_mesh"]["triangles"].get<std::size_t>() / 2);
  EXPECT_TRUE(std::filesystem::exists(dir / "from-job" / "stock.ply"));

  // The machined stock, read back as an STL stock: its volume is the mesh's, within the
  // scan's discretisation (area × s, area ≈ 2·(600 + 200 + 300) + the slot's walls).
  const Result again = run_cwe({"simulate", "--stock", stl.string(), "--tool", "flat:10,20",
                                "--path", program.string(), "--out", (dir / "again").string(),
                                "--resolution", "0.25", "--quiet"});
  ASSERT_EQ(again.status, 0) << again.err;
  std::ifstream again_in(dir / "again" / "summary.json");
  const nlohmann::json again_summary = nlohmann::json::parse(again_in);
  EXPECT_NEAR(again_summary["initial_volume_mm3"].get<double>(),
              summary["stock_mesh"]["volume_mm3"].get<double>(), 2400 * 0.25);
  EXPECT_LT(again_summary["removed_volume_mm3"].get<double>(), 1.0);  // already cut

  // Removal only: the same stock, no engagement outputs.
  const Result stock_only =
      run_cwe({"simulate", "--stock", "box:0,0,-10,30,20,0", "--tool", "flat:10,20", "--path",
               program.string(), "--out", (dir / "stock-only").string(), "--resolution", "0.25",
               "--stock-only"});
  ASSERT_EQ(stock_only.status, 0) << stock_only.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "stock-only" / "engagement.csv"));
  EXPECT_FALSE(std::filesystem::exists(dir / "stock-only" / "maps"));
  std::ifstream stock_only_in(dir / "stock-only" / "summary.json");
  const nlohmann::json stock_only_summary = nlohmann::json::parse(stock_only_in);
  // Whole moves here, CL steps there: the same solid, up to float rounding of ray ends.
  EXPECT_NEAR(stock_only_summary["removed_volume_mm3"].get<double>(),
              summary["removed_volume_mm3"].get<double>(), 0.05);
  EXPECT_FALSE(stock_only_summary.contains("engagement"));

  // An open STL is refused, saying how many boundary edges it has and where.
  std::ofstream(dir / "open.stl") << "solid open\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\n"
                                     "vertex 1 0 0\nvertex 0 1 0\nendloop\nendfacet\nendsolid\n";
  const Result open =
      run_cwe({"simulate", "--stock", (dir / "open.stl").string(), "--tool", "flat:10", "--path",
               program.string(), "--out", (dir / "none").string()});
  EXPECT_EQ(open.status, 2);
  EXPECT_NE(open.err.find("3 boundary edges"), std::string::npos) << open.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "none"));

  // Errors name what is wrong and write nothing.
  const auto none = dir / "none";
  for (const std::vector<std::string>& bad :
       {std::vector<std::string>{"simulate", "--stock", "box:0,0,0,1,1", "--tool", "flat:10",
                                 "--path", program.string(), "--out", none.string()},
        {"simulate", "--stock", "box:0,0,0,10,10,10", "--tool", "flat:10", "--path",
         program.string(), "--out", none.string(), "--resolution", "-1"},
        {"simulate", "--stock", "box:0,0,0,10,10,10", "--tool", "flat:10", "--out", none.string()},
        {"simulate", (dir / "missing.json").string()},
        {"simulate", "--stock", "box:0,0,0,10,10,10", "--tool", "flat:10", "--path",
         program.string(), "--out", none.string(), "--maps", "every:x"},
        {"simulate", "--stock", "box:0,0,0,10,10,10", "--tool", "flat:10", "--path",
         program.string(), "--out", none.string(), "--cl-step", "-1"}}) {
    const Result e = run_cwe(bad);
    EXPECT_EQ(e.status, 2) << e.err;
    EXPECT_NE(e.err.find("error"), std::string::npos) << e.err;
  }
  std::ofstream(dir / "typo.json") << R"({"stok": "box:0,0,0,1,1,1"})";
  const Result typo = run_cwe({"simulate", (dir / "typo.json").string()});
  EXPECT_EQ(typo.status, 2);
  EXPECT_NE(typo.err.find("stok"), std::string::npos) << typo.err;
  EXPECT_FALSE(std::filesystem::exists(none));
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace cwe::app

namespace cwe::app {
namespace {

// A 3 mm deep slot then a 1 mm side cut, flat end mill D = 10 with 4 flutes at 10,000 rev/min.
const char* const kForceProgram =
    "G21 G90\nS10000 M3\nG0 X-10 Y10 Z1\nG1 Z-3 F200\nG1 X60 F600\nG0 Z5\nG0 X-10 Y-3\n"
    "G1 Z-1 F200\nG1 X60 F900\nG0 Z5\nM2\n";

// stock.off as the mesh workpiece writes it: "OFF", a comment naming cwe, counts, vertices in
// double precision, triangles.
TriangleMesh read_stock_off(const std::filesystem::path& path) {
  std::ifstream off(path);
  std::string keyword, comment;
  std::getline(off, keyword);
  std::getline(off, comment);
  EXPECT_EQ(keyword, "OFF");
  EXPECT_EQ(comment.rfind("# cwe in-process stock", 0), 0u) << comment;
  std::size_t vertices = 0, faces = 0, edges = 0;
  off >> vertices >> faces >> edges;
  TriangleMesh read;
  for (std::size_t k = 0; k < vertices; ++k) {
    double x = 0.0, y = 0.0, z = 0.0;
    off >> x >> y >> z;
    read.vertices.emplace_back(x, y, z);
  }
  for (std::size_t k = 0; k < faces; ++k) {
    int n = 0, a = 0, b = 0, c = 0;
    off >> n >> a >> b >> c;
    EXPECT_EQ(n, 3);
    read.triangles.push_back({a, b, c});
  }
  EXPECT_TRUE(off.good()) << path;
  return read;
}

// With a thread to spare, stock.stl is encoded and written while the stock is contoured (the
// triangles made so far, behind the contouring; the count last). The file is the one a single
// thread writes after the contouring, byte for byte, and reads back closed with the count the
// summary gives. --stock-only: nothing else keeps the spare thread from the contouring.
TEST(CliSimulate, StockStlIsTheSameOnOneThreadAndTwo) {
  const auto dir = scratch_dir("simulate-stl-threads");
  const auto program = write_program("stl_threads.ngc",
                                     "G21 G90\nG0 X8 Y8 Z1\nG1 Z-4 F300\nG1 X32\nG1 Y22\nG1 X8\n"
                                     "G1 Y8\nG0 Z5\nM2\n");
  std::map<int, std::string> bytes;
  for (const int threads : {1, 2}) {
    const auto out = dir / fmt::format("out{}", threads);
    const Result r = run_cwe({"simulate", "--stock", "box:0,0,-10,40,30,0", "--tool", "flat:6,20",
                              "--path", program.string(), "--out", out.string(), "--resolution",
                              "0.2", "--stock-only", "--threads", std::to_string(threads)});
    ASSERT_EQ(r.status, 0) << r.err;
    std::ifstream in(out / "summary.json");
    const nlohmann::json summary = nlohmann::json::parse(in);
    const StlMesh stl = read_stl((out / "stock.stl").string());
    EXPECT_EQ(stl.mesh.triangles.size(), summary["stock_mesh"]["triangles"].get<std::size_t>());
    EXPECT_GT(stl.mesh.triangles.size(), 100'000u);  // tens of milliseconds of contouring
    EXPECT_TRUE(check_closure(stl.mesh).closed());
    std::ifstream file(out / "stock.stl", std::ios::binary);
    bytes[threads].assign(std::istreambuf_iterator<char>(file), {});
  }
  EXPECT_EQ(bytes[1].size(), bytes[2].size());
  EXPECT_TRUE(bytes[1] == bytes[2]) << "stock.stl differs between one thread and two";
  std::filesystem::remove_all(dir);
}

// The mesh workpiece (--workpiece mesh): a slot through the block removes the faceted sweep's
// volume, which for a feed along X is exactly the slot's (the rings' polygons have a vertex on
// each side of the feed), stock.stl is the mesh itself, and the engagement is the slot's.
TEST(CliSimulate, MeshWorkpiece) {
  const auto dir = scratch_dir("simulate-mesh");
  std::filesystem::create_directories(dir);
  const auto program = dir / "slot.ngc";
  std::ofstream(program) << "G21 G90\nG0 X-10 Y10 Z1\nG1 Z-3 F100\nG1 X40 F600\nG0 Z5\nM2\n";
  const std::vector<std::string> args = {"simulate",       "--stock",    "box:0,0,-10,30,20,0",
                                         "--tool",         "flat:10,20", "--path",
                                         program.string(), "--out",      (dir / "out").string(),
                                         "--resolution",   "0.25",       "--workpiece",
                                         "mesh",           "--facet",    "1"};
  std::vector<std::string> with_off = args;
  with_off.push_back("--off");
  const Result r = run_cwe(with_off);
  ASSERT_EQ(r.status, 0) << r.err;
  std::ifstream in(dir / "out" / "summary.json");
  const nlohmann::json summary = nlohmann::json::parse(in);
  EXPECT_EQ(summary["workpiece"], "mesh");
  EXPECT_EQ(summary["facet_mm"], 1.0);
  EXPECT_NEAR(summary["removed_volume_mm3"].get<double>(), 900.0, 1e-6);
  EXPECT_FALSE(summary.contains("rays"));
  EXPECT_EQ(summary["stock_mesh"]["triangles"], summary["triangles"]);
  EXPECT_NEAR(summary["stock_mesh"]["volume_mm3"].get<double>(), 6000.0 - 900.0, 1e-6);
  EXPECT_EQ(std::filesystem::file_size(dir / "out" / "stock.stl"),
            84u + 50u * summary["triangles"].get<std::size_t>());
  EXPECT_NE(r.out.find("as a triangle mesh, 1 mm facets"), std::string::npos) << r.out;
  // stock.off: the workpiece's own mesh in double precision, its volume the summary's.
  EXPECT_EQ(summary["stock_mesh"]["off"], "stock.off");
  const TriangleMesh read = read_stock_off(dir / "out" / "stock.off");
  EXPECT_EQ(read.triangles.size(), summary["triangles"].get<std::size_t>());
  EXPECT_TRUE(check_closure(read).closed());
  EXPECT_NEAR(read.volume(), 6000.0 - 900.0, 1e-9 * 6000.0);
  // The CL in the middle of the block: a full slot 3 mm deep.
  std::ifstream csv(dir / "out" / "engagement.csv");
  std::string line;
  std::getline(csv, line);
  bool seen = false;
  while (std::getline(csv, line)) {
    std::vector<std::string> cells;
    std::stringstream row(line);
    for (std::string cell; std::getline(row, cell, ',');) cells.push_back(cell);
    if (std::abs(std::stod(cells[3]) - 15.0) > 0.26 || std::stod(cells[5]) > -2.9) continue;
    seen = true;
    EXPECT_EQ(cells[12], "1") << line;
    EXPECT_NEAR(std::stod(cells[13]), 0.0, 1.0) << line;    // entry, degrees
    EXPECT_NEAR(std::stod(cells[14]), 180.0, 1.0) << line;  // exit
    EXPECT_NEAR(std::stod(cells[15]), 3.0, 0.25) << line;   // axial depth, mm
  }
  EXPECT_TRUE(seen);
  // Not a representation cwe has: exit 2 naming the option, nothing written.
  std::vector<std::string> bad = args;
  bad[bad.size() - 3] = "cube";
  bad[8] = (dir / "bad").string();
  const Result refused = run_cwe(bad);
  EXPECT_EQ(refused.status, 2);
  EXPECT_NE(refused.err.find("expected \"dexel\", \"mesh\" or \"brep\""), std::string::npos)
      << refused.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "bad"));
  std::filesystem::remove_all(dir);
}

// The bundled example's removal (both operations, three tools) on the mesh workpiece at 2 mm
// facets against the dexel workpiece at s = 0.1 mm. The faceted tools lie inside the true ones
// by at most h = R − √(R² − 1) (the 6 mm ball ends: 0.17 mm), so the mesh's stock holds the
// true stock and exceeds it only within h of its machined faces: it removes less, by at most
// h·S for S the machined area (the stock's faces off the block's). A dexel ray stands for its
// s × s cell, which puts the dexel's volume within s/2·S of the true one either way.
TEST(CliSimulate, MeshWorkpieceRemovesWhatTheDexelOneDoesOnTheExample) {
  const auto dir = scratch_dir("simulate-mesh-example");
  std::filesystem::create_directories(dir);
  const std::string root = test::source_dir().string();
  std::ofstream(dir / "job.json") << fmt::format(
      R"({{"stock": "box:0,0,-30,100,60,0", "tools": "{0}/examples/tool_table.json",
          "operations": [{{"path": "{0}/examples/programs/part.ngc"}},
                         {{"path": "{0}/examples/programs/five_axis_pass.cls"}}],
          "resolution": 0.1, "stock_only": true}})",
      root);
  double removed[2] = {0.0, 0.0};
  for (const std::string workpiece : {"dexel", "mesh"}) {
    const Result r =
        run_cwe({"simulate", (dir / "job.json").string(), "--workpiece", workpiece, "--facet", "2",
                 "--off", "--out", (dir / workpiece).string(), "--quiet"});
    ASSERT_EQ(r.status, 0) << r.err;
    std::ifstream in(dir / workpiece / "summary.json");
    removed[workpiece == "mesh"] = nlohmann::json::parse(in)["removed_volume_mm3"].get<double>();
  }
  const TriangleMesh stock = read_stock_off(dir / "mesh" / "stock.off");
  ASSERT_TRUE(check_closure(stock).closed());
  EXPECT_NEAR(stock.volume(), 180000.0 - removed[1], 1e-6 * 180000.0);
  // The machined area: the faces that do not lie on the block's faces.
  double machined = 0.0;
  for (const auto& t : stock.triangles) {
    const Vec3& a = stock.vertices[static_cast<std::size_t>(t[0])];
    const Vec3& b = stock.vertices[static_cast<std::size_t>(t[1])];
    const Vec3& c = stock.vertices[static_cast<std::size_t>(t[2])];
    const auto on = [&](int axis, double value) {
      return std::abs(a[axis] - value) < 1e-9 && std::abs(b[axis] - value) < 1e-9 &&
             std::abs(c[axis] - value) < 1e-9;
    };
    if (on(0, 0.0) || on(0, 100.0) || on(1, 0.0) || on(1, 60.0) || on(2, -30.0) || on(2, 0.0)) {
      continue;
    }
    machined += 0.5 * (b - a).cross(c - a).norm();
  }
  const double h = 3.0 - std::sqrt(3.0 * 3.0 - 1.0), s = 0.1;
  EXPECT_GT(machined, 1000.0);  // the example's slot, pockets and holes
  EXPECT_GE(removed[0] - removed[1], -0.5 * s * machined);
  EXPECT_LE(removed[0] - removed[1], (h + 0.5 * s) * machined);
  std::printf(
      "removed: dexel %.1f mm³, mesh %.1f mm³ (%+.2f %%); machined area %.0f mm², "
      "bound h·S = %.0f mm³\n",
      removed[0], removed[1], 100.0 * (removed[1] - removed[0]) / removed[0], machined,
      h * machined);
  std::filesystem::remove_all(dir);
}

// A STEP stock (the 60 × 40 × 20 block with two holes of radius 5 at y = 20) slotted 3 mm deep
// along y = 20 by a flat end mill D = 10: the slot takes 60 × 10 × 3 less the two holes' discs
// (the slot's ends lie off the block). On the mesh workpiece the slot's sides and floor are
// exact, and the holes' walls are polygons within the tolerance t inside them: it removes at
// most t times the holes' wall in the slot more. The dexel stock holds the block within s/2 of
// its surface.
TEST(CliSimulate, StepStockOnBothWorkpieces) {
  const auto dir = scratch_dir("simulate-step");
  std::filesystem::create_directories(dir);
  test::write_step_file(test::block_with_holes(), dir / "block.step");
  const auto program = dir / "slot.ngc";
  std::ofstream(program) << "G21 G90\nG0 X-10 Y20 Z25\nG0 Z17\nG1 X70 F600\nG0 Z25\nM2\n";
  const double slot = 60.0 * 10.0 * 3.0 - 2.0 * kPi * 25.0 * 3.0;
  for (const std::string workpiece : {"dexel", "mesh"}) {
    SCOPED_TRACE(workpiece);
    const Result r =
        run_cwe({"simulate", "--stock", (dir / "block.step").string(), "--tool", "flat:10,20",
                 "--path", program.string(), "--out", (dir / workpiece).string(), "--workpiece",
                 workpiece, "--stock-only"});
    ASSERT_EQ(r.status, 0) << r.err;
    EXPECT_NE(r.out.find("STEP stock  1 solid in millimetre"), std::string::npos) << r.out;
    std::ifstream in(dir / workpiece / "summary.json");
    const nlohmann::json summary = nlohmann::json::parse(in);
    const nlohmann::json& step = summary["stock_step"];
    EXPECT_EQ(step["solids"], 1);
    EXPECT_EQ(step["file_unit"], "millimetre");
    EXPECT_NEAR(step["volume_mm3"].get<double>(), test::kBlockWithHolesVolume, 1e-6);
    const double initial = summary["initial_volume_mm3"].get<double>();
    const double removed = summary["removed_volume_mm3"].get<double>();
    if (workpiece == "mesh") {
      const double t = step["tessellation_mm"].get<double>();
      EXPECT_EQ(t, summary["tolerance_mm"].get<double>());
      // The holes' polygons lie inside their circles: the stock holds the solid.
      EXPECT_GE(initial, test::kBlockWithHolesVolume);
      EXPECT_LE(initial, test::kBlockWithHolesVolume + t * 2.0 * kTwoPi * 5.0 * 20.0);
      EXPECT_GE(removed, slot - 1e-6);
      EXPECT_LE(removed, slot + t * 2.0 * kTwoPi * 5.0 * 3.0);
    } else {
      const double s = summary["resolution_mm"].get<double>();
      EXPECT_EQ(step["tessellation_mm"].get<double>(), s / 10.0);
      EXPECT_NEAR(initial, test::kBlockWithHolesVolume, 0.5 * s * test::kBlockWithHolesArea);
      // The slot's floor, sides and the holes' walls in it.
      const double cut_area = 60.0 * 10.0 + 2.0 * 60.0 * 3.0 + 2.0 * kTwoPi * 5.0 * 3.0;
      EXPECT_NEAR(removed, slot, 0.5 * s * cut_area);
    }
    std::printf("%s: stock %.2f mm³ (exact %.2f), removed %.2f mm³ (exact %.2f)\n",
                workpiece.c_str(), initial, test::kBlockWithHolesVolume, removed, slot);
  }
  // A STEP file that holds no solid: exit 2, the file named, nothing written.
  std::ofstream(dir / "junk.stp") << "ISO-10303-21;\nEND-ISO-10303-21;\n";
  const Result bad =
      run_cwe({"simulate", "--stock", (dir / "junk.stp").string(), "--tool", "flat:10,20", "--path",
               program.string(), "--out", (dir / "bad").string()});
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.err.find("junk.stp"), std::string::npos) << bad.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "bad"));
  std::filesystem::remove_all(dir);
}

// The B-rep workpiece (--workpiece brep): a plunge and a full circle of a flat end mill D = 10 at
// radius 10, 3 mm deep, take the ring π(15² − 5²)·3 exactly; the in-process solid written to
// stock.step reads back as a STEP stock of the same volume (the round trip), and a second run on
// it cuts on. With engagement (the solid-model CWE), the plunge engages the whole bottom and
// half-way round the circle the front half is engaged 3 mm deep (a full slot, entry 0°, exit
// 180°), while at its end the circle comes back to where it started, which its start took. What
// it cannot do is refused: a concave cutter (exit 3, the move's line named). stock.stl, as an
// STL stock, is made a solid and cut like the STEP stock. A bull-nose round a corner, and a helix
// narrower than the tool (as linear pieces), are cut like the dexel workpiece cuts them.
TEST(CliSimulate, BrepWorkpieceCutsExactlyAndRoundTripsThroughStep) {
  const auto dir = scratch_dir("simulate-brep");
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "ring.ngc") << "G21 G90\nG0 X40 Y20 Z25\nG0 Z21\nG1 Z17 F200\n"
                                     "G2 X40 Y20 I-10 J0 F600\nG0 Z25\nM2\n";
  std::ofstream(dir / "slot.ngc") << "G21 G90\nG0 X-10 Y35 Z25\nG0 Z18\nG1 X70 F600\n"
                                     "G0 Z25\nM2\n";
  const auto simulate = [&](const std::string& stock, const std::string& program,
                            const std::string& out, bool stock_only = true) {
    std::vector<std::string> args = {"simulate", stock,   "--tool", "flat:10,30",  "--path",
                                     program,    "--out", out,      "--workpiece", "brep"};
    args.insert(args.begin() + 1, "--stock");
    if (stock_only) args.push_back("--stock-only");
    return run_cwe(args);
  };
  const Result r =
      simulate("box:0,0,0,60,40,20", (dir / "ring.ngc").string(), (dir / "ring").string());
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_NE(r.out.find("as an exact solid (B-rep)"), std::string::npos) << r.out;
  std::ifstream in(dir / "ring" / "summary.json");
  const nlohmann::json summary = nlohmann::json::parse(in);
  EXPECT_EQ(summary["workpiece"], "brep");
  const double ring = kPi * (15.0 * 15.0 - 5.0 * 5.0) * 3.0;
  EXPECT_NEAR(summary["removed_volume_mm3"].get<double>(), ring, 1e-6 * ring);
  const double left = summary["stock_solid"]["volume_mm3"].get<double>();
  EXPECT_NEAR(left, 48000.0 - ring, 1e-6 * ring);
  // stock.stl: the solid within s/10, closed; it holds at most that much less than the solid.
  const StlMesh stl = read_stl((dir / "ring" / "stock.stl").string());
  EXPECT_TRUE(check_closure(stl.mesh).closed());
  EXPECT_NEAR(stl.mesh.volume(), left, 0.01 * 2.0 * kTwoPi * 15.0 * 3.0);
  // The round trip, and a slot across the ring's edge on the solid read back.
  const Result again = simulate((dir / "ring" / "stock.step").string(), (dir / "slot.ngc").string(),
                                (dir / "again").string());
  ASSERT_EQ(again.status, 0) << again.err;
  std::ifstream in_again(dir / "again" / "summary.json");
  const nlohmann::json second = nlohmann::json::parse(in_again);
  EXPECT_NEAR(second["stock_step"]["volume_mm3"].get<double>(), left, 1e-9 * left);
  EXPECT_NEAR(second["initial_volume_mm3"].get<double>(), left, 1e-9 * left);
  // The slot (y = 30 … 40, 2 mm deep) takes 60 × 10 × 2 less what the ring took there: the
  // segment of its outer circle (R 15, 10 from the centre) beyond y = 30, 2 mm deep.
  const double segment = 225.0 * std::acos(10.0 / 15.0) - 10.0 * std::sqrt(125.0);
  const double slot = 1200.0 - 2.0 * segment;
  EXPECT_NEAR(second["removed_volume_mm3"].get<double>(), slot, 1e-6 * slot);
  // The engagement, along the circle (line 5) and in the plunge (line 4).
  const Result engaging =
      simulate("box:0,0,0,60,40,20", (dir / "ring.ngc").string(), (dir / "cwe").string(), false);
  ASSERT_EQ(engaging.status, 0) << engaging.err;
  std::ifstream csv(dir / "cwe" / "engagement.csv");
  std::string row;
  std::getline(csv, row);
  int plunging = 0, halfway = 0, closing = 0;
  while (std::getline(csv, row)) {
    std::vector<std::string> cells;
    for (std::size_t at = 0, end = 0; end != std::string::npos; at = end + 1) {
      end = row.find(',', at);
      cells.push_back(row.substr(at, end == std::string::npos ? end : end - at));
    }
    // cl,move,line,x,y,z,i,j,k,feed_x,feed_y,feed_z,engaged,phi_entry_deg,phi_exit_deg,
    // axial_depth_mm,area_mm2,u,…
    ASSERT_GT(cells.size(), 17u) << row;
    const int line = std::stoi(cells[2]);
    const double z = std::stod(cells[5]), area = std::stod(cells[16]), u = std::stod(cells[17]);
    if (line == 4 && z < 19.9 && z > 17.0) {
      EXPECT_NEAR(area, kPi * 25.0, 1e-4) << row;  // the whole bottom (the CSV has 4 decimals)
      ++plunging;
    } else if (line == 5 && u > 0.4 && u < 0.6) {
      EXPECT_EQ(cells[12], "1") << row;
      EXPECT_NEAR(std::stod(cells[13]), 0.0, 0.1) << row;
      EXPECT_NEAR(std::stod(cells[14]), 180.0, 0.1) << row;
      EXPECT_NEAR(std::stod(cells[15]), 3.0, 1e-4) << row;
      ++halfway;
    } else if (line == 5 && u > 0.99) {
      // Within a tool radius of its start the circle's front was cut by the start already.
      EXPECT_LT(area, 0.5 * kPi * 5.0 * 3.0) << row;
      ++closing;
    }
  }
  EXPECT_EQ(plunging, 5);  // z = 19.5 … 17.5
  EXPECT_GT(halfway, 10);
  EXPECT_GT(closing, 0);
  // stock.stl as the stock: its triangles made a solid, the slot cut from it. Its walls lie
  // within s/10 = 0.01 mm inside the ring's, so the slot takes what it took from the STEP stock
  // within 0.01 mm over the ring's wall in the slot (an arc of 2·acos(10/15) at R 15, 2 mm
  // deep).
  const Result from_stl = simulate((dir / "ring" / "stock.stl").string(),
                                   (dir / "slot.ngc").string(), (dir / "from-stl").string());
  ASSERT_EQ(from_stl.status, 0) << from_stl.err;
  EXPECT_NE(from_stl.out.find(
                fmt::format("STL stock   {} triangles made 1 solid", stl.mesh.triangles.size())),
            std::string::npos)
      << from_stl.out;
  std::ifstream in_stl(dir / "from-stl" / "summary.json");
  const nlohmann::json third = nlohmann::json::parse(in_stl);
  EXPECT_EQ(third["stock_mesh_solid"]["solids"], 1);
  EXPECT_NEAR(third["stock_mesh_solid"]["volume_mm3"].get<double>(), stl.mesh.volume(),
              1e-9 * left);
  EXPECT_NEAR(third["initial_volume_mm3"].get<double>(), stl.mesh.volume(), 1e-9 * left);
  EXPECT_NEAR(third["removed_volume_mm3"].get<double>(), slot,
              0.01 * 2.0 * std::acos(10.0 / 15.0) * 15.0 * 2.0);
  // A bull-nose round a corner (R_arc 4 below its radius 5): cut as the tools at both ends and
  // the revolved section, one after the other; the same volume as the dexel workpiece's within
  // its s/2 over the cut's surface (here under 0.5 %).
  std::ofstream(dir / "corner.ngc") << "G21 G90\nG0 X30 Y20 Z25\nG0 Z18\n"
                                       "G2 X34 Y24 I0 J4 F400\nG0 Z25\nM2\n";
  double corner_volume[2] = {0.0, 0.0};
  for (const std::string workpiece : {"dexel", "brep"}) {
    const Result corner =
        run_cwe({"simulate", "--stock", "box:0,0,0,60,40,20", "--tool", "bull:10,2,30", "--path",
                 (dir / "corner.ngc").string(), "--out", (dir / ("corner-" + workpiece)).string(),
                 "--workpiece", workpiece, "--stock-only"});
    ASSERT_EQ(corner.status, 0) << corner.err;
    std::ifstream in_corner(dir / ("corner-" + workpiece) / "summary.json");
    corner_volume[workpiece == "brep"] =
        nlohmann::json::parse(in_corner)["removed_volume_mm3"].get<double>();
  }
  EXPECT_NEAR(corner_volume[1], corner_volume[0], 5e-3 * corner_volume[0]);
  // A helix narrower than the tool (which the exact helix sweeps refuse) is cut as its linear
  // pieces, within the sweep tolerance, and the summary counts it; the same volume as the dexel
  // workpiece's within 0.5 %.
  std::ofstream(dir / "bore.ngc") << "G21 G90\nG0 X30 Y20 Z25\nG0 Z20\n"
                                     "G2 X30 Y20 Z16 I1 J0 F400\nG0 Z25\nM2\n";
  double bore_volume[2] = {0.0, 0.0};
  for (const std::string workpiece : {"dexel", "brep"}) {
    const Result bore =
        run_cwe({"simulate", "--stock", "box:0,0,0,60,40,20", "--tool", "flat:10,30", "--path",
                 (dir / "bore.ngc").string(), "--out", (dir / ("bore-" + workpiece)).string(),
                 "--workpiece", workpiece, "--stock-only"});
    ASSERT_EQ(bore.status, 0) << bore.err;
    std::ifstream in_bore(dir / ("bore-" + workpiece) / "summary.json");
    const nlohmann::json bored = nlohmann::json::parse(in_bore);
    bore_volume[workpiece == "brep"] = bored["removed_volume_mm3"].get<double>();
    if (workpiece == "brep") {
      EXPECT_EQ(bored["stock_solid"]["moves_in_linear_pieces"], 1);
      // Every cut's removal volume within 1e-4 of what the stock lost.
      EXPECT_EQ(bored["stock_solid"]["removal_volumes_off"], 0);
      EXPECT_EQ(bored["stock_solid"]["worst_removal_volume_relative"], 0.0);
      EXPECT_NE(bore.out.find("1 moves (5-axis, or helices, the sweeps or booleans refused) "
                              "as linear pieces"),
                std::string::npos)
          << bore.out;
    }
  }
  EXPECT_NEAR(bore_volume[1], bore_volume[0], 5e-3 * bore_volume[0]);
  // A cutter with a concave profile is refused, exit 3, with the move's line.
  const Result concave = run_cwe(
      {"simulate", "--stock", "box:0,0,0,60,40,20", "--tool",
       (test::source_dir() / "examples/tools/corner-rounding.json").string(), "--path",
       (dir / "slot.ngc").string(), "--out", (dir / "no3").string(), "--workpiece", "brep"});
  EXPECT_EQ(concave.status, 3);
  EXPECT_NE(concave.err.find("slot.ngc:2:"), std::string::npos) << concave.err;  // its first move
  EXPECT_NE(concave.err.find("concave"), std::string::npos) << concave.err;
  for (const char* none : {"no2", "no3"}) EXPECT_FALSE(std::filesystem::exists(dir / none));
  std::filesystem::remove_all(dir);
}

// A real program on the B-rep workpiece: FreeCAD's pocket and profile (tests/engagement/data),
// whole. Its zigzag lines end against walls earlier passes left at the tool's radius, where
// exact cuts left slivers and the third level's cut an invalid solid; with the fuzzy value the
// exact removal agrees with the dexel workpiece's within 0.1 % (the dexel method is within
// 0.03 % of independent references on such programs, docs/performance.md).
TEST(CliSimulate, BrepWorkpieceRunsAFreeCadPocket) {
  const auto dir = scratch_dir("simulate-brep-freecad");
  std::filesystem::create_directories(dir);
  const std::string program =
      (test::source_dir() / "tests/engagement/data/freecad_pocket_profile.ngc").string();
  double removed[2] = {0.0, 0.0};
  for (const std::string workpiece : {"dexel", "brep"}) {
    const Result r = run_cwe({"simulate", "--stock", "box:-1,-1,-1,81,51,21", "--tool", "flat:5,30",
                              "--path", program, "--out", (dir / workpiece).string(), "--workpiece",
                              workpiece, "--stock-only"});
    ASSERT_EQ(r.status, 0) << r.err;
    std::ifstream summary(dir / workpiece / "summary.json");
    removed[workpiece == "brep"] =
        nlohmann::json::parse(summary)["removed_volume_mm3"].get<double>();
  }
  EXPECT_NEAR(removed[1], removed[0], 1e-3 * removed[0]);
  std::filesystem::remove_all(dir);
}

// Writes the lines of the program `from` in `ranges` (first and last line, numbered from 1) to
// `to`, `after` following each range, and M2 at the end.
void write_excerpt(const std::filesystem::path& from, const std::filesystem::path& to,
                   std::initializer_list<std::pair<int, int>> ranges, const std::string& after) {
  std::ifstream in(from);
  std::ofstream out(to);
  std::string line;
  auto range = ranges.begin();
  for (int n = 1; range != ranges.end() && std::getline(in, line); ++n) {
    if (n < range->first) continue;
    out << line << "\n";
    if (n == range->second) {
      out << after;
      ++range;
    }
  }
  out << "M2\n";
}

// The volumes a `simulate` run (`args`, with --stock-only at s = 0.025) removes on the dexel and
// the B-rep workpiece (outputs in dir/dexel and dir/brep), and the dexel's family spread.
struct AgainstDexel {
  double dexel = 0.0, brep = 0.0, spread = 0.0;
};
AgainstDexel removed_against_dexel(const std::vector<std::string>& args,
                                   const std::filesystem::path& dir) {
  AgainstDexel out;
  for (const std::string workpiece : {"dexel", "brep"}) {
    std::vector<std::string> run = args;
    run.insert(run.end(), {"--workpiece", workpiece, "--resolution", "0.025", "--stock-only",
                           "--out", (dir / workpiece).string(), "--quiet"});
    const Result r = run_cwe(run);
    if (r.status != 0) {
      ADD_FAILURE() << workpiece << ": exit " << r.status << ": " << r.err;
      continue;
    }
    const nlohmann::json summary =
        nlohmann::json::parse(std::ifstream(dir / workpiece / "summary.json"));
    (workpiece == "brep" ? out.brep : out.dexel) = summary["removed_volume_mm3"].get<double>();
    if (workpiece == "dexel") out.spread = summary["volume_spread_mm3"].get<double>();
  }
  return out;
}

// The end mill's part of FreeCAD's two-tool program (lines 1-99 of freecad_two_tools.ngc) on the
// B-rep workpiece: its fuzzy cuts leave edges and vertices tolerant, and the two faces on such an
// edge stored their copies of its points 5.3e-4 mm apart, beyond the welder's tolerance (the
// edges' largest, 4.0e-4): stock.stl had 15 open edges of 4,599 and the run wrote nothing. Faces
// are joined on their edges by topology now; the mesh is closed and within the deviation (s/10)
// times its area of the solid.
TEST(CliSimulate, BrepStockOfAFreeCadPocketTessellatesClosed) {
  const auto dir = scratch_dir("simulate-brep-freecad-endmill");
  std::filesystem::create_directories(dir);
  const std::filesystem::path data = test::source_dir() / "tests/app/data";
  write_excerpt(data / "freecad_two_tools.ngc", dir / "endmill.ngc", {{1, 99}}, "");
  const Result r =
      run_cwe({"simulate", "--path", (dir / "endmill.ngc").string(), "--tools",
               (data / "freecad/Library/Default.fctl").string(), "--stock", "box:-1,-1,-1,61,41,16",
               "--workpiece", "brep", "--stock-only", "--out", (dir / "out").string(), "--quiet"});
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json summary = nlohmann::json::parse(std::ifstream(dir / "out" / "summary.json"));
  const double solid = summary["stock_solid"]["volume_mm3"].get<double>();
  EXPECT_GT(summary["removed_volume_mm3"].get<double>(), 30.0 * 16.0 * 6.0);  // the pocket at least
  const StlMesh stl = read_stl((dir / "out" / "stock.stl").string());
  ASSERT_TRUE(check_closure(stl.mesh).closed());
  double area = 0.0;
  for (const auto& t : stl.mesh.triangles) {
    const Vec3& a = stl.mesh.vertices[static_cast<std::size_t>(t[0])];
    area += 0.5 * (stl.mesh.vertices[static_cast<std::size_t>(t[1])] - a)
                      .cross(stl.mesh.vertices[static_cast<std::size_t>(t[2])] - a)
                      .norm();
  }
  EXPECT_NEAR(stl.mesh.volume(), solid, 0.01 * area);
  EXPECT_TRUE(std::filesystem::exists(dir / "out" / "stock.step"));
  std::filesystem::remove_all(dir);
}

// FreeCAD's two-tool program cut down to a plunge and a slot of its end mill (lines 1-22 of
// freecad_two_tools.ngc), then the bull nose's first level round the block (lines 96-120): four
// straight sides and four corners, arcs of the tool's radius (the first corner in two arcs, the
// one it starts on a hair less: 2.99956 mm). On the B-rep workpiece the straight side after the
// third corner left an invalid solid (exit 3) while the bull nose's corner (a horn torus: flat
// and corner radius 1.5 mm) was a general surface of revolution; its faces are tori now. Against
// the dexel workpiece at s = 0.025 within the dexel's family spread (measured 0.06 mm³ apart,
// spread 0.25).
TEST(CliSimulate, BrepCutsABullNoseRoundABlockAfterAPocket) {
  const auto dir = scratch_dir("simulate-brep-freecad-bullnose");
  std::filesystem::create_directories(dir);
  const std::filesystem::path data = test::source_dir() / "tests/app/data";
  write_excerpt(data / "freecad_two_tools.ngc", dir / "loop.ngc", {{1, 22}, {96, 120}}, "G0 Z21\n");
  const AgainstDexel removed = removed_against_dexel(
      {"simulate", "--path", (dir / "loop.ngc").string(), "--tools",
       (data / "freecad/Library/Default.fctl").string(), "--stock", "box:-1,-1,-1,61,41,16"},
      dir);
  // Most of the frame round the block (204 mm² by 5 mm: 1,020 mm³) is cut.
  EXPECT_GT(removed.brep, 900.0);
  EXPECT_NEAR(removed.brep, removed.dexel, removed.spread);
  std::filesystem::remove_all(dir);
}

// An 8 mm bull nose (corner 1) round a 60 x 40 block at two levels, its corners arcs of its
// radius, plunging where the loop closes. OpenCASCADE cut the second level's plunge and the side
// after it as nothing (a common of the same shapes held nothing either): the run lost 474 mm³ of
// 1,997 and ended with exit 0. Whatever OpenCASCADE does with it, the B-rep workpiece must either
// cut it as the dexel workpiece does (at s = 0.025, within its family spread) or refuse it with
// exit 3 and write nothing. The first two attempts at the plunge leave points inside the swept
// volume inside the stock and are refused; the third, with the larger fuzzy value, cuts it
// (measured 0.03 mm³ from the dexel workpiece, spread 0.08). This test guards the silent loss;
// BrepCutsAHornTorusBullNoseRoundABlock needs the third attempt to pass.
TEST(CliSimulate, BrepNeverLosesACutSilently) {
  const auto dir = scratch_dir("simulate-brep-silent");
  std::filesystem::create_directories(dir);
  {
    std::ofstream out(dir / "loop.ngc");
    out << "G21 G90 G17\nG0 Z25\n";
    for (const int z : {11, 6}) {
      out << "G0 X-4 Y0\nG0 Z20\nG1 Z" << z << " F500\n"
          << "G1 X-4 Y40\nG2 X0 Y44 I4 J0\nG1 X60 Y44\nG2 X64 Y40 I0 J-4\n"
          << "G1 X64 Y0\nG2 X60 Y-4 I-4 J0\nG1 X0 Y-4\nG2 X-4 Y0 I0 J4\nG0 Z25\n";
    }
    out << "M2\n";
  }
  const auto run = [&](const std::string& workpiece) {
    return run_cwe({"simulate", "--path", (dir / "loop.ngc").string(), "--tool", "bull:8,1,30",
                    "--stock", "box:-1,-1,-1,61,41,16", "--workpiece", workpiece, "--resolution",
                    "0.025", "--stock-only", "--out", (dir / workpiece).string(), "--quiet"});
  };
  const Result dexel = run("dexel");
  ASSERT_EQ(dexel.status, 0) << dexel.err;
  const nlohmann::json reference = nlohmann::json::parse(std::ifstream(dir / "dexel/summary.json"));
  const Result brep = run("brep");
  if (brep.status == 0) {
    const nlohmann::json summary = nlohmann::json::parse(std::ifstream(dir / "brep/summary.json"));
    EXPECT_NEAR(summary["removed_volume_mm3"].get<double>(),
                reference["removed_volume_mm3"].get<double>(),
                reference["volume_spread_mm3"].get<double>());
  } else {
    EXPECT_EQ(brep.status, 3) << brep.err;
    // Refused where the cut went wrong, not on an earlier move.
    EXPECT_NE(brep.err.find("loop.ngc:17:"), std::string::npos) << brep.err;
    EXPECT_FALSE(std::filesystem::exists(dir / "brep/summary.json"));
  }
  std::filesystem::remove_all(dir);
}

// A 6 mm bull nose round a 60 x 40 block at Z11: a plunge at `start` ("X.. Y..") and the moves
// `loop` back to it, in dir/loop.ngc, run on the dexel and B-rep workpieces. The B-rep must cut the
// frame round the block (204 mm² by 5 mm less the fillet the tool's corner leaves along the block's
// sides: about 925 mm³) as the dexel does, within its family spread.
void bull_nose_loop_against_dexel(const std::filesystem::path& dir, const std::string& start,
                                  const std::string& loop) {
  std::filesystem::create_directories(dir);
  {
    std::ofstream out(dir / "loop.ngc");
    out << "G21 G90 G17\nG0 Z25\nG0 " << start << "\nG0 Z20\nG1 Z11 F500\n"
        << loop << "G0 Z25\nM2\n";
  }
  const AgainstDexel removed =
      removed_against_dexel({"simulate", "--path", (dir / "loop.ngc").string(), "--tool",
                             "bull:6,1.5,30", "--stock", "box:-1,-1,-1,61,41,16"},
                            dir);
  EXPECT_GT(removed.brep, 900.0);
  EXPECT_NEAR(removed.brep, removed.dexel, removed.spread);
}

// A 6 mm bull nose (corner 1.5: a horn torus) round a 60 x 40 block, its corners arcs of its
// radius (the tool's side on each arc's axis), the loop closing where it plunged. The straight
// side after the third corner (line 12) gave a face of no width bounded by one edge of tolerance
// 3 mm, a valid solid of the right volume, and the last corner's cut never finished on it (an
// OpenCASCADE intersector stepping along that edge for ever). Such a result is refused now, and
// the side is cut with the larger fuzzy value (1e-5 of the stock's size). Against the dexel
// workpiece at s = 0.025 within its family spread (measured 0.06 mm³ apart, spread 0.24).
TEST(CliSimulate, BrepCutsAHornTorusBullNoseRoundABlock) {
  const auto dir = scratch_dir("simulate-brep-horn");
  bull_nose_loop_against_dexel(dir, "X-3 Y0",
                               "G1 X-3 Y40\nG2 X0 Y43 I3 J0\nG1 X60 Y43\nG2 X63 Y40 I0 J-3\n"
                               "G1 X63 Y0\nG2 X60 Y-3 I-3 J0\nG1 X0 Y-3\nG2 X-3 Y0 I0 J3\n");
  std::filesystem::remove_all(dir);
}

// The same 6 mm bull nose at one level, its corners arcs of radius 2.5 (tighter than the tool's
// 3): round each corner's axis the tool leaves a spike of stock 0.38 mm high (where the corner's
// radius at a height is under 2.5 mm). OpenCASCADE's cut of each corner's ring left a sliver of
// that spike (0.0063 mm³, which the ring sweeps: BrepStock.TightCornerTakesTheSliverTheLoopLeft)
// as a solid of its own touching the stock along edges; one weld over all the solids' faces made
// those edges non-manifold, and the run stopped with exit 3 writing nothing. Each solid is
// tessellated and checked on its own now, and such a cut is refused and cut again from the
// mended stock: the stock is one solid, its spikes standing on the floor. Against the dexel
// workpiece within its spread; the mesh's volume within its deviation times its area of the
// solid's.
TEST(CliSimulate, BrepStockWithSpikesAtTightCornersIsWritten) {
  const auto dir = scratch_dir("simulate-brep-spikes");
  bull_nose_loop_against_dexel(
      dir, "X-0.5 Y-3",
      "G1 X60.5 Y-3\nG3 X63 Y-0.5 I0 J2.5\nG1 X63 Y40.5\nG3 X60.5 Y43 I-2.5 J0\n"
      "G1 X-0.5 Y43\nG3 X-3 Y40.5 I0 J-2.5\nG1 X-3 Y-0.5\nG3 X-0.5 Y-3 I2.5 J0\n");
  ASSERT_TRUE(std::filesystem::exists(dir / "brep" / "stock.step"));
  const StepModel model = StepModel::read((dir / "brep" / "stock.step").string());
  EXPECT_EQ(model.solids(), 1);  // the block, its spikes standing on the floor
  const nlohmann::json summary =
      nlohmann::json::parse(std::ifstream(dir / "brep" / "summary.json"));
  EXPECT_GE(summary["stock_solid"]["cuts_from_mended_stock"].get<int>(), 1);
  const double deviation = summary["stock_mesh"]["deviation_mm"].get<double>();
  EXPECT_TRUE(check_closure(model.tessellate(deviation)).closed());
  const StlMesh stl = read_stl((dir / "brep" / "stock.stl").string());
  EXPECT_NEAR(stl.mesh.volume(), summary["stock_solid"]["volume_mm3"].get<double>(),
              deviation * stl.mesh.area());
  std::filesystem::remove_all(dir);
}

// The bundled example (examples/jobs/example.json's operations: the program with two tools,
// slot, side milling, ramp, a helical entry of three turns and the circle after it, plunge, peck
// drilling, the ball end's finishing passes; then the simultaneous 5-axis pass) on the B-rep
// workpiece: every 3-axis move its exact sweep, the pass's four tilting moves lofted (within the
// sweep tolerance s/10 inside the stock's box), no move in linear pieces; against the dexel
// workpiece at s = 0.05, within the dexel's own family spread (its three ray families' removals
// differ by that much; measured 4.2 mm³ apart, spread 5.1 mm³).
TEST(CliSimulate, BrepCutsTheBundledExampleExactly) {
  const auto dir = scratch_dir("simulate-brep-bundled");
  std::filesystem::create_directories(dir);
  const std::filesystem::path examples = test::source_dir() / "examples";
  const nlohmann::json job = {{"stock", "box:0,0,-30,100,60,0"},
                              {"tools", (examples / "tool_table.json").string()},
                              {"operations",
                               {{{"path", (examples / "programs/part.ngc").string()}},
                                {{"path", (examples / "programs/five_axis_pass.cls").string()}}}},
                              {"resolution", 0.05}};
  std::ofstream(dir / "job.json") << job.dump();
  double removed[2] = {0.0, 0.0};
  nlohmann::json dexel;
  for (const std::string workpiece : {"dexel", "brep"}) {
    const Result r = run_cwe({"simulate", (dir / "job.json").string(), "--workpiece", workpiece,
                              "--stock-only", "--out", (dir / workpiece).string(), "--quiet"});
    ASSERT_EQ(r.status, 0) << r.err;
    const nlohmann::json summary =
        nlohmann::json::parse(std::ifstream(dir / workpiece / "summary.json"));
    removed[workpiece == "brep"] = summary["removed_volume_mm3"].get<double>();
    if (workpiece == "dexel") dexel = summary;
    if (workpiece == "brep") {
      EXPECT_EQ(summary["stock_solid"]["moves_lofted"], 4);
      EXPECT_LE(summary["stock_solid"]["worst_loft_deviation_mm"].get<double>(), 0.005);
      EXPECT_EQ(summary["stock_solid"]["moves_in_linear_pieces"], 0);
      EXPECT_NE(r.out.find("4 5-axis moves lofted"), std::string::npos) << r.out;
    }
  }
  EXPECT_NEAR(removed[1], removed[0], dexel["volume_spread_mm3"].get<double>());
  std::filesystem::remove_all(dir);
}

// FreeCAD's two-tool program whole, with its engagement, on the B-rep workpiece: the end mill's
// pocket, then the 6 mm bull nose (corner 1.5) round the block at three levels, each loop closing
// on what its first corner cut, along walls earlier passes left at the tool's radius. It stopped
// with exit 3 at the second level's last corner (line 130), where the removal volume held
// nothing: building it on the cut's own intersection had altered the stock kept before, so the
// cuts that followed differed from a run without the engagement. (Where no attempt gives a
// removal volume that holds what the stock lost, the engagement reads the stock before the cut,
// BrepEngagement.ReadingTheStockBeforeTheCutGivesTheRemovalVolumesMaps; seen once at line 142,
// not on every run.) Against the dexel workpiece at the same settings (s = 0.25, a location a
// millimetre, the sweep tolerance 0.01 mm to keep the B-rep's cuts those of the default run):
// the same removal within the dexel's family spread and the same locations engaged; entry and
// exit angles everywhere within the dexel's cell s/(√2·ρ) plus the reach of its contact
// tolerance s/10 past a wall the tool grazes, √(2·s/10/ρ), at the smallest radius of a side disc
// (ρ = 1.5 mm, the bull nose's torus at its tip: 17.3°), and at the 95th percentile within the
// cell on the end mill's side (ρ = 2.5 mm: 4.1°), where most of the angles lie (measured 3.0°,
// at most 9.1°).
TEST(CliSimulate, BrepRunsFreeCadsTwoToolProgramWithItsEngagement) {
  const auto dir = scratch_dir("simulate-brep-freecad-engagement");
  std::filesystem::create_directories(dir);
  const std::filesystem::path data = test::source_dir() / "tests/app/data";
  const double s = 0.25;
  std::vector<std::vector<std::vector<std::string>>> rows;
  std::vector<nlohmann::json> summaries;
  for (const std::string workpiece : {"dexel", "brep"}) {
    const Result r = run_cwe({"simulate",
                              "--path",
                              (data / "freecad_two_tools.ngc").string(),
                              "--tools",
                              (data / "freecad/Library/Default.fctl").string(),
                              "--stock",
                              "box:-1,-1,-1,61,41,16",
                              "--workpiece",
                              workpiece,
                              "--resolution",
                              "0.25",
                              "--tolerance",
                              "0.01",
                              "--cl-step",
                              "1",
                              "--maps",
                              "none",
                              "--out",
                              (dir / workpiece).string(),
                              "--quiet"});
    ASSERT_EQ(r.status, 0) << workpiece << ": " << r.err;
    rows.push_back(read_csv(dir / workpiece / "engagement.csv"));
    summaries.push_back(nlohmann::json::parse(std::ifstream(dir / workpiece / "summary.json")));
  }
  EXPECT_NEAR(summaries[1]["removed_volume_mm3"].get<double>(),
              summaries[0]["removed_volume_mm3"].get<double>(),
              summaries[0]["volume_spread_mm3"].get<double>());
  const auto& dexel = rows[0];
  const auto& brep = rows[1];
  ASSERT_EQ(brep.size(), dexel.size());
  ASSERT_GT(brep.size(), 1000U);
  const auto cell = [&](double rho) { return s / (std::sqrt(2.0) * rho) * 180.0 / kPi; };
  const auto reach = [&](double rho) { return std::sqrt(2.0 * s / 10.0 / rho) * 180.0 / kPi; };
  std::vector<double> off;  // entry and exit angle differences, degrees
  for (std::size_t k = 1; k < brep.size(); ++k) {
    ASSERT_EQ(brep[k][12], dexel[k][12]) << "CL " << brep[k][0] << ", line " << brep[k][2];
    if (brep[k][12] != "1") continue;
    for (const std::size_t column : {13U, 14U}) {
      const double a = std::abs(std::stod(brep[k][column]) - std::stod(dexel[k][column]));
      const double d = std::min(a, 360.0 - a);  // 359.9° and 0.1° are 0.2° apart
      EXPECT_LE(d, cell(1.5) + reach(1.5)) << "CL " << brep[k][0] << ", line " << brep[k][2];
      off.push_back(d);
    }
  }
  std::sort(off.begin(), off.end());
  EXPECT_LE(off[off.size() * 95 / 100], cell(2.5));
  std::filesystem::remove_all(dir);
}

// The tilted pass of tests/toolpath/data/contour_catia.aptsource and the tilted slot after it:
// a 10 mm bull-nose descending while it tilts from vertical to 30°, whose grazing curve changes
// its kind twice, so the pass is lofted in parts; the sliver the slot leaves where the pass ends
// collapses in the stock's tessellation into a fold, which stock.stl must not keep. The dexel
// workpiece removes 432.05 mm³ at s = 0.1 and 432.11 at s = 0.05 (207 s on 2 threads: too slow
// to run here), which extrapolate (first order, as the slot alone converges) to 432.18; the
// B-rep gives 432.47, 0.29 over, where its stock is known to be off (docs/brep.md, "Not yet").
// The bound 0.5 mm³ holds that and fails a lost or doubled part (200 mm³) or chip.
TEST(CliSimulate, BrepLoftsATiltingPassInPartsAndWritesItsStock) {
  const auto dir = scratch_dir("simulate-brep-tilting");
  std::filesystem::create_directories(dir);
  const auto program = dir / "tilt.aptsource";
  // The CATIA contour's last moves (tests/toolpath/data/contour_catia.aptsource): the tilted
  // pass, the tilted slot and the return rapid, which rises out of the slot while the tool turns
  // back upright and takes almost nothing. With the slot's opening integrated as part of the
  // stock's top face the stock's volume came out 0.74 mm³ short, and the rapid, whose cut
  // rebuilt that face, made the stock seem to grow: the run stopped with exit 3 at line 12
  // (shape_volume, docs/brep.md).
  std::ofstream(program) << "PARTNO TILT\nUNITS/MM\nCUTTER/10,1,4,1,0,0,50\nMULTAX\n"
                            "FROM/0,0,100,0,0,1\nRAPID\nGOTO/30,-20,20,0,0,1\nFEDRAT/800,MMPM\n"
                            "GOTO/40,0,10,0.5,0,0.866025\nGOTO/40,10,10,0.5,0,0.866025\n"
                            "RAPID\nGOTO/0,0,100,0,0,1\nFINI\n";
  const Result r = run_cwe({"simulate", "--stock", "box:-40,-40,-10,50,40,12", "--path",
                            program.string(), "--workpiece", "brep", "--resolution", "0.05",
                            "--stock-only", "--out", (dir / "out").string(), "--quiet"});
  ASSERT_EQ(r.status, 0) << r.err;
  const nlohmann::json summary = nlohmann::json::parse(std::ifstream(dir / "out" / "summary.json"));
  // The dexel workpiece removes 432.126, 432.155 and 432.110 mm³ of the pass and the slot at
  // s = 0.1, 0.05 and 0.025 in a box round them (it does not converge more closely than that);
  // the rapid takes 0.057 at s = 0.05, the B-rep's 0.03.
  EXPECT_NEAR(summary["removed_volume_mm3"].get<double>(), 432.16, 0.1);
  EXPECT_EQ(summary["stock_solid"]["moves_lofted"], 2);
  EXPECT_LE(summary["stock_solid"]["worst_loft_deviation_mm"].get<double>(), 0.005);
  EXPECT_EQ(summary["stock_solid"]["moves_in_linear_pieces"], 0);
  // The tessellation within 0.005 mm holds the solid's volume within that depth over the
  // machined faces (some 400 mm² of them).
  EXPECT_NEAR(summary["stock_mesh"]["volume_mm3"].get<double>(),
              summary["stock_solid"]["volume_mm3"].get<double>(), 2.0);
  std::filesystem::remove_all(dir);
}

// A mesh boolean that cannot give a solid: the second slot leaves the two remaining blocks
// touching along the line y = 10, z = 5 (the rings' vertices lie exactly on the slots' sides),
// which no 2-manifold can hold. The run stops with exit 3 naming the move's line, in the
// engagement run and in the removal-only run alike, and writes nothing.
TEST(CliSimulate, MeshBooleanThatCannotBeASolidExitsThree) {
  const auto dir = scratch_dir("simulate-mesh-fails");
  std::filesystem::create_directories(dir);
  const auto program = dir / "edge.ngc";
  std::ofstream(program) << "G21 G90 F600\nG0 X-10 Y5 Z20\nG1 Z5\nG1 X40\nG0 Z40\n"
                            "G0 X-10 Y15\nG0 Z-15\nG1 X40\nG0 Z40\nM2\n";
  for (const bool stock_only : {false, true}) {
    SCOPED_TRACE(stock_only ? "stock only" : "engagement");
    std::vector<std::string> args = {
        "simulate",       "--stock", "box:0,0,0,30,20,10",   "--tool",      "flat:10,20", "--path",
        program.string(), "--out",   (dir / "out").string(), "--workpiece", "mesh"};
    if (stock_only) args.push_back("--stock-only");
    const Result r = run_cwe(args);
    EXPECT_EQ(r.status, 3) << r.err;
    EXPECT_NE(r.err.find("edge.ngc:8: mesh removal:"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("2-manifold"), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir / "out"));
  }
  std::filesystem::remove_all(dir);
}

TEST(CliForces, SlotForcesMatchTheClosedForm) {
  const auto dir = scratch_dir("forces");
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "cut.ngc") << kForceProgram;
  const Result r = run_cwe({"simulate", "--stock", "box:0,0,-10,50,20,0", "--tool", "flat:10,20",
                            "--path", (dir / "cut.ngc").string(), "--out", (dir / "out").string(),
                            "--resolution", "0.25", "--forces", "al7075-t6-carbide", "--helix", "0",
                            "--force-curves", "cl:40", "--maps", "none"});
  ASSERT_EQ(r.status, 0) << r.err;
  const auto rows = read_csv(dir / "out" / "forces.csv");
  ASSERT_GT(rows.size(), 50u);
  const std::vector<std::string> required = {"cl",
                                             "move",
                                             "feed_per_tooth_mm",
                                             "mean_fx_n",
                                             "mean_fy_n",
                                             "mean_fz_n",
                                             "peak_fx_n",
                                             "peak_fy_n",
                                             "peak_fz_n",
                                             "peak_resultant_n",
                                             "mean_torque_nm",
                                             "peak_torque_nm",
                                             "mean_power_w"};
  ASSERT_GE(rows[0].size(), required.size());
  for (std::size_t i = 0; i < required.size(); ++i) EXPECT_EQ(rows[0][i], required[i]);
  EXPECT_EQ(rows.size(), read_csv(dir / "out" / "engagement.csv").size());
  // CL 40 is mid-slot (x ≈ 15): full immersion 0..180°, a = 3 mm, c = 600/(4·10000) = 0.015 mm.
  // Closed forms (docs/forces.md) with the bundled Al7075-T6 set.
  const std::vector<std::string>& row = rows[41];
  ASSERT_EQ(row[0], "40");
  const double ktc = 767.01, krc = 168.8, kte = 27.7, kre = 26.6;
  const double n = 4, a = 3, c = 0.015;
  const double fx = n * a * c / (8 * kPi) * (-krc * 2 * kPi) + n * a / (2 * kPi) * (-2 * kre);
  const double fy = n * a * c / (8 * kPi) * (ktc * 2 * kPi) + n * a / (2 * kPi) * (2 * kte);
  EXPECT_NEAR(std::stod(row[2]), c, 1e-9);
  // The map's angles are within a ray spacing of 0°/180° and its discs span 3 mm: 2%.
  EXPECT_NEAR(std::stod(row[3]), fx, 0.02 * std::abs(fy));
  EXPECT_NEAR(std::stod(row[4]), fy, 0.02 * std::abs(fy));
  for (const char* ext : {".csv", ".png", ".svg"}) {
    EXPECT_TRUE(
        std::filesystem::exists(dir / "out" / "force_curves" / (std::string("cl_000040") + ext)));
  }
  const nlohmann::json summary = nlohmann::json::parse(std::ifstream(dir / "out" / "summary.json"));
  EXPECT_GT(summary["forces"]["max_peak_resultant_n"]["value"].get<double>(), std::abs(fy));
  EXPECT_NE(r.out.find("forces.csv"), std::string::npos) << r.out;
  // A feed override sets the feed per tooth: 1200 / (4 × 10000).
  const Result fed =
      run_cwe({"simulate", "--stock", "box:0,0,-10,50,20,0", "--tool", "flat:10,20", "--path",
               (dir / "cut.ngc").string(), "--out", (dir / "fed").string(), "--resolution", "0.5",
               "--forces", "al7075-t6-carbide", "--feed", "1200", "--maps", "none"});
  ASSERT_EQ(fed.status, 0) << fed.err;
  const auto fed_rows = read_csv(dir / "fed" / "forces.csv");
  ASSERT_GT(fed_rows.size(), 2u);
  EXPECT_EQ(fed_rows[1][2], "0.030000");
  EXPECT_EQ(fed_rows[1][15], "1200.000");
  // Curves without forces, and a spindle step finer than 0.01°, are refused.
  const std::vector<std::string> base = {"simulate",
                                         "--stock",
                                         "box:0,0,-10,50,20,0",
                                         "--tool",
                                         "flat:10,20",
                                         "--path",
                                         (dir / "cut.ngc").string(),
                                         "--out",
                                         (dir / "bad").string(),
                                         "--resolution",
                                         "0.5"};
  std::vector<std::string> curves = base;
  curves.insert(curves.end(), {"--force-curves", "cl:1"});
  const Result no_forces = run_cwe(curves);
  EXPECT_EQ(no_forces.status, 2);
  EXPECT_NE(no_forces.err.find("force curves need --forces"), std::string::npos) << no_forces.err;
  std::vector<std::string> fine = base;
  fine.insert(fine.end(), {"--forces", "al7075-t6-carbide", "--force-step", "0.001"});
  EXPECT_EQ(run_cwe(fine).status, 2);
  EXPECT_FALSE(std::filesystem::exists(dir / "bad" / "forces.csv"));
}

TEST(CliSchedule, ScheduledProgramNeverExceedsTheLimit) {
  const auto dir = scratch_dir("schedule");
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "cut.ngc") << kForceProgram;
  const std::vector<std::string> job = {"--stock",    "box:0,0,-10,50,20,0", "--tool",
                                        "flat:10,20", "--resolution",        "0.25",
                                        "--forces",   "al7075-t6-carbide",   "--quiet"};
  auto with = [&](std::vector<std::string> args) {
    args.insert(args.end(), job.begin(), job.end());
    return args;
  };
  // At the programmed 600 mm/min the slot peaks at about 198 N and at the 2× ceiling at about
  // 235 N, so 220 N binds inside the bounds (a limit below the edge forces alone, ~165 N, cannot
  // be met at any feed: tested below).
  const double limit = 220.0;
  const Result s =
      run_cwe(with({"schedule", "--path", (dir / "cut.ngc").string(), "--limit", "force=220N",
                    "--out", (dir / "scheduled.ngc").string(), "--max-change", "4"}));
  ASSERT_EQ(s.status, 0) << s.err;
  EXPECT_NE(s.out.find("feed time"), std::string::npos) << s.out;
  // The scheduled program reads back and, simulated, stays within the limit at every CL.
  const Result r = run_cwe(with({"simulate", "--path", (dir / "scheduled.ngc").string(), "--out",
                                 (dir / "out").string(), "--maps", "none"}));
  ASSERT_EQ(r.status, 0) << r.err;
  const auto rows = read_csv(dir / "out" / "forces.csv");
  double peak = 0.0;
  for (std::size_t i = 1; i < rows.size(); ++i) peak = std::max(peak, std::stod(rows[i][9]));
  EXPECT_LE(peak, limit * (1 + 1e-5));
  // The slot is the heavy cut: it runs at the limit (within the CL sampling of its entry).
  EXPECT_GT(peak, 0.95 * limit);
  // Only F words changed: the text has the same lines apart from them.
  std::ifstream in(dir / "scheduled.ngc");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("G1 X60 F"), std::string::npos) << text;
  EXPECT_EQ(text.find("G1 X60 F600\n"), std::string::npos) << text;
  // Asking for a limit the edge forces alone exceed is reported, not hidden.
  const Result low = run_cwe(with({"schedule", "--path", (dir / "cut.ngc").string(), "--limit",
                                   "force=20N", "--out", (dir / "low.ngc").string()}));
  ASSERT_EQ(low.status, 0) << low.err;
  EXPECT_NE(low.out.find("exceed the limit even at the lowest feed"), std::string::npos) << low.out;
  // Errors: the schedule over its own input, no coefficients, a bad limit.
  EXPECT_EQ(run_cwe(with({"schedule", "--path", (dir / "cut.ngc").string(), "--limit", "force=220N",
                          "--out", (dir / "cut.ngc").string()}))
                .status,
            2);
  EXPECT_EQ(run_cwe({"schedule", "--stock", "box:0,0,-10,50,20,0", "--tool", "flat:10,20", "--path",
                     (dir / "cut.ngc").string(), "--limit", "force=250N", "--out",
                     (dir / "x.ngc").string()})
                .status,
            2);
  EXPECT_EQ(run_cwe(with({"schedule", "--path", (dir / "cut.ngc").string(), "--limit", "speed=3",
                          "--out", (dir / "x.ngc").string()}))
                .status,
            2);
}

// A slot in two 3 mm levels: the second level cuts no deeper than the first, so the schedule
// gives both the same feed (the walls the first level left beside the second are not engagement).
// A program whose moves come from a subroutine file is refused before the run: only the program
// file is rewritten. A subroutine file without moves does not stop it.
TEST(CliSchedule, MovesFromASubroutineFileAreRefused) {
  const auto dir = scratch_dir("schedule-sub");
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "slot.ngc") << "o<slot> sub\nG1 X60 F600\no<slot> endsub\n";
  std::ofstream(dir / "depth.ngc") << "o<depth> sub\n#<_depth> = -3\no<depth> endsub\n";
  std::ofstream(dir / "main.ngc")
      << "G21 G90 G17\nS10000 M3\nG0 X-10 Y10 Z1\nG1 Z-3 F300\no<slot> call\nG0 Z5\nM2\n";
  std::ofstream(dir / "own.ngc") << "G21 G90 G17\nS10000 M3\no<depth> call\nG0 X-10 Y10 Z1\n"
                                    "G1 Z#<_depth> F300\nG1 X60 F600\nG0 Z5\nM2\n";
  const auto schedule = [&](const char* program) {
    return run_cwe({"schedule", "--path", (dir / program).string(), "--stock",
                    "box:0,0,-10,50,20,0", "--tool", "flat:10,20", "--resolution", "0.5",
                    "--forces", "al7075-t6-carbide", "--quiet", "--limit", "force=220N", "--out",
                    (dir / "scheduled.ngc").string()});
  };
  const Result refused = schedule("main.ngc");
  EXPECT_EQ(refused.status, 2);
  EXPECT_NE(refused.err.find("main.ngc: error: the program includes other files"),
            std::string::npos)
      << refused.err;
  EXPECT_FALSE(std::filesystem::exists(dir / "scheduled.ngc"));
  const Result own = schedule("own.ngc");
  EXPECT_EQ(own.status, 0) << own.err;
  EXPECT_TRUE(std::filesystem::exists(dir / "scheduled.ngc"));
}

TEST(CliSchedule, StepDownLevelsOfEqualDepthGetEqualFeeds) {
  const auto dir = scratch_dir("schedule_levels");
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "levels.ngc")
      << "G21 G90\nS10000 M3\nG0 X-10 Y10 Z1\nG1 Z-3 F200\nG1 X60 F600\nG0 Z5\nG0 X-10\n"
         "G1 Z-6 F200\nG1 X60 F600\nG0 Z5\nM2\n";
  const Result s = run_cwe({"schedule", "--stock", "box:0,0,-10,50,20,0", "--tool", "flat:10,20",
                            "--resolution", "0.25", "--forces", "al7075-t6-carbide", "--quiet",
                            "--path", (dir / "levels.ngc").string(), "--limit", "force=220N",
                            "--max-change", "4", "--out", (dir / "scheduled.ngc").string()});
  ASSERT_EQ(s.status, 0) << s.err;
  std::ifstream in(dir / "scheduled.ngc");
  std::vector<std::string> feeds;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("G1 X60 F", 0) == 0) feeds.push_back(line.substr(8));
  }
  ASSERT_EQ(feeds.size(), 2u);
  EXPECT_EQ(feeds[0], feeds[1]);
  EXPECT_NE(feeds[0], "600");  // the limit binds: the feed was rescheduled
}

// A program that changes tools, G-code as posts write it: a flat end mill slots, a ball end
// mill follows in the slot's floor.
constexpr const char* kTwoToolHeader = "G21 G90 G17\n";
constexpr const char* kFlatPart = "T1 M6\nS10000 M3\nG0 X-10 Y10 Z1\nG1 Z-3 F300\nG1 X60 F600\nG0 Z5\n";
constexpr const char* kBallPart = "T2 M6\nS12000 M3\nG0 X-10 Y13 Z1\nG1 Z-4 F300\nG1 X60 F600\nG0 Z5\n";

// Every move is cut by the tool loaded at it, from a tool table: the same removal and the same
// engagement as the two programs run as two operations, and a tool column in the outputs.
TEST(CliTools, AProgramThatChangesToolsIsCutByEachTool) {
  const auto dir = scratch_dir("tools");
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "both.ngc") << kTwoToolHeader << kFlatPart << kBallPart << "M2\n";
  std::ofstream(dir / "flat.ngc") << kTwoToolHeader << kFlatPart << "M2\n";
  std::ofstream(dir / "ball.ngc") << kTwoToolHeader << kBallPart << "M2\n";
  std::ofstream(dir / "table.json")
      << R"({"tools": {"1": "flat:10,20", "2": {"spec": "ball:6,20", "flutes": 2}}})";
  const std::vector<std::string> common = {"--stock", "box:0,0,-10,50,20,0", "--resolution",
                                           "0.25", "--maps", "none", "--quiet"};
  auto with = [&](std::vector<std::string> args) {
    args.insert(args.end(), common.begin(), common.end());
    return args;
  };
  const Result both =
      run_cwe(with({"simulate", "--path", (dir / "both.ngc").string(), "--tools",
                    (dir / "table.json").string(), "--out", (dir / "both").string()}));
  ASSERT_EQ(both.status, 0) << both.err;
  std::ofstream(dir / "split.json") << R"({"operations": [{"tool": "flat:10,20", "path": "flat.ngc"},
                                                          {"tool": "ball:6,20", "path": "ball.ngc"}]})";
  const Result split = run_cwe(with({"simulate", (dir / "split.json").string(), "--out",
                                     (dir / "split").string()}));
  ASSERT_EQ(split.status, 0) << split.err;
  const auto summary = [](const std::filesystem::path& file) {
    std::ifstream in(file);
    return nlohmann::json::parse(in);
  };
  const double removed = summary(dir / "both" / "summary.json")["removed_volume_mm3"];
  const double reference = summary(dir / "split" / "summary.json")["removed_volume_mm3"];
  EXPECT_NEAR(removed, reference, 1e-4 * reference);
  EXPECT_GT(removed, 1000.0);
  // The same cutter locations, each with its tool, engaged alike.
  const auto a = read_csv(dir / "both" / "engagement.csv");
  const auto b = read_csv(dir / "split" / "engagement.csv");
  ASSERT_EQ(a.size(), b.size());
  ASSERT_EQ(a[0].back(), "tool");
  std::set<std::string> tools;
  for (std::size_t i = 1; i < a.size(); ++i) {
    tools.insert(a[i].back());
    EXPECT_EQ(a[i].back(), std::stoi(a[i][2]) <= 9 ? "1" : "2") << "line " << a[i][2];
    for (const std::size_t column : {13u, 14u, 15u, 16u}) EXPECT_EQ(a[i][column], b[i][column]);
  }
  EXPECT_EQ(tools, (std::set<std::string>{"1", "2"}));
  EXPECT_EQ(summary(dir / "both" / "summary.json")["operations"][1]["tool_number"], 2);
}

// Never a silent reuse: a tool the table lacks, or one --tool for a program that changes tools,
// is an error at the tool change; --tool-for-all asks for the reuse.
TEST(CliTools, MissingToolsAreErrorsAtTheToolChange) {
  const auto dir = scratch_dir("tools_errors");
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "both.ngc") << kTwoToolHeader << kFlatPart << kBallPart << "M2\n";
  std::ofstream(dir / "one.json") << R"({"1": "flat:10,20"})";
  const std::vector<std::string> common = {"simulate", "--path", (dir / "both.ngc").string(),
                                           "--stock", "box:0,0,-10,50,20,0", "--resolution", "0.5",
                                           "--out", (dir / "out").string(), "--maps", "none",
                                           "--quiet"};
  auto with = [&](std::vector<std::string> args) {
    args.insert(args.begin(), common.begin(), common.end());
    return args;
  };
  // The ball's T2 M6 is line 8.
  const std::string at = (dir / "both.ngc").string() + ":8:1: error: ";
  const Result missing = run_cwe(with({"--tools", (dir / "one.json").string()}));
  EXPECT_EQ(missing.status, 2);
  EXPECT_NE(missing.err.find(at + "tool 2 is not in the tool table"), std::string::npos)
      << missing.err;
  const Result single = run_cwe(with({"--tool", "flat:10,20"}));
  EXPECT_EQ(single.status, 2);
  EXPECT_NE(single.err.find(at), std::string::npos) << single.err;
  EXPECT_NE(single.err.find("--tool-for-all"), std::string::npos) << single.err;
  const Result none = run_cwe(with({}));
  EXPECT_EQ(none.status, 2);
  EXPECT_NE(none.err.find(at), std::string::npos) << none.err;
  EXPECT_EQ(run_cwe(with({"--tool", "flat:10,20", "--tool-for-all"})).status, 0);
  // `cwe path` says where each tool is loaded.
  const Result listing = run_cwe({"path", (dir / "both.ngc").string()});
  ASSERT_EQ(listing.status, 0) << listing.err;
  EXPECT_NE(listing.out.find("tool T2         4 moves, loaded at line 8"), std::string::npos)
      << listing.out;
  // A table that is not one.
  for (const char* bad : {R"({"one": "flat:10"})", R"({"1": "flat:-3"})", R"({"1": 7})",
                          R"({"1": {"spec": "ball:6", "flutes": 0}})", R"([1, 2])", "{1:"}) {
    std::ofstream(dir / "bad.json") << bad;
    const Result r = run_cwe(with({"--tools", (dir / "bad.json").string()}));
    EXPECT_EQ(r.status, 2) << bad;
    EXPECT_NE(r.err.find("bad.json"), std::string::npos) << bad << ": " << r.err;
  }
}

// The schedule of a program that changes tools follows each tool and writes the program once.
TEST(CliTools, ScheduleFollowsEachTool) {
  const auto dir = scratch_dir("tools_schedule");
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "both.ngc") << kTwoToolHeader << kFlatPart << kBallPart << "M2\n";
  std::ofstream(dir / "table.json") << R"({"1": "flat:10,20", "2": "ball:6,20"})";
  const Result s = run_cwe({"schedule", "--path", (dir / "both.ngc").string(), "--tools",
                            (dir / "table.json").string(), "--stock", "box:0,0,-10,50,20,0",
                            "--resolution", "0.25", "--forces", "al7075-t6-carbide", "--quiet",
                            "--limit", "force=220N", "--max-change", "4", "--out",
                            (dir / "scheduled.ngc").string()});
  ASSERT_EQ(s.status, 0) << s.err;
  EXPECT_NE(s.out.find("(tool 1)"), std::string::npos) << s.out;
  EXPECT_NE(s.out.find("(tool 2)"), std::string::npos) << s.out;
  std::ifstream in(dir / "scheduled.ngc");
  std::vector<std::string> slots;
  for (std::string line; std::getline(in, line);) {
    if (line.rfind("G1 X60 F", 0) == 0) slots.push_back(line);
  }
  // Both slots rescheduled, each for its own tool, cutter and spindle speed.
  ASSERT_EQ(slots.size(), 2u);
  EXPECT_NE(slots[0], "G1 X60 F600");
  EXPECT_NE(slots[1], "G1 X60 F600");
  EXPECT_NE(slots[0], slots[1]);
}

// A straight groove along X at Y10, `depth` mm deep, with tool `tool`.
std::string groove_program(int tool, int depth) {
  return "G21 G90\nT" + std::to_string(tool) + " M6\nS10000 M3\nG0 X-10 Y10 Z1\nG1 Z-" +
         std::to_string(depth) + " F300\nG1 X60 F600\nG0 Z5\nM2\n";
}

// FreeCAD 0.20's own tool library and bits (tests/app/data/freecad, as FreeCAD ships them): the
// tool numbers a program loads map to cwe's cutters; a bit cwe cannot model (the library's
// slitting saw) is an error only for a program that loads it, at that line.
TEST(CliTools, FreeCadLibraryAndBits) {
  const auto dir = scratch_dir("tools_freecad");
  std::filesystem::create_directories(dir);
  const std::string library =
      (test::source_dir() / "tests/app/data/freecad/Library/Default.fctl").string();
  std::ofstream(dir / "prog.ngc") << kTwoToolHeader << kFlatPart
                                  << "T3 M6\nS12000 M3\nG0 X-10 Y13 Z1\nG1 Z-4 F300\n"
                                     "G1 X60 F600\nG0 Z5\nT4 M6\nG0 X-10 Y8 Z1\nG1 Z-2 F300\n"
                                     "G1 X60 F600\nG0 Z5\nM2\n";
  const Result r = run_cwe({"simulate", "--path", (dir / "prog.ngc").string(), "--tools", library,
                            "--stock", "box:0,0,-10,50,20,0", "--resolution", "0.5", "--out",
                            (dir / "out").string(), "--maps", "none", "--quiet"});
  ASSERT_EQ(r.status, 0) << r.err;
  std::ifstream in(dir / "out" / "summary.json");
  const nlohmann::json summary = nlohmann::json::parse(in);
  ASSERT_EQ(summary["operations"].size(), 3u);
  // 5mm_Endmill.fctb, 6mm_Ball_End.fctb and 6mm_Bullnose.fctb (FlatRadius 1.5: corner 1.5).
  EXPECT_EQ(summary["operations"][0]["tool"], "flat:5,30");
  EXPECT_EQ(summary["operations"][1]["tool"], "ball:6,40");
  EXPECT_EQ(summary["operations"][2]["tool"], "bull:6,1.5,40");
  EXPECT_EQ(summary["operations"][2]["tool_number"], 4);
  // T5 and T6, the 60° v-bit (tip 1 mm) and the 45° chamfer mill (tip 5 mm): cones at half their
  // CuttingEdgeAngle from the axis, as FreeCAD draws them. A groove 2 mm deep with the v-bit across
  // the 50 mm block removes 50·∫₀² 2(0.5 + t·tan 30°) dt = 215.5 mm³; 1 mm deep with the chamfer
  // mill, 50·∫₀¹ 2(2.5 + t·tan 22.5°) dt = 270.7 mm³ (within 1 %: the rays at s = 0.1 cross the
  // grooves' slanted walls).
  for (const auto& [tool, depth, expected] :
       {std::tuple{5, 2, 50 * 2 * (0.5 * 2 + std::tan(kPi / 6) * 2)},
        std::tuple{6, 1, 50 * 2 * (2.5 + std::tan(kPi / 8) / 2)}}) {
    SCOPED_TRACE(testing::Message() << "T" << tool);
    std::ofstream(dir / "cone.ngc") << groove_program(tool, depth);
    const Result cone = run_cwe({"simulate", "--path", (dir / "cone.ngc").string(), "--tools",
                                 library, "--stock", "box:0,0,-10,50,20,0", "--resolution", "0.1",
                                 "--out", (dir / "cone").string(), "--maps", "none", "--quiet",
                                 "--stock-only"});
    ASSERT_EQ(cone.status, 0) << cone.err;
    std::ifstream cone_summary(dir / "cone" / "summary.json");
    EXPECT_NEAR(nlohmann::json::parse(cone_summary)["removed_volume_mm3"].get<double>(), expected,
                0.01 * expected);
  }
  // T7, the slitting saw.
  std::ofstream(dir / "saw.ngc") << kTwoToolHeader << kFlatPart << "T7 M6\nG0 X-10 Y8 Z1\nM2\n";
  const Result saw = run_cwe({"simulate", "--path", (dir / "saw.ngc").string(), "--tools",
                              library, "--stock", "box:0,0,-10,50,20,0", "--out",
                              (dir / "out2").string(), "--quiet"});
  EXPECT_EQ(saw.status, 2);
  EXPECT_NE(saw.err.find((dir / "saw.ngc").string() + ":8:1: error: tool 7"), std::string::npos)
      << saw.err;
  EXPECT_NE(saw.err.find("slittingsaw"), std::string::npos) << saw.err;
}

// A job whose program calls a subroutine kept in a library folder named relative to the job.
TEST(CliSimulate, JobSubroutinePathIsRelativeToTheJob) {
  const auto dir = scratch_dir("job_subroutines");
  std::filesystem::create_directories(dir / "lib");
  // A 10 mm flat end mill slotting 1 mm deep along 40 mm of a block: 10 × 1 × 40 mm³, plus the
  // half disc at each end of the slot, π·5²/2 × 1 mm³ each.
  std::ofstream(dir / "lib" / "slot.ngc") << "o<slot> sub\nG1 Z#1 F300\nG1 X40\no<slot> endsub\n";
  std::ofstream(dir / "main.ngc") << "G21 G0 X0 Y10 Z2\no<slot> call [-1]\nG0 Z5\nM2\n";
  std::ofstream(dir / "job.json") << nlohmann::json{{"stock", "box:-10,0,-5,50,20,0"},
                                                     {"tool", "flat:10,20"},
                                                     {"path", "main.ngc"},
                                                     {"subroutine_path", "lib"},
                                                     {"resolution", 0.1},
                                                     {"stock_only", true},
                                                     {"out", "out"}}
                                         .dump();
  const Result r = run_cwe({"simulate", (dir / "job.json").string(), "--quiet"});
  ASSERT_EQ(r.status, 0) << r.err;
  std::ifstream summary(dir / "out" / "summary.json");
  const double expected = 10.0 * 1.0 * 40.0 + kPi * 25.0;
  // Within 1 %: the rays at s = 0.1 mm cross the slot's round ends.
  EXPECT_NEAR(nlohmann::json::parse(summary)["removed_volume_mm3"].get<double>(), expected,
              0.01 * expected);
}

// A job's machine definition (inline) and tool table reach the G-code reader: a program in G55
// with a G53 retract and cutter radius compensation cuts exactly what its plain equivalent in
// the stock's frame cuts.
TEST(CliSimulate, MachineDefinitionAndCompensationInAJob) {
  const auto dir = scratch_dir("job_machine");
  std::filesystem::create_directories(dir);
  // A 10 mm tool to the left of the line Y-5 (G41 D1): its centre runs along Y0.
  std::ofstream(dir / "posted.ngc")
      << "G21 G90 G53 G0 Z0\nT1 M6\nG55\nG0 X-20 Y-20\nZ2\nG1 Z-1 F300\n"
         "G41 D1 G1 X0 Y-5\nX40\nG40 G1 X60 Y-20\nG53 G0 Z0\nM2\n";
  // Compensated by hand: the entry ends 5 mm left of (0, -5) square to its direction (4, 3)/5,
  // at (-3, -1); an arc about (0, -5) rounds the convex corner onto Y0; G40 leaves from (40, 0).
  std::ofstream(dir / "plain.ngc")
      << "G21 G90 G0 Z300\nT1 M6\nG0 X-20 Y-20\nZ2\nG1 Z-1 F300\n"
         "G1 X-3 Y-1\nG2 X0 Y0 I3 J-4\nG1 X40\nX60 Y-20\nG0 Z300\nM2\n";
  const nlohmann::json machine = {{"work_offsets", {{"G54", {-400, -200, -300}},
                                                    {"G55", {-300, -200, -300}}}},
                                  {"travel", {{"min", {-800, -500, -400}}, {"max", {0, 0, 0}}}},
                                  {"frame", "G55"}};
  double volumes[2] = {0.0, 0.0};
  for (int k = 0; k < 2; ++k) {
    nlohmann::json job = {{"stock", "box:-10,-10,-5,50,10,0"},
                          {"tools", {{"1", "flat:10,20"}}},
                          {"path", k == 0 ? "posted.ngc" : "plain.ngc"},
                          {"resolution", 0.2},
                          {"stock_only", true},
                          {"out", k == 0 ? "out0" : "out1"}};
    if (k == 0) job["machine"] = machine;
    std::ofstream(dir / "job.json") << job.dump();
    const Result r = run_cwe({"simulate", (dir / "job.json").string(), "--quiet"});
    ASSERT_EQ(r.status, 0) << r.err;
    std::ifstream summary(dir / (k == 0 ? "out0" : "out1") / "summary.json");
    volumes[k] = nlohmann::json::parse(summary)["removed_volume_mm3"].get<double>();
  }
  EXPECT_GT(volumes[0], 400.0);
  // The moves agree to rounding (1e-12 mm): the removal is the same ray for ray.
  EXPECT_NEAR(volumes[0], volumes[1], 1e-6 * volumes[1]);

  // The same through cwe path --machine, and the definition's errors.
  std::ofstream(dir / "machine.json") << machine.dump();
  std::ofstream(dir / "tools.json") << R"({"1": "flat:10,20"})";
  const Result dump = run_cwe({"path", (dir / "posted.ngc").string(), "--dump", "--tools",
                               (dir / "tools.json").string(), "--machine",
                               (dir / "machine.json").string()});
  ASSERT_EQ(dump.status, 0) << dump.err;
  EXPECT_NE(dump.out.find("\"end\":[0.0,0.0,300.0]"), std::string::npos) << dump.out;
  std::ofstream(dir / "bad.json") << R"({"work_offsets": {"G60": [0, 0, 0]}})";
  const Result bad = run_cwe({"path", (dir / "posted.ngc").string(), "--machine",
                              (dir / "bad.json").string()});
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.err.find("bad.json: \"work_offsets\": error: \"G60\": expected G54"),
            std::string::npos)
      << bad.err;
}

// Command-line values are checked like every other value, and CLI11's own errors come in cwe's
// form: OPTION: error: 'VALUE': expected …, exit 2. Written 0 is never "the default".
TEST(CliErrors, CommandLineValuesInCwesForm) {
  const std::vector<std::string> base = {"simulate", "--stock", "box:0,0,0,1,1,1", "--tool",
                                         "flat:1",   "--path",  "x.ngc",           "--out", "o"};
  const std::pair<std::vector<std::string>, std::string> cases[] = {
      {{"--threads", "0"}, "--threads: error: '0': expected a whole number of threads, at least 1"},
      {{"--resolution", "abc"}, "--resolution: error: 'abc': expected a positive length in mm"},
      {{"--resolution", "0"}, "--resolution: error: '0': expected a positive length in mm"},
      {{"--tolerance", "-1"}, "--tolerance: error: '-1': expected a positive length in mm"},
      {{"--cl-step", "1e-400"}, "--cl-step: error: '1e-400': expected a positive length in mm"},
      {{"--spindle", "0"}, "--spindle: error: '0': expected a positive speed in rev/min"},
      {{"--feed", "nan"}, "--feed: error: 'nan': expected a positive feed rate in mm/min"},
      {{"--helix", "-3"}, "--helix: error: '-3': expected an angle in degrees, 0 or more"},
      {{"--force-step", "0"}, "--force-step: error: '0': expected a positive angle in degrees"},
      {{"--flutes", "two"}, "--flutes: error: 'two': expected a whole number of flutes"},
      {{"--threads", "2.5"}, "--threads: error: '2.5': expected a whole number of threads"},
      {{"--threads", "1e10"}, "--threads: error: '1e10': expected a whole number of threads"},
      {{"--no-such-option"}, "cwe: error: unexpected argument --no-such-option"},
  };
  for (const auto& [extra, expected] : cases) {
    std::vector<std::string> args = base;
    args.insert(args.end(), extra.begin(), extra.end());
    const Result r = run_cwe(args);
    EXPECT_EQ(r.status, 2) << expected;
    EXPECT_EQ(r.err.rfind(expected, 0), 0u) << r.err;
  }
  const Result required = run_cwe({"path"});
  EXPECT_EQ(required.status, 2);
  EXPECT_EQ(required.err.rfind("file: error: required", 0), 0u) << required.err;
  // In a job file, a written 0 is refused too, at its key.
  const auto dir = scratch_dir("job_zero");
  std::filesystem::create_directories(dir);
  for (const char* key : {"resolution", "tolerance", "cl_step", "spindle", "feed", "force_step"}) {
    std::ofstream(dir / "job.json") << nlohmann::json{{"stock", "box:0,0,0,10,10,10"},
                                                      {"tool", "flat:4"},
                                                      {"path", "p.ngc"},
                                                      {"out", "out"},
                                                      {key, 0}}
                                           .dump();
    const Result r = run_cwe({"simulate", (dir / "job.json").string()});
    EXPECT_EQ(r.status, 2) << key;
    // At the value's line and column, naming the key.
    const std::string text = nlohmann::json{{"stock", "box:0,0,0,10,10,10"},
                                            {"tool", "flat:4"},
                                            {"path", "p.ngc"},
                                            {"out", "out"},
                                            {key, 0}}
                                 .dump();
    const std::size_t column = text.find(fmt::format("\"{}\":", key)) + std::strlen(key) + 4;
    EXPECT_NE(r.err.find(fmt::format("job.json:1:{}: error: \"{}\": 0: expected a ", column, key)),
              std::string::npos)
        << r.err;
  }
}

// Before the long part: an output that is an input, or a folder that cannot take files, is an
// error at --out, and nothing is written.
TEST(CliSimulate, OutputsNeverOverwriteInputsAndTheFolderIsCheckedFirst) {
  const auto dir = scratch_dir("outputs_checked");
  std::filesystem::create_directories(dir / "out");
  std::ofstream(dir / "p.ngc") << "G21 G0 X0 Y0 Z2\nG1 Z-1 F300\nX10\nM2\n";
  // A stock kept as out/stock.stl, which the run writes.
  run_cwe({"simulate", "--stock", "box:-5,-5,-3,15,5,0", "--tool", "flat:4", "--path",
           (dir / "p.ngc").string(), "--out", (dir / "first").string(), "--stock-only",
           "--quiet"});
  std::filesystem::copy_file(dir / "first" / "stock.stl", dir / "out" / "stock.stl");
  const auto before = std::filesystem::file_size(dir / "out" / "stock.stl");
  const Result r = run_cwe({"simulate", "--stock", (dir / "out" / "stock.stl").string(), "--tool",
                            "flat:4", "--path", (dir / "p.ngc").string(), "--out",
                            (dir / "out").string(), "--quiet"});
  EXPECT_EQ(r.status, 2);
  EXPECT_EQ(r.err.rfind("--out: error: ", 0), 0u) << r.err;
  EXPECT_NE(r.err.find("is the stock, inside the output folder, which this run replaces"),
            std::string::npos);
  EXPECT_EQ(std::filesystem::file_size(dir / "out" / "stock.stl"), before);
  EXPECT_FALSE(std::filesystem::exists(dir / "out" / "summary.json"));
  // An output folder below a file cannot be made.
  std::ofstream(dir / "a_file") << "x";
  const Result blocked = run_cwe({"simulate", "--stock", "box:-5,-5,-3,15,5,0", "--tool",
                                  "flat:4", "--path", (dir / "p.ngc").string(), "--out",
                                  (dir / "a_file" / "out").string(), "--quiet"});
  EXPECT_EQ(blocked.status, 2);
  EXPECT_EQ(blocked.err.rfind("--out: error: cannot create", 0), 0u) << blocked.err;
}

// LinuxCNC tool tables (tests/app/data: sim_mm.tbl and sim.tbl of LinuxCNC's sample
// configurations): flat end mills of diameter D, in the table's units, unless a "cwe:" comment
// names the cutter.
TEST(CliTools, LinuxCncToolTables) {
  const auto dir = scratch_dir("tools_linuxcnc");
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "both.ngc") << kTwoToolHeader << kFlatPart << kBallPart << "M2\n";
  const auto run = [&](const std::string& table, std::vector<std::string> extra = {}) {
    std::vector<std::string> args = {"simulate", "--path", (dir / "both.ngc").string(), "--tools",
                                     table, "--stock", "box:0,0,-10,50,20,0", "--resolution",
                                     "0.5", "--out", (dir / "out").string(), "--maps", "none",
                                     "--quiet"};
    args.insert(args.end(), extra.begin(), extra.end());
    return run_cwe(args);
  };
  const auto tools = [&] {
    std::ifstream in(dir / "out" / "summary.json");
    const nlohmann::json summary = nlohmann::json::parse(in);
    std::vector<std::string> names;
    for (const auto& op : summary["operations"]) names.push_back(op["tool"]);
    return names;
  };
  const std::string data = (test::source_dir() / "tests/app/data").string();
  // sim_mm.tbl: "T1 P1 Z0.511 D3 ;3mm end mill", "T2 P4 Z0.1 D1.5 ;1.5mm  end mill".
  Result r = run(data + "/linuxcnc_sim_mm.tbl");
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(tools(), (std::vector<std::string>{"flat:3", "flat:1.5"}));
  // sim.tbl is in inches: "T1 P1 D0.125 …", "T2 P2 D0.0625 …".
  r = run(data + "/linuxcnc_sim.tbl", {"--tool-units", "in"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(tools(), (std::vector<std::string>{"flat:3.175", "flat:1.5875"}));
  // A cwe key in the comment names the cutter.
  std::ofstream(dir / "own.tbl") << "T1 P1 Z+25.0 D10 ;10 mm flat\nT2 P2 Z+30 D6 ;cwe:ball:6,20 6 mm ball\n";
  r = run((dir / "own.tbl").string());
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_EQ(tools(), (std::vector<std::string>{"flat:10", "ball:6,20"}));
  // Errors name the line and column.
  std::ofstream(dir / "bad.tbl") << "T1 P1 D10\nT2 P2 K6\n";
  r = run((dir / "bad.tbl").string());
  EXPECT_EQ(r.status, 2);
  EXPECT_NE(r.err.find((dir / "bad.tbl").string() + ":2:7: error: 'K'"), std::string::npos) << r.err;
  EXPECT_EQ(run(data + "/linuxcnc_sim.tbl", {"--tool-units", "ft"}).status, 2);
}

// Job files a fuzzer found (tests/data/fuzz-findings, numbers beyond double range): input
// errors naming the file, never an internal error.
TEST(CliSimulate, FuzzFoundJobsAreInputErrors) {
  int files = 0;
  for (const auto& entry :
       std::filesystem::directory_iterator(test::source_dir() / "tests/data/fuzz-findings")) {
    if (entry.path().filename().string().rfind("job-crash-", 0) != 0) continue;
    const Result r = run_cwe({"simulate", entry.path().string(), "--out",
                              scratch_dir("fuzz").string(), "--quiet"});
    EXPECT_EQ(r.status, 2) << entry.path() << ": " << r.err;
    // Located: the number that overflows a double, at its line and column.
    EXPECT_NE(r.err.find(entry.path().string() + ":1:"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("error: not valid JSON: number overflow"), std::string::npos) << r.err;
    EXPECT_EQ(r.err.find("internal error"), std::string::npos) << r.err;
    ++files;
  }
  EXPECT_EQ(files, 4);
}

// Tool and stock in inches give the same job as their millimetre equivalents.
TEST(CliSimulate, InchToolAndStockEqualTheirMillimetres) {
  const auto dir = scratch_dir("inches");
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "cut.ngc") << kForceProgram;
  const auto removed = [&](const char* tool, const char* stock, const char* out) {
    const Result r = run_cwe({"simulate", "--path", (dir / "cut.ngc").string(), "--tool", tool,
                              "--stock", stock, "--resolution", "0.25", "--out",
                              (dir / out).string(), "--maps", "none", "--quiet"});
    EXPECT_EQ(r.status, 0) << r.err;
    std::ifstream in(dir / out / "summary.json");
    return nlohmann::json::parse(in)["removed_volume_mm3"].get<double>();
  };
  const double inch = removed("flat:0.375in,0.75in", "box:0,0,-0.5,2,1,0:in", "in");
  const double mm = removed("flat:9.525,19.05", "box:0,0,-12.7,50.8,25.4,0", "mm");
  EXPECT_GT(mm, 500.0);
  EXPECT_NEAR(inch, mm, 1e-9 * mm);
  // --units in (or the job's "units") makes bare lengths inches: stock box, --tool and a tool
  // table's specifications; a length written in mm stays mm.
  const auto run_in_inches = [&](std::vector<std::string> extra, const char* out) {
    std::vector<std::string> args = {"simulate", "--path", (dir / "cut.ngc").string(), "--stock",
                                     "box:0,0,-0.5,2,1,0", "--units", "in", "--resolution",
                                     "0.25", "--out", (dir / out).string(), "--maps", "none",
                                     "--quiet", "--forces", "al7075-t6-carbide"};
    args.insert(args.end(), extra.begin(), extra.end());
    const Result r = run_cwe(args);
    EXPECT_EQ(r.status, 0) << r.err;
    std::ifstream in(dir / out / "summary.json");
    return nlohmann::json::parse(in)["removed_volume_mm3"].get<double>();
  };
  EXPECT_NEAR(run_in_inches({"--tool", "flat:0.375,0.75"}, "units"), mm, 1e-9 * mm);
  EXPECT_NEAR(run_in_inches({"--tool", "flat:9.525mm,0.75"}, "units_mm"), mm, 1e-9 * mm);
  std::ofstream(dir / "table.json") << R"({"1": "flat:0.375,0.75"})";
  std::ofstream(dir / "t1.ngc") << "T1 M6\n" << kForceProgram;
  const Result table = run_cwe({"simulate", "--path", (dir / "t1.ngc").string(), "--stock",
                                "box:0,0,-0.5,2,1,0", "--tools", (dir / "table.json").string(),
                                "--units", "in", "--resolution", "0.25", "--out",
                                (dir / "table").string(), "--maps", "none", "--quiet"});
  ASSERT_EQ(table.status, 0) << table.err;
  std::ifstream in(dir / "table" / "summary.json");
  EXPECT_NEAR(nlohmann::json::parse(in)["removed_volume_mm3"].get<double>(), mm, 1e-9 * mm);

  // --report-units in: the per-CL files in inches, their columns named so; summary.json in mm.
  run_in_inches({"--tool", "flat:0.375,0.75"}, "report_mm");
  run_in_inches({"--tool", "flat:0.375,0.75", "--report-units", "in"}, "report_in");
  const auto a = read_csv(dir / "report_mm" / "engagement.csv");
  const auto b = read_csv(dir / "report_in" / "engagement.csv");
  const auto fa = read_csv(dir / "report_mm" / "forces.csv");
  const auto fb = read_csv(dir / "report_in" / "forces.csv");
  ASSERT_EQ(a.size(), b.size());
  ASSERT_EQ(fa.size(), fb.size());
  EXPECT_EQ(b[0][15], "axial_depth_in");
  EXPECT_EQ(b[0][16], "area_in2");
  EXPECT_EQ(b[0][18], "path_in");
  EXPECT_EQ(fb[0][2], "feed_per_tooth_in");
  EXPECT_EQ(fb[0][15], "feed_in_min");
  EXPECT_EQ(fb[0][17], "max_chip_in");
  int engaged = 0;
  for (std::size_t i = 1; i < a.size(); ++i) {
    // Printed to 1e-4 mm and 1e-5 in: within half of each last digit.
    for (const std::size_t c : {3u, 4u, 5u, 15u, 18u}) {
      EXPECT_NEAR(std::stod(b[i][c]) * 25.4, std::stod(a[i][c]), 0.5e-4 + 25.4 * 0.5e-5) << i;
    }
    EXPECT_NEAR(std::stod(b[i][16]) * 25.4 * 25.4, std::stod(a[i][16]),
                0.5e-4 + 645.16 * 0.5e-6);
    EXPECT_EQ(a[i][13], b[i][13]);  // angles unchanged
    engaged += a[i][12] == "1";
    EXPECT_NEAR(std::stod(fb[i][15]) * 25.4, std::stod(fa[i][15]), 0.5e-3 + 25.4 * 0.5e-4);
    EXPECT_NEAR(std::stod(fb[i][17]) * 25.4, std::stod(fa[i][17]), 0.5e-6 + 25.4 * 0.5e-7);
    EXPECT_EQ(fa[i][9], fb[i][9]);  // forces in N either way
  }
  EXPECT_GT(engaged, 10);
  std::ifstream report(dir / "report_in" / "summary.json");
  const nlohmann::json summary = nlohmann::json::parse(report);
  EXPECT_EQ(summary["report_units"], "in");
  EXPECT_NEAR(summary["removed_volume_mm3"].get<double>(), mm, 1e-9 * mm);
  for (const char* bad : {"--units", "--report-units", "--tool-units"}) {
    const Result r = run_cwe({"simulate", "--path", (dir / "cut.ngc").string(), "--tool",
                              "flat:0.375", "--stock", "box:0,0,-0.5,2,1,0", "--out",
                              (dir / "bad").string(), bad, "inch"});
    EXPECT_EQ(r.status, 2) << bad;
    EXPECT_NE(r.err.find("'inch': expected mm or in"), std::string::npos) << r.err;
  }
}

// Where the tool starts: by default above the stock's top at the program's first XY, so a stock
// whose top is above Z0 gets no false rapid cut from the first positioning move; from the
// origin (LinuxCNC's machine starts wherever it is) that move cuts the stock.
TEST(CliSimulate, ToolStartsAboveTheStock) {
  const auto dir = scratch_dir("start");
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "cut.ngc") << "G21 G90\nS10000 M3\nG0 X20 Y10 Z15\nG1 Z7 F300\n"
                                    "G1 X40 F600\nG0 Z15\nM2\n";
  // Rapid cuts of `program` (in `dir`) started as `extra` says.
  const auto program_rapid_cuts = [&](const char* program, std::vector<std::string> extra) {
    std::vector<std::string> args = {"simulate", "--path", (dir / program).string(), "--tool",
                                     "flat:10,20", "--stock", "box:0,0,0,50,20,10",
                                     "--resolution", "0.25", "--out", (dir / "out").string(),
                                     "--maps", "none", "--quiet"};
    args.insert(args.end(), extra.begin(), extra.end());
    const Result r = run_cwe(args);
    EXPECT_EQ(r.status, 0) << r.err;
    std::ifstream in(dir / "out" / "summary.json");
    return nlohmann::json::parse(in)["rapid_cuts"]["count"].get<int>();
  };
  const auto rapid_cuts = [&](std::vector<std::string> extra) {
    return program_rapid_cuts("cut.ngc", std::move(extra));
  };
  EXPECT_EQ(rapid_cuts({}), 0);
  EXPECT_EQ(rapid_cuts({"--start", "auto"}), 0);
  EXPECT_EQ(rapid_cuts({"--start", "20,10,30"}), 0);
  EXPECT_EQ(rapid_cuts({"--start", "origin"}), 1);
  // A CLDATA program without FROM starts alike, in its first GOTO's orientation.
  std::ofstream(dir / "cut.cls") << "SPINDL/10000,CLW\nRAPID\nGOTO/20,10,15,0,0.6,0.8\n"
                                    "FEDRAT/300\nGOTO/20,10,7\nGOTO/40,10,7\nFINI\n";
  const auto cldata_rapid_cuts = [&](std::vector<std::string> extra) {
    return program_rapid_cuts("cut.cls", std::move(extra));
  };
  EXPECT_EQ(cldata_rapid_cuts({}), 0);
  EXPECT_EQ(cldata_rapid_cuts({"--start", "origin"}), 1);
  for (const char* bad : {"up", "1,2", "1,2,3,4", "1,x,3"}) {
    const Result r = run_cwe({"simulate", "--path", (dir / "cut.ngc").string(), "--tool",
                              "flat:10,20", "--stock", "box:0,0,0,50,20,10", "--out",
                              (dir / "bad").string(), "--start", bad});
    EXPECT_EQ(r.status, 2) << bad;
    EXPECT_NE(r.err.find("--start: error:"), std::string::npos) << r.err;
  }
}

// At a tool change the old tool goes straight up to the clearance above the stock and the new one
// comes in above its first XY (auto); `stay` starts the new tool where the old one stopped, as a
// machine without a tool-change position does; x,y,z is a tool-change position.
TEST(CliTools, ToolChangesComeFromAbove) {
  const auto dir = scratch_dir("tool_change");
  std::filesystem::create_directories(dir);
  // The flat end mill stops inside the stock, at the end of its slot; no retract before T2 M6.
  std::ofstream(dir / "both.ngc")
      << kTwoToolHeader << "T1 M6\nS10000 M3\nG0 X-10 Y10 Z1\nG1 Z-3 F300\nG1 X40 F600\n"
      << "T2 M6\nS12000 M3\nG0 X10 Y3 Z1\nG1 Z-4 F300\nG1 X40 F600\nG0 Z5\nM2\n";
  std::ofstream(dir / "table.json") << R"({"1": "flat:10,20", "2": "ball:6,20"})";
  const auto run = [&](std::vector<std::string> extra) {
    std::vector<std::string> args = {"simulate", "--path", (dir / "both.ngc").string(), "--tools",
                                     (dir / "table.json").string(), "--stock",
                                     "box:0,0,-10,50,20,0", "--resolution", "0.25", "--out",
                                     (dir / "out").string(), "--maps", "none", "--quiet"};
    args.insert(args.end(), extra.begin(), extra.end());
    const Result r = run_cwe(args);
    EXPECT_EQ(r.status, 0) << r.err;
    std::ifstream in(dir / "out" / "summary.json");
    return nlohmann::json::parse(in);
  };
  const nlohmann::json automatic = run({});
  EXPECT_EQ(automatic["rapid_cuts"]["count"], 0);
  const nlohmann::json given = run({"--tool-change", "40,10,20"});
  EXPECT_EQ(given["rapid_cuts"]["count"], 0);
  // A machine whose tool-change position is that point, with G54's zero at (-100, -50, -200):
  // the same moves.
  std::ofstream(dir / "machine.json")
      << R"({"work_offsets": {"G54": [-100, -50, -200]}, "tool_change": [-60, -40, -180]})";
  const nlohmann::json machine = run({"--machine", (dir / "machine.json").string()});
  EXPECT_EQ(machine["operations"][0]["moves"], 4);
  EXPECT_EQ(machine["removed_volume_mm3"], given["removed_volume_mm3"]);
  EXPECT_NEAR(given["removed_volume_mm3"].get<double>(),
              automatic["removed_volume_mm3"].get<double>(), 1e-9);
  // The old tool's way up and across are moves of their own.
  EXPECT_EQ(automatic["operations"][0]["moves"], 5);
  EXPECT_EQ(given["operations"][0]["moves"], 4);  // up; across is nothing
  // Staying, the ball's first rapid runs from the slot's end through the stock beside it:
  // reported at its line (9, the G0 after T2 M6 at line 7). The ball's cut that follows takes
  // that material anyway.
  const nlohmann::json stay = run({"--tool-change", "stay"});
  EXPECT_EQ(stay["operations"][0]["moves"], 3);
  ASSERT_EQ(stay["rapid_cuts"]["count"], 1);
  EXPECT_EQ(stay["rapid_cuts"]["first"][0]["line"], 9);
  EXPECT_GT(stay["rapid_cuts"]["first"][0]["removed_mm3"].get<double>(), 1.0);
  EXPECT_NEAR(stay["removed_volume_mm3"].get<double>(),
              automatic["removed_volume_mm3"].get<double>(), 1e-9);
  for (const char* bad : {"up", "1,2", "origin"}) {
    const Result r = run_cwe({"simulate", "--path", (dir / "both.ngc").string(), "--tools",
                              (dir / "table.json").string(), "--stock", "box:0,0,-10,50,20,0",
                              "--out", (dir / "bad").string(), "--tool-change", bad});
    EXPECT_EQ(r.status, 2) << bad;
    EXPECT_NE(r.err.find("--tool-change: error:"), std::string::npos) << r.err;
  }
}

// Each tool may bring its own cutting coefficients ("forces" in its table entry): a set twice the
// job's doubles that tool's forces and leaves the other tool's alone.
TEST(CliTools, EachToolItsOwnCoefficients) {
  const auto dir = scratch_dir("tools_forces");
  std::filesystem::create_directories(dir / "sets");
  std::ofstream(dir / "both.ngc") << kTwoToolHeader << kFlatPart << kBallPart << "M2\n";
  std::ofstream(dir / "base.json")
      << R"({"Ktc": 800, "Krc": 300, "Kac": 100, "Kte": 20, "Kre": 15, "Kae": 2})";
  std::ofstream(dir / "sets" / "double.json")
      << R"({"name": "twice", "Ktc": 1600, "Krc": 600, "Kac": 200, "Kte": 40, "Kre": 30, "Kae": 4})";
  std::ofstream(dir / "plain.json") << R"({"1": "flat:10,20", "2": "ball:6,20"})";
  std::ofstream(dir / "own.json")
      << R"({"1": "flat:10,20", "2": {"spec": "ball:6,20", "forces": "sets/double.json"}})";
  std::ofstream(dir / "all.json")
      << R"({"1": {"spec": "flat:10,20", "forces": "base.json"},
             "2": {"spec": "ball:6,20", "forces": "sets/double.json"}})";
  const auto run = [&](const std::string& table, std::vector<std::string> extra) {
    std::vector<std::string> args = {"simulate", "--path", (dir / "both.ngc").string(), "--tools",
                                     (dir / table).string(), "--stock", "box:0,0,-10,50,20,0",
                                     "--resolution", "0.25", "--out",
                                     (dir / ("out_" + table)).string(), "--maps", "none",
                                     "--quiet"};
    args.insert(args.end(), extra.begin(), extra.end());
    return run_cwe(args);
  };
  const std::string base = (dir / "base.json").string();
  for (const auto& [table, extra] :
       std::vector<std::pair<std::string, std::vector<std::string>>>{
           {"plain.json", {"--forces", base}}, {"own.json", {"--forces", base}},
           {"all.json", {}}}) {
    const Result r = run(table, extra);
    ASSERT_EQ(r.status, 0) << table << ": " << r.err;
  }
  const auto plain = read_csv(dir / "out_plain.json" / "forces.csv");
  for (const char* table : {"own.json", "all.json"}) {
    const auto own = read_csv(dir / ("out_" + std::string(table)) / "forces.csv");
    ASSERT_EQ(own.size(), plain.size());
    int doubled = 0;
    for (std::size_t i = 1; i < own.size(); ++i) {
      const double factor = own[i].back() == "2" ? 2.0 : 1.0;
      const double reference = std::stod(plain[i][9]);  // peak_resultant_n
      // forces.csv prints N to 3 decimals: each value is within 0.0005 N of its own.
      EXPECT_NEAR(std::stod(own[i][9]), factor * reference, 0.0005 * (1.0 + factor) + 1e-9)
          << i;
      if (factor == 2.0 && reference > 1.0) ++doubled;
    }
    EXPECT_GT(doubled, 10) << table;
  }
  std::ifstream in(dir / "out_own.json" / "summary.json");
  const nlohmann::json summary = nlohmann::json::parse(in);
  EXPECT_EQ(summary["operations"][0]["coefficients"], base);  // a set without a name: its file
  EXPECT_EQ(summary["operations"][1]["coefficients"], "twice");
  EXPECT_EQ(summary["forces"]["coefficients"], base + "; twice");
  // A tool with no coefficients of its own and no --forces: an error where it is loaded.
  const Result missing = run("own.json", {});
  EXPECT_EQ(missing.status, 2);
  EXPECT_NE(missing.err.find((dir / "both.ngc").string() + ":2:1: error: tool 1 has no cutting "
                                                          "coefficients"),
            std::string::npos)
      << missing.err;
  std::ofstream(dir / "bad.json") << R"({"1": {"spec": "flat:10", "forces": "nothing-known"}})";
  const Result bad = run("bad.json", {});
  EXPECT_EQ(bad.status, 2);
  EXPECT_NE(bad.err.find("tool \"1\""), std::string::npos) << bad.err;
}

// A program as FreeCAD 0.20's CAM workbench posts it for LinuxCNC, with two tools of its Default
// library (tests/app/data/freecad_two_tools.py): cut with the library as the tool table, it
// removes what the two tools' parts run as two operations remove, and each cutter location is
// engaged and loaded as there.
TEST(CliTools, FreeCadTwoToolProgram) {
  const auto dir = scratch_dir("freecad_two_tools");
  std::filesystem::create_directories(dir);
  const std::filesystem::path data = test::source_dir() / "tests/app/data";
  const std::string program = (data / "freecad_two_tools.ngc").string();
  // The parts: the bull nose's part keeps the preamble and its line numbers, the end mill's
  // lines made comments (the bull nose's T4 M6 is line 100).
  std::vector<std::string> lines;
  {
    std::ifstream in(program);
    for (std::string line; std::getline(in, line);) lines.push_back(line);
  }
  ASSERT_EQ(lines[99], "M6 T4 ");
  {
    std::ofstream first(dir / "endmill.ngc");
    std::ofstream second(dir / "bullnose.ngc");
    for (std::size_t i = 0; i < lines.size(); ++i) {
      const bool preamble = i < 6;
      first << (i < 99 ? lines[i] : "(bull nose part)") << "\n";
      second << (preamble || i >= 99 ? lines[i] : "(end mill part)") << "\n";
    }
    first << "M2\n";
  }
  std::ofstream(dir / "split.json")
      << R"({"operations": [{"path": "endmill.ngc"}, {"path": "bullnose.ngc"}]})";
  const std::string table = (data / "freecad/Library/Default.fctl").string();
  const std::vector<std::string> common = {"--tools", table, "--stock", "box:-1,-1,-1,61,41,16",
                                           "--resolution", "0.25", "--forces",
                                           "al7075-t6-carbide", "--maps", "none", "--quiet"};
  auto with = [&](std::vector<std::string> args) {
    args.insert(args.end(), common.begin(), common.end());
    return args;
  };
  const Result both = run_cwe(
      with({"simulate", "--path", program, "--out", (dir / "both").string()}));
  ASSERT_EQ(both.status, 0) << both.err;
  const Result split = run_cwe(
      with({"simulate", (dir / "split.json").string(), "--out", (dir / "split").string()}));
  ASSERT_EQ(split.status, 0) << split.err;
  const auto summary = [](const std::filesystem::path& file) {
    std::ifstream in(file);
    return nlohmann::json::parse(in);
  };
  const nlohmann::json a = summary(dir / "both" / "summary.json");
  const nlohmann::json b = summary(dir / "split" / "summary.json");
  const double removed = a["removed_volume_mm3"];
  EXPECT_NEAR(removed, b["removed_volume_mm3"].get<double>(), 1e-4 * removed);
  EXPECT_GT(removed, 30.0 * 16.0 * 6.0);  // the pocket at least
  EXPECT_EQ(a["rapid_cuts"]["count"], 0);
  ASSERT_EQ(a["operations"].size(), 2u);
  EXPECT_EQ(a["operations"][0]["tool_number"], 1);
  EXPECT_EQ(a["operations"][1]["tool_number"], 4);
  EXPECT_EQ(a["operations"][1]["tool"], b["operations"][1]["tool"]);
  // The engaged cutter locations, by line and position: the same, engaged and loaded alike. (The
  // rapids between the parts differ: the split part comes in from its own start.)
  const auto engaged = [](const std::filesystem::path& folder) {
    const auto rows = read_csv(folder / "engagement.csv");
    const auto forces = read_csv(folder / "forces.csv");
    EXPECT_EQ(rows.size(), forces.size());
    std::map<std::string, std::vector<std::string>> by_place;
    EXPECT_EQ(rows[0][20], "operation");
    EXPECT_EQ(rows[0][21], "tool");
    for (std::size_t i = 1; i < rows.size() && i < forces.size(); ++i) {
      if (rows[i][12] != "1") continue;
      const std::string key = fmt::format("{}:{},{},{}", rows[i][2], rows[i][3], rows[i][4],
                                          rows[i][5]);
      // phi_entry_deg … motion and the tool (not the operation: one program is two here).
      std::vector<std::string> values(rows[i].begin() + 13, rows[i].begin() + 20);
      values.push_back(rows[i][21]);
      values.push_back(forces[i][9]);   // peak_resultant_n
      values.push_back(forces[i][11]);  // peak_torque_nm
      by_place[key] = values;
    }
    return by_place;
  };
  const auto x = engaged(dir / "both");
  const auto y = engaged(dir / "split");
  EXPECT_GT(x.size(), 1000u);
  EXPECT_EQ(x, y);
  std::set<std::string> tools;
  for (const auto& [place, values] : x) tools.insert(values[values.size() - 3]);
  EXPECT_EQ(tools, (std::set<std::string>{"1", "4"}));
}

// Every key of a job file is checked for its kind; a count beyond int is refused, never wrapped.
TEST(CliSimulate, JobFileValuesAreChecked) {
  const auto dir = scratch_dir("job_values");
  std::filesystem::create_directories(dir);
  for (const char* bad : {R"("threads": 4294967297)", R"("threads": 0)", R"("flutes": 2.5)",
                          R"("ply": "yes")", R"("resolution": "fine")", R"("stock": 5)",
                          R"("helix": "steep")", R"("maps": 10)"}) {
    const std::string key = std::string(bad).substr(1, std::string(bad).find('"', 1) - 1);
    const std::string text =
        "{" + std::string(key == "stock" ? "" : "\"stock\": \"box:0,0,0,10,10,10\", ") +
        "\"tool\": \"flat:4\", \"path\": \"p.ngc\", \"out\": \"out\", " + bad + "}";
    std::ofstream(dir / "job.json") << text;
    const Result r = run_cwe({"simulate", (dir / "job.json").string()});
    EXPECT_EQ(r.status, 2) << bad;
    // At the value's line and column, naming the key.
    const std::size_t column = text.find(bad) + key.size() + 5;
    EXPECT_NE(r.err.find(fmt::format("job.json:1:{}: error: \"{}\": ", column, key)),
              std::string::npos)
        << bad << ": " << r.err;
  }
  // A key written twice: an error at the second, not the last one silently winning.
  std::ofstream(dir / "job.json") << "{\"stock\": \"box:0,0,0,10,10,10\",\n \"tool\": \"flat:4\","
                                     " \"tool\": \"ball:4\"}";
  const Result twice = run_cwe({"simulate", (dir / "job.json").string()});
  EXPECT_EQ(twice.status, 2);
  EXPECT_NE(twice.err.find("job.json:2:20: error: key \"tool\" written twice in one object"),
            std::string::npos)
      << twice.err;
}

}  // namespace
}  // namespace cwe::app

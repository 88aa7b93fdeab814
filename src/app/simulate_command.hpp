#pragma once
// `cwe simulate`: the main job. Runs a toolpath through a stock on the tri-dexel workpiece,
// extracting the cutter–workpiece engagement at every cutter location, and writes the engagement
// (engagement.csv, engagement.jsonl, maps/), the in-process workpiece (stock.stl) and a summary
// (summary.json). The job comes from options or
// from a JSON job file (see docs/simulate.md); options given on the command line win.

#include <CLI/CLI.hpp>

#include <cstddef>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "tool_table.hpp"

namespace cwe::app {

// The triangle budget that picks the stock mesh's stride when none is given: about 50 MB of
// binary STL.
inline constexpr std::size_t kStockMeshTriangles = 1'000'000;

// One toolpath with its tool (empty: the program's own CUTTER).
struct Operation {
  std::string tool;
  std::string path;
};

struct SimulateCommandOptions {
  std::string job;    // JSON job file (optional)
  std::string stock;  // box:xmin,ymin,zmin,xmax,ymax,zmax or an STL file
  std::string tool;
  std::string path;
  std::vector<Operation> operations;  // from a job file; else the one --tool/--path
  // Tool table (docs/simulate.md, src/app/tool_table.hpp): --tools FILE, or the job's "tools"
  // (a file or the table itself), read by read_job or prepare_job.
  std::string tools;
  std::optional<ToolTable> tool_table;
  bool tool_for_all = false;  // one --tool cuts every move of a program that changes tools
  std::string tool_units;     // "mm" or "in": lengths of a LinuxCNC tool table (default mm)
  // Where a program's tool starts: "auto" (default: kStartClearance above the stock's top at the
  // program's first XY), "origin", or "x,y,z" in mm; and where it changes tools: "auto" (default:
  // up to that height, then across to the new tool's first XY), "stay", or "x,y,z" in mm.
  std::string start;
  std::string tool_change;
  // "mm" (default) or "in": the unit of the lengths given without one (stock box, tool
  // specifications and tables, start and tool-change points).
  std::string units;
  // "mm" (default) or "in": the lengths of engagement.csv, engagement.jsonl, forces.csv and the
  // terminal report (summary.json stays in mm).
  std::string report_units;
  std::string out;
  double resolution = 0.0;  // 0: from the job, else 0.1 mm
  double tolerance = 0.0;   // 0: from the job, else resolution / 10
  int threads = 0;          // 0: from the job, else all cores
  int mesh_stride = 0;      // 0: from the job, else chosen for ≤ kStockMeshTriangles
  bool ply = false;         // also write stock.ply
  double cl_step = 0.0;     // 0: from the job, else min(0.5, D/20) mm
  std::string maps;         // every:N, cl:i,j,…, or none; empty: from the job, else ~10 maps
  bool stock_only = false;  // material removal only: no engagement outputs
  bool quiet = false;       // no progress bar
  // Cutting forces (docs/forces.md): a coefficient JSON file or bundled material; empty: none.
  std::string forces;
  double spindle = 0.0;      // rev/min overriding the program's; 0: the program's S / SPINDL
  double feed = 0.0;         // mm/min overriding the program's F / FEDRAT; 0: the program's
  int flutes = 0;            // 0: the cutter's
  double helix = -1.0;       // degrees; < 0: the cutter's
  double force_step = 0.0;   // spindle angle step, degrees; 0: 1°
  std::string runout;        // offset_mm[,angle_deg]; empty: none
  std::string force_curves;  // every:N, cl:i,j,… or none (default none)
};

// The options a job has whatever it writes (stock, tools, paths, resolution, forces), shared by
// `cwe simulate` and `cwe schedule`.
void add_job_options(CLI::App* cmd, SimulateCommandOptions& options);
// Fills the options not given on the command line from options.job (a JSON file), if any.
void read_job(SimulateCommandOptions& options);

void add_simulate_command(CLI::App& app, SimulateCommandOptions& options);
// `progress` receives the progress bar (stderr when it is a terminal), or nullptr.
int run_simulate_command(SimulateCommandOptions options, std::ostream& out, std::ostream* progress);

}  // namespace cwe::app

#pragma once
// `cwe simulate`: the main job. Runs a toolpath through a stock on the tri-dexel workpiece,
// extracting the cutter–workpiece engagement at every cutter location, and writes the engagement
// (engagement.csv, engagement.jsonl, maps/), the in-process workpiece (stock.stl) and a summary
// (summary.json). The job comes from options or
// from a JSON job file (see docs/simulate.md); options given on the command line win.

#include <CLI/CLI.hpp>

#include <cstddef>
#include <filesystem>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "cwe/job/job.hpp"

namespace cwe::app {

// The triangle budget that picks the stock mesh's stride when none is given: about 50 MB of
// binary STL.
inline constexpr std::size_t kStockMeshTriangles = 1'000'000;

// The command's options: the job (cwe/job/job.hpp) and what to write of it.
struct SimulateCommandOptions : Job {
  std::string job_file;  // JSON job file (optional)
  // "mm" (default) or "in": the lengths of engagement.csv, engagement.jsonl, forces.csv and the
  // terminal report (summary.json stays in mm).
  std::string report_units;
  std::string out;
  std::optional<int> mesh_stride;  // absent: chosen for ≤ kStockMeshTriangles
  bool ply = false;         // also write stock.ply
  bool off = false;         // also write stock.off
  std::string maps;         // every:N, cl:i,j,…, or none; empty: from the job, else ~10 maps
  bool stock_only = false;  // material removal only: no engagement outputs
  bool quiet = false;       // no progress bar
  std::string force_curves;  // every:N, cl:i,j,… or none (default none)
};

// The options a job has whatever it writes (stock, tools, paths, resolution, forces), shared by
// `cwe simulate` and `cwe schedule`.
void add_job_options(CLI::App* cmd, SimulateCommandOptions& options);
// Fills the options not given on the command line from options.job_file (a JSON file), if any.
void read_job(SimulateCommandOptions& options);

void add_simulate_command(CLI::App& app, SimulateCommandOptions& options);
// InputError at --out when an input of the job (stock, program, table, …) lies inside `folder`,
// which a run replaces whole.
void check_output_folder(const std::filesystem::path& folder, const SimulateCommandOptions& options,
                         const PreparedJob& job);
// `progress` receives the progress bar (stderr when it is a terminal), or nullptr.
int run_simulate_command(SimulateCommandOptions options, std::ostream& out, std::ostream* progress);

}  // namespace cwe::app

#pragma once
// summary.json of a job's run (docs/simulate.md, "Outputs"): volumes, moves, memory, the
// engagement and force extremes, rapid cuts and the readers' warnings.

#include <cstddef>
#include <string>

#include "cwe/geometry/triangle_mesh.hpp"
#include "cwe/job/job.hpp"
#include "cwe/job/run.hpp"

namespace cwe {

// What the summary reports besides the job and its run.
struct JobSummary {
  std::string stock;               // as given
  std::string report_units = "mm"; // of the per-CL files
  // Wall time of the job's three stages (summary.json's seconds is their sum): reading and
  // preparing the job and making the stock; the run (removal, engagement, forces and the
  // figures beside them); the closing stage (contouring and encoding stock.stl beside the last
  // figures and files).
  double set_up_seconds = 0.0, simulation_seconds = 0.0, closing_seconds = 0.0;
  bool engagement = true;          // the run extracted the engagement
  int mesh_stride = 1;             // of stock.stl
  const TriangleMesh* mesh = nullptr;  // stock.stl's mesh; none: no stock_mesh entry
  bool ply = false;                // stock.ply written too
  bool off = false;                // stock.off written too
  std::size_t maps = 0, curves = 0;    // figures written
};

// Rapid moves listed by line in the summary (all are counted).
inline constexpr std::size_t kRapidCutsListed = 10;

// The job's toolpath files, comma-separated (summary.json's "path").
std::string job_paths(const PreparedJob& job);

// The summary as JSON text (two-space indents, a final newline).
std::string job_summary(const PreparedJob& job, const JobResult& run, const JobSummary& extras);

}  // namespace cwe

#pragma once
// A prepared job run on its stock: every operation in order on the one workpiece, the engagement
// (and forces) at each cutter location handed to sinks, and the figures a report needs.

#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "cwe/io/cl_sink.hpp"
#include "cwe/job/job.hpp"
#include "cwe/simulation/simulation.hpp"
#include "cwe/workpiece/brep/brep_stock.hpp"
#include "cwe/workpiece/dexel/tri_dexel.hpp"
#include "cwe/workpiece/mesh/mesh_stock.hpp"

namespace cwe {

// The largest force, torque and power of a job, and where they occur.
struct ForceExtremes {
  struct Extreme {
    double value = 0.0;
    std::size_t cl = 0;
    std::string file;
    int line = 0;
  };
  Extreme force, torque, power, chip;  // peak resultant N, peak torque N·m, mean power W, mm
  std::size_t cutting = 0;             // CLs where some flute cut a chip
  void add(const ClForces& f, std::size_t cl, const std::string& file, int line);
};

struct JobResult {
  explicit JobResult(TriDexel workpiece) : stock(std::move(workpiece)) {}
  explicit JobResult(MeshStock workpiece) : mesh(std::move(workpiece)) {}
  explicit JobResult(BrepStock workpiece) : brep(std::move(workpiece)) {}
  // The in-process workpiece after the job: the rays, the mesh or the solid
  // (PreparedJob::workpiece).
  std::optional<TriDexel> stock;
  std::optional<MeshStock> mesh;
  std::optional<BrepStock> brep;
  // Volumes before and after, mm³: the rays' by family; the mesh's one figure in all three.
  TriDexel::Volume initial_volume, final_volume;
  RemovalSummary removal;  // of the whole job (move indices over all operations)
  std::vector<RemovalSummary> per_operation;
  // With engagement:
  std::size_t cl_points = 0, engaged_cl_points = 0;
  double deepest = 0.0;       // largest axial depth, mm
  double largest_area = 0.0;  // largest engaged area, mm²
  ForceExtremes extremes;     // with forces
};

struct RunOptions {
  bool engagement = true;  // false: removal only (remove_toolpath, batched), no sinks called
  bool forces = true;      // evaluate the forces at each CL (when the job has a force model)
};

// Runs `job` on `stock` (make_stock of the job's stock, at its resolution): every operation in
// order, with engagement through simulate_engagement, each CL's engagement (and forces) handed to
// every sink in turn. `progress` gets (moves done, moves of the job).
JobResult run_job(const PreparedJob& job, TriDexel stock, const RunOptions& options,
                  std::span<ClSink* const> sinks, const Progress& progress = {});
// The same on the mesh workpiece (MeshWorkpiece at the job's facet size), for a job whose
// workpiece is "mesh". Throws ComputationError naming the move's file and line when a boolean
// fails.
JobResult run_job(const PreparedJob& job, MeshStock stock, const RunOptions& options,
                  std::span<ClSink* const> sinks, const Progress& progress = {});

// The same on the B-rep workpiece (BrepWorkpiece: exact sweeps, the solid-model engagement).
// Throws ComputationError naming the move's file and line when a sweep or a cut fails.
JobResult run_job(const PreparedJob& job, BrepStock stock, const RunOptions& options,
                  std::span<ClSink* const> sinks, const Progress& progress = {});

// The job's stock in the representation its workpiece asks (make_stock, make_mesh_stock or a
// B-rep solid), made before a run so that a bad stock is reported before any output is opened.
struct JobStock {
  std::optional<TriDexel> rays;
  std::optional<MeshStock> mesh;
  std::optional<BrepStock> brep;
};
JobStock make_job_stock(const PreparedJob& job);
// run_job on whichever the stock holds.
JobResult run_job(const PreparedJob& job, JobStock stock, const RunOptions& options,
                  std::span<ClSink* const> sinks, const Progress& progress = {});

}  // namespace cwe

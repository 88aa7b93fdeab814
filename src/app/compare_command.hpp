#pragma once
// `cwe compare`: one job on several in-process workpieces (tri-dexel, mesh, B-rep), cutter
// location by cutter location against the reference (the B-rep one when it runs, else the
// first): compare.csv (every CL's entry, exit, depth and area by each, and each one's
// differences) and compare.json (removed volumes, time and memory of each, percentiles of every
// difference). With a sweep, the runs at each setting, and convergence.csv and the figures of
// their errors and costs against the setting. See docs/accuracy.md.

#include <CLI/CLI.hpp>

#include <ostream>
#include <string>

#include "simulate_command.hpp"

namespace cwe::app {

struct CompareCommandOptions : SimulateCommandOptions {
  std::string workpieces = "dexel,mesh,brep";  // comma-separated; one may come twice
  // Convergence: each workpiece but the reference run again at each of these resolutions (the
  // reference at the finest), or the mesh one at each of these facet sizes; comma-separated mm.
  std::string sweep_resolution;
  std::string sweep_facet;
};

void add_compare_command(CLI::App& app, CompareCommandOptions& options);
int run_compare_command(CompareCommandOptions options, std::ostream& out, std::ostream* progress);

}  // namespace cwe::app

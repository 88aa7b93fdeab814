#include "cwe/job/job.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <tbb/info.h>

#include "cwe/core/error.hpp"
#include "cwe/core/text_file.hpp"
#include "program_runs.hpp"

namespace cwe {

void require(const std::string& value, const char* what, const char* option) {
  if (value.empty()) {
    throw InputError(SourceLocation{"cwe"},
                     fmt::format("no {}: give {} or put it in a job file", what, option));
  }
}

void check_units(const std::string& units, const char* option) {
  if (!units.empty() && units != "mm" && units != "in") {
    throw InputError(SourceLocation{option}, fmt::format("'{}': expected mm or in", units));
  }
}

double unit_length(const std::string& units) {
  return units == "in" ? kMillimetresPerInch : 1.0;
}

std::string coefficient_names(const PreparedJob& job, bool sources) {
  std::vector<std::string> names;
  for (const PreparedOperation& op : job.operations) {
    if (!op.forces) continue;
    const CuttingCoefficients& k = op.forces->coefficients();
    const std::string& name = sources ? k.source : k.name;
    if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
  }
  return fmt::format("{}", fmt::join(names, "; "));
}

PreparedJob prepare_job(Job& options) {
  require(options.stock, "stock", "--stock");
  if (!options.path.empty()) {
    options.operations = {{options.tool, options.path}};
  } else if (!options.tool.empty() && !options.operations.empty()) {
    for (Operation& op : options.operations) {
      if (op.tool.empty()) op.tool = options.tool;
    }
  }
  if (options.operations.empty()) require(options.path, "toolpath", "--path");
  PreparedJob job;
  SimulationOptions& simulation = job.simulation;
  simulation.resolution = options.resolution != 0.0 ? options.resolution : 0.1;
  simulation.tolerance = options.tolerance;
  if (options.tolerance < 0.0 || !std::isfinite(options.tolerance)) {
    throw InputError(SourceLocation{"--tolerance"},
                     fmt::format("{} mm: expected a positive length", options.tolerance));
  }
  if (options.cl_step < 0.0 || !std::isfinite(options.cl_step)) {
    throw InputError(SourceLocation{"--cl-step"},
                     fmt::format("{} mm: expected a positive length", options.cl_step));
  }
  job.threads = options.threads > 0 ? options.threads : tbb::info::default_concurrency();
  check_units(options.units, "--units");
  check_units(options.tool_units, "--tool-units");
  if (options.tool_units.empty()) options.tool_units = options.units;
  if (!options.tools.empty()) {
    options.tool_table = read_tool_table(options.tools, options.tool_units == "in");
  }
  if (!options.machine.empty()) options.machine_definition = read_machine_file(options.machine);
  // A box written without its unit is in --units.
  if (options.units == "in" && options.stock.rfind("box:", 0) == 0 &&
      !options.stock.ends_with(":in") && !options.stock.ends_with(":mm")) {
    options.stock += ":in";
  }

  // Everything the job needs is read and checked before the long part starts.
  job.stock = read_stock_spec(options.stock, SourceLocation{"--stock"});
  const EntryRules entries = entry_rules(options, stock_top(job.stock));
  std::vector<std::pair<std::size_t, ToolRun>> runs;  // with their operation
  for (std::size_t o = 0; o < options.operations.size(); ++o) {
    for (ToolRun& run : program_runs(options.operations[o], options, entries)) {
      runs.emplace_back(o, std::move(run));
    }
  }
  // Forces: with --forces, or when the tool table gives a tool its coefficients.
  const bool own_coefficients = std::any_of(
      runs.begin(), runs.end(), [](const auto& run) { return run.second.coefficients.has_value(); });
  if (options.forces.empty() && !own_coefficients &&
      (options.feed != 0.0 || options.spindle != 0.0)) {
    throw InputError(SourceLocation{options.feed != 0.0 ? "--feed" : "--spindle"},
                     "spindle speed and feed overrides are for the force model: give --forces");
  }
  if (!options.forces.empty() || own_coefficients) {
    job.forces = force_settings(options.forces, options.spindle, options.feed, options.flutes,
                                options.helix, options.force_step, options.runout);
  }
  for (auto& [o, run] : runs) {
    const std::string& program = options.operations[o].path;
    SamplingOptions sampling;
    sampling.step =
        options.cl_step > 0.0 ? options.cl_step : default_cl_step(run.cutter.diameter());
    const std::size_t cls = count_cl_points(run.read.toolpath, sampling);
    job.cl_count += cls;
    std::optional<ForceModel> forces;
    if (job.forces) {
      if (!run.coefficients && !job.forces->coefficients) {
        throw InputError(run.loaded,
                         fmt::format("tool {} has no cutting coefficients: give --forces, or "
                                     "\"forces\" in its tool table entry",
                                     run.tool));
      }
      check_spindle(run.read.toolpath, program, *job.forces);
      forces.emplace(run.cutter, run.coefficients.value_or(*job.forces->coefficients),
                     job.forces->model);
    }
    job.operations.push_back({program, std::move(run.read), std::move(run.cutter), sampling, cls,
                              std::move(forces), run.tool, o, std::move(run.gcode)});
  }
  return job;
}

}  // namespace cwe

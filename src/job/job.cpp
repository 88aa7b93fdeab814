#include "cwe/job/job.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <tbb/info.h>

#include "cwe/core/error.hpp"
#include "cwe/core/memory_limit.hpp"
#include "cwe/core/text_file.hpp"
#include "cwe/engagement/mesh_workpiece.hpp"
#include "cwe/io/step.hpp"
#include "program_runs.hpp"

namespace cwe {

void require(const std::string& value, const char* what, const char* option) {
  if (value.empty()) {
    throw InputError(SourceLocation{"cwe"},
                     fmt::format("no {}: give {} or put it in a job file", what, option));
  }
}

void check_units(const Job& job, std::string_view key, const std::string& units) {
  if (!units.empty() && units != "mm" && units != "in") {
    throw job.error(key, fmt::format("'{}': expected mm or in", units));
  }
}

double unit_length(const std::string& units) { return units == "in" ? kMillimetresPerInch : 1.0; }

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

SourceLocation Job::origin(std::string_view key) const {
  if (const auto found = given_at.find(key); found != given_at.end()) return found->second;
  std::string option = "--" + std::string(key);
  std::replace(option.begin(), option.end(), '_', '-');
  return SourceLocation{option};
}

SourceLocation Job::text_origin(std::string_view key) const {
  SourceLocation where = origin(key);
  if (where.line > 0) ++where.column;
  return where;
}

InputError Job::error(std::string_view key, const std::string& message) const {
  const SourceLocation where = origin(key);
  if (where.line == 0) return InputError(where, message);
  return InputError(where, fmt::format("\"{}\": {}", key, message));
}

namespace {

// Checks a number given for `key` against [lo, hi] (bounds excluded when `open`); `expected` says
// what is wanted, e.g. "a positive length in mm".
template <class T>
void check_number(const Job& job, std::string_view key, const std::optional<T>& value, double lo,
                  bool lo_open, double hi, std::string_view expected) {
  if (!value) return;
  const auto v = static_cast<double>(*value);
  if (std::isfinite(v) && (lo_open ? v > lo : v >= lo) && v <= hi) return;
  throw job.error(key, fmt::format("{}: expected {}", *value, expected));
}

// Every number of the job, at its origin. The upper bounds are far beyond any machine; they keep
// later arithmetic finite.
void check_numbers(const Job& job) {
  constexpr bool kOpen = true;
  check_number(job, "resolution", job.resolution, 0.0, kOpen, 1e4,
               "a positive length in mm, at most 10000");
  // Below 1e-6 mm a tolerance only multiplies the pieces of arcs, helices and 5-axis moves.
  check_number(job, "tolerance", job.tolerance, 1e-6, !kOpen, 1e4,
               "a length in mm from 1e-6 to 10000");
  check_number(job, "facet", job.facet, 0.0, kOpen, 1e3, "a positive length in mm, at most 1000");
  check_number(job, "threads", job.threads, 1.0, !kOpen, 4096.0,
               "a whole number of threads, 1 to 4096");
  check_number(job, "cl_step", job.cl_step, 0.0, kOpen, 1e6,
               "a positive length in mm, at most 1e6");
  check_number(job, "spindle", job.spindle, 0.0, kOpen, 1e6,
               "a positive speed in rev/min, at most 1e6");
  check_number(job, "feed", job.feed, 0.0, kOpen, 1e7,
               "a positive feed rate in mm/min, at most 1e7");
  check_number(job, "flutes", job.flutes, 1.0, !kOpen, 1000.0,
               "a whole number of flutes, 1 to 1000");
  check_number(job, "helix", job.helix, 0.0, !kOpen, std::nextafter(90.0, 0.0),
               "a helix angle in [0°, 90°)");
  check_number(job, "force_step", job.force_step, 0.01, !kOpen, 90.0,
               "a spindle angle step in [0.01°, 90°]");
}

// Counts the CL samples of every operation, the programs read again move by move (a move with
// too many is an error at its line), notes the operations with moves from other files, and with
// forces checks that every feed move turns the spindle.
void count_cl_points(PreparedJob& job) {
  std::optional<ClSampler> sampler;
  PreparedOperation* op = nullptr;
  OperationVisitor visitor;
  visitor.begin = [&](std::size_t o) {
    op = &job.operations[o];
    sampler.emplace(op->sampling);
  };
  visitor.move = [&](const Move& move, const std::vector<std::string>& sources) {
    op->cl_points += static_cast<std::size_t>(sampler->steps(move, &sources));
    if (move.source != 0) op->moves_from_other_files = true;
    if (op->forces) check_spindle(move, sources, op->path, *job.forces);
  };
  visitor.end = [&](std::size_t) { job.cl_count += op->cl_points; };
  for_each_move(job, visitor);
}

}  // namespace

PreparedJob prepare_job(Job& options) {
  require(options.stock, "stock", "--stock");
  if (!options.path.empty()) {
    options.operations = {{options.tool, options.path, options.text_origin("tool")}};
  } else if (!options.tool.empty() && !options.operations.empty()) {
    for (Operation& op : options.operations) {
      if (op.tool.empty()) {
        op.tool = options.tool;
        op.tool_at = options.text_origin("tool");
      }
    }
  }
  if (options.operations.empty()) require(options.path, "toolpath", "--path");
  PreparedJob job;
  check_numbers(options);
  if (!options.memory_limit.empty()) {
    set_memory_limit(parse_memory_limit(options.memory_limit, options.origin("memory_limit")));
  }
  SimulationOptions& simulation = job.simulation;
  simulation.resolution = options.resolution.value_or(0.1);
  simulation.tolerance = options.tolerance.value_or(0.0);  // 0: resolution / 10
  job.threads = options.threads.value_or(tbb::info::default_concurrency());
  check_units(options, "units", options.units);
  check_units(options, "tool_units", options.tool_units);
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
  job.stock = read_stock_spec(options.stock, options.origin("stock"));
  if (options.workpiece.empty() || options.workpiece == "dexel") {
    // The rays are the run's big allocation: checked here, where the resolution's origin is
    // known.
    TriDexel::check_grid(stock_box(job.stock), simulation.resolution, options.origin("resolution"));
  } else if (options.workpiece == "mesh") {
    job.workpiece = WorkpieceKind::kMesh;
    job.facet = options.facet.value_or(1.0);
  } else if (options.workpiece == "brep") {
    job.workpiece = WorkpieceKind::kBrep;
    if (job.stock.mesh) {
      job.stock.mesh_solid =
          std::make_shared<const StepModel>(mesh_solid_model(*job.stock.mesh, job.stock.path));
    }
  } else {
    throw options.error("workpiece", fmt::format("\"{}\": expected \"dexel\", \"mesh\" or \"brep\"",
                                                 options.workpiece));
  }
  const EntryRules entries = entry_rules(options, stock_top(job.stock));
  std::vector<std::pair<std::size_t, ToolRun>> runs;  // with their operation
  for (std::size_t o = 0; o < options.operations.size(); ++o) {
    for (ToolRun& run : program_runs(options.operations[o], options, entries)) {
      runs.emplace_back(o, std::move(run));
    }
  }
  // On the mesh workpiece the tool's facets lie up to h inside it: arcs, helices and 5-axis
  // moves cut in pieces much finer than that buy nothing but booleans (the bundled example's
  // 5-axis pass: 85 s at s/10, 11 s at h, the same volume to 0.02 %). The default tolerance there
  // is the smallest h of the job's tools, when above s/10.
  if (job.workpiece == WorkpieceKind::kMesh && !options.tolerance) {
    for (const auto& [o, run] : runs) {
      const double h = MeshWorkpiece::facet_depth(run.cutter, job.facet);
      if (simulation.tolerance == 0.0 || h < simulation.tolerance) simulation.tolerance = h;
    }
    simulation.tolerance = std::max(simulation.tolerance, simulation.resolution / 10.0);
  }
  // Forces: with --forces, or when the tool table gives a tool its coefficients.
  const bool own_coefficients = std::any_of(runs.begin(), runs.end(), [](const auto& run) {
    return run.second.coefficients.has_value();
  });
  if (options.forces.empty() && !own_coefficients && (options.feed || options.spindle)) {
    throw options.error(options.feed ? "feed" : "spindle",
                        "spindle speed and feed overrides are for the force model: give --forces");
  }
  if (!options.forces.empty() || own_coefficients) {
    try {
      job.forces = force_settings(options.forces,
                                  {options.spindle, options.feed, options.flutes, options.helix,
                                   options.force_step, options.runout, options.origin("runout")});
    } catch (const InputError& e) {
      // A material name that is not bundled is an error in the option (or key) that gave it.
      if (e.location().source != kCoefficientNameSource) throw;
      throw options.error("forces", e.message());
    }
  }
  for (auto& [o, run] : runs) {
    const std::string& program = options.operations[o].path;
    SamplingOptions sampling;
    sampling.step = options.cl_step.value_or(default_cl_step(run.cutter.diameter()));
    std::optional<ForceModel> forces;
    if (job.forces) {
      if (!run.coefficients && !job.forces->coefficients) {
        throw InputError(run.loaded,
                         fmt::format("tool {} has no cutting coefficients: give --forces, or "
                                     "\"forces\" in its tool table entry",
                                     run.tool));
      }
      forces.emplace(run.cutter, run.coefficients.value_or(*job.forces->coefficients),
                     job.forces->model);
    }
    // A cutter across fewer than kFewestRaysAcross ray spacings cuts and engages only the rays it
    // happens to meet: the figures are coarse (a cutter below one spacing may remove nothing).
    const double across = run.cutter.diameter() / simulation.resolution;
    if (across < kFewestRaysAcross) {
      job.warnings.push_back(
          {options.origin("resolution"),
           fmt::format("the cutter {} is {:g} mm across, {:.2g} ray spacings at {:g} mm: "
                       "its removal and engagement are coarse; use a resolution of {:.3g} mm "
                       "or finer",
                       run.cutter.name(), run.cutter.diameter(), across, simulation.resolution,
                       run.cutter.diameter() / (2.0 * kFewestRaysAcross))});
    }
    job.operations.push_back({program, std::move(run.header), run.format, std::move(run.moves),
                              std::move(run.cutter), sampling, 0, std::move(forces), run.tool, o,
                              std::move(run.gcode), run.program_moves});
  }
  count_cl_points(job);
  return job;
}

}  // namespace cwe

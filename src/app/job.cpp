#include "job.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include <fmt/format.h>
#include <tbb/info.h>
#include <nlohmann/json.hpp>

#include "cwe/core/error.hpp"
#include "cwe/core/text_file.hpp"
#include "cwe/toolpath/cl_sampling.hpp"
#include "cwe/io/mesh_io.hpp"
#include "cwe/tool/apt.hpp"
#include "tool_choice.hpp"
#include "tool_table.hpp"

namespace cwe::app {

void require(const std::string& value, const char* what, const char* option) {
  if (value.empty()) {
    throw InputError(SourceLocation{"cwe"},
                     fmt::format("no {}: give {} or put it in a job file", what, option));
  }
}

// Paths in the job are relative to the job file's folder.
void read_job(SimulateCommandOptions& options) {
  if (options.job.empty()) return;
  const std::string text = read_text_file(options.job, "job file");
  nlohmann::json job;
  try {
    job = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {  // parse errors, numbers beyond double range
    throw InputError(SourceLocation{options.job}, fmt::format("not valid JSON: {}", e.what()));
  }
  if (!job.is_object()) throw InputError(SourceLocation{options.job}, "expected a JSON object");
  const std::filesystem::path folder = std::filesystem::path(options.job).parent_path();
  const auto where = [&](const std::string& key) {
    return SourceLocation{fmt::format("{}: \"{}\"", options.job, key)};
  };
  static const char* const kKeys[] = {
      "stock",       "tool",       "path",   "operations",  "out",  "resolution",
      "tolerance",   "threads",    "ply",    "cl_step",     "maps", "stock_only",
      "mesh_stride", "comment",    "forces", "spindle",     "feed", "flutes",
      "helix",       "force_step", "runout", "force_curves", "tools", "tool_for_all",
      "tool_units",  "start"};
  for (const auto& [key, value] : job.items()) {
    if (std::find(std::begin(kKeys), std::end(kKeys), key) == std::end(kKeys)) {
      throw InputError(where(key),
                       "unknown key; expected stock, tool, tools, tool_units, tool_for_all, start, "
                       "path, operations, "
                       "out, resolution, tolerance, threads, mesh_stride, ply, cl_step, maps, "
                       "stock_only, forces, spindle, feed, flutes, helix, force_step, runout, "
                       "force_curves or comment");
    }
  }
  const auto text_of = [&](const char* key, std::string& field, bool is_path) {
    if (!job.contains(key) || !field.empty()) return;
    if (!job[key].is_string()) throw InputError(where(key), "expected a string");
    std::string value = job[key].get<std::string>();
    if (is_path && !value.empty() && std::filesystem::path(value).is_relative()) {
      value = (folder / value).lexically_normal().string();
    }
    field = value;
  };
  const auto number_of = [&](const char* key, double& field) {
    if (!job.contains(key) || field != 0.0) return;
    if (!job[key].is_number()) throw InputError(where(key), "expected a number");
    field = job[key].get<double>();
  };
  // A stock given as a file is a path; a box is not.
  if (job.contains("stock") && options.stock.empty()) {
    if (!job["stock"].is_string()) throw InputError(where("stock"), "expected a string");
    const std::string stock = job["stock"].get<std::string>();
    text_of("stock", options.stock, stock.rfind("box:", 0) != 0);
  }
  // A tool specification is a path only when it names a JSON tool file.
  if (job.contains("tool") && options.tool.empty()) {
    if (!job["tool"].is_string()) throw InputError(where("tool"), "expected a string");
    const std::string tool = job["tool"].get<std::string>();
    text_of("tool", options.tool, tool.size() > 5 && tool.ends_with(".json"));
  }
  text_of("path", options.path, true);
  text_of("out", options.out, true);
  // A tool table: a file (relative to the job) or the table itself.
  if (job.contains("tools") && options.tools.empty()) {
    if (job["tools"].is_string()) {
      text_of("tools", options.tools, true);
    } else {
      options.tool_table = tool_table_from_json(job["tools"], where("tools").source, folder);
    }
  }
  text_of("tool_units", options.tool_units, false);
  text_of("start", options.start, false);
  if (job.contains("tool_for_all") && !options.tool_for_all) {
    if (!job["tool_for_all"].is_boolean()) {
      throw InputError(where("tool_for_all"), "expected true or false");
    }
    options.tool_for_all = job["tool_for_all"].get<bool>();
  }
  // Operations: toolpaths run one after the other on the same stock, each with its tool.
  if (job.contains("operations") && options.operations.empty() && options.path.empty()) {
    const nlohmann::json& list = job["operations"];
    if (!list.is_array() || list.empty()) {
      throw InputError(where("operations"), "expected a non-empty array of {\"tool\", \"path\"}");
    }
    for (std::size_t k = 0; k < list.size(); ++k) {
      const nlohmann::json& op = list[k];
      const SourceLocation at{fmt::format("{}: \"operations\"[{}]", options.job, k)};
      if (!op.is_object()) throw InputError(at, "expected an object {\"tool\", \"path\"}");
      for (const auto& [key, value] : op.items()) {
        if (key != "tool" && key != "path" && key != "comment") {
          throw InputError(at,
                           fmt::format("unknown key \"{}\"; expected tool, path or comment", key));
        }
      }
      if (!op.contains("path") || !op["path"].is_string()) {
        throw InputError(at, "expected \"path\": a toolpath file");
      }
      if (op.contains("tool") && !op["tool"].is_string()) {
        throw InputError(at, "expected \"tool\" to be a string");
      }
      Operation operation;
      operation.path = op["path"].get<std::string>();
      if (std::filesystem::path(operation.path).is_relative()) {
        operation.path = (folder / operation.path).lexically_normal().string();
      }
      operation.tool = op.value("tool", std::string());
      if (operation.tool.size() > 5 && operation.tool.ends_with(".json") &&
          std::filesystem::path(operation.tool).is_relative()) {
        operation.tool = (folder / operation.tool).lexically_normal().string();
      }
      options.operations.push_back(operation);
    }
  }
  number_of("resolution", options.resolution);
  number_of("tolerance", options.tolerance);
  // A whole number of at least 1 (0 in `field`: not given on the command line).
  const auto count_of = [&](const char* key, int& field, const char* expected) {
    if (!job.contains(key) || field != 0) return;
    if (!job[key].is_number_integer() || job[key].get<int>() < 1) {
      throw InputError(where(key), expected);
    }
    field = job[key].get<int>();
  };
  count_of("threads", options.threads, "expected a whole number of threads, at least 1");
  count_of("mesh_stride", options.mesh_stride, "expected a whole number, at least 1");
  if (job.contains("ply") && !options.ply) {
    if (!job["ply"].is_boolean()) throw InputError(where("ply"), "expected true or false");
    options.ply = job["ply"].get<bool>();
  }
  if (job.contains("stock_only") && !options.stock_only) {
    if (!job["stock_only"].is_boolean()) {
      throw InputError(where("stock_only"), "expected true or false");
    }
    options.stock_only = job["stock_only"].get<bool>();
  }
  number_of("cl_step", options.cl_step);
  text_of("maps", options.maps, false);
  // A coefficient set is a path only when it names a JSON file.
  if (job.contains("forces") && options.forces.empty()) {
    if (!job["forces"].is_string()) throw InputError(where("forces"), "expected a string");
    const std::string forces = job["forces"].get<std::string>();
    text_of("forces", options.forces, forces.ends_with(".json"));
  }
  number_of("spindle", options.spindle);
  number_of("feed", options.feed);
  number_of("force_step", options.force_step);
  count_of("flutes", options.flutes, "expected a whole number of flutes, at least 1");
  if (job.contains("helix") && options.helix < 0.0) {
    if (!job["helix"].is_number()) throw InputError(where("helix"), "expected a number");
    options.helix = job["helix"].get<double>();
  }
  text_of("runout", options.runout, false);
  text_of("force_curves", options.force_curves, false);
}

void add_job_options(CLI::App* cmd, SimulateCommandOptions& options) {
  cmd->add_option("job", options.job,
                  "JSON job file (keys: stock, tool, tools, tool_for_all, path or operations, out, "
                  "resolution, "
                  "tolerance, threads, cl_step, maps, stock_only, mesh_stride, ply, forces, "
                  "spindle, feed, flutes, helix, force_step, runout, force_curves); options below "
                  "override it");
  cmd->add_option("--stock", options.stock,
                  "box:xmin,ymin,zmin,xmax,ymax,zmax (mm) or a closed STL file");
  cmd->add_option("--tool", options.tool,
                  "Tool specification or JSON tool file (default: the program's own CUTTER)");
  cmd->add_option("--tools", options.tools,
                  "Tool table (JSON: {\"1\": \"flat:10,30\", …}): the cutter of each tool number "
                  "the program loads (T… M6, LOADTL)");
  cmd->add_option("--start", options.start,
                  "Where a G-code program's tool starts: auto (5 mm above the stock's top at the "
                  "program's first XY), origin, or x,y,z in mm (default auto)");
  cmd->add_option("--tool-units", options.tool_units,
                  "Units of a LinuxCNC tool table's lengths: mm or in (default mm)");
  cmd->add_flag("--tool-for-all", options.tool_for_all,
                "Cut every move of a program that changes tools with the one --tool");
  cmd->add_option("--path", options.path, "Toolpath file (G-code or APT CLDATA)");
  cmd->add_option("--resolution", options.resolution, "Ray spacing s, mm (default 0.1)");
  cmd->add_option("--tolerance", options.tolerance,
                  "Subdivision tolerance of arcs, helices and 5-axis moves, mm (default s/10)");
  cmd->add_option("--threads", options.threads, "Worker threads (default: all cores)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--cl-step", options.cl_step,
                  "Cutter-location spacing along the tip path, mm (default: 0.5 or D/20, the "
                  "smaller)");
  cmd->add_option("--forces", options.forces,
                  "Cutting forces: a coefficient JSON file {Ktc,Krc,Kac,Kte,Kre,Kae} or a bundled "
                  "material (cwe materials lists them)");
  cmd->add_option("--spindle", options.spindle,
                  "Spindle speed, rev/min (default: the program's S words or SPINDL records)");
  cmd->add_option("--feed", options.feed,
                  "Feed rate of every feed move for the force model, mm/min (default: the "
                  "program's F words or FEDRAT records)");
  cmd->add_option("--flutes", options.flutes, "Number of flutes (default: the tool's)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--helix", options.helix, "Helix angle, degrees (default: the tool's)");
  cmd->add_option("--force-step", options.force_step,
                  "Spindle angle step of the force integration, degrees (default 1)");
  cmd->add_option("--runout", options.runout,
                  "Radial runout offset_mm[,angle_deg] of the cutter (default none)");
  cmd->add_flag("--quiet", options.quiet, "No progress bar");
}

namespace {

// A stretch of a program cut by one tool.
struct ToolRun {
  ReadToolpath read;  // the program with only the stretch's moves
  Cutter cutter;
  int tool = 0;
};

// Where a program loads `tool` (its first tool change to it), for errors.
SourceLocation loading(const Toolpath& path, int tool, const std::string& file) {
  for (const ToolChange& change : path.tool_changes) {
    if (change.tool == tool) return change.location;
  }
  return SourceLocation{file};
}

// The program cut into stretches of one tool each, with their cutters: from the tool table, else
// the program's own definition of that tool (CLDATA CUTTER/). A program that loads one tool (or
// none) is one stretch with the operation's --tool (or its one definition). Moves before the
// first tool change go with the first tool loaded.
std::vector<ToolRun> split_by_tool(const ReadToolpath& read, const Operation& op,
                                   const SimulateCommandOptions& options) {
  const Toolpath& path = read.toolpath;
  std::vector<int> tools;  // the tool of each move, moves before any change taking the first
  int first = 0;
  for (const Move& m : path.moves) {
    if (m.tool != 0) {
      first = m.tool;
      break;
    }
  }
  std::vector<int> used;
  for (const Move& m : path.moves) {
    tools.push_back(m.tool != 0 ? m.tool : (tools.empty() ? first : tools.back()));
    if (std::find(used.begin(), used.end(), tools.back()) == used.end()) {
      used.push_back(tools.back());
    }
  }
  const bool table = options.tool_table.has_value();
  // At most one tool: --tool when given (it names the cutter of this operation), else the table's
  // entry for it, else the program's own cutter.
  if (used.size() <= 1 && (!table || !op.tool.empty() || used.empty() || used.front() == 0)) {
    return {{read, choose_cutter(op.tool, path, op.path), used.empty() ? 0 : used.front()}};
  }
  if (!table) {
    if (!op.tool.empty() && options.tool_for_all) {
      return {{read, choose_cutter(op.tool, path, op.path), 0}};
    }
    const bool defined = std::all_of(used.begin(), used.end(), [&](int t) {
      return path.tool_definitions.count(t) > 0;
    });
    if (op.tool.empty() && !defined) {
      throw InputError(loading(path, used[1], op.path),
                       fmt::format("the program loads tool {} here after tool {}: give a tool "
                                   "table (--tools) that names the cutter of each",
                                   used[1], used[0]));
    }
    if (!op.tool.empty()) {
      throw InputError(loading(path, used[1], op.path),
                       fmt::format("the program loads tool {} here after tool {}, but --tool names "
                                   "one cutter: give a tool table (--tools), or --tool-for-all to "
                                   "cut every move with {}",
                                   used[1], used[0], op.tool));
    }
  }
  // The cutter of each tool the program uses.
  std::map<int, Cutter> cutters;
  for (const int t : used) {
    if (table) {
      const auto entry = options.tool_table->tools.find(t);
      if (entry != options.tool_table->tools.end()) {
        try {
          cutters.emplace(t, cutter_of(entry->second));
        } catch (const InputError& e) {
          throw InputError(loading(path, t, op.path), fmt::format("tool {}: {}", t, e.what()));
        }
        continue;
      }
    }
    const auto defined = path.tool_definitions.find(t);
    if (defined == path.tool_definitions.end()) {
      throw InputError(loading(path, t, op.path),
                       fmt::format("tool {} is not in the tool table {}", t,
                                   options.tool_table->source));
    }
    CutterOptions named;
    named.name = fmt::format("{} T{} {}", op.path, t, to_string(defined->second));
    named.apt = defined->second;
    cutters.emplace(t, Cutter(apt_profile(defined->second, SourceLocation{op.path}), named));
  }
  std::vector<ToolRun> runs;
  for (std::size_t m = 0; m < path.moves.size();) {
    std::size_t end = m;
    while (end < path.moves.size() && tools[end] == tools[m]) ++end;
    // The program's warnings go with its first stretch only.
    ReadToolpath part{Toolpath{path.sources, {}, path.tool_definitions, path.tool_changes,
                               runs.empty() ? path.warnings : std::vector<Diagnostic>{},
                               path.units},
                      read.format};
    part.toolpath.moves.assign(path.moves.begin() + static_cast<std::ptrdiff_t>(m),
                               path.moves.begin() + static_cast<std::ptrdiff_t>(end));
    runs.push_back({std::move(part), cutters.at(tools[m]), tools[m]});
    m = end;
  }
  return runs;
}

// Where G-code programs start (docs/simulate.md, "Where the tool starts").
struct StartRule {
  enum class Kind { kAuto, kOrigin, kGiven } kind = Kind::kAuto;
  Vec3 given = Vec3::Zero();
  double top = 0.0;  // the stock's top, for kAuto
};

StartRule start_rule(const SimulateCommandOptions& options) {
  StartRule rule;
  const SourceLocation where{"--start"};
  if (options.start.empty() || options.start == "auto") {
    const StockSpec stock = parse_stock_spec(options.stock, SourceLocation{"--stock"});
    rule.top = stock.is_box ? stock.box.max.z() : read_stl(stock.path).mesh.bounds().max.z();
    return rule;
  }
  if (options.start == "origin") {
    rule.kind = StartRule::Kind::kOrigin;
    return rule;
  }
  std::vector<double> values;
  std::size_t from = 0;
  while (from <= options.start.size()) {
    const std::size_t comma = std::min(options.start.find(',', from), options.start.size());
    const std::string word = options.start.substr(from, comma - from);
    double value = 0.0;
    const std::size_t used = leading_number(word, value);
    if (used == 0 || used != word.size()) {
      throw InputError(where, fmt::format("'{}': expected auto, origin or x,y,z in mm",
                                          options.start));
    }
    values.push_back(value);
    from = comma + 1;
  }
  if (values.size() != 3) {
    throw InputError(where, fmt::format("'{}': expected auto, origin or x,y,z in mm",
                                        options.start));
  }
  rule.kind = StartRule::Kind::kGiven;
  rule.given = Vec3(values[0], values[1], values[2]);
  return rule;
}

// A program read with its tool starting where `rule` says. For "auto", a first reading from the
// origin finds the program's first XY (the end of the first move that leaves the origin's XY,
// else the origin's), and the program is read again from kStartClearance above the stock's top
// there.
ReadToolpath read_program(const std::string& path, const StartRule& rule) {
  if (rule.kind == StartRule::Kind::kOrigin) return read_toolpath_file(path);
  GcodeOptions gcode;
  if (rule.kind == StartRule::Kind::kGiven) {
    gcode.initial_position = rule.given;
    return read_toolpath_file(path, gcode);
  }
  ReadToolpath first = read_toolpath_file(path);
  if (first.format != ToolpathFormat::kGcode) return first;
  Vec3 at(0.0, 0.0, rule.top + kStartClearance);
  for (const Move& m : first.toolpath.moves) {
    if (m.end.head<2>() != Vec2::Zero()) {
      at.head<2>() = m.end.head<2>();
      break;
    }
  }
  gcode.initial_position = at;
  return read_toolpath_file(path, gcode);
}

}  // namespace

PreparedJob prepare_job(SimulateCommandOptions& options, bool sample) {
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
  if (options.forces.empty() && (options.feed != 0.0 || options.spindle != 0.0)) {
    throw InputError(SourceLocation{options.feed != 0.0 ? "--feed" : "--spindle"},
                     "spindle speed and feed overrides are for the force model: give --forces");
  }
  if (!options.forces.empty()) {
    job.forces = force_settings(options.forces, options.spindle, options.feed, options.flutes,
                                options.helix, options.force_step, options.runout);
  }

  if (!options.tool_units.empty() && options.tool_units != "mm" && options.tool_units != "in") {
    throw InputError(SourceLocation{"--tool-units"},
                     fmt::format("'{}': expected mm or in", options.tool_units));
  }
  if (!options.tools.empty()) {
    options.tool_table = read_tool_table(options.tools, options.tool_units == "in");
  }

  // Everything the job needs is read and checked before the long part starts.
  const StartRule start = start_rule(options);
  for (std::size_t o = 0; o < options.operations.size(); ++o) {
    const Operation& op = options.operations[o];
    ReadToolpath read = read_program(op.path, start);
    for (ToolRun& run : split_by_tool(read, op, options)) {
      SamplingOptions sampling;
      sampling.step =
          options.cl_step > 0.0 ? options.cl_step : default_cl_step(run.cutter.diameter());
      const std::size_t cls = sample ? sample_cl_points(run.read.toolpath, sampling).size() : 0;
      job.cl_count += cls;
      std::optional<ForceModel> forces;
      if (job.forces) {
        check_spindle(run.read.toolpath, op.path, *job.forces);
        forces.emplace(run.cutter, job.forces->coefficients, job.forces->model);
      }
      job.operations.push_back({op.path, std::move(run.read), std::move(run.cutter), sampling, cls,
                                std::move(forces), run.tool, o});
    }
  }
  return job;
}

}  // namespace cwe::app

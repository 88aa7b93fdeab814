#include "job_file.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <tbb/info.h>
#include <nlohmann/json.hpp>

#include "cwe/core/error.hpp"
#include "cwe/core/text_file.hpp"
#include "cwe/toolpath/cl_sampling.hpp"

namespace cwe::app {

// Paths in the job are relative to the job file's folder.
void read_job(SimulateCommandOptions& options) {
  if (options.job_file.empty()) return;
  const std::string text = read_text_file(options.job_file, "job file");
  nlohmann::json job;
  try {
    job = nlohmann::json::parse(text);
  } catch (const nlohmann::json::exception& e) {  // parse errors, numbers beyond double range
    throw InputError(SourceLocation{options.job_file}, fmt::format("not valid JSON: {}", e.what()));
  }
  if (!job.is_object()) throw InputError(SourceLocation{options.job_file}, "expected a JSON object");
  const std::filesystem::path folder = std::filesystem::path(options.job_file).parent_path();
  const auto where = [&](const std::string& key) {
    return SourceLocation{fmt::format("{}: \"{}\"", options.job_file, key)};
  };
  // The job's keys, in the order the error lists them.
  static const char* const kKeys[] = {
      "units",  "report_units", "stock",    "tool",         "tools",
      "tool_units",   "tool_for_all", "start",
      "tool_change", "path",  "operations", "out",          "resolution",   "tolerance",
      "threads", "mesh_stride", "ply",      "cl_step",      "maps",         "stock_only",
      "forces", "spindle",    "feed",       "flutes",       "helix",        "force_step",
      "runout", "force_curves", "comment"};
  for (const auto& [key, value] : job.items()) {
    if (std::find(std::begin(kKeys), std::end(kKeys), key) == std::end(kKeys)) {
      throw InputError(where(key), fmt::format("unknown key; expected one of {}",
                                               fmt::join(std::begin(kKeys), std::end(kKeys), ", ")));
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
  text_of("units", options.units, false);
  text_of("report_units", options.report_units, false);
  check_units(options.units, "--units");
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
      options.tool_table = tool_table_from_json(job["tools"], where("tools").source, folder,
                                                unit_length(options.units));
    }
  }
  text_of("tool_units", options.tool_units, false);
  text_of("start", options.start, false);
  text_of("tool_change", options.tool_change, false);
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
      const SourceLocation at{fmt::format("{}: \"operations\"[{}]", options.job_file, k)};
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
  cmd->add_option("job", options.job_file,
                  "JSON job file (keys as the options below, with _ for -, plus operations; "
                  "docs/simulate.md); options below override it");
  cmd->add_option("--stock", options.stock,
                  "box:xmin,ymin,zmin,xmax,ymax,zmax (mm) or a closed STL file");
  cmd->add_option("--tool", options.tool,
                  "Tool specification or JSON tool file (default: the program's own CUTTER)");
  cmd->add_option("--tools", options.tools,
                  "Tool table (JSON: {\"1\": \"flat:10,30\", …}): the cutter of each tool number "
                  "the program loads (T… M6, LOADTL)");
  cmd->add_option("--start", options.start,
                  "Where a program's tool starts: auto (5 mm above the stock's top at the "
                  "program's first XY), origin, or x,y,z (default auto)");
  cmd->add_option("--tool-change", options.tool_change,
                  "Where a program changes tools: auto (the old tool straight up to 5 mm above "
                  "the stock's top, the new one across to its first XY), stay, or x,y,z "
                  "(default auto)");
  cmd->add_option("--units", options.units,
                  "Unit of the lengths given without one (stock box, tool specifications and "
                  "tables, --start, --tool-change): mm or in (default mm)");
  cmd->add_option("--report-units", options.report_units,
                  "Lengths of engagement.csv, engagement.jsonl, forces.csv and the report: mm or "
                  "in (default mm; summary.json stays in mm)");
  cmd->add_option("--tool-units", options.tool_units,
                  "Units of a tool table's bare lengths (LinuxCNC D, cwe specifications): mm or "
                  "in (default: --units)");
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

}  // namespace cwe::app

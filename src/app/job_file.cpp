#include "job_file.hpp"
#include "cli_checks.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <string_view>
#include <utility>
#include <variant>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <tbb/info.h>
#include <nlohmann/json.hpp>

#include "cwe/core/error.hpp"
#include "cwe/core/json_input.hpp"
#include "cwe/core/text_file.hpp"
#include "cwe/toolpath/cl_sampling.hpp"

namespace cwe::app {

namespace {

using Options = SimulateCommandOptions;

// How a job key's value is read (the command line's value, when given, wins).
enum class Kind {
  kText,          // a string
  kPath,          // a file, relative to the job file's folder
  kFolders,       // ':'-separated folders, each relative to the job file's folder
  kStock,         // a path unless a box
  kToolSpec,      // a path when it names a JSON tool file
  kCoefficients,  // a path when it names a JSON file, else a bundled material
  kNumber,        // a number (checked where it is used: prepare_job)
  kCount,         // a whole number
  kFlag,          // true or false
  kTools,         // a tool table: a file, or the table itself
  kMachine,       // a machine definition: a file, or the definition itself
  kOperations,    // the programs with their tools
  kComment,       // anything
};

using Field = std::variant<std::monostate, std::string Options::*, std::optional<double> Options::*,
                           std::optional<int> Options::*, bool Options::*>;

// One key of a JSON job file: its name, how it is read and the option it fills.
struct JobKey {
  const char* name;
  Kind kind;
  Field field;
};

// The job file's keys, in the order they are read (units first: the stock and an inline tool
// table take it) and listed in errors.
const JobKey kJobKeys[] = {
    {"units", Kind::kText, &Options::units},
    {"report_units", Kind::kText, &Options::report_units},
    {"stock", Kind::kStock, &Options::stock},
    {"tool", Kind::kToolSpec, &Options::tool},
    {"path", Kind::kPath, &Options::path},
    {"out", Kind::kPath, &Options::out},
    {"tools", Kind::kTools, &Options::tools},
    {"tool_units", Kind::kText, &Options::tool_units},
    {"tool_for_all", Kind::kFlag, &Options::tool_for_all},
    {"start", Kind::kText, &Options::start},
    {"tool_change", Kind::kText, &Options::tool_change},
    {"subroutine_path", Kind::kFolders, &Options::subroutine_path},
    {"machine", Kind::kMachine, {}},
    {"operations", Kind::kOperations, {}},
    {"workpiece", Kind::kText, &Options::workpiece},
    {"resolution", Kind::kNumber, &Options::resolution},
    {"facet", Kind::kNumber, &Options::facet},
    {"tolerance", Kind::kNumber, &Options::tolerance},
    {"threads", Kind::kCount, &Options::threads},
    {"mesh_stride", Kind::kCount, &Options::mesh_stride},
    {"ply", Kind::kFlag, &Options::ply},
    {"off", Kind::kFlag, &Options::off},
    {"stock_only", Kind::kFlag, &Options::stock_only},
    {"cl_step", Kind::kNumber, &Options::cl_step},
    {"maps", Kind::kText, &Options::maps},
    {"forces", Kind::kCoefficients, &Options::forces},
    {"spindle", Kind::kNumber, &Options::spindle},
    {"feed", Kind::kNumber, &Options::feed},
    {"force_step", Kind::kNumber, &Options::force_step},
    {"flutes", Kind::kCount, &Options::flutes},
    {"helix", Kind::kNumber, &Options::helix},
    {"runout", Kind::kText, &Options::runout},
    {"force_curves", Kind::kText, &Options::force_curves},
    {"memory_limit", Kind::kText, &Options::memory_limit},
    {"comment", Kind::kComment, {}},
};

// A job file being read into options.
class JobFileReader {
 public:
  JobFileReader(Options& options, nlohmann::json job, JsonPlaces places)
      : options_(options),
        job_(std::move(job)),
        places_(std::move(places)),
        folder_(std::filesystem::path(options.job_file).parent_path()) {}

  void read(const JobKey& key) {
    if (!job_.contains(key.name)) return;
    const nlohmann::json& value = job_[key.name];
    switch (key.kind) {
      case Kind::kText:
      case Kind::kPath:
      case Kind::kFolders:
      case Kind::kStock:
      case Kind::kToolSpec:
      case Kind::kCoefficients: {
        std::string& field = options_.*std::get<std::string Options::*>(key.field);
        if (!field.empty()) return;
        if (!value.is_string()) fail(key.name, "expected a string");
        field = text(key.kind, value.get<std::string>());
        given(key.name);
        return;
      }
      case Kind::kNumber: {
        std::optional<double>& field =
            options_.*std::get<std::optional<double> Options::*>(key.field);
        if (field) return;
        if (!value.is_number()) fail(key.name, "expected a number");
        field = value.get<double>();
        given(key.name);
        return;
      }
      case Kind::kCount: {
        std::optional<int>& field = options_.*std::get<std::optional<int> Options::*>(key.field);
        if (field) return;
        // A whole number; its range is checked with the command line's (prepare_job).
        const bool whole =
            value.is_number_integer() ||
            (value.is_number_float() && std::trunc(value.get<double>()) == value.get<double>());
        if (!whole || std::abs(value.get<double>()) > std::numeric_limits<int>::max()) {
          fail(key.name, fmt::format("{}: expected a whole number", value.dump()));
        }
        field = static_cast<int>(value.get<double>());
        given(key.name);
        return;
      }
      case Kind::kFlag: {
        bool& field = options_.*std::get<bool Options::*>(key.field);
        if (field) return;
        if (!value.is_boolean()) fail(key.name, "expected true or false");
        field = value.get<bool>();
        given(key.name);
        return;
      }
      case Kind::kTools:
        if (!options_.tools.empty()) return;
        if (value.is_string()) {
          options_.tools = text(Kind::kPath, value.get<std::string>());
        } else {
          options_.tool_table =
              tool_table_from_json(value, label(key.name), folder_, unit_length(options_.units));
        }
        return;
      case Kind::kMachine:
        if (!options_.machine.empty()) return;
        if (value.is_string()) {
          options_.machine = text(Kind::kPath, value.get<std::string>());
        } else {
          options_.machine_definition = machine_from_json(value, label(key.name));
        }
        return;
      case Kind::kOperations:
        if (options_.operations.empty() && options_.path.empty()) operations(value);
        return;
      case Kind::kComment:
        return;
    }
  }

 private:
  // The place of the value of `key` (a JSON pointer below the top object: "operations/0").
  SourceLocation where(const std::string& key) const { return places_.at("/" + key); }

  // The job file and key, naming a value whose own reader reports no line (tools, machine).
  std::string label(const std::string& key) const {
    return fmt::format("{}: \"{}\"", options_.job_file, key);
  }

  // An error at the value of `key` (a pointer below the top: "operations/2"), naming it.
  [[noreturn]] void fail(const std::string& key, const std::string& message) const {
    std::string name = "\"" + key + "\"";
    if (const std::size_t slash = key.find('/'); slash != key.npos) {
      const std::size_t next = key.find('/', slash + 1);
      name = fmt::format("\"{}\"[{}]", key.substr(0, slash),
                         key.substr(slash + 1, next == key.npos ? key.npos : next - slash - 1));
      if (next != key.npos) name += fmt::format(".\"{}\"", key.substr(next + 1));
    }
    throw InputError(where(key), fmt::format("{}: {}", name, message));
  }

  // Notes where the job file gave `key`, for the errors of checks made later.
  void given(const std::string& key) { options_.given_at[key] = where(key); }

  std::string relative(const std::string& value) const {
    if (value.empty() || !std::filesystem::path(value).is_relative()) return value;
    return (folder_ / value).lexically_normal().string();
  }

  std::string text(Kind kind, const std::string& value) const {
    if (kind == Kind::kFolders) {
      std::string joined;
      for (const std::string& folder : parse_search_path(value)) {
        joined += (joined.empty() ? "" : ":") + relative(folder);
      }
      return joined;
    }
    const bool path = kind == Kind::kPath ||
                      (kind == Kind::kStock && value.rfind("box:", 0) != 0) ||
                      (kind == Kind::kToolSpec && value.size() > 5 && value.ends_with(".json")) ||
                      (kind == Kind::kCoefficients && value.ends_with(".json"));
    return path ? relative(value) : value;
  }

  // Toolpaths run one after the other on the same stock, each with its tool.
  void operations(const nlohmann::json& list) {
    if (!list.is_array() || list.empty()) {
      fail("operations", "expected a non-empty array of {\"tool\", \"path\"}");
    }
    for (std::size_t k = 0; k < list.size(); ++k) {
      const nlohmann::json& op = list[k];
      const std::string at = fmt::format("operations/{}", k);
      if (!op.is_object()) fail(at, "expected an object {\"tool\", \"path\"}");
      for (const auto& [key, value] : op.items()) {
        if (key != "tool" && key != "path" && key != "comment") {
          fail(at + "/" + json_pointer_token(key),
               fmt::format("unknown key \"{}\"; expected tool, path or comment", key));
        }
      }
      if (!op.contains("path") || !op["path"].is_string()) {
        fail(at, "expected \"path\": a toolpath file");
      }
      if (op.contains("tool") && !op["tool"].is_string()) fail(at + "/tool", "expected a string");
      if (op.contains("tool")) given(at + "/tool");
      const SourceLocation tool_at = options_.text_origin(at + "/tool");
      options_.operations.push_back({text(Kind::kToolSpec, op.value("tool", std::string())),
                                     relative(op["path"].get<std::string>()), tool_at});
    }
  }

  Options& options_;
  nlohmann::json job_;
  JsonPlaces places_;
  std::filesystem::path folder_;
};

}  // namespace

// Paths in the job are relative to the job file's folder.
void read_job(SimulateCommandOptions& options) {
  if (options.job_file.empty()) return;
  const std::string text = read_text_file(options.job_file, "job file");
  nlohmann::json job = parse_json_input(text, options.job_file);
  JsonPlaces places(text, options.job_file);
  if (!job.is_object())
    throw InputError(SourceLocation{options.job_file}, "expected a JSON object");
  for (const auto& [key, value] : job.items()) {
    const auto known = std::find_if(std::begin(kJobKeys), std::end(kJobKeys),
                                    [&name = key](const JobKey& k) { return name == k.name; });
    if (known == std::end(kJobKeys)) {
      std::vector<std::string> names;
      for (const JobKey& k : kJobKeys) names.emplace_back(k.name);
      throw InputError(
          places.at("/" + json_pointer_token(key)),
          fmt::format("unknown key \"{}\"; expected one of {}", key, fmt::join(names, ", ")));
    }
  }
  JobFileReader reader(options, std::move(job), std::move(places));
  for (const JobKey& key : kJobKeys) {
    reader.read(key);
    if (std::string_view(key.name) == "units") check_units(options, "units", options.units);
  }
}

void add_job_options(CLI::App* cmd, SimulateCommandOptions& options) {
  cmd->add_option("job", options.job_file,
                  "JSON job file (keys as the options below, with _ for -, plus operations; "
                  "docs/simulate.md); options below override it");
  cmd->add_option("--stock", options.stock,
                  "box:xmin,ymin,zmin,xmax,ymax,zmax (mm), a closed STL file or a STEP file");
  cmd->add_option("--tool", options.tool,
                  "Tool specification or JSON tool file (default: the program's own CUTTER)");
  cmd->add_option("--tools", options.tools,
                  "Tool table (JSON: {\"1\": \"flat:10,30\", …}): the cutter of each tool number "
                  "the program loads (T… M6, LOADTL)");
  cmd->add_option("--start", options.start,
                  "Where a program's tool starts: auto (5 mm above the stock's top at the "
                  "program's first XY), origin, or x,y,z (default auto)");
  cmd->add_option("--subroutine-path", options.subroutine_path,
                  "Folders (':'-separated) searched for a G-code subroutine file <name>.ngc that "
                  "a program calls but does not define, after the program's own folder");
  cmd->add_option("--machine", options.machine,
                  "Machine definition (JSON: work offsets G54…, G28/G30 positions, travel; "
                  "docs/gcode.md): what G53, G28, G30 and the work systems mean");
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
  const CLI::Validator length = positive("a positive length in mm");
  cmd->add_option("--workpiece", options.workpiece,
                  "The in-process workpiece: dexel (tri-dexel rays, default), mesh (a closed "
                  "triangle mesh cut by CGAL's booleans, the polyhedral method) or brep (an "
                  "exact OpenCASCADE solid, the solid-model method; from a box, a STEP stock or "
                  "an STL stock made a solid)");
  cmd->add_option("--resolution", options.resolution,
                  "Ray spacing s, and the engagement maps' disc height, mm (default 0.1)")
      ->check(length);
  cmd->add_option("--facet", options.facet,
                  "Mesh workpiece: edge of the faceted tool at its largest radius, mm (default 1)")
      ->check(length);
  cmd->add_option("--tolerance", options.tolerance,
                  "Subdivision tolerance of arcs, helices and 5-axis moves, mm (default s/10; on "
                  "the mesh workpiece the tools' facet depth h when larger)")
      ->check(length);
  cmd->add_option("--threads", options.threads, "Worker threads (default: all cores)")
      ->check(count("a whole number of threads, at least 1"));
  cmd->add_option("--cl-step", options.cl_step,
                  "Cutter-location spacing along the tip path, mm (default: 0.5 or D/20, the "
                  "smaller)")
      ->check(length);
  cmd->add_option("--forces", options.forces,
                  "Cutting forces: a coefficient JSON file {Ktc,Krc,Kac,Kte,Kre,Kae} or a bundled "
                  "material (cwe materials lists them)");
  cmd->add_option("--spindle", options.spindle,
                  "Spindle speed, rev/min (default: the program's S words or SPINDL records)")
      ->check(positive("a positive speed in rev/min"));
  cmd->add_option("--feed", options.feed,
                  "Feed rate of every feed move for the force model, mm/min (default: the "
                  "program's F words or FEDRAT records)")
      ->check(positive("a positive feed rate in mm/min"));
  cmd->add_option("--flutes", options.flutes, "Number of flutes (default: the tool's)")
      ->check(count("a whole number of flutes, at least 1"));
  cmd->add_option("--helix", options.helix, "Helix angle, degrees (default: the tool's)")
      ->check(non_negative("an angle in degrees, 0 or more"));
  cmd->add_option("--force-step", options.force_step,
                  "Spindle angle step of the force integration, degrees (default 1)")
      ->check(positive("a positive angle in degrees"));
  cmd->add_option("--runout", options.runout,
                  "Radial runout offset_mm[,angle_deg] of the cutter (default none)");
  cmd->add_option("--memory-limit", options.memory_limit,
                  "Most memory the run may take: 16G, 4096M or 50% (default 80% of physical "
                  "memory); a resolution or program that would need more is refused at the start");
  cmd->add_flag("--quiet", options.quiet, "No progress bar");
}

}  // namespace cwe::app

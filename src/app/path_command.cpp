#include "path_command.hpp"

#include "cli_checks.hpp"

#include <algorithm>
#include <map>

#include <fmt/format.h>
#include <fmt/ostream.h>
#include <nlohmann/json.hpp>

#include "cwe/core/error.hpp"
#include "cwe/core/text_file.hpp"
#include "cwe/geometry/tolerance.hpp"
#include "cwe/job/machine.hpp"
#include "cwe/job/tool_table.hpp"
#include "cwe/toolpath/cl_sampling.hpp"
#include "cwe/toolpath/toolpath_reader.hpp"

namespace cwe::app {
namespace {

nlohmann::json vec_json(const Vec3& v) { return {v.x(), v.y(), v.z()}; }

// One JSON object for a move, millimetres whatever the program units. A move from a subroutine
// file also names that file ("file"); `line` is always the line in the move's own file.
void dump_move(const Move& m, const std::vector<std::string>& sources, std::ostream& out) {
  nlohmann::json j;
  j["line"] = m.line;
  if (m.source > 0 && static_cast<std::size_t>(m.source) < sources.size()) {
    j["file"] = sources[static_cast<std::size_t>(m.source)];
  }
  j["type"] = m.is_arc() ? "arc" : (m.is_rapid() ? "rapid" : "feed");
  j["end"] = vec_json(m.end);
  if (m.is_arc()) {
    j["center"] = vec_json(m.center);
    j["normal"] = vec_json(m.normal);
    j["turns"] = m.extra_turns();
  }
  j["axis"] = vec_json(m.end_axis);
  out << j.dump() << '\n';
}

// One CL point as a JSON line; k is its index among the program's.
void dump_cl_point(std::size_t k, const ClPoint& p, std::ostream& out) {
  nlohmann::json j;
  j["cl"] = k;
  j["move"] = p.move;
  j["line"] = p.line;
  j["u"] = p.u;
  j["position"] = vec_json(p.position);
  j["axis"] = vec_json(p.axis);
  j["feed_direction"] = vec_json(p.feed_direction);
  j["velocity_mm_s"] = vec_json(p.velocity);
  j["angular_velocity_rad_s"] = vec_json(p.angular_velocity);
  j["path_length_mm"] = p.path_length;
  out << j.dump() << '\n';
}

// What `cwe path` reports of a program, tallied move by move.
struct PathTally {
  std::size_t moves = 0, cl_points = 0;
  int rapids = 0, lines = 0, arcs = 0, helices = 0, full_circles = 0, five_axis = 0, empty = 0;
  double feed_length = 0.0, rapid_length = 0.0;
  double feed_min = 0.0, feed_max = 0.0;
  bool any_feed = false;
  Aabb bounds;
  std::map<int, int> moves_per_tool;
  std::map<std::pair<int, int>, int> spindles;  // (rpm, direction) → feed moves

  void add(const Move& m, const ClSampler& sampler, const std::vector<std::string>& sources);
};

void PathTally::add(const Move& m, const ClSampler& sampler,
                    const std::vector<std::string>& sources) {
  const double length = m.length();
  // The first move starts at an assumed position (the origin), not a programmed one.
  if (moves++ == 0 && !m.is_arc()) {
    bounds.extend(m.end);
  } else {
    bounds.extend(m.bounds());
  }
  cl_points += static_cast<std::size_t>(sampler.steps(m, &sources));
  ++moves_per_tool[m.tool];
  if (length <= tol::kLength && m.axis_angle() <= tol::kAngle) ++empty;
  if (m.axis_angle() > tol::kAngle) ++five_axis;
  if (m.is_rapid()) {
    ++rapids;
    rapid_length += length;
    return;
  }
  ++spindles[{static_cast<int>(std::lround(m.spindle_speed)), static_cast<int>(m.spindle)}];
  feed_length += length;
  if (m.is_arc()) {
    ++arcs;
    if (std::abs(m.axial) > tol::kLength) ++helices;
    if (m.sweep >= kTwoPi - tol::kAngle) ++full_circles;
  } else {
    ++lines;
  }
  feed_min = any_feed ? std::min(feed_min, m.feed_rate) : m.feed_rate;
  feed_max = any_feed ? std::max(feed_max, m.feed_rate) : m.feed_rate;
  any_feed = true;
}

// The spindle and tool lines of the summary.
void print_spindles_and_tools(const Toolpath& path, const PathTally& t, std::ostream& out) {
  for (const auto& [key, count] : t.spindles) {
    const char* dir = key.second == static_cast<int>(SpindleDirection::kClockwise) ? "CW"
                      : key.second == static_cast<int>(SpindleDirection::kCounterClockwise)
                          ? "CCW"
                          : "stopped";
    fmt::print(out, "  spindle         {} rpm {} ({} feed moves)\n", key.first, dir, count);
  }
  for (const auto& [tool, count] : t.moves_per_tool) {
    const auto def = path.tool_definitions.find(tool);
    // Where the program loads it (the line a tool table's errors name).
    std::string loaded;
    for (const ToolChange& change : path.tool_changes) {
      if (change.tool == tool) {
        loaded = fmt::format(", loaded at line {}", change.location.line);
        break;
      }
    }
    fmt::print(out, "  tool {:<10} {} moves{}{}\n", tool == 0 ? "(none)" : fmt::format("T{}", tool),
               count, loaded,
               def != path.tool_definitions.end() ? "  " + to_string(def->second) : "");
  }
}

void print_summary(const std::string& file, const ReadToolpath& read, const PathTally& t,
                   const PathCommandOptions& options, std::ostream& out) {
  const Toolpath& path = read.toolpath;
  fmt::print(out, "Toolpath {} ({}, written in {})\n", file, to_string(read.format),
             path.units == ProgramUnits::kMillimetres ? "millimetres" : "inches");
  fmt::print(out,
             "  moves           {}: {} rapid, {} linear feed, {} arc ({} helical, {} of a full "
             "turn or more)\n",
             t.moves, t.rapids, t.lines, t.arcs, t.helices, t.full_circles);
  if (t.five_axis > 0) fmt::print(out, "  5-axis moves    {} (tool axis turning)\n", t.five_axis);
  if (t.empty > 0) fmt::print(out, "  zero-length     {} (no motion; not sampled)\n", t.empty);
  fmt::print(out, "  feed length     {:.3f} mm\n", t.feed_length);
  fmt::print(out, "  rapid length    {:.3f} mm\n", t.rapid_length);
  if (!t.bounds.is_empty()) {
    const Aabb& b = t.bounds;
    fmt::print(out,
               "  tip bounds      X {:.3f} .. {:.3f}, Y {:.3f} .. {:.3f}, Z {:.3f} .. {:.3f} mm\n",
               b.min.x(), b.max.x(), b.min.y(), b.max.y(), b.min.z(), b.max.z());
  }
  if (t.any_feed) {
    fmt::print(out, "  feed rates      {:.6g} .. {:.6g} mm/min\n", t.feed_min, t.feed_max);
  }
  print_spindles_and_tools(path, t, out);
  fmt::print(out, "  CL points       {} (every {:g} mm of tip path and {:g} deg of axis turn)\n",
             t.cl_points, options.cl_step, options.cl_angle_deg);
  fmt::print(out, "  warnings        {}\n", path.warnings.size());
  const std::size_t shown = std::min<std::size_t>(path.warnings.size(), 10);
  for (std::size_t i = 0; i < shown; ++i) {
    const Diagnostic& d = path.warnings[i];
    fmt::print(out, "    {}:{}: warning: {}\n", d.location.source, d.location.line, d.message);
  }
  if (shown < path.warnings.size()) {
    fmt::print(out, "    … {} more\n", path.warnings.size() - shown);
  }
}

}  // namespace

void add_path_command(CLI::App& app, PathCommandOptions& options) {
  CLI::App* path = app.add_subcommand(
      "path", "Read a toolpath (G-code or APT CLDATA) and summarise it, or dump its moves.");
  path->add_option("file", options.file,
                   "The toolpath file (.ngc/.nc/.tap/.gcode or .cl/.cls/.apt)")
      ->required();
  path->add_flag("--dump", options.dump,
                 "Write one JSON object per move (mm) instead of the summary");
  path->add_flag("--cl-dump", options.cl_dump,
                 "Write one JSON object per cutter-location point instead of the summary");
  path->add_option("--subroutine-path", options.subroutine_path,
                   "Folders (':'-separated) searched for a G-code subroutine file <name>.ngc that "
                   "the program calls but does not define, after the program's own folder");
  path->add_option("--tool", options.tool,
                   "The cutter whose diameter G41/G42 (cutter radius compensation) offset by, "
                   "whatever the tool number: a tool specification or JSON tool file");
  path->add_option("--tools", options.tools,
                   "Tool table (JSON, FreeCAD .fctl or LinuxCNC .tbl): the diameters G41/G42 "
                   "offset by, by tool number (D word, or the tool in the spindle)");
  path->add_option("--tool-units", options.tool_units,
                   "Units of the bare lengths of --tool and --tools: mm or in")
      ->check(CLI::IsMember({"mm", "in"}))
      ->capture_default_str();
  path->add_option("--machine", options.machine,
                   "Machine definition (JSON: work offsets G54…, G28/G30 positions, travel; "
                   "docs/gcode.md): what G53, G28, G30 and the work systems mean");
  path->add_option("--cl-step", options.cl_step, "CL spacing along the tip path, mm")
      ->check(positive("a positive length in mm"))
      ->capture_default_str();
  path->add_option("--cl-angle", options.cl_angle_deg, "CL spacing in tool-axis turn, degrees")
      ->check(positive("a positive angle in degrees"))
      ->capture_default_str();
}

int run_path_command(const PathCommandOptions& options, std::ostream& out) {
  if (options.dump && options.cl_dump) {
    throw InputError(SourceLocation{"--dump"}, "cannot go with --cl-dump: choose one");
  }
  GcodeOptions gcode;
  gcode.subroutine_path = parse_search_path(options.subroutine_path);
  const bool inches = options.tool_units == "in";
  std::optional<ToolTable> table;
  if (!options.tools.empty()) table = read_tool_table(options.tools, inches);
  gcode.tool_diameter =
      compensation_diameters(table, options.tool, inches ? kMillimetresPerInch : 1.0);
  if (!options.machine.empty()) gcode.machine = read_machine_file(options.machine);
  SamplingOptions sampling;
  sampling.step = options.cl_step;
  sampling.angular_step = degrees_to_radians(options.cl_angle_deg);
  // The program is streamed, never held: any length reads in bounded memory. The summary is
  // tallied in one reading; a dump reads the program twice, so that a program in error writes
  // nothing (its errors come at the end of a reading).
  ClSampler sampler(sampling);
  PathTally tally;
  const ReadToolpath read = read_toolpath_file(
      options.file, gcode, [&](const Move& m, const std::vector<std::string>& sources) {
        tally.add(m, sampler, sources);
      });
  if (options.dump) {
    read_toolpath_file(options.file, gcode,
                       [&](const Move& m, const std::vector<std::string>& sources) {
                         dump_move(m, sources, out);
                       });
  } else if (options.cl_dump) {
    std::vector<ClPoint> points;
    std::size_t k = 0;
    int index = 0;
    read_toolpath_file(options.file, gcode, [&](const Move& m, const std::vector<std::string>&) {
      sampler.next(m, index++, points);  // memory for one move's points only
      for (const ClPoint& p : points) dump_cl_point(k++, p, out);
    });
  } else {
    print_summary(options.file, read, tally, options, out);
  }
  return 0;
}

}  // namespace cwe::app

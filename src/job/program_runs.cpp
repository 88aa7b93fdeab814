#include "program_runs.hpp"

#include <algorithm>
#include <map>
#include <optional>

#include <fmt/format.h>

#include "cwe/core/error.hpp"
#include "cwe/core/numbers.hpp"
#include "cwe/job/job.hpp"
#include "cwe/job/tool_choice.hpp"
#include "cwe/job/tool_table.hpp"
#include "cwe/simulation/simulation.hpp"
#include "cwe/tool/apt.hpp"

namespace cwe {
namespace {

// "x,y,z", or nullopt when `text` is not three numbers.
std::optional<Vec3> point_of(const std::string& text) {
  const NumberList list = parse_number_list(text);
  if (list.bad || list.values.size() != 3) return std::nullopt;
  return Vec3(list.values[0], list.values[1], list.values[2]);
}

// Where `path` loads `tool` at or before `line` (the last such change), for errors and for the
// moves of a tool change.
SourceLocation loading(const Toolpath& path, int tool, const std::string& file, int line = 0) {
  const ToolChange* found = nullptr;
  for (const ToolChange& change : path.tool_changes) {
    if (change.tool != tool) continue;
    if (found == nullptr || line == 0 || change.location.line <= line) found = &change;
    if (line == 0) break;
  }
  return found != nullptr ? found->location : SourceLocation{file};
}

// The program read with `gcode` and its tool starting where `rules` say (set in `gcode`). For
// "auto", a first reading from the origin finds the program's first XY (the end of the first move
// that leaves the origin's XY, else the origin's), and the program is read again from
// kStartClearance above the stock's top there. A CLDATA program with FROM starts there whatever
// the rule.
ReadToolpath read_program(const std::string& path, const EntryRules& rules, GcodeOptions& gcode) {
  if (rules.start == EntryRules::Kind::kOrigin) return read_toolpath_file(path, gcode);
  if (rules.start == EntryRules::Kind::kGiven) {
    gcode.initial_position = rules.start_at;
    return read_toolpath_file(path, gcode);
  }
  const ReadToolpath first = read_toolpath_file(path, gcode);
  Vec3 at(0.0, 0.0, rules.clearance_z);
  for (const Move& m : first.toolpath.moves) {
    if (m.end.head<2>() != Vec2::Zero()) {
      at.head<2>() = m.end.head<2>();
      break;
    }
  }
  gcode.initial_position = at;
  return read_toolpath_file(path, gcode);
}

// A rapid of the tool of `like` from `from` to `to`, at `line`; nullopt when they meet.
std::optional<Move> rapid(const Move& like, const Vec3& from, const Vec3& to, int line) {
  if (from == to) return std::nullopt;
  Move m;
  m.mode = MotionMode::kRapid;
  m.start = from;
  m.end = to;
  m.start_axis = m.end_axis = like.end_axis;
  m.spindle_speed = like.spindle_speed;
  m.spindle = like.spindle;
  m.tool = like.tool;
  m.line = line;
  m.source = like.source;
  return m;
}

// The tool change between `before` (the old tool's moves) and `after` (the new tool's): the old
// tool goes up and across to the change position, and the new tool's first move starts there.
void change_tools(std::vector<Move>& before, std::vector<Move>& after, const EntryRules& rules,
                  int line) {
  const Move last = before.back();
  const Vec3 from = last.end;
  Vec3 to = from;
  if (rules.change == EntryRules::Kind::kAuto) {
    to = Vec3(after.front().end.x(), after.front().end.y(), std::max(from.z(), rules.clearance_z));
  } else if (rules.change == EntryRules::Kind::kGiven) {
    to = rules.change_at;
  }
  // Up first, then across.
  const Vec3 up(from.x(), from.y(), std::max(from.z(), to.z()));
  for (const auto& [a, b] : {std::pair{from, up}, std::pair{up, to}}) {
    if (auto m = rapid(last, a, b, line)) before.push_back(*m);
  }
  Move& first = after.front();
  if (first.start == to) return;
  if (!first.is_arc()) {
    first.start = to;
  } else if (auto m = rapid(first, to, first.start, line)) {
    m->start_axis = m->end_axis = first.start_axis;
    after.insert(after.begin(), *m);
  }
}

// The whole program as one run, its moves moved (not copied: a long program is held once).
std::vector<ToolRun> whole(ReadToolpath read, Cutter cutter, int tool, SourceLocation loaded,
                           const GcodeOptions& gcode) {
  std::vector<ToolRun> runs;
  runs.push_back(
      ToolRun{std::move(read), std::move(cutter), tool, std::nullopt, std::move(loaded), gcode});
  return runs;
}

}  // namespace

EntryRules entry_rules(const Job& options, double stock_top) {
  EntryRules rules;
  rules.clearance_z = stock_top + kStartClearance;
  // "auto" (or empty), the option's own word, or x,y,z in --units.
  const auto parse = [&](const std::string& text, const char* option, const char* word,
                         EntryRules::Kind word_kind, EntryRules::Kind& kind, Vec3& at) {
    if (text.empty() || text == "auto") return;
    if (text == word) {
      kind = word_kind;
      return;
    }
    const std::optional<Vec3> point = point_of(text);
    if (!point) {
      throw options.error(option, fmt::format("'{}': expected auto, {} or x,y,z", text, word));
    }
    kind = EntryRules::Kind::kGiven;
    at = *point * unit_length(options.units);
  };
  parse(options.start, "start", "origin", EntryRules::Kind::kOrigin, rules.start, rules.start_at);
  parse(options.tool_change, "tool_change", "stay", EntryRules::Kind::kStay, rules.change,
        rules.change_at);
  // "auto" on a machine with a tool-change position: there, in the frame's coordinates.
  const std::optional<MachineDefinition>& machine = options.machine_definition;
  if (rules.change == EntryRules::Kind::kAuto &&
      (options.tool_change.empty() || options.tool_change == "auto") && machine &&
      machine->tool_change) {
    rules.change = EntryRules::Kind::kGiven;
    rules.change_at =
        *machine->tool_change - machine->work_offsets[static_cast<std::size_t>(machine->frame - 1)];
  }
  return rules;
}

std::vector<ToolRun> program_runs(const Operation& op, const Job& options,
                                  const EntryRules& rules) {
  GcodeOptions gcode;
  gcode.subroutine_path = parse_search_path(options.subroutine_path);
  gcode.tool_diameter =
      compensation_diameters(options.tool_table, op.tool, unit_length(options.units), op.tool_at);
  gcode.machine = options.machine_definition;
  ReadToolpath read = read_program(op.path, rules, gcode);
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
    const int tool = used.empty() ? 0 : used.front();
    return whole(std::move(read),
                 choose_cutter(op.tool, op.tool_at, path, op.path, unit_length(options.units)),
                 tool, loading(path, tool, op.path), gcode);
  }
  if (!table) {
    if (!op.tool.empty() && options.tool_for_all) {
      return whole(std::move(read),
                   choose_cutter(op.tool, op.tool_at, path, op.path, unit_length(options.units)), 0,
                   SourceLocation{op.path}, gcode);
    }
    const bool defined = std::all_of(used.begin(), used.end(),
                                     [&](int t) { return path.tool_definitions.count(t) > 0; });
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
      throw InputError(loading(path, t, op.path), fmt::format("tool {} is not in the tool table {}",
                                                              t, options.tool_table->source));
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
    ReadToolpath part{Toolpath{path.sources,
                               {},
                               path.tool_definitions,
                               path.tool_changes,
                               runs.empty() ? path.warnings : std::vector<Diagnostic>{},
                               path.units},
                      read.format};
    part.toolpath.moves.assign(path.moves.begin() + static_cast<std::ptrdiff_t>(m),
                               path.moves.begin() + static_cast<std::ptrdiff_t>(end));
    const SourceLocation loaded = loading(path, tools[m], op.path, path.moves[m].line);
    if (!runs.empty()) {
      change_tools(runs.back().read.toolpath.moves, part.toolpath.moves, rules, loaded.line);
    }
    std::optional<CuttingCoefficients> coefficients;
    if (table) {
      const auto entry = options.tool_table->tools.find(tools[m]);
      if (entry != options.tool_table->tools.end()) coefficients = entry->second.coefficients;
    }
    runs.push_back(
        {std::move(part), cutters.at(tools[m]), tools[m], std::move(coefficients), loaded, gcode});
    m = end;
  }
  return runs;
}

}  // namespace cwe

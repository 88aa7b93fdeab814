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

// Thrown from a reading's sink to stop the reading there.
struct StopReading {};

// The program's first XY, read only that far: the end of the first move that leaves the origin's
// XY, else the origin's.
Vec2 first_xy(const std::string& path, const GcodeOptions& gcode) {
  Vec2 at = Vec2::Zero();
  try {
    (void)read_toolpath_file(path, gcode, [&](const Move& m, const std::vector<std::string>&) {
      if (m.end.head<2>() != Vec2::Zero()) {
        at = m.end.head<2>();
        throw StopReading{};
      }
    });
  } catch (const StopReading&) {
  }
  return at;
}

// A stretch of a program's moves with one tool, with its first and last move (for the moves of a
// tool change).
struct Stretch {
  int tool = 0;
  std::size_t first = 0, count = 0;
  Move first_move, last_move;
};

// A program read through, its moves not kept: what it is without them and its stretches.
struct ProgramScan {
  ReadToolpath header;
  std::vector<Stretch> stretches;  // moves before any tool change are the first tool's
  std::size_t moves = 0;
};

// The program read with `gcode` and its tool starting where `rules` say (set in `gcode`). For
// "auto", a first reading from the origin, as far as the program's first XY (first_xy), and the
// program is read again from kStartClearance above the stock's top there. A CLDATA program with
// FROM starts there whatever the rule.
ProgramScan scan_program(const std::string& path, const EntryRules& rules, GcodeOptions& gcode) {
  if (rules.start == EntryRules::Kind::kGiven) gcode.initial_position = rules.start_at;
  if (rules.start == EntryRules::Kind::kAuto) {
    const Vec2 xy = first_xy(path, gcode);
    gcode.initial_position = Vec3(xy.x(), xy.y(), rules.clearance_z);
  }
  ProgramScan scan;
  int current = 0;
  scan.header =
      read_toolpath_file(path, gcode, [&](const Move& m, const std::vector<std::string>&) {
        const int tool = m.tool != 0 ? m.tool : current;
        // The moves before the program's first tool change are that tool's.
        if (current == 0 && tool != 0 && scan.stretches.size() == 1) scan.stretches[0].tool = tool;
        current = tool;
        if (scan.stretches.empty() || scan.stretches.back().tool != tool) {
          scan.stretches.push_back({tool, scan.moves, 0, m, m});
        }
        Stretch& stretch = scan.stretches.back();
        ++stretch.count;
        stretch.last_move = m;
        ++scan.moves;
      });
  return scan;
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

// The tool change between `before` (the old tool's moves, ending with `last`) and `after` (the
// new tool's, starting with `first`): the old tool goes up and across to the change position,
// and the new tool's first move starts there.
void change_tools(const Move& last, OperationMoves& before, const Move& first,
                  OperationMoves& after, const EntryRules& rules, int line) {
  const Vec3 from = last.end;
  Vec3 to = from;
  if (rules.change == EntryRules::Kind::kAuto) {
    to = Vec3(first.end.x(), first.end.y(), std::max(from.z(), rules.clearance_z));
  } else if (rules.change == EntryRules::Kind::kGiven) {
    to = rules.change_at;
  }
  // Up first, then across.
  const Vec3 up(from.x(), from.y(), std::max(from.z(), to.z()));
  for (const auto& [a, b] : {std::pair{from, up}, std::pair{up, to}}) {
    if (auto m = rapid(last, a, b, line)) before.lead_out.push_back(*m);
  }
  if (first.start == to) return;
  if (!first.is_arc()) {
    after.first_start = to;
  } else if (auto m = rapid(first, to, first.start, line)) {
    m->start_axis = m->end_axis = first.start_axis;
    after.lead_in.push_back(*m);
  }
}

// The whole program as one run.
std::vector<ToolRun> whole(ProgramScan scan, Cutter cutter, int tool, SourceLocation loaded,
                           const GcodeOptions& gcode) {
  std::vector<ToolRun> runs;
  OperationMoves moves;
  moves.count = scan.moves;
  runs.push_back(ToolRun{std::move(scan.header.toolpath), scan.header.format, std::move(moves),
                         std::move(cutter), tool, std::nullopt, std::move(loaded), gcode,
                         scan.moves});
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
  ProgramScan scan = scan_program(op.path, rules, gcode);
  const Toolpath& path = scan.header.toolpath;
  std::vector<int> used;
  for (const Stretch& s : scan.stretches) {
    if (std::find(used.begin(), used.end(), s.tool) == used.end()) used.push_back(s.tool);
  }
  const bool table = options.tool_table.has_value();
  // At most one tool: --tool when given (it names the cutter of this operation), else the table's
  // entry for it, else the program's own cutter.
  if (used.size() <= 1 && (!table || !op.tool.empty() || used.empty() || used.front() == 0)) {
    const int tool = used.empty() ? 0 : used.front();
    Cutter cutter = choose_cutter(op.tool, op.tool_at, path, op.path, unit_length(options.units));
    SourceLocation loaded = loading(path, tool, op.path);
    return whole(std::move(scan), std::move(cutter), tool, std::move(loaded), gcode);
  }
  if (!table) {
    if (!op.tool.empty() && options.tool_for_all) {
      Cutter cutter = choose_cutter(op.tool, op.tool_at, path, op.path, unit_length(options.units));
      return whole(std::move(scan), std::move(cutter), 0, SourceLocation{op.path}, gcode);
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
  for (std::size_t k = 0; k < scan.stretches.size(); ++k) {
    const Stretch& stretch = scan.stretches[k];
    // The program's warnings go with its first stretch only.
    Toolpath header{path.sources,
                    {},
                    path.tool_definitions,
                    path.tool_changes,
                    runs.empty() ? path.warnings : std::vector<Diagnostic>{},
                    path.units};
    OperationMoves moves;
    moves.first = stretch.first;
    moves.count = stretch.count;
    const SourceLocation loaded = loading(path, stretch.tool, op.path, stretch.first_move.line);
    if (k > 0) {
      change_tools(scan.stretches[k - 1].last_move, runs.back().moves, stretch.first_move, moves,
                   rules, loaded.line);
    }
    std::optional<CuttingCoefficients> coefficients;
    if (table) {
      const auto entry = options.tool_table->tools.find(stretch.tool);
      if (entry != options.tool_table->tools.end()) coefficients = entry->second.coefficients;
    }
    runs.push_back({std::move(header), scan.header.format, std::move(moves),
                    cutters.at(stretch.tool), stretch.tool, std::move(coefficients), loaded, gcode,
                    scan.moves});
  }
  return runs;
}

namespace {

// Thrown when a program read again gives other moves than when the job was prepared.
[[noreturn]] void changed(const PreparedOperation& op, std::size_t moves) {
  throw InputError(SourceLocation{op.path},
                   fmt::format("the program reads differently than when the job started ({} "
                               "moves, not {}): was it changed while the job ran?",
                               moves, op.program_moves));
}

}  // namespace

void for_each_move(const PreparedJob& job, const OperationVisitor& visitor) {
  const std::vector<PreparedOperation>& ops = job.operations;
  for (std::size_t o = 0; o < ops.size();) {
    // The operations cut from one program, [o, end), all read in one reading.
    std::size_t end = o + 1;
    while (end < ops.size() && ops[end].operation == ops[o].operation) ++end;
    std::size_t at = o;  // the operation whose moves come next
    bool begun = false;
    const auto open = [&] {
      if (visitor.begin) visitor.begin(at);
      for (const Move& m : ops[at].moves.lead_in) visitor.move(m, ops[at].toolpath.sources);
      begun = true;
    };
    const auto close = [&] {
      if (!begun) open();
      for (const Move& m : ops[at].moves.lead_out) visitor.move(m, ops[at].toolpath.sources);
      if (visitor.end) visitor.end(at);
      ++at;
      begun = false;
    };
    std::size_t index = 0;  // of the program's move
    (void)read_toolpath_file(ops[o].path, ops[o].gcode,
                             [&](const Move& move, const std::vector<std::string>& sources) {
                               const std::size_t i = index++;
                               while (at < end && i >= ops[at].moves.first + ops[at].moves.count)
                                 close();
                               if (at == end) changed(ops[o], index);
                               const OperationMoves& moves = ops[at].moves;
                               if (!begun) open();
                               if (i == moves.first && moves.first_start) {
                                 Move first = move;
                                 first.start = *moves.first_start;
                                 visitor.move(first, sources);
                               } else {
                                 visitor.move(move, sources);
                               }
                             });
    if (index != ops[o].program_moves) changed(ops[o], index);
    while (at < end) close();
    o = end;
  }
}

std::size_t move_count(const PreparedJob& job) {
  std::size_t moves = 0;
  for (const PreparedOperation& op : job.operations) moves += op.moves.size();
  return moves;
}

}  // namespace cwe

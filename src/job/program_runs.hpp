#pragma once
// A job's programs as the stretches each tool cuts, and where each tool comes in: at the start of
// a program (--start) and at each tool change (--tool-change). See docs/simulate.md, "Where the
// tool starts" and "Programs that change tools".

#include <optional>
#include <string>
#include <vector>

#include "cwe/geometry/vec.hpp"
#include "cwe/job/job.hpp"
#include "cwe/process/cutting_coefficients.hpp"
#include "cwe/tool/cutter.hpp"
#include "cwe/toolpath/toolpath_reader.hpp"

namespace cwe {

// Where tools come in, from --start and --tool-change.
struct EntryRules {
  enum class Kind {
    kAuto,    // kStartClearance above the stock's top, at the first XY the tool goes to
    kOrigin,  // start only: (0, 0, 0)
    kStay,    // tool change only: the new tool starts where the old one stopped
    kGiven,   // at `start_at` / `change_at`
  };
  Kind start = Kind::kAuto;
  Vec3 start_at = Vec3::Zero();
  Kind change = Kind::kAuto;
  Vec3 change_at = Vec3::Zero();
  double clearance_z = kStartClearance;  // the stock's top + kStartClearance
};

// The rules of the options, for a stock whose top is at `stock_top`. Throws InputError naming
// the option.
EntryRules entry_rules(const Job& options, double stock_top);

// A stretch of a program cut by one tool.
struct ToolRun {
  Toolpath header;  // the program without its moves (its warnings with the first stretch only)
  ToolpathFormat format = ToolpathFormat::kGcode;
  OperationMoves moves;  // the stretch's moves in the program, with the tool change's rapids
  Cutter cutter;
  int tool = 0;                                     // 0: the program loads no tool
  std::optional<CuttingCoefficients> coefficients;  // the tool table's for this tool, if any
  SourceLocation loaded;          // where the program loads the tool (the file when it does not)
  GcodeOptions gcode;             // what the program was read with (G-code)
  std::size_t program_moves = 0;  // of the whole program
};

// The program of `op` read with its tool starting where `rules` say, cut into stretches of one
// tool each (the cutter of each from the tool table, else the program's own definition; one
// stretch with op.tool for a program that loads at most one tool), each new tool coming in as
// `rules` say: the old tool rapids up and across to the change position (moves of its own, at
// the line that loads the new tool), and the new tool's first move starts there. The program is
// read move by move and its moves are not kept. Throws InputError at the line that loads a tool
// no table or definition names, or for one --tool with a program that changes tools (unless
// options.tool_for_all).
std::vector<ToolRun> program_runs(const Operation& op, const Job& options, const EntryRules& rules);

}  // namespace cwe

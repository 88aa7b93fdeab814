#pragma once
// A whole program as a list of moves, with what a reader learned on the way: the source files,
// the tools it selected or defined, and warnings (never silently dropped input).

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "cwe/core/error.hpp"
#include "cwe/tool/apt.hpp"
#include "cwe/toolpath/move.hpp"

namespace cwe {

enum class ProgramUnits { kMillimetres, kInches };

// A remark about the input that did not stop reading it (an unknown CLDATA record, a rapid
// through material, …), with its location.
struct Diagnostic {
  SourceLocation location;
  std::string message;
};

// A tool loaded by the program (G-code M6 after T, CLDATA LOADTL/), where the program loads it.
struct ToolChange {
  int tool = 0;
  SourceLocation location;
};

struct Toolpath {
  std::vector<std::string> sources;  // file names; Move::source indexes this
  std::vector<Move> moves;
  // Tools defined in the program (CLDATA CUTTER/ records), by tool number (LOADTL; 0 when the
  // program never numbers its tools).
  std::map<int, AptCutter> tool_definitions;
  std::vector<ToolChange> tool_changes;  // in program order
  std::vector<Diagnostic> warnings;
  ProgramUnits units = ProgramUnits::kMillimetres;  // the units the program was written in
};

// The file of `sources` (Toolpath::sources) that `move` comes from; `otherwise` when its `source`
// names none.
const std::string& source_file(const Move& move, const std::vector<std::string>& sources,
                               const std::string& otherwise);

// Appends `move` to moves held in memory. When the vector must grow, its new size is first
// checked against the memory limit (cwe/core/memory_limit.hpp): a program too long to hold is an
// InputError at `where` (the move's file and line), before the allocation.
void hold_move(std::vector<Move>& moves, const Move& move, const SourceLocation& where);

}  // namespace cwe

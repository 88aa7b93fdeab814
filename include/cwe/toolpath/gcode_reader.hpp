#pragma once
// G-code (RS274NGC as LinuxCNC 2.9 interprets it) to moves.
//
// The language LinuxCNC's interpreter reads, with its semantics, move for move: parameters and
// expressions, O-word subroutines, conditions and loops (subroutine files from a search path),
// coordinate systems, canned cycles, cutter radius compensation. What cwe does not model (rotary
// axes, lathe modes, I/O, …) is refused with an InputError naming file, line and column ("not
// supported"), never ignored or misread. See docs/gcode.md. Moves are in machine coordinates of
// the tool tip; the tool axis is +Z throughout. Lengths are converted to millimetres (G20 programs
// are scaled by 25.4).

#include <array>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "cwe/geometry/aabb.hpp"
#include "cwe/toolpath/toolpath.hpp"

namespace cwe {

// The machine a program runs on, as far as the tip path depends on it (the job key "machine",
// docs/gcode.md "Coordinate systems"). Machine coordinates are those of the tool tip (no tool
// length offset), mm.
struct MachineDefinition {
  // Where the zeros of G54 … G59.3 are in machine coordinates: the work offsets (LinuxCNC's
  // #5221 …, its parameter file).
  std::array<Vec3, 9> work_offsets{};
  // The positions G28 and G30 go to (#5161 …, #5181 …).
  Vec3 g28 = Vec3::Zero();
  Vec3 g30 = Vec3::Zero();
  // The tip's travel; a move beyond it is an error. None: not checked.
  std::optional<Aabb> travel;
  // Where the machine changes tools (LinuxCNC's TOOL_CHANGE_POSITION). The reader does not use
  // it: a job's tool changes go there (docs/simulate.md, "Where the tool starts").
  std::optional<Vec3> tool_change;
  // Moves are reported in this work system's coordinates (1 = G54 … 9 = G59.3), the frame the
  // stock is given in.
  int frame = 1;
};

struct GcodeOptions {
  Vec3 initial_position = Vec3::Zero();  // where the tip is before the first move, mm
  ProgramUnits initial_units = ProgramUnits::kMillimetres;  // until G20/G21
  // Folders searched for <name>.ngc when the program calls a subroutine it does not define
  // (after the main program's own folder), as LinuxCNC's SUBROUTINE_PATH.
  std::vector<std::string> subroutine_path;
  // The diameter (mm) of tool number n > 0, for cutter radius compensation (G41/G42 take the
  // radius of tool D, or of the tool in the spindle); nullopt, or no function, when it is not
  // known: a program that compensates with that tool is then refused.
  std::function<std::optional<double>(int tool)> tool_diameter;
  // The machine (work offsets, G28/G30 positions, travel). None: every offset and stored position
  // is 0, so machine coordinates are the program's, with a warning at the first G53, G28 or G30.
  // `initial_position` is in the frame's coordinates either way.
  std::optional<MachineDefinition> machine;
  // Loop iterations and subroutine calls in a row without a move after which the program is
  // refused as never ending (LinuxCNC would run it forever); about 10 s at the default.
  long max_idle_iterations = 10'000'000;
  // Lines read, counting each pass through a loop, after which reading stops with an error;
  // 0: no limit. Bounds the work of a fuzzed input; a user's program has no such limit.
  std::size_t max_lines_read = 0;
};

// Folders from a ':'-separated list (LinuxCNC's SUBROUTINE_PATH form); empty entries are dropped.
std::vector<std::string> parse_search_path(std::string_view text);

// Parses program text; `source` names it in errors and in Toolpath::sources.
Toolpath read_gcode(std::string_view text, const std::string& source,
                    const GcodeOptions& options = {});

// Reads and parses a file (mapped, not copied: its pages leave memory as reading moves on).
Toolpath read_gcode_file(const std::string& path, const GcodeOptions& options = {});

// The same, handing each move to `sink` as soon as it is final instead of keeping it: the
// returned Toolpath has no moves (its sources, tool changes, warnings and units are filled), and
// memory stays bounded whatever the program's length. `sources` are the files read so far
// (Move::source indexes them). Errors are thrown at the end, as above, after the moves before
// them were handed on: a caller that must not act on a program in error reads it twice.
using MoveSink = std::function<void(const Move& move, const std::vector<std::string>& sources)>;
Toolpath read_gcode(std::string_view text, const std::string& source, const GcodeOptions& options,
                    const MoveSink& sink);
Toolpath read_gcode_file(const std::string& path, const GcodeOptions& options,
                         const MoveSink& sink);

}  // namespace cwe

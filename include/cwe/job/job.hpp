#pragma once
// A job: the stock, the programs with their tools, the resolution and the force model's settings,
// as the command line and JSON job files give them (docs/simulate.md); and the job made ready to
// run — programs read and cut into one operation per tool, cutters chosen, CL sampling set, force
// models built — with every input checked before the long part starts.

#include <cstddef>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "cwe/job/force_settings.hpp"
#include "cwe/job/machine.hpp"
#include "cwe/job/tool_table.hpp"
#include "cwe/process/force_model.hpp"
#include "cwe/simulation/simulation.hpp"
#include "cwe/toolpath/cl_sampling.hpp"
#include "cwe/toolpath/toolpath_reader.hpp"

namespace cwe {

// How far above the stock's top a tool starts, and goes up to at a tool change, by default, mm.
inline constexpr double kStartClearance = 5.0;

// One toolpath with its tool (empty: the job's tool, else the program's own).
struct Operation {
  std::string tool;
  std::string path;
  // Where `tool` was written: its first character in a job file, else the option.
  SourceLocation tool_at{"--tool"};
};

// A job as given. Empty strings and absent numbers mean "not given" (the defaults in the
// comments); every number given is checked by prepare_job, located where it was given.
struct Job {
  std::string stock;  // box:xmin,ymin,zmin,xmax,ymax,zmax, an STL or a STEP file
  std::string tool;   // for operations without their own
  std::string path;   // one program; else `operations`
  std::vector<Operation> operations;
  // Tool table (docs/simulate.md, tool_table.hpp): a file, or the table itself.
  std::string tools;
  std::optional<ToolTable> tool_table;
  bool tool_for_all = false;  // one `tool` cuts every move of a program that changes tools
  std::string tool_units;     // "mm" or "in": a tool table's bare lengths (default: `units`)
  // Where a program's tool starts: "auto" (default: kStartClearance above the stock's top at the
  // program's first XY), "origin", or "x,y,z"; and where it changes tools: "auto" (default: up to
  // that height, then across to the new tool's first XY), "stay", or "x,y,z".
  std::string start;
  std::string tool_change;
  // Folders searched for a G-code subroutine file <name>.ngc that a program calls but does not
  // define, ':'-separated (LinuxCNC's SUBROUTINE_PATH); the program's own folder comes first.
  std::string subroutine_path;
  // The machine (work offsets, G28/G30 positions, travel; machine.hpp): a JSON file, or the
  // definition itself. None: G-code machine coordinates are the program's.
  std::string machine;
  std::optional<MachineDefinition> machine_definition;
  // "mm" (default) or "in": the unit of the lengths given without one (stock box, tool
  // specifications and tables, start and tool-change points).
  std::string units;
  // The in-process workpiece: "dexel" (default: tri-dexel rays) or "mesh" (a closed triangle
  // mesh cut by CGAL's booleans, the thesis's polyhedral method; docs/engagement.md).
  std::string workpiece;
  // Numbers: absent means the default in the comment.
  std::optional<double> resolution;  // ray spacing (dexel), engagement grid (both), mm; 0.1
  std::optional<double> facet;       // mesh: the faceted tool's edge at its largest radius, mm; 1
  std::optional<double> tolerance;   // mm; resolution / 10
  std::optional<int> threads;        // all cores
  std::optional<double> cl_step;     // mm; min(0.5, D/20)
  // Cutting forces (docs/forces.md): a coefficient JSON file or bundled material; empty: none
  // (unless the tool table gives coefficients).
  std::string forces;
  std::optional<double> spindle;     // rev/min overriding the program's S / SPINDL
  std::optional<double> feed;        // mm/min overriding the program's F / FEDRAT
  std::optional<int> flutes;         // the cutter's
  std::optional<double> helix;       // degrees; the cutter's
  std::optional<double> force_step;  // spindle angle step, degrees; 1°
  std::string runout;                // offset_mm[,angle_deg]; empty: none
  // The most memory the run may take (cwe/core/memory_limit.hpp: 16G, 4096M, 50%); empty: 80 %
  // of physical memory.
  std::string memory_limit;

  // Where the values a job file gave were written, by key ("resolution" → job.json:7:17). A
  // value not here was given by its command-line option (or by the library's caller).
  std::map<std::string, SourceLocation, std::less<>> given_at;
  // Where `key`'s value came from: its place in the job file, else its option ("--cl-step").
  SourceLocation origin(std::string_view key) const;
  // The same for a text value: in a job file, its first character (after the quote), so that a
  // column within the text adds to it.
  SourceLocation text_origin(std::string_view key) const;
  // An error in `key`'s value, at its origin; from a job file the message names the key.
  InputError error(std::string_view key, const std::string& message) const;
};

// The moves of an operation: a stretch of its program's moves, which is read again from its file
// each time they are needed (for_each_move: a program is never held whole, so memory does not
// grow with its length), with the rapids of the tool changes around it.
struct OperationMoves {
  std::size_t first = 0;  // the program's moves [first, first + count), in reading order
  std::size_t count = 0;
  std::optional<Vec3> first_start;  // the first of them starts here (after a tool change)
  std::vector<Move> lead_in;        // before them: to an arc's start after a tool change
  std::vector<Move> lead_out;       // after them: the old tool up and across to the tool change
  std::size_t size() const { return lead_in.size() + count + lead_out.size(); }
};

// An operation ready to run: its program read and checked, its cutter chosen, its force model
// (with forces). A program that changes tools becomes one operation per stretch of one tool.
struct PreparedOperation {
  std::string path;
  // The program's sources, tool definitions, tool changes and units, and its warnings (with its
  // first operation only); no moves: those are in `moves`.
  Toolpath toolpath;
  ToolpathFormat format = ToolpathFormat::kGcode;
  OperationMoves moves;
  Cutter cutter;
  SamplingOptions sampling;
  std::size_t cl_points = 0;
  std::optional<ForceModel> forces;
  int tool = 0;  // the tool number whose moves these are (0: the program loads no tool)
  std::size_t operation = 0;            // the job's operation (program) this comes from, from 0
  GcodeOptions gcode;                   // what the program was read with (G-code), to read it again
  std::size_t program_moves = 0;        // the moves of the whole program, to check a reading again
  bool moves_from_other_files = false;  // some of `moves` come from a subroutine file
};

// A cutter narrower than this many ray spacings gets a warning (prepare_job).
inline constexpr double kFewestRaysAcross = 4.0;

// The in-process workpiece's representation (Job::workpiece).
enum class WorkpieceKind { kDexel, kMesh, kBrep };

struct PreparedJob {
  StockSpec stock;  // an STL stock read
  WorkpieceKind workpiece = WorkpieceKind::kDexel;
  double facet = 1.0;  // mm, the mesh workpiece's facet size
  // What the job's settings make doubtful (a cutter too small for the resolution), in the
  // summary and the terminal report.
  std::vector<Diagnostic> warnings;
  SimulationOptions simulation;
  int threads = 1;
  std::vector<PreparedOperation> operations;
  std::size_t cl_count = 0;  // CL samples of all operations
  std::optional<ForceSettings> forces;
};

// Checks the job and prepares it, counting its CL samples. `job` is completed on the way:
// `operations` from `path` and `tool`, the tool table read, `tool_units` defaulted, a bare box in
// inches marked so. Throws InputError naming the option, file and line of the first problem.
PreparedJob prepare_job(Job& job);

// What for_each_move calls: `begin` and `end` around each operation's moves (by index into
// PreparedJob::operations), `move` with each move and the files its `source` indexes.
struct OperationVisitor {
  std::function<void(std::size_t)> begin;
  MoveSink move;
  std::function<void(std::size_t)> end;
};

// The moves of every operation of `job`, in order: each program read again, once for all of its
// operations. Throws InputError when a program reads differently than when the job was prepared
// (it was changed meanwhile).
void for_each_move(const PreparedJob& job, const OperationVisitor& visitor);
// How many moves the job's operations have (with their tool changes' rapids).
std::size_t move_count(const PreparedJob& job);

// The cutting coefficient sets of the job's operations, each named once in order of use: their
// names, or (sources) where their numbers come from. Empty without forces.
std::string coefficient_names(const PreparedJob& job, bool sources = false);

// InputError at the origin of `key` (units, tool_units, report_units) unless `units` is empty,
// "mm" or "in".
void check_units(const Job& job, std::string_view key, const std::string& units);
// mm per length unit: 25.4 for "in", else 1.
double unit_length(const std::string& units);

// Throws InputError "no <what>: give <option> or put it in a job file" when value is empty.
void require(const std::string& value, const char* what, const char* option);

}  // namespace cwe

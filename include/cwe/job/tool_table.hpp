#pragma once
// Tool tables: which cutter cuts the moves of each tool number a program loads (G-code T… M6,
// CLDATA LOADTL/). The cwe table is JSON, a file given with --tools or the job key "tools":
//
//   {"tools": {"1": "flat:10,30", "2": {"spec": "ball:6,25", "flutes": 2, "helix": 30,
//                                        "forces": "ti6al4v-carbide"},
//              "3": "tools/bull.json"}}
//
// (the outer {"tools": …}, which may carry a "comment", may be left out in a file). A value is a
// tool specification (or a JSON tool file, relative to the table's folder), or an object with
// "spec" and optional "flutes" and "helix" (degrees) that override the specification's, and
// "forces": the tool's cutting coefficients (a bundled material or a coefficient file, as --forces
// takes), which replace the job's for that tool's moves.

#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <string>

#include <nlohmann/json_fwd.hpp>

#include "cwe/core/error.hpp"
#include "cwe/process/cutting_coefficients.hpp"
#include "cwe/tool/cutter.hpp"

namespace cwe {

struct ToolEntry {
  std::string spec;  // a tool specification or a JSON tool file (absolute or as written)
  std::string json;  // else the text of a JSON tool file (a profile, for FreeCAD's cones)
  std::optional<int> flutes;
  std::optional<double> helix_deg;
  std::optional<CuttingCoefficients> coefficients;  // the tool's own ("forces")
  double unit = 1.0;     // mm per length of `spec` written without a unit
  SourceLocation where;  // the entry, for errors
  // Non-empty: why cwe cannot cut with this entry (a FreeCAD probe or slitting saw in a library);
  // an error only for a program that loads it.
  std::string refused;
};

struct ToolTable {
  std::string source;  // where the table came from
  std::map<int, ToolEntry> tools;
};

// A table from its JSON value (an object of entries, or {"tools": {…}}); relative tool files are
// taken from `folder`. Throws InputError naming `source` and the entry.
// `unit`: mm per length written without a unit in the specifications (25.4: inches).
ToolTable tool_table_from_json(const nlohmann::json& value, const std::string& source,
                               const std::filesystem::path& folder, double unit = 1.0);
// A table read from a file: a FreeCAD tool library (.fctl, its .fctb bits mapped to cwe's
// cutters: endmill → flat, ballend → ball, bullnose/torus → bull, drill → chamfer at its tip
// angle, chamfer and v-bit → a cone from the tip diameter; other shapes are errors), a LinuxCNC
// tool table (.tbl: flat end mills of diameter D, or the cutter a "cwe:spec" comment names; D in
// inches when `inches`), else a cwe JSON table (its bare lengths in inches when `inches`).
ToolTable read_tool_table(const std::string& path, bool inches = false);

// The cutter of one entry (the specification with the entry's flutes and helix). Throws
// InputError for a refused entry.
Cutter cutter_of(const ToolEntry& entry);

// The diameter G-code cutter radius compensation (G41/G42) offsets by, mm: the APT D of an APT
// cutter (its nominal diameter, a tool table's D), else the largest diameter of its profile.
double compensation_diameter(const Cutter& cutter);

// Tool diameters for G-code cutter radius compensation (GcodeOptions::tool_diameter): with
// `tool_spec` (--tool), that one cutter's for every tool number, as it cuts every move; else the
// cutter of the tool's entry in `table`; else unknown. `unit`: mm per bare length of `tool_spec`,
// written at `tool_at`.
std::function<std::optional<double>(int tool)> compensation_diameters(
    const std::optional<ToolTable>& table, const std::string& tool_spec, double unit = 1.0,
    const SourceLocation& tool_at = SourceLocation{"--tool"});

}  // namespace cwe

#pragma once
// Tool specifications, the one way every command names a cutter.
//
//   flat:D[,h]             flat end mill of diameter D
//   ball:D[,h]             ball end mill of diameter D
//   bull:D,r[,h]           bull nose (fillet) end mill, corner radius r
//   taper-flat:D,beta[,h]  tapered flat end mill, tip diameter D, side taper beta degrees
//   taper-ball:D,beta[,h]  tapered ball end mill, ball diameter D, taper beta degrees
//   chamfer:D,tip[,h]      chamfer mill or drill point, diameter D, included tip angle degrees
//   apt:d,r,e,f,alpha,beta,h   the APT 7-parameter form (1 to 7 values, see apt.hpp)
//   <file>.json            a tool file (below)
//
// Lengths in millimetres, or in inches when written so (flat:0.375in,1.5in; 9.525mm is allowed
// too), angles in degrees, h the cutting length (default 3 D). A tool file is a
// JSON object with exactly one of "spec" (a string as above), "apt" (array of 1 to 7 numbers) or
// "profile" (array of pieces, see below), and optionally "name", "flutes", "helix_deg" and
// "shank": {"diameter": mm, "length": mm}. A profile starts at the tip [0, 0]; each piece is
// {"line": [ρ, z]} (a line to that point) or {"arc": [ρ, z], "center": [ρ, z], "ccw": bool}.
// Unknown keys are errors (they are usually typos).

#include <string>
#include <string_view>

#include "cwe/tool/cutter.hpp"

namespace cwe {

// Parses a specification string; a string ending in ".json" is read as a tool file. Lengths
// written without a unit are in `unit` mm (25.4: inches; a tool file keeps its own). Errors are
// InputErrors at `where` (column of the offending value within the string), or in the file.
Cutter cutter_from_spec(std::string_view spec, const SourceLocation& where = {"tool spec"},
                        double unit = 1.0);

// Reads a JSON tool file.
Cutter cutter_from_file(const std::string& path);

// Parses the text of a JSON tool file; `source` names it in errors.
Cutter cutter_from_json(std::string_view text, const std::string& source);

}  // namespace cwe

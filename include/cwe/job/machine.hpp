#pragma once
// The machine a job's programs run on (GcodeOptions::machine): a JSON file (--machine) or, in a
// job, the object itself (key "machine"):
//
//   {"units": "mm",
//    "work_offsets": {"G54": [-400, -200, -300], "G55": [-100, -200, -300]},
//    "g28": [0, 0, 0], "g30": [-500, 0, 0],
//    "travel": {"min": [-800, -500, -400], "max": [0, 0, 0]},
//    "tool_change": [-50, 0, 0],
//    "frame": "G54"}
//
// Every key is optional: "work_offsets" are the machine coordinates of the zeros of G54 … G59.3
// (unlisted ones 0), "g28" and "g30" the positions G28 and G30 go to, "travel" the tip's travel
// (a move beyond it is an error), "tool_change" where the machine changes tools (a job's tool
// changes go up to its height, then across to it, unless --tool-change says otherwise), "frame" the work system the moves — and the stock — are given
// in (default G54); lengths in "units" (mm or in, default mm). Machine coordinates are those of
// the tool tip: no tool length offset is applied.

#include <string>

#include <nlohmann/json_fwd.hpp>

#include "cwe/toolpath/gcode_reader.hpp"

namespace cwe {

// Throws InputError naming `source` and the key for anything but the form above.
MachineDefinition machine_from_json(const nlohmann::json& value, const std::string& source);
MachineDefinition read_machine_file(const std::string& path);

}  // namespace cwe

#pragma once
// Reads a toolpath file of either format.
//
// The format follows the extension: .ngc .nc .tap .gcode .cnc .g → G-code; .cl .cls .cldata
// .apt .aps → APT CLDATA. Any other extension: the text is CLDATA if a record of the form
// WORD/… (GOTO/, FROM/, CUTTER/, …) starts one of its first non-comment lines, G-code otherwise.

#include <string>

#include "cwe/toolpath/gcode_reader.hpp"
#include "cwe/toolpath/toolpath.hpp"

namespace cwe {

enum class ToolpathFormat { kGcode, kCldata };

const char* to_string(ToolpathFormat format);

// The format of a file from its name and, when the name does not tell, its text.
ToolpathFormat detect_toolpath_format(const std::string& path, std::string_view text);

struct ReadToolpath {
  Toolpath toolpath;
  ToolpathFormat format = ToolpathFormat::kGcode;
};

// Reads a G-code or CLDATA file; `gcode.initial_position` is where the tool tip is before the
// first move (of a CLDATA program, unless it has a FROM).
ReadToolpath read_toolpath_file(const std::string& path, const GcodeOptions& gcode = {});

// The same, handing each move to `sink` instead of keeping it (read_gcode_file with a sink: a
// G-code program in bounded memory; a CLDATA program is read whole first). The result has no
// moves.
ReadToolpath read_toolpath_file(const std::string& path, const GcodeOptions& gcode,
                                const MoveSink& sink);

}  // namespace cwe

#pragma once
// Which cutter a command uses for a toolpath: the --tool specification when given, else the one
// cutter the program defines (CLDATA CUTTER/), else an error that says what to do.

#include <string>

#include "cwe/tool/cutter.hpp"
#include "cwe/toolpath/toolpath.hpp"

namespace cwe {

// `unit`: mm per length of the specification written without a unit (25.4 for --units in).
// `tool_at`: where the specification was written (the option, or its place in a job file).
Cutter choose_cutter(const std::string& tool_spec, const SourceLocation& tool_at,
                     const Toolpath& path, const std::string& path_name, double unit = 1.0);

}  // namespace cwe

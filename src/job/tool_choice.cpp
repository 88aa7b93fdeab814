#include "cwe/job/tool_choice.hpp"

#include "cwe/core/error.hpp"
#include "cwe/tool/tool_spec.hpp"

namespace cwe {

Cutter choose_cutter(const std::string& tool_spec, const SourceLocation& tool_at,
                     const Toolpath& path, const std::string& path_name, double unit) {
  if (!tool_spec.empty()) return cutter_from_spec(tool_spec, tool_at, unit);
  if (path.tool_definitions.size() == 1) {
    const AptCutter& apt = path.tool_definitions.begin()->second;
    CutterOptions named;
    named.name = path_name + " " + to_string(apt);
    named.apt = apt;
    return Cutter(apt_profile(apt, SourceLocation{path_name}), named);
  }
  throw InputError(SourceLocation{path_name},
                   path.tool_definitions.empty()
                       ? "the program defines no cutter: name one with --tool"
                       : "the program defines several cutters: name the one to use with --tool");
}

}  // namespace cwe

#include "cwe/toolpath/toolpath_reader.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <sstream>

#include "cwe/core/error.hpp"
#include "cwe/core/text_file.hpp"
#include "cwe/toolpath/cldata_reader.hpp"
#include "cwe/toolpath/gcode_reader.hpp"

namespace cwe {
namespace {

std::string lower(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return s;
}

// Does the line start with a CLDATA record "WORD/"?
bool is_cldata_record(std::string_view line) {
  std::size_t i = 0;
  while (i < line.size() && std::isspace(static_cast<unsigned char>(line[i]))) ++i;
  const std::size_t word = i;
  while (i < line.size() && std::isalpha(static_cast<unsigned char>(line[i]))) ++i;
  return i - word >= 2 && i < line.size() && line[i] == '/';
}

}  // namespace

const char* to_string(ToolpathFormat format) {
  return format == ToolpathFormat::kGcode ? "G-code" : "APT CLDATA";
}

ToolpathFormat detect_toolpath_format(const std::string& path, std::string_view text) {
  const std::string ext = lower(std::filesystem::path(path).extension().string());
  for (const char* g : {".ngc", ".nc", ".tap", ".gcode", ".cnc", ".g"}) {
    if (ext == g) return ToolpathFormat::kGcode;
  }
  for (const char* c : {".cl", ".cls", ".cldata", ".apt", ".aps"}) {
    if (ext == c) return ToolpathFormat::kCldata;
  }
  std::istringstream lines{std::string(text.substr(0, 1 << 16))};
  std::string line;
  for (int n = 0; n < 50 && std::getline(lines, line); ++n) {
    if (is_cldata_record(line)) return ToolpathFormat::kCldata;
  }
  return ToolpathFormat::kGcode;
}

ReadToolpath read_toolpath_file(const std::string& path, const GcodeOptions& gcode) {
  const MappedText file(path, "toolpath file");
  ReadToolpath result;
  result.format = detect_toolpath_format(path, file.text());
  result.toolpath = result.format == ToolpathFormat::kGcode
                        ? read_gcode_file(path, gcode)
                        : read_cldata(file.text(), path, gcode.initial_position);
  return result;
}

ReadToolpath read_toolpath_file(const std::string& path, const GcodeOptions& gcode,
                                const MoveSink& sink) {
  ReadToolpath result;
  {
    const MappedText file(path, "toolpath file");
    result.format = detect_toolpath_format(path, file.text());
    if (result.format == ToolpathFormat::kCldata) {
      result.toolpath = read_cldata(file.text(), path, gcode.initial_position);
    }
  }
  if (result.format == ToolpathFormat::kGcode) {
    result.toolpath = read_gcode_file(path, gcode, sink);
    return result;
  }
  for (const Move& m : result.toolpath.moves) sink(m, result.toolpath.sources);
  result.toolpath.moves.clear();
  result.toolpath.moves.shrink_to_fit();
  return result;
}

}  // namespace cwe

#pragma once
// `cwe tool`: describe cutters and draw their profiles.

#include <CLI/CLI.hpp>

#include <ostream>
#include <string>
#include <vector>

namespace cwe::app {

struct ToolCommandOptions {
  std::vector<std::string> specs;
  std::string svg_file;  // one spec: its drawing
  std::string svg_dir;   // any number of specs: <dir>/<n>-<type>.svg
  bool json = false;
};

void add_tool_command(CLI::App& app, ToolCommandOptions& options);
int run_tool_command(const ToolCommandOptions& options, std::ostream& out);

}  // namespace cwe::app

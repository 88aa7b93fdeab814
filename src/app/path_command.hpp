#pragma once
// `cwe path`: read a toolpath (G-code or CLDATA), summarise it, or dump its moves as JSON lines.

#include <CLI/CLI.hpp>

#include <ostream>
#include <string>

namespace cwe::app {

struct PathCommandOptions {
  std::string file;
  bool dump = false;
  bool cl_dump = false;
  double cl_step = 0.5;       // mm
  double cl_angle_deg = 1.0;  // degrees of tool-axis turn
  std::string subroutine_path;  // ':'-separated folders for G-code subroutine files
  // The cutters whose diameters G41/G42 (cutter radius compensation) offset by.
  std::string tool;
  std::string tools;
  std::string tool_units = "mm";
  std::string machine;  // a machine definition file (work offsets, G28/G30, travel)
};

void add_path_command(CLI::App& app, PathCommandOptions& options);
int run_path_command(const PathCommandOptions& options, std::ostream& out);

}  // namespace cwe::app

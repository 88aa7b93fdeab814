#pragma once
// `cwe envelope`: swept volumes, grazing curves and feasible-contact pictures for the moves of a
// toolpath.

#include <CLI/CLI.hpp>

#include <ostream>
#include <string>
#include <vector>

namespace cwe::app {

struct EnvelopeCommandOptions {
  std::string tool;
  std::string path;
  std::string moves;  // "a-b" or "a", 1-based move numbers; empty: every feed move
  std::string out;
  double tolerance = 0.01;
  std::vector<double> fcs_at{0.5};  // move fractions u at which the FCS is drawn
  std::string subroutine_path;       // ':'-separated folders for G-code subroutine files
  std::string machine;               // a machine definition file (work offsets, G28/G30, travel)
};

void add_envelope_command(CLI::App& app, EnvelopeCommandOptions& options);
int run_envelope_command(const EnvelopeCommandOptions& options, std::ostream& out);

}  // namespace cwe::app

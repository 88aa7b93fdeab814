#pragma once
// `cwe schedule`: feed-rate scheduling. Runs the job of `cwe simulate` (same stock, tools,
// programs and force options) and, at every cutter location, finds the largest feed that keeps
// the chosen limit (peak force, peak torque, mean power or thickest chip); each feed move then
// gets the smallest of its locations' feeds, within the feed bounds and with a bounded change
// from move to move, and the program is written again in its own format with only its feeds
// changed (G-code F words, CLDATA FEDRAT records). See docs/forces.md.

#include <CLI/CLI.hpp>

#include <ostream>
#include <string>

#include "simulate_command.hpp"

namespace cwe::app {

struct ScheduleCommandOptions {
  SimulateCommandOptions job;  // the simulation: stock, tools, programs, forces
  std::string limit;           // force=800N, torque=…, power=…, chip=…
  std::string out;             // the scheduled program (a folder when the job has several)
  double min_feed = 0.0;       // mm/min; 0: not set
  double max_feed = 0.0;       // mm/min; 0: not set
  double min_scale = 0.1;      // of each move's programmed feed
  double max_scale = 2.0;
  double max_change = 1.5;  // largest ratio between consecutive feed moves
};

void add_schedule_command(CLI::App& app, ScheduleCommandOptions& options);
int run_schedule_command(ScheduleCommandOptions options, std::ostream& out, std::ostream* progress);

}  // namespace cwe::app

#pragma once
// What `cwe simulate` and `cwe schedule` share: the job's options (command line and JSON job
// file) and the job made ready to run — programs read, cutters chosen, CL sampling set, force
// models built — with every input checked before the long part starts.

#include <CLI/CLI.hpp>

#include <fmt/ostream.h>
#include <cstddef>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "cwe/process/force_model.hpp"
#include "cwe/simulation/simulation.hpp"
#include "cwe/toolpath/toolpath_reader.hpp"
#include "force_outputs.hpp"
#include "simulate_command.hpp"

namespace cwe::app {

// An operation ready to run: its program read, its cutter chosen, its force model (with
// --forces). A program that changes tools becomes one operation per stretch of one tool.
struct PreparedOperation {
  std::string path;
  ReadToolpath read;
  Cutter cutter;
  SamplingOptions sampling;
  std::size_t cl_points = 0;
  std::optional<ForceModel> forces;
  int tool = 0;  // the tool number whose moves these are (0: the program loads no tool)
  std::size_t operation = 0;  // the job's operation (program) this comes from, from 0
};

struct PreparedJob {
  SimulationOptions simulation;
  int threads = 1;
  std::vector<PreparedOperation> operations;
  std::size_t cl_count = 0;  // CL samples of all operations (0 unless sampled)
  std::optional<ForceSettings> forces;
};

// The cutting coefficient sets of the job's operations, each named once in order of use: their
// names, or (sources) where their numbers come from. Empty without forces.
std::string coefficient_names(const PreparedJob& job, bool sources = false);

// Checks the options (after read_job) and prepares the job; `sample` counts the CL samples.
// Throws InputError naming the option, file and line of the first problem.
PreparedJob prepare_job(SimulateCommandOptions& options, bool sample);

// A one-line progress bar, redrawn when the shown percentage changes.
class ProgressBar {
 public:
  explicit ProgressBar(std::ostream* stream) : stream_(stream) {}
  void operator()(std::size_t done, std::size_t total) {
    if (stream_ == nullptr || total == 0) return;
    const int percent = static_cast<int>(100 * done / total);
    if (percent == shown_) return;
    shown_ = percent;
    constexpr int kWidth = 40;
    const int filled = percent * kWidth / 100;
    fmt::print(*stream_, "\rremoving material [{}{}] {:3d}%  move {}/{}", std::string(filled, '#'),
               std::string(kWidth - filled, ' '), percent, done, total);
    if (done == total) fmt::print(*stream_, "\n");
    stream_->flush();
  }

 private:
  std::ostream* stream_;
  int shown_ = -1;
};

// InputError unless `units` is empty, "mm" or "in"; `option` names it.
void check_units(const std::string& units, const char* option);
// mm per length unit: 25.4 for "in", else 1.
double unit_length(const std::string& units);

// Throws InputError "no <what>: give <option> or put it in a job file" when value is empty.
void require(const std::string& value, const char* what, const char* option);

}  // namespace cwe::app

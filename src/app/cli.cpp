#include "cwe/app/cli.hpp"

#include <CLI/CLI.hpp>

#include <unistd.h>

#include <algorithm>
#include <exception>
#include <iostream>

#include "cli_checks.hpp"
#include "compare_command.hpp"
#include "cwe/core/assert.hpp"
#include "cwe/core/computation_error.hpp"
#include "cwe/core/error.hpp"
#include "cwe/process/cutting_coefficients.hpp"
#include "envelope_command.hpp"
#include "path_command.hpp"
#include "schedule_command.hpp"
#include "simulate_command.hpp"
#include "tool_command.hpp"

namespace cwe::app {

int run(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
  CLI::App app{"cwe: cutter-workpiece engagement for 3-, 3+2- and 5-axis milling", "cwe"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "cwe 0.1.0");
  ToolCommandOptions tool_options;
  add_tool_command(app, tool_options);
  PathCommandOptions path_options;
  add_path_command(app, path_options);
  EnvelopeCommandOptions envelope_options;
  add_envelope_command(app, envelope_options);
  SimulateCommandOptions simulate_options;
  add_simulate_command(app, simulate_options);
  ScheduleCommandOptions schedule_options;
  add_schedule_command(app, schedule_options);
  CompareCommandOptions compare_options;
  add_compare_command(app, compare_options);
  app.add_subcommand("materials",
                     "List the bundled cutting-coefficient sets (for --forces) with their "
                     "sources");

  // A first word that is no command is named (CLI11 would only say that one is required).
  if (args.size() > 1 && !args[1].empty() && args[1][0] != '-') {
    const auto commands = app.get_subcommands([](const CLI::App*) { return true; });
    const bool known = std::any_of(commands.begin(), commands.end(),
                                   [&](const CLI::App* c) { return c->get_name() == args[1]; });
    if (!known) {
      err << "cwe: error: '" << args[1]
          << "' is not a command; expected tool, path, envelope, simulate, schedule, compare or "
             "materials "
             "(cwe --help)\n";
      return 2;
    }
  }
  std::vector<std::string> reversed(args.rbegin(), args.rend());
  if (!reversed.empty()) reversed.pop_back();  // the program name
  try {
    app.parse(reversed);
  } catch (const CLI::ParseError& e) {
    // Help and version requests are "errors" to CLI11 with exit code 0.
    if (e.get_exit_code() == 0) return app.exit(e, out, err);
    err << cli_error_message(e) << '\n';
    return 2;
  }
  try {
    if (app.got_subcommand("tool")) return run_tool_command(tool_options, out);
    if (app.got_subcommand("path")) return run_path_command(path_options, out);
    if (app.got_subcommand("envelope")) return run_envelope_command(envelope_options, out);
    // The progress bar goes to the error stream only when that is a terminal.
    const bool terminal = &err == &std::cerr && isatty(STDERR_FILENO) == 1;
    if (app.got_subcommand("simulate")) {
      return run_simulate_command(simulate_options, out, terminal ? &err : nullptr);
    }
    if (app.got_subcommand("schedule")) {
      return run_schedule_command(schedule_options, out, terminal ? &err : nullptr);
    }
    if (app.got_subcommand("compare")) {
      return run_compare_command(compare_options, out, terminal ? &err : nullptr);
    }
    if (app.got_subcommand("materials")) {
      for (const std::string& name : bundled_materials()) {
        const CuttingCoefficients k = bundled_coefficients(name);
        out << name << ": Ktc " << k.ktc << ", Krc " << k.krc << ", Kac " << k.kac << " N/mm²; Kte "
            << k.kte << ", Kre " << k.kre << ", Kae " << k.kae << " N/mm\n  " << k.source << '\n';
      }
      return 0;
    }
  } catch (const InputError& e) {
    err << e.what() << '\n';
    return 2;
  } catch (const ComputationError& e) {
    err << "cwe: error: " << e.what() << '\n';
    return 3;
  } catch (const InternalError& e) {
    err << e.what() << "\n(this is a bug in cwe)\n";
    return 1;
  } catch (const std::exception& e) {
    err << "cwe: internal error: " << e.what() << "\n(this is a bug in cwe)\n";
    return 1;
  }
  return 0;
}

}  // namespace cwe::app

#pragma once
// The `cwe` command line: subcommands, option parsing and the exit-code contract.
//
// Exit status: 0 success; 1 an internal error (a bug: please report it); 2 bad input (the message
// on stderr names file, line and column where there is one, as "file:line:col: error: …").

#include <ostream>
#include <string>
#include <vector>

namespace cwe::app {

// Runs the program with `args` (args[0] is the program name), writing normal output to `out`
// and diagnostics to `err`. Returns the exit status.
int run(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);

}  // namespace cwe::app

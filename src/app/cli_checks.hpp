#pragma once
// Command-line values checked as cwe checks every value the user gives, and CLI11's own errors
// said in cwe's form ("--resolution: error: '0': expected a positive length"), so that every
// bad input reads alike whether it came from the command line, a job file or a program.

#include <CLI/CLI.hpp>

#include <string>

namespace cwe::app {

// A number > 0 (finite); `what` says what it is ("a positive length in mm").
CLI::Validator positive(const std::string& what);
// A whole number ≥ 1 (a count: threads, flutes).
CLI::Validator count(const std::string& what);
// A number ≥ 0 (finite).
CLI::Validator non_negative(const std::string& what);

// CLI11's message for a parse error, in cwe's form "OPTION: error: …" (or "cwe: error: …").
std::string cli_error_message(const CLI::ParseError& e);

}  // namespace cwe::app

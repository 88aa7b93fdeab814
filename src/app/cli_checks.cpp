#include "cli_checks.hpp"

#include <charconv>
#include <cmath>
#include <system_error>

#include <fmt/format.h>

namespace cwe::app {
namespace {

// The number `text` holds, whole; NaN when it holds something else.
double number_of(const std::string& text) {
  double value = 0.0;
  const char* end = text.data() + text.size();
  const auto [ptr, ec] = std::from_chars(text.data(), end, value);
  if (ec != std::errc() || ptr != end || !std::isfinite(value)) return std::nan("");
  return value;
}

CLI::Validator bounded(const std::string& what, bool zero_allowed, bool whole = false) {
  return CLI::Validator(
      [what, zero_allowed, whole](const std::string& text) -> std::string {
        const double value = number_of(text);
        const bool in_range = value > 0.0 || (zero_allowed && value == 0.0);
        if (in_range && (!whole || (value == std::floor(value) && value <= 2147483647.0))) {
          return {};
        }
        return fmt::format("'{}': expected {}", text, what);
      },
      whole ? "INTEGER >= 1" : (zero_allowed ? "NUMBER >= 0" : "NUMBER > 0"));
}

}  // namespace

CLI::Validator positive(const std::string& what) { return bounded(what, false); }
CLI::Validator non_negative(const std::string& what) { return bounded(what, true); }
CLI::Validator count(const std::string& what) { return bounded(what, false, true); }

std::string cli_error_message(const CLI::ParseError& e) {
  const std::string message = e.what();
  // "--threads: '0': expected …" (our validators), "Could not convert: --x = abc",
  // "The following argument was not expected: foo", "--out is required".
  if (dynamic_cast<const CLI::ValidationError*>(&e) != nullptr) {
    if (const std::size_t colon = message.find(": "); colon != std::string::npos) {
      return message.substr(0, colon) + ": error: " + message.substr(colon + 2);
    }
  }
  if (dynamic_cast<const CLI::ConversionError*>(&e) != nullptr) {
    const std::string prefix = "Could not convert: ";
    if (message.starts_with(prefix)) {
      const std::string rest = message.substr(prefix.size());
      if (const std::size_t eq = rest.find(" = "); eq != std::string::npos) {
        return fmt::format("{}: error: '{}': expected a number", rest.substr(0, eq),
                           rest.substr(eq + 3));
      }
    }
  }
  if (dynamic_cast<const CLI::ExtrasError*>(&e) != nullptr) {
    const std::size_t colon = message.find(": ");
    return fmt::format(
        "cwe: error: unexpected argument{} (cwe --help lists the commands, cwe "
        "COMMAND --help their options)",
        colon == std::string::npos ? "" : " " + message.substr(colon + 2));
  }
  if (dynamic_cast<const CLI::ArgumentMismatch*>(&e) != nullptr) {
    // "--cl-step: 1 required FLOAT:NUMBER > 0 missing": the option was given without its value.
    if (const std::size_t colon = message.find(": ");
        colon != std::string::npos && message.ends_with(" missing")) {
      return message.substr(0, colon) + ": error: expected a value after it";
    }
  }
  if (dynamic_cast<const CLI::RequiredError*>(&e) != nullptr) {
    if (message.starts_with("A subcommand")) {
      return "cwe: error: expected a command: tool, path, envelope, simulate, schedule, "
             "compare or materials (cwe --help)";
    }
    if (const std::size_t is = message.find(" is required"); is != std::string::npos) {
      return message.substr(0, is) + ": error: required (see --help)";
    }
  }
  return "cwe: error: " + message;
}

}  // namespace cwe::app

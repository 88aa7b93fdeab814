#pragma once
// Errors the library reports to its users.
//
// The library never prints. A problem with the user's input (a tool specification, a file, a
// parameter) is a cwe::InputError whose message says where it is and what was expected; a broken
// internal invariant is a CWE_ASSERT failure (see assert.hpp). Numerical "no solution" is never
// an error: it is an empty interval or std::nullopt.

#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

namespace cwe {

// Where in the user's input a problem sits. `source` is a file name, or a label such as
// "tool spec" for a string given on the command line. `line` and `column` count from 1;
// 0 means "not applicable".
struct SourceLocation {
  std::string source;
  int line = 0;
  int column = 0;
};

// Thrown for input the library cannot accept. what() is "source:line:col: error: message"
// (line and column omitted when 0), the form compilers use, so editors can jump to it.
class InputError : public std::runtime_error {
 public:
  InputError(SourceLocation location, const std::string& message);
  explicit InputError(const std::string& message) : InputError(SourceLocation{}, message) {}

  const SourceLocation& location() const { return location_; }
  // The message without the location prefix.
  const std::string& message() const { return message_; }

 private:
  SourceLocation location_;
  std::string message_;
};

// Several input errors found in one pass over an input (a G-code program read to its end). The
// first is this exception's own location and message; what() lists every error kept, a line
// each, then how many more there were.
class InputErrors : public InputError {
 public:
  InputErrors(std::vector<InputError> errors, std::size_t more);

  const std::vector<InputError>& errors() const { return errors_; }
  std::size_t more() const { return more_; }  // errors found beyond those kept
  const char* what() const noexcept override { return text_.c_str(); }

 private:
  std::vector<InputError> errors_;
  std::size_t more_ = 0;
  std::string text_;
};

}  // namespace cwe

#pragma once
// Errors the library reports to its users.
//
// The library never prints. A problem with the user's input (a tool specification, a file, a
// parameter) is a cwe::InputError whose message says where it is and what was expected; a broken
// internal invariant is a CWE_ASSERT failure (see assert.hpp). Numerical "no solution" is never
// an error: it is an empty interval or std::nullopt.

#include <stdexcept>
#include <string>

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

}  // namespace cwe

#pragma once
// JSON the user wrote (jobs, tool files and tables, machines, cutting coefficients), parsed with
// errors in the promised form: source:line:col for a syntax error, the place of a number beyond
// double range (1e400), and of a key written twice in one object (which JSON parsers otherwise
// resolve silently, the last one winning).

#include <map>
#include <string>
#include <string_view>
#include <utility>

#include <nlohmann/json_fwd.hpp>

#include "cwe/core/error.hpp"

namespace cwe {

// Throws InputError located in `text`, named `source`.
nlohmann::json parse_json_input(std::string_view text, const std::string& source);

// Where the values of a JSON text start, by JSON pointer ("/resolution", "/operations/0/path";
// values nested deeper than kDepth are not indexed), so that a value that parses but is not
// acceptable is reported at its line and column. The text must be valid JSON (parsed first).
class JsonPlaces {
 public:
  static constexpr int kDepth = 4;
  JsonPlaces() = default;
  JsonPlaces(std::string_view text, std::string source);

  // The value's place; the source alone when the pointer is not indexed.
  SourceLocation at(const std::string& pointer) const;
  const std::string& source() const { return source_; }

 private:
  std::string source_;
  std::map<std::string, std::pair<int, int>, std::less<>> places_;  // line, column
};

// A JSON pointer's token for an object key (RFC 6901: '~' as "~0", '/' as "~1").
std::string json_pointer_token(std::string_view key);

}  // namespace cwe

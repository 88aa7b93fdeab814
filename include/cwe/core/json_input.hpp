#pragma once
// JSON the user wrote (jobs, tool files and tables, machines, cutting coefficients), parsed with
// errors in the promised form: source:line:col for a syntax error, the place of a number beyond
// double range (1e400), and of a key written twice in one object (which JSON parsers otherwise
// resolve silently, the last one winning).

#include <string>
#include <string_view>

#include <nlohmann/json_fwd.hpp>

namespace cwe {

// Throws InputError located in `text`, named `source`.
nlohmann::json parse_json_input(std::string_view text, const std::string& source);

}  // namespace cwe

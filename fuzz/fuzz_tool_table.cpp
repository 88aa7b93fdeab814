// Tool tables: a cwe JSON table (cwe::tool_table_from_json on cwe::parse_json_input's value) when
// the input starts with '{' after blanks, else a LinuxCNC tool table (.tbl), read as
// cwe::read_tool_table reads a file: written to table.tbl in a scratch folder, in mm and in
// inches. Tool files a JSON table names are looked up in a folder that does not exist.

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "cwe/core/json_input.hpp"
#include "cwe/job/tool_table.hpp"
#include "fuzz_check.hpp"
#include "fuzz_scratch.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const cwe::fuzz::ScratchFile file("table.tbl");  // removed at exit
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const std::size_t first = text.find_first_not_of(" \t\r\n");
  if (first != std::string_view::npos && text[first] == '{') {
    static const std::string source = "input-tools.json";
    cwe::fuzz::expect_value_or_input_error(text, source, cwe::fuzz::Lines::kByLine, [&] {
      (void)cwe::tool_table_from_json(cwe::parse_json_input(text, source), source,
                                      "/nonexistent-cwe-fuzz");
    });
    return 0;
  }
  const std::string& path = file.write(text);
  for (const bool inches : {false, true}) {
    cwe::fuzz::expect_value_or_input_error(text, path, cwe::fuzz::Lines::kByLine,
                                           [&] { (void)cwe::read_tool_table(path, inches); });
  }
  return 0;
}

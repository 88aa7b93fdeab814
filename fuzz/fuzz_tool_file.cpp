// JSON tool files (cwe::cutter_from_json): a specification with flutes and helix, or a profile
// of lines and arcs.

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "cwe/tool/tool_spec.hpp"
#include "fuzz_check.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  static const std::string source = "input-tool.json";
  cwe::fuzz::expect_value_or_input_error(text, source, cwe::fuzz::Lines::kByLine,
                                         [&] { (void)cwe::cutter_from_json(text, source); });
  return 0;
}

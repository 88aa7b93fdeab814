// Tool specifications as given on the command line (cwe::cutter_from_spec): "flat:10,30",
// "ball:6", "apt:…", …, in mm and in inches. Columns run over the whole string. A specification
// ending in ".json" names a tool file: the fuzzer's working folder (scripts/fuzz.sh runs it in a
// scratch folder) has none.

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "cwe/tool/tool_spec.hpp"
#include "fuzz_check.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view spec(reinterpret_cast<const char*>(data), size);
  static const std::string source = "tool spec";
  for (const double unit : {1.0, 25.4}) {
    cwe::fuzz::expect_value_or_input_error(spec, source, cwe::fuzz::Lines::kOneLine, [&] {
      (void)cwe::cutter_from_spec(spec, cwe::SourceLocation{source}, unit);
    });
  }
  return 0;
}

// Machine definitions (cwe::machine_from_json on cwe::parse_json_input's value).

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "cwe/core/json_input.hpp"
#include "cwe/job/machine.hpp"
#include "fuzz_check.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  static const std::string source = "input-machine.json";
  cwe::fuzz::expect_value_or_input_error(text, source, cwe::fuzz::Lines::kByLine, [&] {
    (void)cwe::machine_from_json(cwe::parse_json_input(text, source), source);
  });
  return 0;
}

// Cutting-coefficient files (cwe::parse_cutting_coefficients).

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "cwe/process/cutting_coefficients.hpp"
#include "fuzz_check.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  static const std::string source = "input-coefficients.json";
  cwe::fuzz::expect_value_or_input_error(text, source, cwe::fuzz::Lines::kByLine, [&] {
    (void)cwe::parse_cutting_coefficients(text, source);
  });
  return 0;
}

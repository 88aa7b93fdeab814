// APT CLDATA programs (cwe::read_cldata). A line ends at '\n', "\r\n" or a lone '\r'.

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "cwe/toolpath/cldata_reader.hpp"
#include "fuzz_check.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  static const std::string source = "input.apt";
  cwe::fuzz::expect_value_or_input_error(text, source, cwe::fuzz::Lines::kByLineOrCr, [&] {
    (void)cwe::read_cldata(text, source, cwe::Vec3(0.0, 0.0, 50.0));
  });
  return 0;
}

// STL files, ASCII and binary (cwe::parse_stl).

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "cwe/io/mesh_io.hpp"
#include "fuzz_check.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  static const std::string source = "input.stl";
  cwe::fuzz::expect_value_or_input_error(bytes, source, cwe::fuzz::Lines::kByLine,
                                         [&] { (void)cwe::parse_stl(bytes, source); });
  return 0;
}

#pragma once
// Reading the user's input files whole, with errors that name the file.

#include <cstddef>
#include <string>
#include <string_view>

#include "cwe/core/error.hpp"

namespace cwe {

// Millimetres per inch, for programs and tools written in inches.
inline constexpr double kMillimetresPerInch = 25.4;

// Largest magnitude accepted for any number in an input file. No machining quantity comes near
// it (1e9 mm is 1000 km; feeds and spindle speeds are far smaller), and refusing larger ones keeps
// every sum, square and product a reader forms finite.
inline constexpr double kLargestInputValue = 1e9;

// The bytes of the file at `path`. Throws InputError naming the path and `what` ("G-code file",
// "tool file", …) when it cannot be opened or read.
std::string read_text_file(const std::string& path, const std::string& what);

// Line and column (from 1) of a byte offset in `text`, for errors in `source`.
SourceLocation location_of(std::string_view text, std::size_t offset, const std::string& source);

}  // namespace cwe

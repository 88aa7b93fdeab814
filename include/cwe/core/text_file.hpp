#pragma once
// Reading the user's input files, with errors that name the file.

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

// A file read whole (not a regular file, which MappedText maps) may be this large.
inline constexpr std::size_t kLargestTextFile = std::size_t{1} << 30;

// The bytes of the file at `path`. Throws InputError naming the path and `what` ("G-code file",
// "tool file", …) when it cannot be opened or read, is a directory, holds a NUL byte (it is not
// text: /dev/zero, a binary file) or is over kLargestTextFile.
std::string read_text_file(const std::string& path, const std::string& what);
// The same for a file that may be binary (an STL): NUL bytes allowed.
std::string read_binary_file(const std::string& path, const std::string& what);

// The bytes of a file, in memory without a copy on the heap: a regular file is mapped (its pages
// come from the file as they are read and can be let go again), anything else (a pipe) is read
// whole. Throws InputError naming the path and `what` when it cannot be opened or read, or is a
// directory.
class MappedText {
 public:
  MappedText(const std::string& path, const std::string& what);
  ~MappedText();
  MappedText(const MappedText&) = delete;
  MappedText& operator=(const MappedText&) = delete;

  std::string_view text() const { return text_; }
  // The pages before `offset` may leave memory; reading them again brings them back from the
  // file (so views into the text stay valid). Keeps a long program's resident memory bounded.
  void release_before(std::size_t offset);

 private:
  void* map_ = nullptr;
  std::size_t size_ = 0;
  std::size_t released_ = 0;
  std::string owned_;
  std::string_view text_;
};

// Line and column (from 1) of a byte offset in `text`, for errors in `source`.
SourceLocation location_of(std::string_view text, std::size_t offset, const std::string& source);

}  // namespace cwe

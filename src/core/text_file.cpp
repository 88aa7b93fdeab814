#include "cwe/core/text_file.hpp"

#include <fstream>
#include <iterator>

#include "cwe/core/error.hpp"

namespace cwe {

std::string read_text_file(const std::string& path, const std::string& what) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(SourceLocation{path}, "cannot open the " + what);
  std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  if (in.bad()) throw InputError(SourceLocation{path}, "cannot read the " + what);
  return text;
}

SourceLocation location_of(std::string_view text, std::size_t offset, const std::string& source) {
  int line = 1, column = 1;
  for (std::size_t i = 0; i < offset && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      column = 1;
    } else {
      ++column;
    }
  }
  return {source, line, column};
}

}  // namespace cwe

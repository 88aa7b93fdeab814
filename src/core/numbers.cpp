#include "cwe/core/numbers.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <system_error>

namespace cwe {

NumberList parse_number_list(std::string_view text) {
  NumberList list;
  std::size_t start = 0;
  while (start <= text.size()) {
    const std::size_t comma = std::min(text.find(',', start), text.size());
    const std::string_view word = text.substr(start, comma - start);
    double v = 0.0;
    const auto [end, ec] = std::from_chars(word.data(), word.data() + word.size(), v);
    if (word.empty() || ec != std::errc() || end != word.data() + word.size() ||
        !std::isfinite(v)) {
      list.bad = std::string(word);
      return list;
    }
    list.values.push_back(v);
    start = comma + 1;
  }
  return list;
}

}  // namespace cwe

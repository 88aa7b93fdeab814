#pragma once
// Lists of numbers as options and specifications write them: "1,2.5,-3".

#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace cwe {

struct NumberList {
  std::vector<double> values;      // the numbers, up to the first word that is not one
  std::optional<std::string> bad;  // that word, if any
};

// The comma-separated numbers of `text`, each a whole word std::from_chars reads as a finite
// double (no blanks, no leading '+'). An empty text is one empty, bad word.
NumberList parse_number_list(std::string_view text);

}  // namespace cwe

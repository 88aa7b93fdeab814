#pragma once
// What every fuzz target asserts: a reader given any bytes returns a value or throws a
// cwe::InputError (or InputErrors) located inside the input. Anything else is a finding and ends
// the run through abort(), which libFuzzer reports as a crash and saves the input:
//   - an exception that is not an InputError (std::out_of_range, nlohmann::json's, bad_alloc,
//     cwe::InternalError from a failed CWE_ASSERT, …);
//   - an InputError naming the input's source at a line past its last line, or a column past
//     the end of its line (lines from 1, columns counted in bytes from 1; the end of a line, one
//     past its last byte, is a place too).
// AddressSanitizer and UndefinedBehaviorSanitizer (float-to-int overflow included) end the run
// by themselves.

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>
#include <string_view>
#include <typeinfo>

#include "cwe/core/error.hpp"

namespace cwe::fuzz {

[[noreturn]] inline void finding(const std::string& what) {
  std::fprintf(stderr, "\n==fuzz finding: %s\n", what.c_str());
  std::fflush(stderr);
  std::abort();
}

// How the reader counts places in the input: by lines ending at '\n' (a file), by lines ending
// at '\n', "\r\n" or a lone '\r' (CLDATA, which old CAM systems end with CR), or as one line
// whatever it holds (a specification string, whose columns run over the whole string).
enum class Lines { kByLine, kByLineOrCr, kOneLine };

inline void check_location(const SourceLocation& at, std::string_view text,
                           const std::string& source, Lines lines, const char* what) {
  if (at.source != source) return;  // another file, a key path, an option: not placed in text
  if (at.line < 0 || at.column < 0) finding(std::string("negative line or column: ") + what);
  if (at.line == 0) {
    if (at.column != 0) finding(std::string("a column without a line: ") + what);
    return;
  }
  std::string_view line_text = text;
  if (lines != Lines::kOneLine) {
    const char* const ends = lines == Lines::kByLine ? "\n" : "\r\n";
    std::size_t start = 0;
    for (int line = 1; line < at.line; ++line) {
      const std::size_t end = text.find_first_of(ends, start);
      if (end == std::string_view::npos) {
        finding(std::string("line past the end of the input: ") + what);
      }
      start = end + 1;
      if (text[end] == '\r' && start < text.size() && text[start] == '\n') ++start;
    }
    line_text = text.substr(start, text.find_first_of(ends, start) - start);
  } else if (at.line != 1) {
    finding(std::string("line other than 1 in a one-line input: ") + what);
  }
  if (static_cast<std::size_t>(at.column) > line_text.size() + 1) {
    finding(std::string("column past the end of its line: ") + what);
  }
}

// Runs `read`; returns normally for a value or an InputError located inside `text`.
template <typename Read>
void expect_value_or_input_error(std::string_view text, const std::string& source, Lines lines,
                                 Read&& read) {
  try {
    read();
  } catch (const InputErrors& errors) {
    for (const InputError& e : errors.errors()) {
      check_location(e.location(), text, source, lines, e.what());
    }
  } catch (const InputError& e) {
    check_location(e.location(), text, source, lines, e.what());
  } catch (const std::exception& e) {
    finding(std::string("not an InputError: ") + typeid(e).name() + ": " + e.what());
  } catch (...) {
    finding("an exception that is not a std::exception");
  }
}

}  // namespace cwe::fuzz

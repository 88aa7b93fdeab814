#pragma once
// Shared by the reader tests: robustness checks of a reader on arbitrary input.

#include <gtest/gtest.h>

#include <cmath>
#include <exception>
#include <string>
#include <string_view>

#include "cwe/core/error.hpp"
#include "cwe/toolpath/toolpath.hpp"

namespace cwe::test {

// Runs `read(text)` expecting an InputError or success, nothing else (no crash, no other
// exception); on success every move must be finite and well formed: unit axes and arc normals
// (normalised once: 1e-12 is ~5000 ulps), positive arc sweeps, a non-negative feed.
// Returns whether the text was read.
template <typename Reader>
bool read_or_input_error(const Reader& read, std::string_view text) {
  try {
    const Toolpath path = read(text);
    for (const Move& m : path.moves) {
      EXPECT_TRUE(m.start.allFinite() && m.end.allFinite() && m.center.allFinite());
      EXPECT_NEAR(m.start_axis.norm(), 1.0, 1e-12);
      EXPECT_NEAR(m.end_axis.norm(), 1.0, 1e-12);
      EXPECT_TRUE(std::isfinite(m.sweep) && std::isfinite(m.axial));
      if (m.is_arc()) {
        EXPECT_GT(m.sweep, 0.0);
        EXPECT_NEAR(m.normal.norm(), 1.0, 1e-12);
      }
      EXPECT_TRUE(std::isfinite(m.feed_rate) && m.feed_rate >= 0.0);
    }
    return true;
  } catch (const InputError&) {
    return false;
  } catch (const std::exception& e) {
    ADD_FAILURE() << "unexpected exception " << e.what() << " for input:\n" << text;
    return false;
  }
}

// Reading `text` with `read` throws an InputError from `source` at line:column (0: not named)
// whose message contains `fragment`, and what() starts with that location.
template <typename Reader>
void expect_input_error(const Reader& read, const std::string& source, std::string_view text,
                        int line, int column, const std::string& fragment) {
  SCOPED_TRACE(std::string(text));
  try {
    read(text);
    ADD_FAILURE() << "expected cwe::InputError containing: " << fragment;
  } catch (const InputError& e) {
    EXPECT_EQ(e.location().source, source);
    EXPECT_EQ(e.location().line, line) << e.what();
    EXPECT_EQ(e.location().column, column) << e.what();
    EXPECT_NE(e.message().find(fragment), std::string::npos)
        << "message: " << e.what() << "\nexpected to contain: " << fragment;
    std::string where = source;
    if (line > 0) where += ":" + std::to_string(line);
    if (line > 0 && column > 0) where += ":" + std::to_string(column);
    EXPECT_EQ(std::string(e.what()).rfind(where + ": error: ", 0), 0u) << e.what();
  }
}

}  // namespace cwe::test

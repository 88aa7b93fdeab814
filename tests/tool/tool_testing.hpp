#pragma once
// Helpers shared by the tool tests.

#include <gtest/gtest.h>

#include <string>

#include "cwe/core/error.hpp"
#include "cwe/tool/profile.hpp"
#include "input_error.hpp"

namespace cwe::test {

// Two profiles describe the same outline: same pieces, same kind, end points and centres within
// `tolerance` (mm).
inline void expect_same_profile(const Profile& a, const Profile& b, double tolerance) {
  ASSERT_EQ(a.segments().size(), b.segments().size());
  for (std::size_t i = 0; i < a.segments().size(); ++i) {
    const ProfileSegment& s = a.segments()[i];
    const ProfileSegment& t = b.segments()[i];
    SCOPED_TRACE("piece " + std::to_string(i + 1));
    EXPECT_EQ(s.kind, t.kind);
    EXPECT_NEAR((s.start - t.start).norm(), 0.0, tolerance);
    EXPECT_NEAR((s.end - t.end).norm(), 0.0, tolerance);
    if (s.kind == ProfileSegment::Kind::kArc && t.kind == ProfileSegment::Kind::kArc) {
      EXPECT_NEAR((s.center - t.center).norm(), 0.0, tolerance);
      EXPECT_EQ(s.counterclockwise, t.counterclockwise);
    }
  }
}

}  // namespace cwe::test

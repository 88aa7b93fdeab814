#pragma once
// EXPECT_INPUT_ERROR, shared by the test suites of every reader.

#include <gtest/gtest.h>

#include <string>

#include "cwe/core/error.hpp"

// Asserts that `statement` throws cwe::InputError whose what() contains `fragment`.
#define EXPECT_INPUT_ERROR(statement, fragment)                                  \
  do {                                                                           \
    try {                                                                        \
      statement;                                                                 \
      ADD_FAILURE() << "expected cwe::InputError containing: " << (fragment);    \
    } catch (const ::cwe::InputError& e) {                                       \
      EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos)         \
          << "message: " << e.what() << "\nexpected to contain: " << (fragment); \
    }                                                                            \
  } while (false)

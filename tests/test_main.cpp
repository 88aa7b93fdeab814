// Test entry point for every cwe test binary.
#include <cfenv>

#include <gtest/gtest.h>

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  // Library code must never compute NaN or divide by zero silently: trap both.
  feenableexcept(FE_INVALID | FE_DIVBYZERO);
  return RUN_ALL_TESTS();
}

#pragma once
// The source tree, for tests that read bundled files (examples/, tests/*/golden, tests/*/data).
// Compiled in by tests/CMakeLists.txt, so test binaries also work when run by hand.

#include <filesystem>

namespace cwe::test {

inline std::filesystem::path source_dir() { return CWE_TEST_SOURCE_DIR; }

}  // namespace cwe::test

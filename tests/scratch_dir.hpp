#pragma once
// A test's own folder in the system's temporary folder, emptied and made afresh.

#include <filesystem>
#include <string>

namespace cwe::test {

inline std::filesystem::path fresh_scratch_dir(const std::string& name) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("cwe-" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

}  // namespace cwe::test

#pragma once
// Running the command line in the tests' own process, and reading what it writes.

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cwe/app/cli.hpp"

namespace cwe::app {

struct Result {
  int status = 0;
  std::string out;
  std::string err;
};

// `cwe args…`, its exit status and what it printed.
inline Result run_cwe(std::vector<std::string> args) {
  args.insert(args.begin(), "cwe");
  std::ostringstream out, err;
  const int status = run(args, out, err);
  return {status, out.str(), err.str()};
}

// A fresh (absent) folder in the temporary directory for one test.
inline std::filesystem::path scratch_dir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("cwe-cli-test-" + name);
  std::filesystem::remove_all(dir);
  return dir;
}

// A CSV file's rows and cells, split at every comma (the files read hold no commas in cells).
inline std::vector<std::vector<std::string>> read_csv(const std::filesystem::path& file) {
  std::ifstream stream(file);
  std::vector<std::vector<std::string>> rows;
  for (std::string line; std::getline(stream, line);) {
    std::vector<std::string> cells;
    std::stringstream cells_in(line);
    for (std::string cell; std::getline(cells_in, cell, ',');) cells.push_back(cell);
    rows.push_back(cells);
  }
  return rows;
}

}  // namespace cwe::app

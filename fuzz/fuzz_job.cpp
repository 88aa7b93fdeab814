// Job files (the reader of `cwe simulate JOB`, cwe::app::read_job): the input is written to
// job.json in a scratch folder and read from there. Files the job names (stock, programs, tool
// tables) are not opened by the reader, except tool files of an inline tool table, looked up in
// the scratch folder.

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "fuzz_check.hpp"
#include "fuzz_scratch.hpp"
#include "simulate_command.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const cwe::fuzz::ScratchFile file("job.json");  // removed at exit
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const std::string& path = file.write(text);
  cwe::fuzz::expect_value_or_input_error(text, path, cwe::fuzz::Lines::kByLine, [&] {
    cwe::app::SimulateCommandOptions options;
    options.job_file = path;
    cwe::app::read_job(options);
  });
  return 0;
}

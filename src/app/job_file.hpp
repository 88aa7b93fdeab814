#pragma once
// What `cwe simulate` and `cwe schedule` share besides the job itself (cwe/job/job.hpp): the
// progress bar. The job's options and job files are read by job_file.cpp.

#include <fmt/ostream.h>
#include <cstddef>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "cwe/job/job.hpp"
#include "simulate_command.hpp"

namespace cwe::app {

// A one-line progress bar, redrawn when the shown percentage changes.
class ProgressBar {
 public:
  explicit ProgressBar(std::ostream* stream) : stream_(stream) {}
  void operator()(std::size_t done, std::size_t total) {
    if (stream_ == nullptr || total == 0) return;
    const int percent = static_cast<int>(100 * done / total);
    if (percent == shown_) return;
    shown_ = percent;
    constexpr int kWidth = 40;
    const int filled = percent * kWidth / 100;
    fmt::print(*stream_, "\rremoving material [{}{}] {:3d}%  move {}/{}", std::string(filled, '#'),
               std::string(kWidth - filled, ' '), percent, done, total);
    if (done == total) fmt::print(*stream_, "\n");
    stream_->flush();
  }

 private:
  std::ostream* stream_;
  int shown_ = -1;
};

}  // namespace cwe::app

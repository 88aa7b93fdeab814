#pragma once
// The sink of feed-rate scheduling (`cwe schedule`, docs/forces.md): the largest feed rate each
// move of a job allows under a limit, from the engagement at its cutter locations.

#include <cstddef>
#include <optional>
#include <vector>

#include "cwe/io/cl_sink.hpp"
#include "cwe/process/feed_schedule.hpp"

namespace cwe {

// Scheduled feeds stay this fraction below the admissible ones, so that rounding never tips a
// cutter location over the limit.
inline constexpr double kFeedSafety = 1e-5;

class FeedAllowance : public ClSink {
 public:
  // `moves`: the moves of the job (all operations); `bounds`: the highest feed a move may get
  // (max_scale of its programmed feed, max_feed).
  FeedAllowance(std::size_t moves, const FeedLimit& limit, const ScheduleOptions& bounds);
  // At an engaged CL of a feed move with a force model: the feed per tooth that meets the limit
  // (max_feed_per_tooth) below the upper bound lowers its move's allowance.
  void add(const ClResult& r) override;
  // The allowed feed (mm/min) of each move of the job: unset for moves without CLs, infinite
  // for moves whose CLs allow their upper bound.
  const std::vector<std::optional<double>>& allowed() const { return allowed_; }

 private:
  FeedLimit limit_;
  ScheduleOptions bounds_;
  std::vector<std::optional<double>> allowed_;
};

}  // namespace cwe

#pragma once
// The same job run on several workpieces, cutter location by cutter location (`cwe compare`,
// docs/accuracy.md): what each run keeps of every CL, the differences of each against the
// reference, and their percentiles.

#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include "cwe/engagement/map_difference.hpp"
#include "cwe/io/cl_sink.hpp"
#include "cwe/job/job.hpp"

namespace cwe {

// A cutter location of a run, as a comparison needs it.
struct ClRecord {
  std::size_t operation = 0;
  Vec3 position = Vec3::Zero();
  std::string file;
  int line = 0;
  EngagementMap map;
};

// Keeps every CL's record (the maps whole: a few kB a CL).
class RecordingSink : public ClSink {
 public:
  void add(const ClResult& result) override;
  std::vector<ClRecord> records;
};

struct ClDifference {
  std::size_t cl = 0;
  bool reference_engaged = false, other_engaged = false;
  double reference_area = 0.0;  // mm²
  MapDifference difference;     // other − reference
};

// The differences of `other` against `reference`, CL by CL, each map measured on the cutter of
// its operation in `job`. Throws ComputationError when the runs' CLs do not line up (another
// count, or a CL more than 1e-6 mm from its counterpart): they come from the same job.
std::vector<ClDifference> compare_runs(const PreparedJob& job,
                                       const std::vector<ClRecord>& reference,
                                       const std::vector<ClRecord>& other);

// Percentiles (nearest rank) of |value| over the differences `counted` takes, the largest and
// its CL. All zero when none is counted.
struct DifferenceStats {
  std::size_t count = 0;
  double p50 = 0.0, p95 = 0.0, p99 = 0.0, max = 0.0;
  std::size_t max_cl = 0;
};
DifferenceStats difference_stats(const std::vector<ClDifference>& differences,
                                 const std::function<double(const ClDifference&)>& value,
                                 const std::function<bool(const ClDifference&)>& counted);

}  // namespace cwe

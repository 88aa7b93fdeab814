#include "cwe/job/compare.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "cwe/core/computation_error.hpp"

namespace cwe {

void RecordingSink::add(const ClResult& result) {
  records.push_back(
      {result.operation, result.cl.position, result.file, result.cl.line, result.map});
}

std::vector<ClDifference> compare_runs(const PreparedJob& job,
                                       const std::vector<ClRecord>& reference,
                                       const std::vector<ClRecord>& other) {
  if (reference.size() != other.size()) {
    throw ComputationError(
        fmt::format("the runs have {} and {} cutter locations; the same job should give the same",
                    reference.size(), other.size()));
  }
  std::vector<ClDifference> differences;
  differences.reserve(reference.size());
  for (std::size_t k = 0; k < reference.size(); ++k) {
    const ClRecord& a = reference[k];
    const ClRecord& b = other[k];
    if (a.operation != b.operation || (a.position - b.position).norm() > 1e-6 ||
        a.operation >= job.operations.size()) {
      throw ComputationError(
          fmt::format("cutter location {} ({} line {}) is not at the same place in both runs", k,
                      a.file, a.line));
    }
    const Profile& profile = job.operations[a.operation].cutter.profile();
    differences.push_back(
        {k, a.map.engaged, b.map.engaged, a.map.area, map_difference(a.map, b.map, profile)});
  }
  return differences;
}

DifferenceStats difference_stats(const std::vector<ClDifference>& differences,
                                 const std::function<double(const ClDifference&)>& value,
                                 const std::function<bool(const ClDifference&)>& counted) {
  DifferenceStats stats;
  std::vector<double> values;
  for (const ClDifference& d : differences) {
    if (!counted(d)) continue;
    const double v = std::abs(value(d));
    if (values.empty() || v > stats.max) {  // the first CL with the largest
      stats.max = v;
      stats.max_cl = d.cl;
    }
    values.push_back(v);
  }
  stats.count = values.size();
  if (values.empty()) return stats;
  std::sort(values.begin(), values.end());
  const auto rank = [&](double p) {
    const auto k = static_cast<std::size_t>(std::ceil(p * static_cast<double>(values.size())));
    return values[std::clamp<std::size_t>(k, 1, values.size()) - 1];
  };
  stats.p50 = rank(0.50);
  stats.p95 = rank(0.95);
  stats.p99 = rank(0.99);
  return stats;
}

}  // namespace cwe

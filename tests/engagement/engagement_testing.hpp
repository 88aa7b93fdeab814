#pragma once
// Helpers shared by the engagement tests: a whole job run through simulate_engagement, every
// cutter location kept with its state and map; a feed move; the check of a run of discs against
// closed-form entry and exit angles.

#include <vector>

#include <gtest/gtest.h>

#include "cwe/simulation/simulation.hpp"
#include "cwe/tool/tool_spec.hpp"

namespace cwe::test {

struct Sample {
  ClPoint cl;
  ToolState state;
  EngagementMap map;
};

// Every cutter location of `path` cut by the cutter `tool` (a specification) through the box
// `block`, at ray spacing `spacing` and CL step `step`; arcs, helices and 5-axis moves subdivided
// within `tolerance` (0: spacing / 10).
inline std::vector<Sample> simulate_samples(const Toolpath& path, const char* tool,
                                            const Aabb& block, double spacing, double step,
                                            double tolerance = 0.0) {
  TriDexel stock = TriDexel::from_box(block, spacing);
  const Cutter cutter = cutter_from_spec(tool);
  SimulationOptions options;
  options.resolution = spacing;
  options.tolerance = tolerance;
  SamplingOptions sampling;
  sampling.step = step;
  std::vector<Sample> samples;
  simulate_engagement(stock, cutter, path, {options, sampling, {}}, [&](const ClEngagement& e) {
    samples.push_back({e.cl, e.state, e.map});
  });
  return samples;
}

// A feed move (600 mm/min) from tip a to tip b with the tool along +Z.
inline Move line(const Vec3& a, const Vec3& b) {
  Move m;
  m.start = a;
  m.end = b;
  m.feed_rate = 600.0;
  return m;
}

// Entry and exit of the discs between heights z0 and z1: every disc there must be one interval
// matching [entry, exit] within `tolerance`.
inline void expect_discs(const EngagementMap& map, double z0, double z1, double entry, double exit,
                         double tolerance) {
  int checked = 0;
  for (const DiscEngagement& disc : map.discs) {
    if (disc.z0 < z0 || disc.z1 > z1) continue;
    SCOPED_TRACE(testing::Message() << "disc " << disc.z0 << "–" << disc.z1);
    ASSERT_EQ(disc.phi.size(), 1u);
    EXPECT_NEAR(disc.phi[0].lo, entry, tolerance);
    EXPECT_NEAR(disc.phi[0].hi, exit, tolerance);
    ++checked;
  }
  EXPECT_GT(checked, 0);
}

}  // namespace cwe::test

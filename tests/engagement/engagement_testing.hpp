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

// The dexel workpiece's map at the location of `moves` nearest `probe` (on move `on_move` when it
// is not negative), cut by `tool` through `block` at ray spacing `spacing`, CL step 0.5 mm.
inline EngagementMap dexel_map_near(const std::vector<Move>& moves, const char* tool,
                                    const Aabb& block, double spacing, double subdivision,
                                    const Vec3& probe, int on_move = -1) {
  Toolpath path;
  path.sources = {"test"};
  path.moves = moves;
  const std::vector<Sample> samples =
      simulate_samples(path, tool, block, spacing, 0.5, subdivision);
  const Sample* nearest = nullptr;
  for (const Sample& sample : samples) {
    if (on_move >= 0 && sample.cl.move != on_move) continue;
    if (!nearest || (sample.cl.position - probe).norm() < (nearest->cl.position - probe).norm()) {
      nearest = &sample;
    }
  }
  EXPECT_NE(nearest, nullptr);
  return nearest ? nearest->map : EngagementMap{};
}

// `map` (another method's) agrees with the dexel method's `dexel` at the same location within
// `tolerance` on every disc both engage; the disc at the top of the cut may be engaged by one
// method only (depth within 2s, s the dexel's `spacing`). More than 20 discs are compared.
inline void expect_agrees_with_dexel(const EngagementMap& map, const EngagementMap& dexel,
                                     double tolerance, double spacing) {
  ASSERT_TRUE(dexel.engaged);
  ASSERT_EQ(map.discs.size(), dexel.discs.size());
  int compared = 0;
  for (std::size_t k = 0; k < dexel.discs.size(); ++k) {
    const DiscEngagement& d = dexel.discs[k];
    const DiscEngagement& m = map.discs[k];
    if (d.phi.empty() != m.phi.empty()) {
      EXPECT_NEAR(d.z0, dexel.axial_depth, 2 * spacing) << "disc " << d.z0;
      continue;
    }
    if (d.phi.empty()) continue;
    SCOPED_TRACE(testing::Message() << "disc " << d.z0);
    ASSERT_EQ(m.phi.size(), d.phi.size());
    for (std::size_t i = 0; i < d.phi.size(); ++i) {
      EXPECT_NEAR(m.phi[i].lo, d.phi[i].lo, tolerance);
      EXPECT_NEAR(m.phi[i].hi, d.phi[i].hi, tolerance);
    }
    ++compared;
  }
  EXPECT_GT(compared, 20);
  EXPECT_NEAR(map.axial_depth, dexel.axial_depth, 2 * spacing);
}

}  // namespace cwe::test

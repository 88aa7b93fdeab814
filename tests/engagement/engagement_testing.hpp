#pragma once
// Helpers shared by the engagement tests: a whole job run through simulate_engagement, every
// cutter location kept with its state and map.

#include <vector>

#include "cwe/simulation/simulation.hpp"
#include "cwe/tool/tool_spec.hpp"

namespace cwe::test {

struct Sample {
  ClPoint cl;
  ToolState state;
  EngagementMap map;
};

// Every cutter location of `path` cut by the cutter `tool` (a specification) through the box
// `block`, at ray spacing `spacing` and CL step `step`.
inline std::vector<Sample> simulate_samples(const Toolpath& path, const char* tool,
                                            const Aabb& block, double spacing, double step) {
  TriDexel stock = TriDexel::from_box(block, spacing);
  const Cutter cutter = cutter_from_spec(tool);
  SimulationOptions options;
  options.resolution = spacing;
  SamplingOptions sampling;
  sampling.step = step;
  std::vector<Sample> samples;
  simulate_engagement(stock, cutter, path, {options, sampling, {}}, [&](const ClEngagement& e) {
    samples.push_back({e.cl, e.state, e.map});
  });
  return samples;
}

}  // namespace cwe::test

// Engagement maps against a brute-force oracle: dense points of the cutter surface tested against
// the exact workpiece (the block minus the true swept volume of all motion before the cutter
// location) and the true swept volume of the step that follows it, both decided by
// test::union_side over densely sampled tool positions, for a bull-nose ramp beside an earlier
// slot and a tilted 3+2 pass. A point is engaged where the step removes material next to it
// (CWE = FCS ∩ (W ∩ SV)).
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "cwe/engagement/dexel_engagement.hpp"
#include "cwe/simulation/simulation.hpp"
#include "cwe/tool/tool_spec.hpp"
#include "engagement/engagement_oracle.hpp"

namespace cwe {
namespace {

constexpr double kSpacing = 0.1;

Move line(const Vec3& a, const Vec3& b, const Vec3& axis = Vec3::UnitZ()) {
  Move m;
  m.start = a;
  m.end = b;
  m.start_axis = m.end_axis = axis.normalized();
  m.feed_rate = 600.0;
  return m;
}

struct Case {
  const char* tool;
  Aabb block;
  std::vector<Move> moves;
  double along_last = 0.6;  // the CL to check: this fraction along the last move
};

void check(const Case& c) {
  TriDexel stock = TriDexel::from_box(c.block, kSpacing);
  const Move& last = c.moves.back();
  const Vec3 probe = last.position(c.along_last);
  Toolpath path;
  path.sources = {"test"};
  path.moves = c.moves;
  const Cutter cutter = cutter_from_spec(c.tool);
  SimulationOptions options;
  options.resolution = kSpacing;
  SamplingOptions sampling;
  sampling.step = 0.5;
  EngagementMap map;
  ClPoint cl;
  ToolState state;
  double nearest = 1e300;
  std::vector<ClPoint> cls;
  std::size_t chosen = 0;
  simulate_engagement(stock, cutter, path, {options, sampling, {}}, [&](const ClEngagement& e) {
    cls.push_back(e.cl);
    const double d = (e.cl.position - probe).norm();
    if (d < nearest) {
      nearest = d;
      map = e.map;
      cl = e.cl;
      state = e.state;
      chosen = e.index;
    }
  });
  ASSERT_LT(nearest, 0.5);
  ASSERT_TRUE(map.engaged);
  // The step that follows the CL: to the next sample of the same move, or to the move's end.
  const double u_next =
      chosen + 1 < cls.size() && cls[chosen + 1].move == cl.move ? cls[chosen + 1].u : 1.0;
  const test::OracleCount count =
      test::check_against_oracle(cutter, c.block, c.moves, cl, state, map, u_next, kSpacing);
  const int agreed = count.agreed, engaged = count.engaged;
  EXPECT_GT(agreed, 500);
  EXPECT_GT(engaged, 100);
  EXPECT_GT(agreed - engaged, 100);
}

TEST(EngagementOracle, BullNoseRampBesideASlot) {
  // A slot along X at depth 2, then a bull-nose ramp crossing it diagonally, descending.
  check({"bull:10,2,6",
         {{0, 0, 4}, {36, 30, 12}},
         {line({-8, 12, 10}, {48, 12, 10}), line({-8, 4, 11}, {30, 22, 7})}});
}

TEST(EngagementOracle, TiltedThreePlusTwo) {
  // A flat end mill with its axis tilted about 20° from Z, side-cutting along X, then a ramp
  // along the first cut's wall.
  const Vec3 axis(std::sin(20 * kPi / 180), -std::sin(10 * kPi / 180), 1.0);
  check({"flat:8,6",
         {{0, 0, 4}, {36, 30, 12}},
         {line({-8, 25, 8}, {48, 25, 8}, axis), line({-8, 15, 9}, {40, 21, 7.5}, axis)}});
}

}  // namespace
}  // namespace cwe

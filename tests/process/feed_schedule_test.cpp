// Feed scheduling: the admissible feed per tooth at a cutter location is tight (the limit is met
// there and broken just above it) for every limited quantity, with and without runout; the
// per-move schedule keeps its bounds and its largest change.
#include "cwe/process/feed_schedule.hpp"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "cwe/core/error.hpp"
#include "cwe/tool/tool_spec.hpp"
#include "process_testing.hpp"

namespace cwe {
namespace {

CuttingCoefficients coefficients() { return test::test_coefficients(); }

EngagementMap slot_map(double depth, double phi0, double phi1) {
  EngagementMap map;
  for (int i = 0; i * 0.1 < depth - 1e-9; ++i) {
    map.discs.push_back({i * 0.1, (i + 1) * 0.1, 0, {{phi0, phi1}}});
  }
  map.engaged = true;
  return map;
}

TEST(FeedLimit, ParsesQuantitiesAndUnits) {
  const FeedLimit f = parse_feed_limit("force=800N", "--limit");
  EXPECT_EQ(f.quantity, FeedLimit::Quantity::kForce);
  EXPECT_EQ(f.value, 800.0);
  EXPECT_EQ(parse_feed_limit("force=1.2kN", "x").value, 1200.0);
  EXPECT_EQ(parse_feed_limit("torque=12Nm", "x").quantity, FeedLimit::Quantity::kTorque);
  EXPECT_EQ(parse_feed_limit("power=1.5kW", "x").value, 1500.0);
  EXPECT_EQ(parse_feed_limit("power=900", "x").value, 900.0);
  const FeedLimit chip = parse_feed_limit("chip=80um", "x");
  EXPECT_EQ(chip.quantity, FeedLimit::Quantity::kChip);
  EXPECT_NEAR(chip.value, 0.08, 1e-15);
  for (const char* bad : {"force", "force=", "force=-3N", "force=800Nm", "speed=3", "chip=0"}) {
    EXPECT_THROW(parse_feed_limit(bad, "--limit"), InputError) << bad;
  }
  try {
    parse_feed_limit("force=800lbf", "--limit");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("unknown unit 'lbf'"), std::string::npos) << e.what();
  }
}

// At the returned feed the quantity is at the limit (to 1e-6 relative: the affine solution is
// exact up to rounding); 0.1% more feed breaks it.
TEST(FeedLimit, AdmissibleFeedIsTightForEveryQuantity) {
  const Cutter cutter = cutter_from_spec("flat:10,30");
  struct Case {
    const char* limit;
    Runout runout;
  };
  const Case cases[] = {
      {"force=600N", {}},  {"torque=2.5Nm", {}},         {"power=2kW", {}},
      {"chip=0.04mm", {}}, {"force=600N", {0.005, 0.4}}, {"torque=2.5Nm", {0.01, 1.0}}};
  for (const Case& cs : cases) {
    SCOPED_TRACE(fmt::format("{} runout {}", cs.limit, cs.runout.offset));
    ForceModelOptions options;
    options.flutes = 3;
    options.runout = cs.runout;
    const ForceModel model(cutter, coefficients(), options);
    const FeedLimit limit = parse_feed_limit(cs.limit, "test");
    const EngagementMap map = slot_map(4.0, 0.2, 2.9);
    const double c = max_feed_per_tooth(model, map, Vec3::UnitX(), 9000.0, limit, 1.0);
    ASSERT_GT(c, 0.0);
    ASSERT_LT(c, 1.0);
    const double at = limited_value(model.evaluate(map, Vec3::UnitX(), c, 9000.0), limit.quantity);
    const double above =
        limited_value(model.evaluate(map, Vec3::UnitX(), c * 1.001, 9000.0), limit.quantity);
    EXPECT_LE(at, limit.value);
    EXPECT_GT(at, limit.value * (1.0 - 1e-6));
    EXPECT_GT(above, limit.value);
  }
}

TEST(FeedLimit, FeedsThatAlreadyMeetTheLimitOrNeverCanAreReported) {
  const Cutter cutter = cutter_from_spec("flat:10,30");
  const ForceModel model(cutter, coefficients());
  const EngagementMap map = slot_map(2.0, 0.0, kPi);
  // A generous limit: the largest feed asked for is admissible.
  EXPECT_EQ(
      max_feed_per_tooth(model, map, Vec3::UnitX(), 8000, {FeedLimit::Quantity::kForce, 1e6}, 0.2),
      0.2);
  // Edge forces alone (27.7 N/mm over 2 mm on up to two flutes) exceed 10 N: no feed helps.
  EXPECT_EQ(
      max_feed_per_tooth(model, map, Vec3::UnitX(), 8000, {FeedLimit::Quantity::kForce, 10.0}, 0.2),
      0.0);
  // Air: nothing to limit.
  EngagementMap air;
  EXPECT_EQ(
      max_feed_per_tooth(model, air, Vec3::UnitX(), 8000, {FeedLimit::Quantity::kForce, 1.0}, 0.2),
      0.2);
}

TEST(Schedule, KeepsBoundsAndLargestChange) {
  std::vector<MoveFeed> moves = {
      {1000, std::numeric_limits<double>::infinity(), 10},  // air: up to 2×
      {1000, 300.0, 10},                                    // heavy cut
      {1000, 1200.0, 10},
      {1000, std::nullopt, 10},  // not sampled: keeps its feed as the bound
      {1000, 50.0, 10},          // below the minimum (10% = 100): runs at 100, flagged
  };
  ScheduleOptions options;
  options.max_change = 1.5;
  const Schedule s = schedule_feeds(moves, options);
  ASSERT_EQ(s.moves.size(), 5u);
  EXPECT_NEAR(s.moves[1].feed, 300.0, 1e-12);
  EXPECT_NEAR(s.moves[0].feed, 450.0, 1e-12);  // lowered so that 450/300 = 1.5
  EXPECT_NEAR(s.moves[4].feed, 100.0, 1e-12);
  EXPECT_TRUE(s.moves[4].limit_exceeded);
  EXPECT_EQ(s.exceeded, 1);
  EXPECT_NEAR(s.moves[3].feed, 150.0, 1e-12);  // 1.5 × the 100 after it
  EXPECT_NEAR(s.moves[2].feed, 225.0, 1e-12);
  for (std::size_t i = 1; i < s.moves.size(); ++i) {
    const double ratio = s.moves[i].feed / s.moves[i - 1].feed;
    EXPECT_LE(ratio, 1.5 + 1e-12);
    EXPECT_GE(ratio, 1 / 1.5 - 1e-12);
  }
  EXPECT_NEAR(s.programmed_minutes, 0.05, 1e-15);
  EXPECT_NEAR(s.scheduled_minutes, 10 / 450.0 + 10 / 300.0 + 10 / 225.0 + 10 / 150.0 + 10 / 100.0,
              1e-12);
  EXPECT_EQ(s.limited, 5);

  // A move held at its minimum bounds its neighbours by that minimum, not by a lower feed the
  // ratio alone would have given: after a slow plunge the feed climbs 100, 150, 225.
  const Schedule climb = schedule_feeds({{100, 10.0, 1},
                                         {1000, std::numeric_limits<double>::infinity(), 1},
                                         {1000, std::numeric_limits<double>::infinity(), 1},
                                         {1000, std::numeric_limits<double>::infinity(), 1}},
                                        options);
  EXPECT_NEAR(climb.moves[0].feed, 10.0, 1e-12);
  EXPECT_NEAR(climb.moves[1].feed, 100.0, 1e-12);
  EXPECT_NEAR(climb.moves[2].feed, 150.0, 1e-12);
  EXPECT_NEAR(climb.moves[3].feed, 225.0, 1e-12);
  EXPECT_EQ(climb.exceeded, 0);

  options.max_feed = 1500.0;
  options.max_change = 10.0;
  const Schedule fast =
      schedule_feeds({{1000, std::numeric_limits<double>::infinity(), 5}}, options);
  EXPECT_NEAR(fast.moves[0].feed, 1500.0, 1e-12);
  EXPECT_EQ(fast.raised, 1);

  options.min_feed = 2000.0;
  EXPECT_THROW(schedule_feeds(moves, options), InputError);
}

}  // namespace
}  // namespace cwe

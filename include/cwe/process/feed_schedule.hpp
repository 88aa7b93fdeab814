#pragma once
// Feed-rate scheduling (docs/forces.md): the largest feed at each cutter location that keeps a
// chosen quantity at or below a limit, and from those a feed per move of the program, within
// minimum and maximum feeds and with a bounded change from one feed move to the next.
//
// The engagement (which part of the cutter cuts) does not depend on the feed; only the chip
// thickness does. Without runout every sample of the force over a revolution is affine in the
// feed per tooth c for c > 0 (F_k(c) = c·A_k + B_k: shear terms grow with the chip, edge terms
// do not), and so are torque, power and the thickest chip; the largest admissible c is then
// solved for exactly. With runout the chip is piecewise affine in c; the affine solution is then
// checked and, where it overshoots, bisected down. Either way the returned feed meets the limit
// when the model is evaluated there.

#include <optional>
#include <string>
#include <vector>

#include "cwe/engagement/engagement_map.hpp"
#include "cwe/process/force_model.hpp"

namespace cwe {

struct FeedLimit {
  enum class Quantity { kForce, kTorque, kPower, kChip };
  Quantity quantity = Quantity::kForce;
  // N for the peak resultant force, N·m for the peak torque, W for the mean power, mm for the
  // thickest chip.
  double value = 0.0;
};

const char* to_string(FeedLimit::Quantity quantity);

// Parses force=800N, torque=12Nm (or N·m), power=1.5kW / 1500W, chip=0.08mm (units optional;
// defaults N, N·m, W, mm). Throws cwe::InputError naming `source` for anything else or a value
// that is not a positive finite number.
FeedLimit parse_feed_limit(const std::string& text, const std::string& source);

// The limited quantity of a CL's forces.
double limited_value(const ClForces& forces, FeedLimit::Quantity quantity);

// The largest feed per tooth in (0, c_max] for which the limited quantity at this cutter
// location stays at or below the limit: c_max when even c_max does, 0 when no positive feed does
// (edge forces alone exceed a force, torque or power limit). The map and feed direction are those
// of ForceModel::evaluate.
double max_feed_per_tooth(const ForceModel& model, const EngagementMap& map,
                          const Vec3& feed_direction_tcs, double spindle_speed,
                          const FeedLimit& limit, double c_max);

struct ScheduleOptions {
  // Bounds on the scheduled feed, as fractions of each move's programmed feed and, when set, in
  // mm/min (both apply).
  double min_scale = 0.1;
  double max_scale = 2.0;
  std::optional<double> min_feed;  // mm/min
  std::optional<double> max_feed;  // mm/min
  // Largest ratio between the feeds of consecutive feed moves (≥ 1).
  double max_change = 1.5;

  // Throws cwe::InputError, saying which, unless 0 < min_scale ≤ max_scale (finite), the
  // feeds given are finite and positive with min_feed ≤ max_feed, and max_change is finite ≥ 1.
  void check() const;
};

// One feed move's input to the schedule.
struct MoveFeed {
  double programmed = 0.0;  // mm/min
  // The largest feed rate (mm/min) its cutter locations allow, or nullopt when the move was not
  // sampled (it keeps its programmed feed as an upper bound) — +inf when it never cuts.
  std::optional<double> allowed;
  double length = 0.0;  // tip path length, mm (cycle time)
};

struct ScheduledMove {
  double feed = 0.0;  // mm/min
  // The limit could not be met within the minimum feed: the move runs at the minimum and its
  // CLs exceed the limit.
  bool limit_exceeded = false;
};

struct Schedule {
  std::vector<ScheduledMove> moves;
  double programmed_minutes = 0.0;  // feed-move time at the programmed feeds
  double scheduled_minutes = 0.0;
  int limited = 0;   // moves slowed below their programmed feed
  int raised = 0;    // moves sped up
  int exceeded = 0;  // moves that cannot meet the limit within the minimum feed
};

// The feeds: each move's allowed feed clipped to its bounds, then lowered (never below its
// minimum) where needed so that consecutive moves differ by at most max_change (a forward and a
// backward pass: the largest such sequence below the allowed feeds; a move held at its minimum
// may differ from its neighbours by more). Checks the options first (ScheduleOptions::check).
Schedule schedule_feeds(const std::vector<MoveFeed>& moves, const ScheduleOptions& options);

}  // namespace cwe

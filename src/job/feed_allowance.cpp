#include "cwe/job/feed_allowance.hpp"

#include <algorithm>
#include <limits>

namespace cwe {

FeedAllowance::FeedAllowance(std::size_t moves, const FeedLimit& limit,
                             const ScheduleOptions& bounds)
    : limit_(limit), bounds_(bounds), allowed_(moves) {}

void FeedAllowance::add(const ClResult& r) {
  if (r.force_model == nullptr || !(r.feed_rate > 0.0)) return;
  const ForceModel& model = *r.force_model;
  std::optional<double>& best = allowed_.at(static_cast<std::size_t>(r.cl.move));
  double highest = r.feed_rate * bounds_.max_scale;
  if (bounds_.max_feed) highest = std::min(highest, *bounds_.max_feed);
  const double c_max = feed_per_tooth(highest, model.flutes(), r.spindle_speed);
  const Vec3 v = r.state.tip_velocity_tcs();
  double feed = std::numeric_limits<double>::infinity();
  if (v.norm() > 0.0 && r.map.engaged) {
    const double c =
        max_feed_per_tooth(model, r.map, v.normalized(), r.spindle_speed, limit_, c_max);
    if (c < c_max) feed = c * model.flutes() * r.spindle_speed * (1.0 - kFeedSafety);
  }
  best = std::min(best.value_or(feed), feed);
}

}  // namespace cwe

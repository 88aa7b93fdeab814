#include "cwe/process/feed_schedule.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <limits>

#include "cwe/core/error.hpp"
#include "cwe/geometry/tolerance.hpp"

namespace cwe {

namespace {

// The admissible feed per tooth is bisected to this fraction of its upper bound: 1e-9 of a feed
// is far below any feed a program can state (4 to 5 significant digits).
constexpr double kBisectionRelative = 1e-9;

constexpr double kInf = std::numeric_limits<double>::infinity();

// The largest c ≥ 0 with |c·a + b| ≤ limit, for vectors a, b (the force samples' affine parts);
// +inf when no c violates it, 0 when c → 0 already does.
template <class V>
double largest_within(const V& a, const V& b, double limit) {
  const double qa = a.squaredNorm(), qb = 2.0 * a.dot(b), qc = b.squaredNorm() - limit * limit;
  if (qc > 0.0 || (qc == 0.0 && qb > 0.0)) return 0.0;  // at or over the limit as c → 0
  if (qa <= 0.0) return qb <= 0.0 ? kInf : -qc / qb;
  const double disc = std::max(0.0, qb * qb - 4.0 * qa * qc);
  // The larger root (qc ≤ 0 makes it ≥ 0), in the form without cancellation.
  return qb >= 0.0 ? -2.0 * qc / (qb + std::sqrt(disc)) : (-qb + std::sqrt(disc)) / (2.0 * qa);
}

double affine_solution(const ClForces& f1, double c1, const ClForces& f2, double c2, double omega,
                       const FeedLimit& limit) {
  const double dc = c1 - c2;
  double best = kInf;
  switch (limit.quantity) {
    case FeedLimit::Quantity::kForce:
      for (std::size_t k = 0; k < f1.curve.size(); ++k) {
        const Vec3 a = (f1.curve[k].force - f2.curve[k].force) / dc;
        const Vec3 b = f1.curve[k].force - c1 * a;
        best = std::min(best, largest_within(a, b, limit.value));
      }
      return best;
    case FeedLimit::Quantity::kTorque:
      for (std::size_t k = 0; k < f1.curve.size(); ++k) {
        const double a = (f1.curve[k].torque - f2.curve[k].torque) / dc;
        const double b = f1.curve[k].torque - c1 * a;
        best = std::min(best, largest_within(Eigen::Matrix<double, 1, 1>(a),
                                             Eigen::Matrix<double, 1, 1>(b), limit.value));
      }
      return best;
    case FeedLimit::Quantity::kPower: {
      if (!(omega > 0.0)) return kInf;
      const double a = (f1.mean_torque - f2.mean_torque) / dc;
      const double b = f1.mean_torque - c1 * a;
      return largest_within(Eigen::Matrix<double, 1, 1>(a), Eigen::Matrix<double, 1, 1>(b),
                            limit.value / omega);
    }
    case FeedLimit::Quantity::kChip: {
      const double a = (f1.max_chip - f2.max_chip) / dc;
      const double b = f1.max_chip - c1 * a;
      return largest_within(Eigen::Matrix<double, 1, 1>(a), Eigen::Matrix<double, 1, 1>(b),
                            limit.value);
    }
  }
  return best;
}

}  // namespace

const char* to_string(FeedLimit::Quantity quantity) {
  switch (quantity) {
    case FeedLimit::Quantity::kForce:
      return "force";
    case FeedLimit::Quantity::kTorque:
      return "torque";
    case FeedLimit::Quantity::kPower:
      return "power";
    case FeedLimit::Quantity::kChip:
      return "chip";
  }
  return "?";
}

FeedLimit parse_feed_limit(const std::string& text, const std::string& source) {
  const auto fail = [&](const std::string& why) {
    throw InputError(SourceLocation{source},
                     fmt::format("'{}': {}; expected force=<N>, torque=<N·m>, power=<W or kW> or "
                                 "chip=<mm>, e.g. force=800N",
                                 text, why));
  };
  const std::size_t eq = text.find('=');
  if (eq == std::string::npos) fail("no '='");
  const std::string name = text.substr(0, eq);
  FeedLimit limit;
  struct Unit {
    const char* text;
    double scale;
  };
  std::vector<Unit> units;
  if (name == "force") {
    limit.quantity = FeedLimit::Quantity::kForce;
    units = {{"", 1.0}, {"N", 1.0}, {"kN", 1000.0}};
  } else if (name == "torque") {
    limit.quantity = FeedLimit::Quantity::kTorque;
    units = {{"", 1.0}, {"Nm", 1.0}, {"N·m", 1.0}, {"N.m", 1.0}};
  } else if (name == "power") {
    limit.quantity = FeedLimit::Quantity::kPower;
    units = {{"", 1.0}, {"W", 1.0}, {"kW", 1000.0}};
  } else if (name == "chip") {
    limit.quantity = FeedLimit::Quantity::kChip;
    units = {{"", 1.0}, {"mm", 1.0}, {"um", 1e-3}, {"µm", 1e-3}};
  } else {
    fail(fmt::format("unknown quantity '{}'", name));
  }
  const std::string value = text.substr(eq + 1);
  double number = 0.0;
  const auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), number);
  if (ec != std::errc() || end == value.data()) fail("no number after '='");
  const std::string unit(end, value.data() + value.size());
  const auto it =
      std::find_if(units.begin(), units.end(), [&](const Unit& u) { return unit == u.text; });
  if (it == units.end()) fail(fmt::format("unknown unit '{}' for {}", unit, name));
  limit.value = number * it->scale;
  if (!(limit.value > 0.0) || !std::isfinite(limit.value)) fail("the limit must be positive");
  return limit;
}

double limited_value(const ClForces& forces, FeedLimit::Quantity quantity) {
  switch (quantity) {
    case FeedLimit::Quantity::kForce:
      return forces.peak_resultant;
    case FeedLimit::Quantity::kTorque:
      return forces.peak_torque;
    case FeedLimit::Quantity::kPower:
      return forces.mean_power;
    case FeedLimit::Quantity::kChip:
      return forces.max_chip;
  }
  return 0.0;
}

double max_feed_per_tooth(const ForceModel& model, const EngagementMap& map,
                          const Vec3& feed_direction_tcs, double spindle_speed,
                          const FeedLimit& limit, double c_max) {
  if (!(c_max > 0.0)) return 0.0;
  const auto value_at = [&](double c, bool curve) {
    return model.evaluate(map, feed_direction_tcs, c, spindle_speed, curve);
  };
  const auto within = [&](const ClForces& f) {
    return limited_value(f, limit.quantity) <= limit.value;
  };
  const ClForces at_max = value_at(c_max, true);
  if (!at_max.cutting || within(at_max)) return c_max;
  // Affine in c (exact without runout): solve, from the samples at c_max and c_max / 2.
  const ClForces at_half = value_at(0.5 * c_max, true);
  const double omega = spindle_speed * 2.0 * kPi / 60.0;
  double c = std::min(c_max, affine_solution(at_max, c_max, at_half, 0.5 * c_max, omega, limit));
  if (c > 0.0 && within(value_at(c, false))) return c;
  // Not affine (runout) or rounding at the limit: bisect below, keeping the lower end admissible.
  double lo = 0.0, hi = c > 0.0 ? c : c_max;
  for (int i = 0; i < 60 && hi - lo > kBisectionRelative * c_max; ++i) {
    const double mid = 0.5 * (lo + hi);
    (within(value_at(mid, false)) ? lo : hi) = mid;
  }
  return lo;
}

void ScheduleOptions::check() const {
  if (!(min_scale > 0.0) || !(max_scale >= min_scale) || !std::isfinite(max_scale)) {
    throw InputError("feed bounds: need 0 < min scale <= max scale");
  }
  for (const std::optional<double>& feed : {min_feed, max_feed}) {
    if (feed && !(*feed > 0.0 && std::isfinite(*feed))) {
      throw InputError("feed bounds: a minimum or maximum feed must be positive");
    }
  }
  if (min_feed && max_feed && *min_feed > *max_feed) {
    throw InputError("feed bounds: the minimum feed exceeds the maximum");
  }
  if (!(max_change >= 1.0) || !std::isfinite(max_change)) {
    throw InputError("the largest change between moves must be a ratio >= 1");
  }
}

Schedule schedule_feeds(const std::vector<MoveFeed>& moves, const ScheduleOptions& options) {
  options.check();
  Schedule out;
  const std::size_t n = moves.size();
  std::vector<double> low(n), feed(n);
  for (std::size_t i = 0; i < n; ++i) {
    const MoveFeed& m = moves[i];
    double lo = m.programmed * options.min_scale, hi = m.programmed * options.max_scale;
    if (options.min_feed) lo = std::max(lo, *options.min_feed);
    if (options.max_feed) hi = std::min(hi, *options.max_feed);
    hi = std::max(hi, lo);
    low[i] = lo;
    const double allowed = m.allowed.value_or(m.programmed);
    feed[i] = std::clamp(allowed, lo, hi);
  }
  // Consecutive moves within the ratio: lower the faster neighbour, forwards then backwards, but
  // never below a move's minimum (the minimum takes precedence over the ratio, and a neighbour
  // is then bounded by the minimum, not by a lower value the ratio alone would have asked for).
  for (std::size_t i = 1; i < n; ++i) {
    feed[i] = std::max(low[i], std::min(feed[i], feed[i - 1] * options.max_change));
  }
  for (std::size_t i = n; i-- > 1;) {
    feed[i - 1] = std::max(low[i - 1], std::min(feed[i - 1], feed[i] * options.max_change));
  }
  out.moves.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const MoveFeed& m = moves[i];
    ScheduledMove& s = out.moves[i];
    s.feed = feed[i];
    s.limit_exceeded = m.allowed && *m.allowed < feed[i] * (1.0 - tol::kRelative);
    out.exceeded += s.limit_exceeded ? 1 : 0;
    out.limited += feed[i] < m.programmed * (1.0 - tol::kRelative) ? 1 : 0;
    out.raised += feed[i] > m.programmed * (1.0 + tol::kRelative) ? 1 : 0;
    if (m.programmed > 0.0) out.programmed_minutes += m.length / m.programmed;
    if (feed[i] > 0.0) out.scheduled_minutes += m.length / feed[i];
  }
  return out;
}

}  // namespace cwe

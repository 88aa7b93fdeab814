#include "cwe/job/force_settings.hpp"

#include <fmt/format.h>

#include <charconv>
#include <cmath>

#include "cwe/core/error.hpp"

namespace cwe {

ForceSettings force_settings(const std::string& forces, const ForceOverrides& overrides) {
  ForceSettings s;
  if (!forces.empty()) s.coefficients = load_cutting_coefficients(forces);
  s.spindle = overrides.spindle;
  s.feed = overrides.feed;
  s.model.flutes = overrides.flutes.value_or(0);
  s.model.helix_angle = overrides.helix_deg ? *overrides.helix_deg * kPi / 180.0 : -1.0;
  if (overrides.step_deg) s.model.angle_step = *overrides.step_deg * kPi / 180.0;
  const std::string& runout = overrides.runout;
  if (!runout.empty()) {
    const SourceLocation& where = overrides.runout_at;
    const std::size_t comma = runout.find(',');
    double values[2] = {0.0, 0.0};
    const std::string parts[2] = {runout.substr(0, comma),
                                  comma == std::string::npos ? "0" : runout.substr(comma + 1)};
    for (int i = 0; i < 2; ++i) {
      const std::string& p = parts[i];
      const auto [end, ec] = std::from_chars(p.data(), p.data() + p.size(), values[i]);
      if (p.empty() || ec != std::errc() || end != p.data() + p.size() ||
          !std::isfinite(values[i])) {
        throw InputError(where,
                         fmt::format("'{}': expected offset_mm[,angle_deg], e.g. 0.01,30", runout));
      }
    }
    if (values[0] < 0.0) throw InputError(where, "the runout offset cannot be negative");
    s.model.runout = {values[0], values[1] * kPi / 180.0};
  }
  return s;
}

void check_spindle(const Move& move, const std::vector<std::string>& sources,
                   const std::string& file, const ForceSettings& settings) {
  if (settings.spindle || move.is_rapid() || move.spindle_speed > 0.0) return;
  throw InputError(SourceLocation{source_file(move, sources, file), move.line},
                   "feed move with no spindle speed (no S word or SPINDL before it): the "
                   "feed per tooth needs one; give --spindle rev/min");
}

double spindle_speed(const Move& move, const ForceSettings& settings) {
  return settings.spindle.value_or(move.spindle_speed);
}

double feed_rate(const Move& move, const ForceSettings& settings) {
  return move.is_rapid() ? 0.0 : settings.feed.value_or(move.feed_rate);
}

}  // namespace cwe

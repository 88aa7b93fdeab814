#include "cwe/job/force_settings.hpp"

#include <fmt/format.h>

#include <charconv>
#include <cmath>

#include "cwe/core/error.hpp"

namespace cwe {

ForceSettings force_settings(const std::string& forces, double spindle, double feed, int flutes,
                             double helix_deg, double step_deg, const std::string& runout) {
  ForceSettings s;
  if (!forces.empty()) s.coefficients = load_cutting_coefficients(forces);
  if (spindle < 0.0 || !std::isfinite(spindle)) {
    throw InputError(SourceLocation{"--spindle"},
                     fmt::format("{} rev/min: expected a positive spindle speed", spindle));
  }
  if (spindle > 0.0) s.spindle = spindle;
  if (feed < 0.0 || !std::isfinite(feed)) {
    throw InputError(SourceLocation{"--feed"},
                     fmt::format("{} mm/min: expected a positive feed rate", feed));
  }
  if (feed > 0.0) s.feed = feed;
  if (flutes < 0) {
    throw InputError(SourceLocation{"--flutes"}, fmt::format("{}: expected at least 1", flutes));
  }
  s.model.flutes = flutes;
  if (helix_deg >= 90.0 || !std::isfinite(helix_deg)) {
    throw InputError(SourceLocation{"--helix"},
                     fmt::format("{}°: expected a helix angle in [0°, 90°)", helix_deg));
  }
  s.model.helix_angle = helix_deg >= 0.0 ? helix_deg * kPi / 180.0 : -1.0;
  if (step_deg < 0.0 || (step_deg > 0.0 && step_deg < 0.01) || step_deg > 90.0 ||
      !std::isfinite(step_deg)) {
    throw InputError(SourceLocation{"--force-step"},
                     fmt::format("{}°: expected a spindle angle step in [0.01°, 90°]", step_deg));
  }
  if (step_deg > 0.0) s.model.angle_step = step_deg * kPi / 180.0;
  if (!runout.empty()) {
    const SourceLocation where{"--runout"};
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

void check_spindle(const Toolpath& path, const std::string& file, const ForceSettings& settings) {
  if (settings.spindle) return;
  for (const Move& move : path.moves) {
    if (move.is_rapid() || move.spindle_speed > 0.0) continue;
    const std::string source =
        move.source >= 0 && static_cast<std::size_t>(move.source) < path.sources.size()
            ? path.sources[static_cast<std::size_t>(move.source)]
            : file;
    throw InputError(SourceLocation{source, move.line},
                     "feed move with no spindle speed (no S word or SPINDL before it): the "
                     "feed per tooth needs one; give --spindle rev/min");
  }
}

double spindle_speed(const Move& move, const ForceSettings& settings) {
  return settings.spindle.value_or(move.spindle_speed);
}

double feed_rate(const Move& move, const ForceSettings& settings) {
  return move.is_rapid() ? 0.0 : settings.feed.value_or(move.feed_rate);
}

}  // namespace cwe

#include "force_outputs.hpp"

#include <fmt/format.h>

#include <charconv>
#include <cmath>

#include "cwe/core/error.hpp"
#include "cwe/core/text_file.hpp"

namespace cwe::app {

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

void ForceExtremes::add(const ClForces& f, std::size_t cl, const std::string& file, int line) {
  if (f.cutting) ++cutting;
  const auto update = [&](Extreme& e, double value) {
    if (value > e.value) e = {value, cl, file, line};
  };
  update(force, f.peak_resultant);
  update(torque, f.peak_torque);
  update(power, f.mean_power);
  update(chip, f.max_chip);
}

const char* const kForcesCsvHeader =
    "cl,move,feed_per_tooth_mm,mean_fx_n,mean_fy_n,mean_fz_n,peak_fx_n,peak_fy_n,peak_fz_n,"
    "peak_resultant_n,mean_torque_nm,peak_torque_nm,mean_power_w,line,operation,feed_mm_min,"
    "spindle_rpm,max_chip_mm,mean_world_fx_n,mean_world_fy_n,mean_world_fz_n,peak_world_fx_n,"
    "peak_world_fy_n,peak_world_fz_n,tool\n";

ReportUnit ReportUnit::of(const std::string& units) {
  if (units != "in") return {};
  return {kMillimetresPerInch, 1, "in"};
}

std::string ReportUnit::header(std::string mm_header) const {
  for (std::size_t at = mm_header.find("mm"); at != std::string::npos;
       at = mm_header.find("mm", at + name.size())) {
    mm_header.replace(at, 2, name);
  }
  return mm_header;
}

std::string forces_csv_row(std::size_t k, const ClPoint& cl, std::size_t operation, int tool,
                           double feed_rate, const ClForces& f, const ReportUnit& unit) {
  const int e = unit.extra_decimals;
  return fmt::format(
      "{},{},{:.{}f},{:.3f},{:.3f},{:.3f},{:.3f},{:.3f},{:.3f},{:.3f},{:.5f},{:.5f},{:.3f},{},{},"
      "{:.{}f},{:.1f},{:.{}f},{:.3f},{:.3f},{:.3f},{:.3f},{:.3f},{:.3f},{}\n",
      k, cl.move + 1, unit.length(f.feed_per_tooth), 6 + e, f.mean_force.x(), f.mean_force.y(),
      f.mean_force.z(), f.peak_force.x(), f.peak_force.y(), f.peak_force.z(), f.peak_resultant,
      f.mean_torque, f.peak_torque, f.mean_power, cl.line, operation, unit.length(feed_rate),
      3 + e, f.spindle_speed, unit.length(f.max_chip), 6 + e, f.mean_force_world.x(),
      f.mean_force_world.y(), f.mean_force_world.z(), f.peak_force_world.x(),
      f.peak_force_world.y(), f.peak_force_world.z(), tool);
}

}  // namespace cwe::app

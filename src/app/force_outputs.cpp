#include "force_outputs.hpp"

#include <fmt/format.h>

#include <charconv>
#include <cmath>

#include "cwe/core/error.hpp"
#include "cwe/core/text_file.hpp"

namespace cwe::app {

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

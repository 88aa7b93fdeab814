#pragma once
// The force outputs of `cwe simulate`: the extremes of a job and the rows of forces.csv.

#include <cstddef>
#include <optional>
#include <string>

#include "cwe/job/force_settings.hpp"
#include "cwe/job/run.hpp"
#include "cwe/process/force_model.hpp"
#include "cwe/toolpath/cl_sampling.hpp"
#include "cwe/toolpath/toolpath.hpp"

namespace cwe::app {

// The unit of the lengths the per-CL files and the terminal report give (--report-units).
struct ReportUnit {
  double mm = 1.0;        // mm per unit
  int extra_decimals = 0; // written with this many more decimals than mm
  std::string name = "mm";
  // "mm" or "" (millimetres) or "in" (inches).
  static ReportUnit of(const std::string& units);
  // `length` mm in this unit; `area` mm² in its square.
  double length(double mm_value) const { return mm_value / mm; }
  double area(double mm2_value) const { return mm2_value / (mm * mm); }
  // A CSV header written for mm with "mm" made this unit's name.
  std::string header(std::string mm_header) const;
};

extern const char* const kForcesCsvHeader;

// One forces.csv row (tool frame; the workpiece-frame means, the chip and the feed after the
// required columns); lengths, feed per tooth, chip and feed rate in `unit`.
std::string forces_csv_row(std::size_t k, const ClPoint& cl, std::size_t operation, int tool,
                           double feed_rate, const ClForces& f, const ReportUnit& unit = {});

}  // namespace cwe::app

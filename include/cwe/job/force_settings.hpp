#pragma once
// The force model's settings of a job (--forces, --spindle, --feed, --flutes, --helix,
// --force-step, --runout), and the spindle speed and feed of a move under them.

#include <optional>
#include <string>

#include "cwe/process/cutting_coefficients.hpp"
#include "cwe/process/force_model.hpp"
#include "cwe/toolpath/toolpath.hpp"

namespace cwe {

struct ForceSettings {
  // The job's (--forces); a tool table's entry may give its tool's own instead.
  std::optional<CuttingCoefficients> coefficients;
  ForceModelOptions model;        // flutes, helix 0/−1 mean: the cutter's
  std::optional<double> spindle;  // rev/min, overriding the program's
  std::optional<double> feed;     // mm/min, overriding the program's (feed moves)
};

// What a job may set of the force model, each absent when not given; numbers already checked
// (prepare_job).
struct ForceOverrides {
  std::optional<double> spindle;  // rev/min
  std::optional<double> feed;     // mm/min
  std::optional<int> flutes;
  std::optional<double> helix_deg;
  std::optional<double> step_deg;  // spindle angle step
  std::string runout;              // offset_mm[,angle_deg]; empty: none
  SourceLocation runout_at{"--runout"};
};

// `forces`: a coefficient JSON file or bundled material (empty: only the tool table's). Throws
// InputError for coefficients that cannot be read or a runout that is not offset[,angle].
ForceSettings force_settings(const std::string& forces, const ForceOverrides& overrides);

// Checks that a feed move turns the spindle (or that an override is given): else InputError at
// its line in its file (`sources` indexed by its `source`; `file` when that names none).
void check_spindle(const Move& move, const std::vector<std::string>& sources,
                   const std::string& file, const ForceSettings& settings);

// Spindle speed (rev/min) of a move, the override first.
double spindle_speed(const Move& move, const ForceSettings& settings);
// Feed rate (mm/min) of a move, the override first (rapids: 0).
double feed_rate(const Move& move, const ForceSettings& settings);

}  // namespace cwe

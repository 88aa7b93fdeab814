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

// `forces`: a coefficient JSON file or bundled material (empty: only the tool table's); the others
// as on the command line (spindle 0, flutes 0, helix < 0, step 0 and an empty runout mean "not
// given"). Throws InputError naming the option.
ForceSettings force_settings(const std::string& forces, double spindle, double feed, int flutes,
                             double helix_deg, double step_deg, const std::string& runout);

// Checks that every feed move of `path` turns the spindle (or that an override is given):
// InputError naming the file and line of the first that does not.
void check_spindle(const Toolpath& path, const std::string& file, const ForceSettings& settings);

// Spindle speed (rev/min) of a move, the override first.
double spindle_speed(const Move& move, const ForceSettings& settings);
// Feed rate (mm/min) of a move, the override first (rapids: 0).
double feed_rate(const Move& move, const ForceSettings& settings);

}  // namespace cwe

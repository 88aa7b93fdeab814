#pragma once
// A picture of the feasible contact surface on the cutter's parameter domain: engagement angle φ
// (0–360°, across) against the profile (arc length from the tip, up), feasible parts shaded by
// patch, the grazing boundary and the patch boundaries drawn (cf. Aras 2008 Fig. 5.10–5.12).

#include <string>

#include "cwe/envelope/tangency.hpp"

namespace cwe {

std::string fcs_svg(const Cutter& cutter, const FeasibleContactSurface& fcs,
                    const std::string& title);

}  // namespace cwe

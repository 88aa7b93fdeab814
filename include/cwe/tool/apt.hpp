#pragma once
// The APT 7-parameter cutter, CUTTER/d, r, e, f, α, β, h, and the named presets built on it.
//
// Conventions (the APT ones; Aras 2008 §5.2 and Fig. 5.3 use the same family with R = e,
// r_c = r, h_c = f, α_t = 90° - α):
//   d  diameter where the (extended) bottom line and side line meet — the "virtual sharp"
//      diameter; for tools with a vertical side it is the cutter diameter;
//   r  corner radius (≥ 0);
//   e  radial distance from the axis to the corner-circle centre (≥ 0);
//   f  height of the corner-circle centre above the tip (≥ 0);
//   α  bottom angle, degrees, measured from the horizontal (0 ≤ α < 90; 0 is a flat bottom);
//   β  side taper, degrees, measured from the axis (-90 < β < 90; > 0 widens upwards);
//   h  height of the cutting part above the tip (> 0).
// The bottom line runs from the tip at angle α and is tangent to the corner circle; the side line
// is tangent to the corner circle at angle β and rises to z = h. With r = 0, (e, f) is the sharp
// corner itself. The seven numbers over-determine the shape, so they must agree:
//   tangency of the bottom line:  -e·sin α + f·cos α = r
//   the diameter:                 d/2 = cos α·(r + e·cos β - f·sin β) / cos(α + β)
// within tol::kInputLength; otherwise the parameter that disagrees is named in an InputError.
//
// Shorter forms, as APT allows: CUTTER/d (flat end mill), CUTTER/d, r (e = d/2 - r, f = r),
// CUTTER/d, r, e, f (α = β = 0), CUTTER/d, r, e, f, α, β (h defaulted). A missing h defaults
// to kDefaultCuttingLengthInDiameters × d (and at least the top of the corner).

#include <optional>
#include <span>
#include <string>

#include "cwe/core/error.hpp"
#include "cwe/tool/profile.hpp"

namespace cwe {

inline constexpr double kDefaultCuttingLengthInDiameters = 3.0;

struct AptCutter {
  double d = 0.0;
  double r = 0.0;
  double e = 0.0;
  double f = 0.0;
  double alpha_deg = 0.0;
  double beta_deg = 0.0;
  double h = 0.0;
};

// Completes 1 to 7 values into the full form (see above). Throws InputError (at `where`) for
// another count or a non-finite value.
AptCutter apt_from_values(std::span<const double> values, const SourceLocation& where = {});

// Checks the parameters and builds the profile: bottom line, corner arc, side line (pieces of
// zero length are left out). Throws InputError naming the parameter and the reason.
Profile apt_profile(const AptCutter& apt, const SourceLocation& where = {});

// Presets, in the user's natural terms, as APT parameter sets. `h` ≤ 0 means the default
// cutting length. Each checks its arguments (InputError at `where`).
//   flat: diameter D.                       APT(D, 0, D/2, 0, 0, 0, h)
//   ball: ball diameter D.                  APT(D, D/2, 0, D/2, 0, 0, h)
//   bull: diameter D, corner radius rc.     APT(D, rc, D/2 - rc, rc, 0, 0, h)
//   taper_flat: tip diameter D, taper β.    APT(D, 0, D/2, 0, 0, β, h)
//   taper_ball: ball diameter D, taper β.   APT(D(1 - sin β)/cos β, D/2, 0, D/2, 0, β, h)
//   chamfer: diameter D, included tip angle θ (e.g. 90 chamfer mill, 118 drill):
//            α = 90 - θ/2,                  APT(D, 0, D/2, (D/2) tan α, α, 0, h)
AptCutter flat_end_mill(double diameter, double h = 0.0, const SourceLocation& where = {});
AptCutter ball_end_mill(double diameter, double h = 0.0, const SourceLocation& where = {});
AptCutter bull_nose_end_mill(double diameter, double corner_radius, double h = 0.0,
                             const SourceLocation& where = {});
AptCutter taper_flat_end_mill(double tip_diameter, double taper_deg, double h = 0.0,
                              const SourceLocation& where = {});
AptCutter taper_ball_end_mill(double ball_diameter, double taper_deg, double h = 0.0,
                              const SourceLocation& where = {});
AptCutter chamfer_mill(double diameter, double tip_angle_deg, double h = 0.0,
                       const SourceLocation& where = {});

// "CUTTER/d, r, e, f, α, β, h" with the numbers written compactly.
std::string to_string(const AptCutter& apt);

}  // namespace cwe

#include "cwe/tool/apt.hpp"

#include <cmath>
#include <vector>

#include <fmt/format.h>

#include "cwe/geometry/tolerance.hpp"
#include "cwe/geometry/vec.hpp"

namespace cwe {
namespace {

[[noreturn]] void fail(const SourceLocation& where, const std::string& message) {
  throw InputError(where, message);
}

void require_positive(double value, const char* name, const char* what,
                      const SourceLocation& where) {
  if (!(value > 0.0))
    fail(where, fmt::format("{} = {}: the {} must be positive", name, value, what));
}

// The default cutting length for a tool of diameter d whose corner ends at height z_corner.
double default_height(double d, double z_corner) {
  return std::max(kDefaultCuttingLengthInDiameters * d, z_corner + d);
}

double resolve_height(double h, double d, double z_corner) {
  return h > 0.0 ? h : default_height(d, z_corner);
}

}  // namespace

AptCutter apt_from_values(std::span<const double> v, const SourceLocation& where) {
  if (v.empty() || v.size() > 7) {
    fail(where,
         fmt::format("CUTTER takes 1 to 7 values (d, r, e, f, alpha, beta, h), got {}", v.size()));
  }
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (!std::isfinite(v[i]))
      fail(where, fmt::format("CUTTER value {} is not a finite number", i + 1));
  }
  AptCutter a;
  a.d = v[0];
  a.r = v.size() >= 2 ? v[1] : 0.0;
  if (v.size() >= 4) {
    a.e = v[2];
    a.f = v[3];
  } else if (v.size() == 3) {
    fail(where, "CUTTER with 3 values is ambiguous: give d, r or d, r, e, f");
  } else {
    a.e = a.d / 2.0 - a.r;
    a.f = a.r;
  }
  if (v.size() == 5) fail(where, "CUTTER with 5 values is ambiguous: alpha needs beta too");
  a.alpha_deg = v.size() >= 6 ? v[4] : 0.0;
  a.beta_deg = v.size() >= 6 ? v[5] : 0.0;
  a.h = v.size() == 7 ? v[6] : 0.0;
  if (a.h <= 0.0) {
    // Defaulted (or written as 0): top of the corner arc plus margin, see default_height.
    const double beta = degrees_to_radians(a.beta_deg);
    a.h = default_height(a.d, a.f - a.r * std::sin(beta));
  }
  return a;
}

Profile apt_profile(const AptCutter& apt, const SourceLocation& where) {
  const std::string form = to_string(apt);
  const auto bad = [&](const std::string& why) { fail(where, form + ": " + why); };
  const double tol = tol::kInputLength;

  if (!(apt.d > 0.0)) bad(fmt::format("d = {}: the diameter must be positive", apt.d));
  // Below a micrometre the profile's tolerances (tol::kInputLength) are no longer small.
  if (apt.d < 1e-3)
    bad(fmt::format("d = {}: below the smallest diameter cwe models, 0.001 mm", apt.d));
  if (!(apt.r >= 0.0)) bad(fmt::format("r = {}: the corner radius cannot be negative", apt.r));
  if (!(apt.e >= -tol))
    bad(fmt::format("e = {}: the corner centre cannot lie left of the axis", apt.e));
  if (!(apt.f >= -tol))
    bad(fmt::format("f = {}: the corner centre cannot lie below the tip", apt.f));
  if (!(apt.alpha_deg >= 0.0 && apt.alpha_deg < 90.0)) {
    bad(fmt::format("alpha = {}°: the bottom angle must be in [0°, 90°)", apt.alpha_deg));
  }
  if (!(apt.beta_deg > -90.0 && apt.beta_deg < 90.0)) {
    bad(fmt::format("beta = {}°: the side taper must be in (-90°, 90°)", apt.beta_deg));
  }
  if (!(apt.alpha_deg + apt.beta_deg < 90.0)) {
    bad(fmt::format("alpha + beta = {}°: the bottom and side lines must meet below 90°",
                    apt.alpha_deg + apt.beta_deg));
  }
  if (!(apt.h > 0.0)) bad(fmt::format("h = {}: the height must be positive", apt.h));

  const double alpha = degrees_to_radians(apt.alpha_deg);
  const double beta = degrees_to_radians(apt.beta_deg);
  const double ca = std::cos(alpha), sa = std::sin(alpha);
  const double cb = std::cos(beta), sb = std::sin(beta);
  const Vec2 c(std::max(apt.e, 0.0), std::max(apt.f, 0.0));

  // The bottom line through the tip at angle α is tangent to the corner circle.
  const double tangency = -c.x() * sa + c.y() * ca;
  if (std::abs(tangency - apt.r) > tol) {
    const double f_expected = (apt.r + c.x() * sa) / ca;
    bad(fmt::format(
        "f = {} does not fit r, e and alpha: the bottom line from the tip at {}° touches the "
        "corner circle only for f = {} (-e sin(alpha) + f cos(alpha) = r)",
        apt.f, apt.alpha_deg, f_expected));
  }
  // d is the diameter where the extended bottom and side lines meet.
  const double d_expected = 2.0 * ca * (apt.r + c.x() * cb - c.y() * sb) / std::cos(alpha + beta);
  if (std::abs(d_expected - apt.d) > tol) {
    bad(
        fmt::format("d = {} does not fit the other parameters: the bottom and side lines meet "
                    "at diameter {}",
                    apt.d, d_expected));
  }

  // Tangent points: bottom line B, side line S (Aras 2008 Fig. 5.3: the corner torus runs from
  // φ_p = π/2 - α_t to π/2 - β, here measured as the arc angle α - 90° to -β).
  Vec2 b = c + apt.r * Vec2(sa, -ca);
  const Vec2 s = c + apt.r * Vec2(cb, -sb);
  if (b.x() < -tol) bad("the corner circle reaches past the axis below its bottom tangent point");
  b.x() = std::max(0.0, b.x());
  if (apt.h < s.y() - tol) {
    bad(
        fmt::format("h = {} is below the top of the corner (z = {}): the cutter would end "
                    "inside its corner",
                    apt.h, s.y()));
  }
  const double top_radius = s.x() + std::max(0.0, apt.h - s.y()) * sb / cb;
  if (top_radius <= tol) {
    bad(
        fmt::format("the side tapers onto the axis below h = {}: beta = {}° is too negative for "
                    "this height",
                    apt.h, apt.beta_deg));
  }
  const Vec2 top(top_radius, std::max(apt.h, s.y()));

  std::vector<ProfileSegment> pieces;
  if (b.norm() > tol) pieces.push_back(ProfileSegment::line(Vec2::Zero(), b));
  if (apt.r > 0.0 && (s - b).norm() > tol) {
    pieces.push_back(ProfileSegment::arc(pieces.empty() ? Vec2::Zero() : b, s, c, true));
  }
  const Vec2 side_start = pieces.empty() ? Vec2::Zero() : pieces.back().end;
  if ((top - side_start).norm() > tol) pieces.push_back(ProfileSegment::line(side_start, top));
  return Profile(std::move(pieces), where.source.empty() ? form : where.source);
}

AptCutter flat_end_mill(double diameter, double h, const SourceLocation& where) {
  require_positive(diameter, "D", "diameter", where);
  return {diameter, 0.0, diameter / 2.0, 0.0, 0.0, 0.0, resolve_height(h, diameter, 0.0)};
}

AptCutter ball_end_mill(double diameter, double h, const SourceLocation& where) {
  require_positive(diameter, "D", "diameter", where);
  const double r = diameter / 2.0;
  return {diameter, r, 0.0, r, 0.0, 0.0, resolve_height(h, diameter, r)};
}

AptCutter bull_nose_end_mill(double diameter, double corner_radius, double h,
                             const SourceLocation& where) {
  require_positive(diameter, "D", "diameter", where);
  if (!(corner_radius >= 0.0 && corner_radius <= diameter / 2.0)) {
    fail(where, fmt::format("r = {}: the corner radius must be in [0, D/2] = [0, {}]",
                            corner_radius, diameter / 2.0));
  }
  return {diameter,
          corner_radius,
          diameter / 2.0 - corner_radius,
          corner_radius,
          0.0,
          0.0,
          resolve_height(h, diameter, corner_radius)};
}

AptCutter taper_flat_end_mill(double tip_diameter, double taper_deg, double h,
                              const SourceLocation& where) {
  require_positive(tip_diameter, "D", "tip diameter", where);
  if (!(taper_deg > -90.0 && taper_deg < 90.0)) {
    fail(where, fmt::format("beta = {}°: the taper must be in (-90°, 90°)", taper_deg));
  }
  return {tip_diameter,
          0.0,
          tip_diameter / 2.0,
          0.0,
          0.0,
          taper_deg,
          resolve_height(h, tip_diameter, 0.0)};
}

AptCutter taper_ball_end_mill(double ball_diameter, double taper_deg, double h,
                              const SourceLocation& where) {
  require_positive(ball_diameter, "D", "ball diameter", where);
  if (!(taper_deg > -90.0 && taper_deg < 90.0)) {
    fail(where, fmt::format("beta = {}°: the taper must be in (-90°, 90°)", taper_deg));
  }
  const double r = ball_diameter / 2.0;
  const double beta = degrees_to_radians(taper_deg);
  const double d = ball_diameter * (1.0 - std::sin(beta)) / std::cos(beta);
  return {d, r, 0.0, r, 0.0, taper_deg, resolve_height(h, ball_diameter, r - r * std::sin(beta))};
}

AptCutter chamfer_mill(double diameter, double tip_angle_deg, double h,
                       const SourceLocation& where) {
  require_positive(diameter, "D", "diameter", where);
  if (!(tip_angle_deg > 0.0 && tip_angle_deg <= 180.0)) {
    fail(where, fmt::format("tip angle = {}°: the included tip angle must be in (0°, 180°]",
                            tip_angle_deg));
  }
  const double alpha_deg = 90.0 - tip_angle_deg / 2.0;
  const double f = diameter / 2.0 * std::tan(degrees_to_radians(alpha_deg));
  return {diameter, 0.0, diameter / 2.0, f, alpha_deg, 0.0, resolve_height(h, diameter, f)};
}

std::string to_string(const AptCutter& a) {
  return fmt::format("CUTTER/{:g},{:g},{:g},{:g},{:g},{:g},{:g}", a.d, a.r, a.e, a.f, a.alpha_deg,
                     a.beta_deg, a.h);
}

}  // namespace cwe

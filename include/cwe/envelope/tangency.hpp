#pragma once
// The tangency function of a moving cutter, its grazing points and its feasible contact surface.
//
// At an instant, a cutter surface point P with outward normal N moves with V(P); the tangency
// function f = N·V (Aras 2008 eq. 5.18) splits the surface into the forward set f > 0 (moving
// into material), the grazing set f = 0 (the characteristic curve that the swept envelope is
// made of) and the backward set f < 0. The feasible contact surface (FCS) is f ≥ 0.
//
// For a surface of revolution, at profile point (ρ, z) with outward profile normal (n_ρ, n_z)
// and engagement angle φ (docs/architecture.md), in TCS components (the seed thesis, Aras 2008, eq.
// 3.58, 5.25, 5.33, 5.39 in one form):
//     f(φ) = a sin φ + b cos φ + c,
//     a = n_ρ V_x - k ω_y,  b = n_ρ V_y + k ω_x,  c = n_z V_z,  k = ρ n_z - z n_ρ,
// so the grazing angles of each profile point come in closed form (solve_sin_cos).

#include <cmath>
#include <vector>

#include "cwe/geometry/interval.hpp"
#include "cwe/kinematics/tool_state.hpp"
#include "cwe/tool/cutter.hpp"

namespace cwe {

struct TangencyCoefficients {
  double a = 0.0;
  double b = 0.0;
  double c = 0.0;
  double operator()(double phi) const { return a * std::sin(phi) + b * std::cos(phi) + c; }
  friend bool operator==(const TangencyCoefficients&, const TangencyCoefficients&) = default;
};

// Coefficients at profile point `rho_z` with outward unit profile normal `normal`, for TCS
// velocities v (tip) and w (angular).
TangencyCoefficients tangency_coefficients(const Vec2& rho_z, const Vec2& normal, const Vec3& v,
                                           const Vec3& w);

// Coefficients at fraction u of a patch, for a tool state.
TangencyCoefficients tangency_coefficients(const Cutter& cutter, int patch, double u,
                                           const ToolState& state);

// f = N·V evaluated directly from the surface point and the velocity field (the definition, for
// checks): same units as the velocities.
double tangency(const Cutter& cutter, int patch, double phi, double u, const ToolState& state);

struct GrazingPoint {
  int patch = 0;
  double u = 0.0;             // fraction along the patch's profile piece
  double phi = 0.0;           // engagement angle, rad in [0, 2π)
  Vec3 point = Vec3::Zero();  // world coordinates
};

struct EnvelopeOptions {
  int samples_per_patch = 64;  // profile samples per patch (u = 0 … 1 inclusive)
};

// Grazing points of every patch at profile samples u = k/(n-1): the characteristic curves.
// A cross-section with a² + b² < c² has none (Aras 2008 Fig. 3.12); one where f vanishes
// identically (the flat bottom of a horizontal translation) is reported as grazing everywhere
// through `identically_grazing` and contributes no points.
struct GrazingCurves {
  std::vector<GrazingPoint> points;
  std::vector<int> identically_grazing;  // patches with f ≡ 0
};
GrazingCurves grazing_points(const Cutter& cutter, const ToolState& state,
                             const EnvelopeOptions& options = {});

// The feasible contact surface on the cutter's (φ, profile) domain: for each profile sample of
// each patch, the φ intervals (within [0, 2π], sorted, disjoint) where f ≥ 0.
struct FcsSection {
  int patch = 0;
  double u = 0.0;
  std::vector<Interval> phi;
};

struct FeasibleContactSurface {
  std::vector<FcsSection> sections;
  // Per patch: does the FCS reach the front face (φ ∈ (0, π), moving into material ahead of
  // the y-z plane) or the back face (φ ∈ (π, 2π))? Points with f > 0 strictly.
  std::vector<bool> front;
  std::vector<bool> back;
};

FeasibleContactSurface feasible_contact_surface(const Cutter& cutter, const ToolState& state,
                                                const EnvelopeOptions& options = {});

}  // namespace cwe

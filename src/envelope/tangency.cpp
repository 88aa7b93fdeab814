#include "cwe/envelope/tangency.hpp"

#include <algorithm>
#include <cmath>

#include "cwe/core/assert.hpp"
#include "cwe/geometry/roots.hpp"
#include "cwe/geometry/tolerance.hpp"

namespace cwe {
namespace {

// The patch's piece, its point and normal at u.
struct ProfileSample {
  Vec2 point;
  Vec2 normal;
};

ProfileSample sample(const Cutter& cutter, int patch, double u) {
  const auto& segment = cutter.profile().segments()[static_cast<std::size_t>(
      cutter.patches()[static_cast<std::size_t>(patch)].segment)];
  return {segment.point_at(u), segment.normal_at(u)};
}

double u_of(int k, int samples) {
  return samples > 1 ? static_cast<double>(k) / (samples - 1) : 0.5;
}

// Scale of f: |n|·|V(P)| bounded by |V_F| + |ω|·|P - F|.
double tangency_scale(const ToolState& state, const Vec2& rho_z) {
  return state.tip_velocity.norm() + state.angular_velocity.norm() * rho_z.norm();
}

}  // namespace

TangencyCoefficients tangency_coefficients(const Vec2& rho_z, const Vec2& normal, const Vec3& v,
                                           const Vec3& w) {
  const double k = rho_z.x() * normal.y() - rho_z.y() * normal.x();
  return {normal.x() * v.x() - k * w.y(), normal.x() * v.y() + k * w.x(), normal.y() * v.z()};
}

TangencyCoefficients tangency_coefficients(const Cutter& cutter, int patch, double u,
                                           const ToolState& state) {
  const ProfileSample s = sample(cutter, patch, u);
  return tangency_coefficients(s.point, s.normal, state.tip_velocity_tcs(),
                               state.angular_velocity_tcs());
}

double tangency(const Cutter& cutter, int patch, double phi, double u, const ToolState& state) {
  const Vec3 p = state.tcs.to_world(cutter.point(patch, phi, u));
  const Vec3 n = state.tcs.direction_to_world(cutter.normal(patch, phi, u));
  return n.dot(state.point_velocity(p));
}

GrazingCurves grazing_points(const Cutter& cutter, const ToolState& state,
                             const EnvelopeOptions& options) {
  CWE_ASSERT(options.samples_per_patch >= 1, "at least one profile sample per patch");
  GrazingCurves curves;
  const Vec3 v = state.tip_velocity_tcs();
  const Vec3 w = state.angular_velocity_tcs();
  for (int patch = 0; patch < static_cast<int>(cutter.patches().size()); ++patch) {
    bool identically_zero = true;
    for (int k = 0; k < options.samples_per_patch; ++k) {
      const double u = u_of(k, options.samples_per_patch);
      const ProfileSample s = sample(cutter, patch, u);
      const TangencyCoefficients t = tangency_coefficients(s.point, s.normal, v, w);
      // Coefficients below rounding of the velocity scale are zero (f ≡ 0 on this section).
      const double zero = tol::kRelative * tangency_scale(state, s.point);
      const Roots roots =
          solve_sin_cos(std::abs(t.a) <= zero ? 0.0 : t.a, std::abs(t.b) <= zero ? 0.0 : t.b,
                        std::abs(t.c) <= zero ? 0.0 : t.c);
      if (roots.identically_zero) continue;
      identically_zero = false;
      for (const double phi : roots) {
        curves.points.push_back({patch, u, phi, state.tcs.to_world(cutter.point(patch, phi, u))});
      }
    }
    if (identically_zero) curves.identically_grazing.push_back(patch);
  }
  return curves;
}

FeasibleContactSurface feasible_contact_surface(const Cutter& cutter, const ToolState& state,
                                                const EnvelopeOptions& options) {
  CWE_ASSERT(options.samples_per_patch >= 1, "at least one profile sample per patch");
  FeasibleContactSurface fcs;
  const std::size_t patches = cutter.patches().size();
  fcs.front.assign(patches, false);
  fcs.back.assign(patches, false);
  const Vec3 v = state.tip_velocity_tcs();
  const Vec3 w = state.angular_velocity_tcs();
  for (int patch = 0; patch < static_cast<int>(patches); ++patch) {
    for (int k = 0; k < options.samples_per_patch; ++k) {
      const double u = u_of(k, options.samples_per_patch);
      const ProfileSample s = sample(cutter, patch, u);
      const TangencyCoefficients t = tangency_coefficients(s.point, s.normal, v, w);
      const double zero = tol::kRelative * tangency_scale(state, s.point);
      FcsSection section{patch, u, {}};
      const double amplitude = std::hypot(t.a, t.b);
      if (amplitude <= zero) {
        // f is the constant c on this section: all of it, or none (f ≡ 0 grazes: kept, f ≥ 0).
        if (t.c >= -zero) section.phi.push_back({0.0, kTwoPi});
      } else {
        // f = A sin(φ + δ) + c ≥ 0 between consecutive roots where the midpoint is positive.
        const Roots roots = solve_sin_cos(t.a, t.b, t.c);
        std::vector<double> cuts{0.0};
        for (const double r : roots) cuts.push_back(r);
        cuts.push_back(kTwoPi);
        std::vector<Interval> pieces;
        for (std::size_t i = 0; i + 1 < cuts.size(); ++i) {
          const double mid = 0.5 * (cuts[i] + cuts[i + 1]);
          if (t(mid) >= 0.0) pieces.push_back({cuts[i], cuts[i + 1]});
        }
        // A tangent root (f touches zero from below) is a single feasible angle.
        for (int i = 0; i < roots.size(); ++i) {
          if (roots.tangent[static_cast<std::size_t>(i)] && t.c < 0.0)
            pieces.push_back(Interval::point(roots[i]));
        }
        section.phi = normalize(std::move(pieces));
      }
      // Front and back presence: f strictly positive somewhere in (0, π) or (π, 2π). Inside a
      // feasible interval f > 0 except at its roots, so the middle of its part on a face decides.
      for (const Interval& i : section.phi) {
        if (i.length() <= tol::kAngle) continue;
        if (i.lo < kPi - tol::kAngle && i.hi > tol::kAngle) {
          const double phi = 0.5 * (std::max(i.lo, 0.0) + std::min(i.hi, kPi));
          if (t(phi) > zero) fcs.front[static_cast<std::size_t>(patch)] = true;
        }
        if (i.hi > kPi + tol::kAngle && i.lo < kTwoPi - tol::kAngle) {
          const double phi = 0.5 * (std::max(i.lo, kPi) + std::min(i.hi, kTwoPi));
          if (t(phi) > zero) fcs.back[static_cast<std::size_t>(patch)] = true;
        }
      }
      fcs.sections.push_back(std::move(section));
    }
  }
  return fcs;
}

}  // namespace cwe

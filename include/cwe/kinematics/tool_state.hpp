#pragma once
// The instantaneous motion of the cutter: its tool coordinate system (TCS) and velocities.
//
// TCS (docs/architecture.md): origin at the tip F, z the tool axis (tip to shank), x the component
// of the tip velocity perpendicular to z, y = z × x. For a pure axial motion (plunge or retract) or
// a
// tip at rest there is no such component: x is then the caller's `previous_x` projected
// perpendicular to z when that is possible, else world X, else world Y (a stable, documented
// fallback, never NaN).
//
// Velocity of any cutter point P (Aras 2008 eq. 5.10, 5.13): V(P) = V_F + ω × (P - F), with
// ṅ = ω × n. The velocities may be true rates (mm/s, rad/s) or rates per unit of any parameter:
// the envelope only needs their directions and ratios.
//
// Feed angle ψ (Aras 2008 eq. 5.42): the angle between V_F and z, in [0, π]. Motion classes
// (§5.4, Table 5.1): ascending ψ < π/2, horizontal ψ = π/2, descending ψ > π/2, with the pure
// axial cases (retract ψ = 0, plunge ψ = π) and a resting tip named separately.

#include "cwe/geometry/vec.hpp"
#include "cwe/toolpath/cl_sampling.hpp"
#include "cwe/toolpath/move.hpp"

namespace cwe {

enum class MotionClass { kAscending, kHorizontal, kDescending, kPlunge, kRetract, kResting };

const char* to_string(MotionClass motion);

struct ToolState {
  Frame tcs;                             // origin at the tip, axes x, y, z as above
  Vec3 tip_velocity = Vec3::Zero();      // V_F, world frame
  Vec3 angular_velocity = Vec3::Zero();  // ω, world frame
  double feed_angle = kPi / 2.0;         // ψ, rad; π/2 when the tip rests
  MotionClass motion = MotionClass::kResting;

  Vec3 tip_velocity_tcs() const { return tcs.direction_to_local(tip_velocity); }
  Vec3 angular_velocity_tcs() const { return tcs.direction_to_local(angular_velocity); }
  // V(P) for a point P given in world coordinates.
  Vec3 point_velocity(const Vec3& world_point) const {
    return tip_velocity + angular_velocity.cross(world_point - tcs.origin);
  }
};

// The state of a tool at `tip` with unit `axis`, moving with the given velocities.
ToolState tool_state(const Vec3& tip, const Vec3& axis, const Vec3& tip_velocity,
                     const Vec3& angular_velocity, const Vec3& previous_x = Vec3::Zero());

// At parameter u of a move, with rates per unit u (tangent and axis rate).
ToolState tool_state(const Move& move, double u, const Vec3& previous_x = Vec3::Zero());

// At a sampled cutter location, with its velocities.
ToolState tool_state(const ClPoint& point, const Vec3& previous_x = Vec3::Zero());

}  // namespace cwe

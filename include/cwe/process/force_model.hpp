#pragma once
// Mechanistic milling forces from an engagement map (docs/forces.md; Altintas, Manufacturing
// Automation, ch. 2; Engin & Altintas 2001 for general cutters).
//
// The cutter is cut into edge elements: one per engaged axial disc of the map (side) and per
// engaged ring (flat bottom), for each of the N flutes. Flute j at spindle angle θ sits at the
// engagement angle
//     φ_j(z) = θ + 2πj/N − ψ(z),   ψ(z) = z·tan β / R        (helix lag, constant lead)
// with β the helix angle and R the cutter's largest radius (exact for a cylinder; for other
// profiles the flute keeps the cylinder's lead, as ground end mills do). An element cuts when
// φ_j lies in its disc's engaged intervals and its chip is thicker than zero. Chip thickness is
// the feed per tooth c along the element's outward normal n:
//     h = c·(f̂·n),   n = sin κ·e_r(φ) − cos κ·z
// with f̂ the unit feed direction in the tool frame and κ the axial immersion angle of the
// profile (π/2 on a cylinder, 0 on a flat bottom). For a feed perpendicular to the axis this is
// the classical h = c·sin φ·sin κ; a plunge loads the bottom with h = c. Radial runout (offset
// e at angle λ from flute 0) shortens or lengthens each flute's radius by e·cos(λ − 2πj/N + ψ)
// (the flute at height z sits ψ(z) behind its tip) and the chip follows the tooth that cut last
// (h_j = min over m of m·c·g + (r_j − r_{j−m})·sin κ).
//
// Element forces, with chip width db the length of the element along the profile and the edge
// length dS taken equal to it:
//     dF_t = K_tc h db + K_te dS,  dF_r = K_rc h db + K_re dS,  dF_a = K_ac h db + K_ae dS.
// (dS leaves out the helix, as the mean-force calibration that published coefficient sets come
// from does: on a cylinder dS = dz, so the mean forces are those of the closed forms whatever the
// helix angle. Counting the helix would scale the edge terms by 1/cos β.) They
// act on the tool as  −dF_t·e_t − dF_r·n − dF_a·a  with e_t the edge velocity direction and
// a = cos κ·e_r + sin κ·z the profile tangent (tip to shank). In the tool frame (x along the
// feed, y = z × x, z the axis) that is Engin & Altintas's
//     dF_x = −dF_t cos φ − (dF_r sin κ + dF_a cos κ) sin φ
//     dF_y = +dF_t sin φ − (dF_r sin κ + dF_a cos κ) cos φ
//     dF_z = +dF_r cos κ − dF_a sin κ
// so a positive K_ac pulls a cylinder's flutes towards −z. Torque about the axis is Σ ρ·dF_t,
// power is torque × spindle speed.
//
// Integration over the spindle angle: one revolution in n = round(360°/step) samples; sample k
// is the mean force over θ ∈ [kΔ − Δ/2, kΔ + Δ/2] (Δ = 2π/n): each element contributes the part
// of that step it spends inside its engaged intervals, evaluated at the middle of that part.
// Means over the revolution are therefore the exact integrals up to a midpoint-rule error of
// order Δ²/24 (4·10⁻⁵ relative at 1°), whatever the step; peaks are of the step-averaged force.
// The whole steps of an element are summed in closed form (harmonics up to 2φ); see docs/forces.md.

#include <vector>

#include "cwe/engagement/engagement_map.hpp"
#include "cwe/geometry/vec.hpp"
#include "cwe/kinematics/tool_state.hpp"
#include "cwe/process/cutting_coefficients.hpp"
#include "cwe/tool/cutter.hpp"

namespace cwe {

struct Runout {
  double offset = 0.0;  // radial offset of the cutter axis from the spindle axis, mm
  double angle = 0.0;   // direction of the offset from flute 0, radians
};

// The finest spindle angle step (0.01°: 36,000 samples a revolution).
inline constexpr double kMinAngleStep = kPi / 18000.0;

struct ForceModelOptions {
  double angle_step = kPi / 180.0;  // spindle angle step, radians (rounded to divide 2π)
  int flutes = 0;                   // 0: the cutter's
  double helix_angle = -1.0;        // radians; < 0: the cutter's
  Runout runout;
};

// The force on the tool over one revolution, sample k at spindle angle k·Δ.
struct ForceSample {
  double angle = 0.0;         // spindle angle θ, radians
  Vec3 force = Vec3::Zero();  // tool frame, N
  double torque = 0.0;        // N·m
};

struct ClForces {
  double feed_per_tooth = 0.0;           // mm
  double spindle_speed = 0.0;            // rev/min
  bool cutting = false;                  // some element cut a chip
  Vec3 mean_force = Vec3::Zero();        // tool frame, N
  Vec3 peak_force = Vec3::Zero();        // largest |F_x|, |F_y|, |F_z| over the revolution, N
  Vec3 mean_force_world = Vec3::Zero();  // workpiece frame, N
  Vec3 peak_force_world = Vec3::Zero();  // largest |F_X|, |F_Y|, |F_Z| in the workpiece frame, N
  double peak_resultant = 0.0;           // largest |F|, N
  double mean_torque = 0.0;              // N·m
  double peak_torque = 0.0;              // N·m
  double mean_power = 0.0;               // W
  // Thickest chip of any flute element over its engaged arcs and its stretch of profile, mm.
  double max_chip = 0.0;
  std::vector<ForceSample> curve;  // the revolution, when asked for
};

class ForceModel {
 public:
  // Throws cwe::InputError for a step outside [0.01°, 90°], fewer than one flute, a helix angle of
  // 90° or more, or a negative runout offset.
  ForceModel(const Cutter& cutter, CuttingCoefficients coefficients,
             ForceModelOptions options = {});

  const CuttingCoefficients& coefficients() const { return coefficients_; }
  int flutes() const { return flutes_; }
  double helix_angle() const { return helix_; }
  int samples() const { return samples_; }  // spindle-angle samples per revolution

  // The forces at one cutter location: `state` gives the tool frame and the feed direction
  // (tip velocity; a tip at rest cuts nothing), `feed_per_tooth` in mm, `spindle_speed` in
  // rev/min (power only).
  ClForces evaluate(const EngagementMap& map, const ToolState& state, double feed_per_tooth,
                    double spindle_speed, bool keep_curve = false) const;

  // The same with the feed direction given in the tool frame (unit) and no world frame (the
  // world-frame figures are those of the tool frame).
  ClForces evaluate(const EngagementMap& map, const Vec3& feed_direction_tcs, double feed_per_tooth,
                    double spindle_speed, bool keep_curve = false) const;

 private:
  ClForces evaluate(const EngagementMap& map, const Vec3& feed_direction_tcs, double feed_per_tooth,
                    double spindle_speed, bool keep_curve, const Frame* world) const;

  Profile profile_;  // the cutter's
  CuttingCoefficients coefficients_;
  int flutes_ = 2;
  double helix_ = 0.0;
  double lead_ = 0.0;  // tan β / R, rad per mm
  Runout runout_;
  int samples_ = 360;
  double step_ = 0.0;
  std::vector<double> sin_, cos_;  // of k·Δ
};

// Feed per tooth, mm: feed rate (mm/min) / (flutes × spindle speed (rev/min)); 0 when the spindle
// is stopped.
double feed_per_tooth(double feed_rate, int flutes, double spindle_speed);

}  // namespace cwe

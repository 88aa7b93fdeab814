#pragma once
// Engagement maps from the tri-dexel workpiece (docs/engagement.md).
//
// Method: surface sampling against the rays. The cutter surface is gridded in φ (cells of
// `phi_step`) × axial discs (side) or rings (flat bottom) of `disc_height`. A cell centre P with
// outward normal N is engaged when f = N·V > f_min (moving into material; grazing excluded) and
// TriDexel::material_outside(P, N, gap) holds: the ray most nearly along N, passing within s/√2
// of P, has material just beyond the point Q where it meets the surface (a surface point near P,
// read exactly: the workpiece was just cut by this very surface). Runs of engaged cells become φ
// intervals whose ends are refined by bisection on the same test, so an angle is located to the
// ray grid's resolution (the Q of a test lies within s/√2 of P), not to the cell size.
//
// Accuracy: boundaries of the engaged region are placed within about s/√2 on the cutter surface
// (an angle error of about s/(√2 ρ) at radius ρ, a depth error within s); regions thinner than
// `gap` beyond the surface count as engaged (near a grazing line that is a band of width about
// √(2·gap/ρ) in φ).
//
// Cost: per cutter location, the discs and rings whose ring meets the workpiece's domain are
// scanned; f is evaluated for every cell of those, the workpiece only where f > 0.

#include "cwe/engagement/engagement_map.hpp"
#include "cwe/kinematics/tool_state.hpp"
#include "cwe/tool/cutter.hpp"
#include "cwe/workpiece/dexel/tri_dexel.hpp"

namespace cwe {

struct EngagementOptions {
  double disc_height = 0.0;  // mm; 0: the workpiece's ray spacing s
  double phi_step = 0.0;     // rad; 0: an arc of s at the cutter's largest radius, ≤ 1°
};

class DexelEngagement {
 public:
  // The grid for `cutter` on a workpiece of ray spacing `spacing`. Throws InputError for a
  // non-positive spacing or option.
  DexelEngagement(const Cutter& cutter, double spacing, const EngagementOptions& options = {});

  // The engagement of the cutter in `state` (tool frame and velocities) with `stock`.
  EngagementMap at(const TriDexel& stock, const ToolState& state) const;

  double disc_height() const { return disc_height_; }
  double phi_step() const { return 2.0 * kPi / phi_cells_; }
  int phi_cells() const { return phi_cells_; }

 private:
  // A line of cells round the cutter: a side disc or a bottom ring.
  struct Band {
    double lo = 0.0, hi = 0.0;   // heights (disc) or radii (ring) it spans
    double rho = 0.0, z = 0.0;   // the sampled circle: radius and height above the tip
    Vec2 normal = Vec2::Zero();  // outward profile normal (n_ρ, n_z) there
    int patch = 0;
    double area_per_radian = 0.0;  // surface area of the band per radian of φ, mm²
    double gap = 0.0;              // material_outside gap, mm
    bool ring = false;             // a ring of the flat bottom (else a side disc)
  };
  // Engaged φ intervals of one band.
  std::vector<Interval> scan(const TriDexel& stock, const ToolState& state, const Band& band,
                             const Vec3& v_tcs, const Vec3& w_tcs) const;

  const Cutter* cutter_;
  double spacing_;
  double disc_height_;
  int phi_cells_;
  std::vector<double> sin_, cos_;  // of the cell centres
  std::vector<Band> discs_, rings_;
};

}  // namespace cwe

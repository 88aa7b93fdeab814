#pragma once
// The grid an engagement extractor fills, whatever the workpiece (docs/engagement.md): the
// cutter's side cut into axial discs and its flat bottom into rings (bands), each a circle of
// φ cells; the engaged φ intervals of a band from a per-cell test (runs of engaged cells, each
// end refined by bisection on the same test); and the EngagementMap with its summaries made from
// the intervals of every band. The tri-dexel extractor (DexelEngagement) and the mesh one
// (MeshWorkpiece) differ only in the test.

#include <cmath>
#include <vector>

#include "cwe/engagement/engagement_map.hpp"
#include "cwe/envelope/tangency.hpp"
#include "cwe/geometry/aabb.hpp"
#include "cwe/geometry/vec.hpp"
#include "cwe/tool/cutter.hpp"

namespace cwe {

// ∫ ρ ds of the profile between heights z0 and z1: the area of the revolved band per radian of
// φ, mm² (16 chords; the discs' and the maps' area).
double side_area_per_radian(const Profile& profile, double z0, double z1);

class EngagementGrid {
 public:
  // A line of cells round the cutter: a side disc or a bottom ring.
  struct Band {
    double lo = 0.0, hi = 0.0;   // heights (disc) or radii (ring) it spans
    double rho = 0.0, z = 0.0;   // the sampled circle: radius and height above the tip
    Vec2 normal = Vec2::Zero();  // outward profile normal (n_ρ, n_z) there
    int patch = 0;
    double area_per_radian = 0.0;  // surface area of the band per radian of φ, mm²
    // How far the surface falls inside its tangent plane within s√(3/2) of the circle, mm.
    double departure = 0.0;
    bool ring = false;  // a ring of the flat bottom (else a side disc)
  };

  // The grid for `cutter` read at `spacing` s (mm): the disc height and φ step default to it
  // (cells of an arc of s at the largest radius, ≤ 1°), and the circles are sampled s/√2 away
  // from the flutes' ends and the bottom's rim, so that a test reading the workpiece within s/√2
  // of a cell reads this surface and not beyond its rim. Throws InputError for a non-positive
  // spacing or option.
  EngagementGrid(const Cutter& cutter, double spacing, const EngagementOptions& options);

  const Cutter& cutter() const { return *cutter_; }
  double disc_height() const { return disc_height_; }
  double phi_step() const { return 2.0 * kPi / static_cast<double>(sin_.size()); }
  int phi_cells() const { return static_cast<int>(sin_.size()); }
  const std::vector<Band>& discs() const { return discs_; }
  const std::vector<Band>& rings() const { return rings_; }
  // Band k of discs() followed by rings().
  std::size_t bands() const { return discs_.size() + rings_.size(); }
  const Band& band(std::size_t k) const {
    return k < discs_.size() ? discs_[k] : rings_[k - discs_.size()];
  }

  // The box of a band's circle with the tool frame `tcs`, grown by `margin` on every side.
  static Aabb circle_bounds(const Band& band, const Frame& tcs, double margin = 0.0);

  // Where a band's cells move into the material: f(φ) = a sin φ + b cos φ + c = N·V above
  // f_min, which absorbs the rounding of the coefficients (grazing points, f = 0, are not
  // engaged). `moves` is false where f vanishes on the whole circle (the flat bottom of a
  // horizontal move).
  struct Front {
    TangencyCoefficients f;
    double f_min = 0.0;
    bool moves = false;
    bool operator()(double s, double c) const { return f.a * s + f.b * c + f.c > f_min; }
    friend bool operator==(const Front&, const Front&) = default;
  };
  // The front of `band` for tip velocity `v_tcs` and angular velocity `w_tcs` (tool frame).
  static Front front(const Band& band, const Vec3& v_tcs, const Vec3& w_tcs);

  // The engaged intervals of a band: `front(s, c)` is the cheap test that the cell at
  // (sin φ, cos φ) moves into the material (f > 0), `engaged(s, c)` the whole test (front
  // included). Every cell centre is tested (front first); each run of engaged cells becomes an
  // interval whose ends are placed by bisection on `engaged` to a 64th of a cell.
  template <class FrontTest, class EngagedTest>
  std::vector<Interval> intervals(const FrontTest& front, const EngagedTest& engaged) const;

  // The map from the intervals found on each band (indexed as band()), with its summaries.
  EngagementMap map(std::vector<std::vector<Interval>> found) const;

 private:
  static constexpr int kRefineSteps = 6;  // bisection steps: the cell width / 2⁶

  const Cutter* cutter_;
  double disc_height_;
  std::vector<double> sin_, cos_;  // of the cell centres
  std::vector<Band> discs_, rings_;
};

template <class FrontTest, class EngagedTest>
std::vector<Interval> EngagementGrid::intervals(const FrontTest& front,
                                                const EngagedTest& engaged) const {
  const auto engaged_at = [&](double phi) { return engaged(std::sin(phi), std::cos(phi)); };
  // The boundary between an engaged angle and one that is not.
  const auto refine = [&](double in, double out) {
    for (int k = 0; k < kRefineSteps; ++k) {
      const double mid = 0.5 * (in + out);
      (engaged_at(mid) ? in : out) = mid;
    }
    return 0.5 * (in + out);
  };
  const int n = phi_cells();
  const double cell = 2.0 * kPi / n;
  const auto centre_of = [cell](int k) { return (k + 0.5) * cell; };
  std::vector<Interval> found;
  int run_start = -1;
  for (int k = 0; k <= n; ++k) {
    // The front-half test first, without a call: it rejects half the cells.
    const double s = k < n ? sin_[static_cast<std::size_t>(k)] : 0.0;
    const double c = k < n ? cos_[static_cast<std::size_t>(k)] : 0.0;
    const bool on = k < n && front(s, c) && engaged(s, c);
    if (on && run_start < 0) run_start = k;
    if (on || run_start < 0) continue;
    const int last = k - 1;
    const double lo = run_start == 0 ? (engaged_at(0.0) ? 0.0 : refine(centre_of(0), 0.0))
                                     : refine(centre_of(run_start), centre_of(run_start - 1));
    const double hi = last == n - 1
                          ? (engaged_at(2.0 * kPi) ? 2.0 * kPi : refine(centre_of(last), 2.0 * kPi))
                          : refine(centre_of(last), centre_of(last + 1));
    found.push_back({lo, hi});
    run_start = -1;
  }
  return found;
}

}  // namespace cwe

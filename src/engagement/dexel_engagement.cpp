#include "cwe/engagement/dexel_engagement.hpp"

#include <cmath>
#include <span>

namespace cwe {

DexelEngagement::DexelEngagement(const Cutter& cutter, double spacing,
                                 const EngagementOptions& options)
    : grid_(cutter, spacing, options), spacing_(spacing) {
  contact_ = options.contact > 0.0 ? options.contact : spacing / 10.0;
  skip_far_cells_ = options.skip_far_cells;
}

std::vector<Interval> DexelEngagement::scan(const TriDexel& stock, const RemovalRecord& step,
                                            const ToolState& state, const Band& band,
                                            const Vec3& v_tcs, const Vec3& w_tcs) const {
  const Frame& tcs = state.tcs;
  const Vec3 x = tcs.x(), y = tcs.y(), z = tcs.z();
  const Vec3 centre = tcs.origin + band.z * z;
  // A stretch the test for a cell P can touch lies within `margin` of P: the ray read meets
  // P's tangent plane within s√(3/2) of P, and the window along it reaches √3·(departure +
  // contact) from there. So a P farther than that from the step's box reads nothing, and a band
  // whose circle's box misses that grown box is skipped whole.
  const double margin = spacing_ * std::sqrt(1.5) + std::sqrt(3.0) * (band.departure + contact_);
  Aabb near = step.bounds();
  near.inflate(margin);
  if (!EngagementGrid::circle_bounds(band, tcs).intersects(near)) return {};

  const EngagementGrid::Front front = EngagementGrid::front(band, v_tcs, w_tcs);
  if (!front.moves) return {};
  // The ray read for P meets the tangent plane at Q, within s√(3/2) of P; a Q beyond the band's
  // own surface (past the bottom's rim, below the tip or above the flutes) says nothing of it.
  const bool bottom = band.ring;
  const double rim = bottom ? grid_.rings().back().hi : 0.0;
  const double top = grid_.cutter().profile().height();
  // Removed stretches shorter than this are float rounding of ray ends that the step's sweep
  // and an earlier one share (a wall at the tool's radius, a floor at the tip): two float
  // spacings of the stock's coordinates.
  const double rounding = 4.0 * stock.float_rounding();
  const auto engaged = [&](double s, double c) __attribute__((always_inline)) {
    if (!front(s, c)) return false;
    const Vec3 radial = s * x + c * y;
    const Vec3 point = centre + band.rho * radial;
    if (skip_far_cells_ && !near.contains(point)) return false;
    const Vec3 normal = band.normal.x() * radial + band.normal.y() * z;
    TriDexel::SurfaceRay ray;
    if (!stock.surface_ray(point, normal, ray)) return false;
    // Most cells' rays lost nothing in the step: the divisions below wait until one did.
    const std::span<const RemovalRecord::Stretch> stretches = step.on_ray(ray.axis, ray.i, ray.j);
    if (stretches.empty()) return false;
    const double t = ray.meet(point, normal);
    // The window along the ray, in outward distance from Q: from where the surface may lie
    // inside the tangent plane (less the contact tolerance) to `contact` outside it.
    const double along = std::abs(ray.along);
    const double inner = -(band.departure + contact_) / along, outer = contact_ / along;
    const double outward = ray.along > 0.0 ? 1.0 : -1.0;
    bool touched = false;
    for (const RemovalRecord::Stretch& taken : stretches) {
      const double u0 = outward * (static_cast<double>(taken.lo) - t);
      const double u1 = outward * (static_cast<double>(taken.hi) - t);
      if (std::min(std::max(u0, u1), outer) - std::max(std::min(u0, u1), inner) > rounding) {
        touched = true;
        break;
      }
    }
    if (!touched) return false;
    // Q = origin + t·e_axis as one vector sum (a coordinate written into a copy of the origin
    // and the copy read back whole stalled on the store); the same values.
    const Vec3 d = (ray.origin + t * Vec3::Unit(ray.axis)) - tcs.origin;
    const double height = d.dot(z);
    return bottom ? d.squaredNorm() - height * height <= rim * rim : height >= 0.0 && height <= top;
  };
  return grid_.intervals(front, engaged);
}

EngagementMap DexelEngagement::at(const TriDexel& stock, const RemovalRecord& step,
                                  const ToolState& state) const {
  const Vec3 v = state.tip_velocity_tcs(), w = state.angular_velocity_tcs();
  // One thread: the main loop finds the engagement of several locations at once
  // (EngagementRun), which gives each thread far more work than one location's bands.
  std::vector<std::vector<Interval>> found(grid_.bands());
  // A step that removes nothing engages nothing: the bands are left empty without a scan.
  if (!step.empty()) {
    for (std::size_t k = 0; k < found.size(); ++k) {
      found[k] = scan(stock, step, state, grid_.band(k), v, w);
    }
  }
  return grid_.map(std::move(found));
}

}  // namespace cwe

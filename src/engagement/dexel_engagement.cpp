#include "cwe/engagement/dexel_engagement.hpp"

#include <algorithm>
#include <cmath>
#include <span>

namespace cwe {

DexelEngagement::DexelEngagement(const Cutter& cutter, double spacing,
                                 const EngagementOptions& options)
    : grid_(cutter, spacing, options), spacing_(spacing) {
  contact_ = options.contact > 0.0 ? options.contact : spacing / 10.0;
  skip_far_cells_ = options.skip_far_cells;
  skip_far_discs_ = options.skip_far_discs;
  reuse_alike_discs_ = options.reuse_alike_discs;
  for (const Band& disc : grid_.discs()) {
    most_departure_ = std::max(most_departure_, disc.departure);
  }
}

double DexelEngagement::margin(double departure) const {
  return spacing_ * std::sqrt(1.5) + std::sqrt(3.0) * (departure + contact_);
}

std::array<std::size_t, 2> DexelEngagement::discs_near(const RemovalRecord& step,
                                                       const ToolState& state) const {
  const std::vector<Band>& discs = grid_.discs();
  const Frame& tcs = state.tcs;
  if (!skip_far_discs_ || tcs.z() != Vec3::UnitZ()) return {0, discs.size()};
  // An upright tool's disc circle lies at height origin + z (its box is flat), within the box
  // grown by the disc's margin or not at all. The heights the largest margin allows, widened by
  // far more than their rounding: a disc kept needlessly is still tested exactly by scan().
  const Aabb& box = step.bounds();
  const double reach =
      margin(most_departure_) +
      1e-9 * (1.0 + std::abs(tcs.origin.z()) + std::abs(box.min.z()) + std::abs(box.max.z()));
  const double lo = box.min.z() - reach - tcs.origin.z();
  const double hi = box.max.z() + reach - tcs.origin.z();
  // Discs rise with their index.
  const auto below = [](const Band& disc, double z) { return disc.z < z; };
  const auto first = std::lower_bound(discs.begin(), discs.end(), lo, below);
  const auto end = std::upper_bound(first, discs.end(), hi,
                                    [](double z, const Band& disc) { return z < disc.z; });
  return {static_cast<std::size_t>(first - discs.begin()),
          static_cast<std::size_t>(end - discs.begin())};
}

std::vector<Interval> DexelEngagement::scan(const TriDexel& stock, const RemovalRecord& step,
                                            const ToolState& state, const Band& band,
                                            const Vec3& v_tcs, const Vec3& w_tcs,
                                            Scanned& last) const {
  const Frame& tcs = state.tcs;
  const Vec3 x = tcs.x(), y = tcs.y(), z = tcs.z();
  const Vec3 centre = tcs.origin + band.z * z;
  // A stretch the test for a cell P can touch lies within `margin` of P: the ray read meets
  // P's tangent plane within s√(3/2) of P, and the window along it reaches √3·(departure +
  // contact) from there. So a P farther than that from the step's box reads nothing, and a band
  // whose circle's box misses that grown box is skipped whole.
  Aabb near = step.bounds();
  near.inflate(margin(band.departure));
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
  const Reuse here = reuse_of(stock, state, band, front);
  if (here.band != nullptr && last.reuse.band != nullptr && here.same(last.reuse, step)) {
    return last.found;
  }
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
  std::vector<Interval> found = grid_.intervals(front, engaged);
  if (here.band != nullptr) last = {here, found};
  return found;
}

// A disc of an upright tool's cylindrical part reads one height of X and Y rays for all its
// cells. Another disc of the same radius and front, whose rays lost in the step ray for ray what
// this disc's rays lost, gets the same intervals: every cell computes the same point and normal
// in plan (the tool's frame has no tilt, the normal no Z), reads the ray at the same place in
// plan at the other height, meets it at the same t and finds the same stretches there. Only the
// cell's height test (its ray within the flutes) and the far-cell test (its point within the
// box) depend on the height. The first must come out the same for every cell of both discs; the
// second does when their rays lost something, as those rays' heights lie in the step's box and
// the points within s/2 of them, inside the test's margin; when they lost nothing, every cell of
// both discs finds nothing. A step's removal along a wall or a floor is alike from height to
// height, so most discs of a flat end mill's side take the intervals of the one below.
DexelEngagement::Reuse DexelEngagement::reuse_of(const TriDexel& stock, const ToolState& state,
                                                 const Band& band,
                                                 const EngagementGrid::Front& front) const {
  Reuse here;
  const Frame& tcs = state.tcs;
  const bool upright = tcs.z() == Vec3::UnitZ() && tcs.x().z() == 0.0 && tcs.y().z() == 0.0;
  if (!reuse_alike_discs_ || band.ring || band.normal.y() != 0.0 || !upright) return here;
  // The cells' point height: the centre's, as the cells' radial direction has no Z.
  const double z = (tcs.origin + band.z * tcs.z()).z();
  double ray_z = 0.0;
  if (!stock.level_at(z, here.level, ray_z)) return here;
  // The height test of every cell, with a margin far above the rounding of the cells' own
  // arithmetic; a disc whose rays lie that close to the tip or the flutes' end is scanned.
  const double top = grid_.cutter().profile().height(), slack = 1e-9 * (1.0 + top);
  const double height = ray_z - tcs.origin.z();
  if (!(height > slack && height < top - slack)) return here;
  here.band = &band;
  here.front = front;
  return here;
}

bool DexelEngagement::Reuse::same(const Reuse& was, const RemovalRecord& step) const {
  return band->rho == was.band->rho && band->normal == was.band->normal &&
         band->departure == was.band->departure && front == was.front &&
         step.alike(0, 1, was.level, level) && step.alike(1, 0, was.level, level);
}

EngagementMap DexelEngagement::at(const TriDexel& stock, const RemovalRecord& step,
                                  const ToolState& state) const {
  const Vec3 v = state.tip_velocity_tcs(), w = state.angular_velocity_tcs();
  // One thread: the main loop finds the engagement of several locations at once
  // (EngagementRun), which gives each thread far more work than one location's bands.
  std::vector<std::vector<Interval>> found(grid_.bands());
  // A step that removes nothing engages nothing: the bands are left empty without a scan.
  if (!step.empty()) {
    Scanned last;
    // The discs out of the step's reach are left empty unscanned, as scan() would leave them.
    const auto [first, end] = discs_near(step, state);
    for (std::size_t k = first; k < end; ++k) {
      found[k] = scan(stock, step, state, grid_.band(k), v, w, last);
    }
    for (std::size_t k = grid_.discs().size(); k < found.size(); ++k) {
      found[k] = scan(stock, step, state, grid_.band(k), v, w, last);
    }
  }
  return grid_.map(std::move(found));
}

}  // namespace cwe

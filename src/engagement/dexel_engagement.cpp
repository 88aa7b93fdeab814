#include "cwe/engagement/dexel_engagement.hpp"

#include <algorithm>
#include <cmath>
#include <span>

#include <fmt/format.h>

#include "cwe/core/error.hpp"
#include "cwe/envelope/tangency.hpp"

namespace cwe {
namespace {

// A count of discs or rings within this of a whole number is that number (a 2 mm depth at
// 0.1 mm discs is 20 discs, not 21 from 20.000000000000004).
constexpr double kWholeCount = 1e-9;
// |f| below this fraction of |a| + |b| + |c| is f = 0 (grazing, not engaged): the coefficients
// are sums of a few products of unit-scale terms, good to ~1e-15 relative, so 1e-9 absorbs
// their rounding while any real motion into the surface is far above it.
constexpr double kGrazingRelative = 1e-9;

// Bisection steps that place an interval end: the cell width / 2⁶.
constexpr int kRefineSteps = 6;

int patch_of_segment(const Cutter& cutter, int segment) {
  for (std::size_t p = 0; p < cutter.patches().size(); ++p) {
    if (cutter.patches()[p].segment == segment) return static_cast<int>(p);
  }
  return 0;
}

// ∫ ρ ds of the profile between heights z0 and z1 (the area of the revolved band per radian).
double side_area_per_radian(const Profile& profile, double z0, double z1) {
  constexpr int kSteps = 16;
  double area = 0.0;
  Vec2 previous(profile.radius_at(z0), z0);
  for (int k = 1; k <= kSteps; ++k) {
    const double z = z0 + (z1 - z0) * k / kSteps;
    const Vec2 p(profile.radius_at(z), z);
    area += 0.5 * (previous.x() + p.x()) * (p - previous).norm();
    previous = p;
  }
  return area;
}

// The smallest-angle merge of intervals on [0, 2π] and the ends of their largest gap.
void entry_exit(std::vector<Interval> all, double& entry, double& exit) {
  entry = exit = 0.0;
  if (all.empty()) return;
  std::sort(all.begin(), all.end(),
            [](const Interval& x, const Interval& y) { return x.lo < y.lo; });
  std::vector<Interval> merged{all.front()};
  for (std::size_t k = 1; k < all.size(); ++k) {
    if (all[k].lo <= merged.back().hi) {
      merged.back().hi = std::max(merged.back().hi, all[k].hi);
    } else {
      merged.push_back(all[k]);
    }
  }
  // The gap through φ = 0 first; an inner gap must be strictly larger to win.
  double best = merged.front().lo + (2.0 * kPi - merged.back().hi);
  entry = merged.front().lo;
  exit = merged.back().hi;
  for (std::size_t k = 1; k < merged.size(); ++k) {
    const double gap = merged[k].lo - merged[k - 1].hi;
    if (gap > best) {
      best = gap;
      entry = merged[k].lo;
      exit = merged[k - 1].hi;
    }
  }
  if (best <= 0.0) {  // a full ring
    entry = 0.0;
    exit = 2.0 * kPi;
  }
}

}  // namespace

DexelEngagement::DexelEngagement(const Cutter& cutter, double spacing,
                                 const EngagementOptions& options)
    : cutter_(&cutter), spacing_(spacing) {
  if (!(spacing > 0.0) || !std::isfinite(spacing)) {
    throw InputError(
        fmt::format("engagement: ray spacing {} mm, expected a positive length", spacing));
  }
  if (!(options.disc_height >= 0.0) || !(options.phi_step >= 0.0) || !(options.contact >= 0.0) ||
      !std::isfinite(options.disc_height) || !std::isfinite(options.phi_step) ||
      !std::isfinite(options.contact)) {
    throw InputError(
        "engagement: disc height, φ step and contact must be positive (or 0 for the default)");
  }
  disc_height_ = options.disc_height > 0.0 ? options.disc_height : spacing;
  contact_ = options.contact > 0.0 ? options.contact : spacing / 10.0;
  skip_far_cells_ = options.skip_far_cells;
  const Profile& profile = cutter.profile();
  const double max_radius = std::max(profile.max_radius(), spacing);
  // Cells of about one ray spacing at the largest radius: interval ends are refined by bisection
  // below the cell size, so cells need only be fine enough not to step over an engaged region.
  const double step =
      options.phi_step > 0.0 ? options.phi_step : std::min(kPi / 180.0, spacing / max_radius);
  phi_cells_ = std::clamp(static_cast<int>(std::ceil(2.0 * kPi / step)), 8, 1 << 16);
  for (int k = 0; k < phi_cells_; ++k) {
    const double phi = (k + 0.5) * 2.0 * kPi / phi_cells_;
    sin_.push_back(std::sin(phi));
    cos_.push_back(std::cos(phi));
  }
  const double reach = spacing / std::sqrt(2.0);  // how far from a point its ray may pass

  // Side discs: every height of the profile's non-horizontal pieces.
  const auto& segments = profile.segments();
  const double height = profile.height();
  const int discs = static_cast<int>(std::ceil(height / disc_height_ - kWholeCount));
  for (int k = 0; k < discs; ++k) {
    Band band;
    band.lo = k * disc_height_;
    band.hi = std::min(height, (k + 1) * disc_height_);
    // Sampled away from the flutes' ends by the reach of a ray (s/√2), so that the ray read for
    // a cell meets this surface and not the tangent plane beyond its rim.
    band.z = std::clamp(0.5 * (band.lo + band.hi), std::min(reach, 0.5 * height),
                        std::max(height - reach, 0.5 * height));
    int segment = -1;
    for (std::size_t s = 0; s < segments.size(); ++s) {
      if (!segments[s].is_horizontal() && segments[s].min_z() <= band.z &&
          band.z <= segments[s].max_z()) {
        segment = static_cast<int>(s);
        break;
      }
    }
    if (segment < 0) continue;  // only horizontal pieces at this height: nothing to map
    const ProfileSegment& piece = segments[static_cast<std::size_t>(segment)];
    band.rho = piece.radius_at(band.z);
    band.normal = piece.normal_at(piece.closest(Vec2(band.rho, band.z)).u);
    band.patch = patch_of_segment(cutter, segment);
    band.area_per_radian = side_area_per_radian(profile, band.lo, band.hi);
    // Curvatures: of the profile (arcs) and of the parallel circle (n_ρ / ρ).
    const double kappa =
        std::max(piece.kind == ProfileSegment::Kind::kArc ? 1.0 / piece.radius : 0.0,
                 std::abs(band.normal.x()) / std::max(band.rho, spacing));
    // Q lies within s√(3/2) of P on the tangent plane, where the surface falls behind the plane
    // by at most κ·(s√(3/2))²/2.
    band.departure = 0.75 * kappa * spacing * spacing;
    discs_.push_back(band);
  }

  // Bottom rings: a horizontal first piece at the tip.
  const ProfileSegment& first = segments.front();
  if (first.is_horizontal() && first.start.y() == 0.0) {
    const double outer = first.max_radius();
    const int rings = static_cast<int>(std::ceil(outer / disc_height_ - kWholeCount));
    for (int k = 0; k < rings; ++k) {
      Band band;
      band.lo = k * disc_height_;
      band.hi = std::min(outer, (k + 1) * disc_height_);
      band.rho = std::max(0.0, std::min(0.5 * (band.lo + band.hi), outer - reach));
      band.z = 0.0;
      band.normal = Vec2(0.0, -1.0);
      band.patch = patch_of_segment(cutter, 0);
      band.area_per_radian = 0.5 * (band.hi * band.hi - band.lo * band.lo);
      band.departure = 0.0;
      band.ring = true;
      rings_.push_back(band);
    }
  }
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
  Aabb circle;
  for (int a = 0; a < 3; ++a) {
    const double e = band.rho * std::sqrt(std::max(0.0, 1.0 - z[a] * z[a]));
    circle.min[a] = centre[a] - e;
    circle.max[a] = centre[a] + e;
  }
  if (!circle.intersects(near)) return {};

  const TangencyCoefficients f =
      tangency_coefficients(Vec2(band.rho, band.z), band.normal, v_tcs, w_tcs);
  // Grazing points (f = 0) are not engaged; f_min absorbs rounding of the coefficients.
  const double f_min = kGrazingRelative * (std::abs(f.a) + std::abs(f.b) + std::abs(f.c));
  if (!(std::abs(f.a) + std::abs(f.b) + std::abs(f.c) > 0.0)) return {};
  // The ray read for P meets the tangent plane at Q, within s√(3/2) of P; a Q beyond the band's
  // own surface (past the bottom's rim, below the tip or above the flutes) says nothing of it.
  const bool bottom = band.ring;
  const double rim = bottom ? rings_.back().hi : 0.0;
  const double top = cutter_->profile().height();
  // Removed stretches shorter than this are float rounding of ray ends that the step's sweep
  // and an earlier one share (a wall at the tool's radius, a floor at the tip): two float
  // spacings of the stock's coordinates.
  const double rounding = 4.0 * stock.float_rounding();
  const auto engaged = [&](double s, double c) __attribute__((always_inline)) {
    if (!(f.a * s + f.b * c + f.c > f_min)) return false;
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
  const auto engaged_at = [&](double phi) { return engaged(std::sin(phi), std::cos(phi)); };
  // The boundary between an engaged angle and one that is not.
  const auto refine = [&](double in, double out) {
    for (int k = 0; k < kRefineSteps; ++k) {
      const double mid = 0.5 * (in + out);
      (engaged_at(mid) ? in : out) = mid;
    }
    return 0.5 * (in + out);
  };

  const int n = phi_cells_;
  const double cell = 2.0 * kPi / n;
  const auto centre_of = [cell](int k) { return (k + 0.5) * cell; };
  std::vector<Interval> intervals;
  int run_start = -1;
  for (int k = 0; k <= n; ++k) {
    // The front-half test first, without a call: it rejects half the cells.
    const double s = k < n ? sin_[static_cast<std::size_t>(k)] : 0.0;
    const double c = k < n ? cos_[static_cast<std::size_t>(k)] : 0.0;
    const bool on = k < n && f.a * s + f.b * c + f.c > f_min && engaged(s, c);
    if (on && run_start < 0) run_start = k;
    if (on || run_start < 0) continue;
    const int last = k - 1;
    const double lo = run_start == 0 ? (engaged_at(0.0) ? 0.0 : refine(centre_of(0), 0.0))
                                     : refine(centre_of(run_start), centre_of(run_start - 1));
    const double hi = last == n - 1
                          ? (engaged_at(2.0 * kPi) ? 2.0 * kPi : refine(centre_of(last), 2.0 * kPi))
                          : refine(centre_of(last), centre_of(last + 1));
    intervals.push_back({lo, hi});
    run_start = -1;
  }
  return intervals;
}

EngagementMap DexelEngagement::at(const TriDexel& stock, const RemovalRecord& step,
                                  const ToolState& state) const {
  EngagementMap map;
  const Vec3 v = state.tip_velocity_tcs(), w = state.angular_velocity_tcs();
  // One thread: the main loop finds the engagement of several locations at once
  // (EngagementRun), which gives each thread far more work than one location's bands.
  std::vector<std::vector<Interval>> found(discs_.size() + rings_.size());
  // A step that removes nothing engages nothing: the bands are left empty without a scan.
  if (!step.empty()) {
    for (std::size_t k = 0; k < found.size(); ++k) {
      const Band& band = k < discs_.size() ? discs_[k] : rings_[k - discs_.size()];
      found[k] = scan(stock, step, state, band, v, w);
    }
  }
  std::vector<Interval> all;
  map.discs.reserve(discs_.size());
  map.rings.reserve(rings_.size());
  for (std::size_t k = 0; k < discs_.size(); ++k) {
    const Band& band = discs_[k];
    DiscEngagement disc{band.lo, band.hi, band.patch, std::move(found[k])};
    for (const Interval& i : disc.phi) {
      map.area += i.length() * band.area_per_radian;
      map.axial_depth = std::max(map.axial_depth, band.hi);
      all.push_back(i);
    }
    map.discs.push_back(std::move(disc));
  }
  for (std::size_t k = 0; k < rings_.size(); ++k) {
    const Band& band = rings_[k];
    RingEngagement ring{band.lo, band.hi, std::move(found[discs_.size() + k])};
    for (const Interval& i : ring.phi) {
      map.area += i.length() * band.area_per_radian;
      all.push_back(i);
    }
    map.rings.push_back(std::move(ring));
  }
  map.engaged = !all.empty();
  entry_exit(std::move(all), map.phi_entry, map.phi_exit);
  return map;
}

}  // namespace cwe

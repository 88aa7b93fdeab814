#include "cwe/engagement/engagement_grid.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "cwe/core/error.hpp"

namespace cwe {
namespace {

// A count of discs or rings within this of a whole number is that number (a 2 mm depth at
// 0.1 mm discs is 20 discs, not 21 from 20.000000000000004).
constexpr double kWholeCount = 1e-9;
int patch_of_segment(const Cutter& cutter, int segment) {
  for (std::size_t p = 0; p < cutter.patches().size(); ++p) {
    if (cutter.patches()[p].segment == segment) return static_cast<int>(p);
  }
  return 0;
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

// |f| below this fraction of |a| + |b| + |c| is f = 0 (grazing, not engaged): the coefficients
// are sums of a few products of unit-scale terms, good to ~1e-15 relative, so 1e-9 absorbs
// their rounding while any real motion into the surface is far above it.
constexpr double kGrazingRelative = 1e-9;

}  // namespace

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

EngagementGrid::EngagementGrid(const Cutter& cutter, double spacing,
                               const EngagementOptions& options)
    : cutter_(&cutter) {
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
  const Profile& profile = cutter.profile();
  const double max_radius = std::max(profile.max_radius(), spacing);
  // Cells of about one ray spacing at the largest radius: interval ends are refined by bisection
  // below the cell size, so cells need only be fine enough not to step over an engaged region.
  const double step =
      options.phi_step > 0.0 ? options.phi_step : std::min(kPi / 180.0, spacing / max_radius);
  const int cells = std::clamp(static_cast<int>(std::ceil(2.0 * kPi / step)), 8, 1 << 16);
  for (int k = 0; k < cells; ++k) {
    const double phi = (k + 0.5) * 2.0 * kPi / cells;
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

EngagementMap EngagementGrid::map(std::vector<std::vector<Interval>> found) const {
  EngagementMap map;
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

Aabb EngagementGrid::circle_bounds(const Band& band, const Frame& tcs, double margin) {
  const Vec3 z = tcs.z();
  const Vec3 centre = tcs.origin + band.z * z;
  Aabb circle;
  for (int a = 0; a < 3; ++a) {
    // A circle of radius ρ about unit axis z extends ρ·√(1 - z_a²) along axis a.
    const double e = band.rho * std::sqrt(std::max(0.0, 1.0 - z[a] * z[a])) + margin;
    circle.min[a] = centre[a] - e;
    circle.max[a] = centre[a] + e;
  }
  return circle;
}

EngagementGrid::Front EngagementGrid::front(const Band& band, const Vec3& v_tcs,
                                            const Vec3& w_tcs) {
  Front front;
  front.f = tangency_coefficients(Vec2(band.rho, band.z), band.normal, v_tcs, w_tcs);
  const double scale = std::abs(front.f.a) + std::abs(front.f.b) + std::abs(front.f.c);
  front.f_min = kGrazingRelative * scale;
  front.moves = scale > 0.0;
  return front;
}

}  // namespace cwe

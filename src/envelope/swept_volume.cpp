#include "cwe/envelope/swept_volume.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "cwe/core/error.hpp"
#include "cwe/geometry/tolerance.hpp"

namespace cwe {
namespace {

// Segments of a circle of radius r whose chords deviate at most `deviation`: the sagitta
// r(1 - cos(θ/2)) of each step θ stays below it.
int steps_for(double radius, double angle, double deviation) {
  if (radius <= deviation || angle <= 0.0) return 1;
  const double step = 2.0 * std::acos(1.0 - deviation / radius);
  return std::max(1, static_cast<int>(std::ceil(angle / step - tol::kRelative)));
}

// (ρ, z) samples of the cutter's profile from the tip to the top edge, chords within
// tolerance/2 of its arcs.
std::vector<Vec2> profile_samples(const Cutter& cutter, double tolerance) {
  const double half = tolerance / 2.0;
  std::vector<Vec2> profile;
  for (const ProfileSegment& s : cutter.profile().segments()) {
    const int steps = s.kind == ProfileSegment::Kind::kArc
                          ? steps_for(s.radius, std::abs(s.end_angle() - s.start_angle()), half)
                          : 1;
    for (int k = profile.empty() ? 0 : 1; k <= steps; ++k) {
      profile.push_back(s.point_at(static_cast<double>(k) / steps));
    }
  }
  return profile;
}

Frame frame_at(const Vec3& tip, const Vec3& axis) {
  return Frame::from_z(tip, axis, Vec3::UnitX());
}

// Composite Simpson's rule of f over [a, b] in n (even) intervals.
template <class F>
double simpson(F f, double a, double b, int n) {
  const double h = (b - a) / n;
  double sum = f(a) + f(b);
  for (int k = 1; k < n; ++k) sum += (k % 2 ? 4.0 : 2.0) * f(a + k * h);
  return sum * h / 3.0;
}

// ∫ g(ρ) dz over the profile, along each piece's length (smooth where ρ(z) is not: a ball's √z
// at the tip).
template <class G>
double over_profile(const Cutter& cutter, G g) {
  double sum = 0.0;
  for (const ProfileSegment& s : cutter.profile().segments()) {
    if (s.max_z() - s.min_z() < 1e-12) continue;
    sum += simpson([&](double u) { return g(s.point_at(u).x()) * s.tangent_at(u).y(); }, 0.0, 1.0,
                   2000) *
           s.length();
  }
  return sum;
}

// ∫₀^2π |A cos φ + B| dφ for A ≥ 0.
double ring_integral(double a, double b) {
  if (std::abs(b) >= a) return 2.0 * M_PI * std::abs(b);
  const double phi0 = std::acos(-b / a);
  return 4.0 * (a * std::sin(phi0) + b * phi0) - 2.0 * M_PI * b;
}

// The area of the tool's shadow along unit local d, ½∮|n·d| dS (Cauchy).
double shadow_area(const Cutter& cutter, const Vec3& d) {
  const double h = std::hypot(d.x(), d.y());
  double twice = 0.0;
  for (const ProfileSegment& s : cutter.profile().segments()) {
    if (s.length() < 1e-12) continue;
    twice += simpson(
                 [&](double u) {
                   const Vec2 q = s.point_at(u), n = s.normal_at(u);
                   return q.x() * ring_integral(n.x() * h, n.y() * d.z());
                 },
                 0.0, 1.0, 2000) *
             s.length();
  }
  const double top = cutter.profile().top_radius();
  return 0.5 * (twice + std::abs(d.z()) * M_PI * top * top);
}

// The area a disc of radius ρ sweeps with its centre on an arc of radius R through α: where
// R ≥ ρ, the annular strip and the two end half discs (2αRρ + πρ²) while the half discs, each
// asin(ρ/R) wide seen from the axis, do not overlap beyond the arc's angles; where they do, the
// strip and, beyond the arc's angles, the union of the two discs' chords along each ray from the
// axis. Where R < ρ the disc covers the arc's axis: the sector out to R + ρ and, beyond the
// arc's angles, the farther reach of the two end discs along each ray from the axis.
double arc_swept_area(double big_r, double rho, double alpha) {
  if (alpha >= 2.0 * M_PI) {
    const double inner = std::max(0.0, big_r - rho);
    return M_PI * ((big_r + rho) * (big_r + rho) - inner * inner);
  }
  if (big_r >= rho) {
    const double strip = 2.0 * alpha * big_r * rho;
    if (!(rho > 0.0) || alpha + 2.0 * std::asin(rho / big_r) <= 2.0 * M_PI) {
      return strip + M_PI * rho * rho;
    }
    // The chord [c − h, c + h] of the end disc centred at angle ψ along the ray at φ.
    const auto chord = [&](double phi, double psi) {
      const double s = big_r * std::sin(phi - psi), c = big_r * std::cos(phi - psi);
      if (!(std::abs(s) < rho) || !(c > 0.0)) return std::pair{0.0, 0.0};
      const double h = std::sqrt(rho * rho - s * s);
      return std::pair{c - h, c + h};
    };
    return strip + simpson(
                       [&](double phi) {
                         auto [a0, b0] = chord(phi, 0.0);
                         auto [a1, b1] = chord(phi, alpha);
                         if (a1 < a0) {
                           std::swap(a0, a1);
                           std::swap(b0, b1);
                         }
                         // ½(b² − a²) over the union of [a0, b0] and [a1, b1] (a0 ≤ a1).
                         if (a1 <= b0) return 0.5 * (std::max(b0, b1) * std::max(b0, b1) - a0 * a0);
                         return 0.5 * (b0 * b0 - a0 * a0 + b1 * b1 - a1 * a1);
                       },
                       alpha, 2.0 * M_PI, 4000);
  }
  const auto reach = [&](double phi) {
    const double s = std::sin(phi);
    return big_r * std::cos(phi) + std::sqrt(rho * rho - big_r * big_r * s * s);
  };
  return 0.5 * alpha * (big_r + rho) * (big_r + rho) +
         simpson(
             [&](double phi) {
               const double r = std::max(reach(phi), reach(phi - alpha));
               return 0.5 * r * r;
             },
             alpha, 2.0 * M_PI, 4000);
}

}  // namespace

bool is_convex(const Cutter& cutter) {
  // Concave ρ(z): lines and counter-clockwise (convex) arcs only, with the slope dρ/dz not
  // increasing at the joints (tangent turning clockwise in (ρ, z), i.e. to the left when going
  // up: cross product of consecutive tangents ≥ 0).
  const auto& segments = cutter.profile().segments();
  for (std::size_t i = 0; i < segments.size(); ++i) {
    if (segments[i].kind == ProfileSegment::Kind::kArc && !segments[i].counterclockwise)
      return false;
    if (i == 0) continue;
    const Vec2 a = segments[i - 1].tangent_at(1.0);
    const Vec2 b = segments[i].tangent_at(0.0);
    if (a.x() * b.y() - a.y() * b.x() < -tol::kAngle) return false;
  }
  // The top edge turns inwards (towards the axis) from the last piece: convex as long as the last
  // piece does not point back down, which a rising profile never does.
  return true;
}

std::vector<Vec3> tool_surface_points(const Cutter& cutter, double tolerance) {
  const double half = tolerance / 2.0;
  const std::vector<Vec2> profile = profile_samples(cutter, tolerance);
  std::vector<Vec3> points;
  points.emplace_back(0.0, 0.0, cutter.profile().height());  // centre of the top disc
  for (const Vec2& p : profile) {
    if (p.x() <= 0.0) {
      points.emplace_back(0.0, 0.0, p.y());
      continue;
    }
    const int ring = std::max(8, steps_for(p.x(), kTwoPi, half));
    for (int j = 0; j < ring; ++j) {
      const double phi = kTwoPi * j / ring;
      points.emplace_back(p.x() * std::sin(phi), p.x() * std::cos(phi), p.y());
    }
  }
  return points;
}

SweptVolume swept_volume(const Cutter& cutter, const Move& move,
                         const SweptVolumeOptions& options) {
  if (!(options.tolerance > 0.0)) {
    throw InputError(
        fmt::format("swept-volume tolerance {} mm: expected a positive length", options.tolerance));
  }
  if (!is_convex(cutter)) {
    throw InputError(SourceLocation{cutter.name()},
                     "swept volumes are built for convex cutters (every APT cutter); this "
                     "profile has a concave part");
  }
  const double half = options.tolerance / 2.0;
  // Subdivision: the path's chords deviate at most tolerance/2 from an arc, and the axis turns
  // at most Δ per piece with reach·Δ ≤ tolerance (`reach`: the farthest tool point from the
  // tip): each piece is the hull of its two end tools in their own poses, which exceeds the
  // motion's sweep by at most reach·Δ/2 (linear_piece_mesh) and misses it by a tool point's
  // sagitta reach·Δ²/8.
  const BoundingCylinder bounds = cutter.bounding_cylinder();
  const double reach = std::hypot(bounds.radius, bounds.z_max);
  int pieces = 1;
  if (move.is_arc()) {
    pieces = std::max(pieces, steps_for(move.radius(), move.sweep, half));
  }
  const double turn = move.axis_angle();
  if (turn > tol::kAngle) {
    pieces = std::max(pieces, static_cast<int>(std::ceil(turn * reach / options.tolerance)));
  }
  const std::vector<Vec3> tool = tool_surface_points(cutter, options.tolerance);
  SweptVolume result;
  const bool curved = pieces > 1 || move.is_arc() || turn > tol::kAngle;
  result.deviation_bound = curved ? 2.0 * options.tolerance : options.tolerance;
  for (int k = 0; k < pieces; ++k) {
    const double u0 = static_cast<double>(k) / pieces;
    const double u1 = static_cast<double>(k + 1) / pieces;
    result.pieces.push_back(linear_piece_mesh(tool, move.position(u0), move.axis(u0),
                                              move.position(u1), move.axis(u1)));
  }
  return result;
}

TriangleMesh linear_piece_mesh(const std::vector<Vec3>& tool, const Vec3& start, const Vec3& end,
                               const Vec3& axis) {
  return linear_piece_mesh(tool, start, axis, end, axis);
}

TriangleMesh linear_piece_mesh(const std::vector<Vec3>& tool, const Vec3& start,
                               const Vec3& start_axis, const Vec3& end, const Vec3& end_axis) {
  std::vector<Vec3> points;
  points.reserve(2 * tool.size());
  for (const Frame& frame : {frame_at(start, start_axis), frame_at(end, end_axis)}) {
    for (const Vec3& p : tool) points.push_back(frame.to_world(p));
  }
  return convex_hull(points);
}

std::vector<TriangleMesh> planar_arc_sweep(const Cutter& cutter, double tolerance,
                                           double path_tolerance, const Move& arc) {
  if (!arc.is_arc() || arc.axial != 0.0 || !is_convex(cutter) || !(tolerance > 0.0) ||
      !(path_tolerance > 0.0)) {
    return {};
  }
  const Vec3 axis = arc.start_axis.normalized();
  if (arc.end_axis.normalized().dot(axis) < 1.0 - 1e-12) return {};
  if (std::abs(axis.dot(arc.normal)) < 1.0 - 1e-12) return {};
  const double half = tolerance / 2.0;
  const double big_r = arc.radius();
  const double rho_max = cutter.profile().max_radius();
  if (!(big_r > 1e-3)) return {};
  const bool full = arc.sweep >= kTwoPi * (1.0 - tol::kRelative);
  // Glued (one mesh): the inner wall stays off the arc's axis, and the two half tools off each
  // other and off the tube (each reaches asin(ρ/R) beyond its end of the arc, seen from the
  // axis). Else the wedge, with the tools whole at both ends, for a union.
  const bool glued = big_r - rho_max > std::max(half, 1e-3) &&
                     (full || arc.sweep + 2.0 * std::asin(rho_max / big_r) < kTwoPi - 1e-3);

  // The meridian polyline M: axis point at the bottom (a flat tip), the profile samples, the
  // centre of the top disc; points on the tool's axis (ρ = 0) are single vertices of every ring.
  std::vector<Vec2> meridian;
  for (const Vec2& p : profile_samples(cutter, tolerance)) {
    if (meridian.empty() && p.x() > 0.0) meridian.emplace_back(0.0, p.y());
    // A point again (a ball's tip: the bottom line of length 0, then the arc) is one vertex.
    const Vec2 q(std::max(0.0, p.x()), p.y());
    if (meridian.empty() || (q - meridian.back()).norm() > 1e-9) meridian.push_back(q);
  }
  meridian.emplace_back(0.0, cutter.profile().height());
  // A radius within a relative 1e-9 of R reaches the arc's axis (R is computed from the arc's
  // ends, a few ulps off the radius of the corner it goes round).
  const double axis_reach = big_r * (1.0 - 1e-9);
  // Where the profile's radius crosses R, a sample: there the section's inner side reaches the
  // arc's axis, and the clamped side runs up the axis from it (a chord across would cut the
  // corner).
  for (std::size_t j = 0; j + 1 < meridian.size(); ++j) {
    const Vec2 a = meridian[j], b = meridian[j + 1];
    if ((a.x() < axis_reach) != (b.x() < axis_reach) && std::abs(b.x() - a.x()) > 0.0) {
      const double u = (big_r - a.x()) / (b.x() - a.x());
      const Vec2 q = a + u * (b - a);
      if ((q - a).norm() > 1e-9 && (q - b).norm() > 1e-9) {
        meridian.insert(meridian.begin() + static_cast<std::ptrdiff_t>(j) + 1, q);
        ++j;
      }
    }
  }
  const auto on_axis = [&](std::size_t j) { return meridian[j].x() <= 0.0; };
  // Ring sides: the largest ring's, even, so that every ring has vertices on the meridian plane
  // (α = 0 and π), where the tools meet the tube's sections.
  int sides = std::max(8, steps_for(rho_max, kTwoPi, half));
  sides += sides % 2;
  const int stations = full ? std::max(8, steps_for(big_r + rho_max, kTwoPi, path_tolerance / 2))
                            : steps_for(big_r + rho_max, arc.sweep, path_tolerance / 2);

  const Vec3 e1 = (arc.start - arc.center).normalized();
  const Vec3 e2 = arc.normal.cross(e1);
  // The tool point at profile sample j, ring angle α (from the radial direction towards the
  // travel), with the tip at arc angle θ.
  const auto point = [&](double theta, std::size_t j, double alpha) -> Vec3 {
    const Vec3 u = std::cos(theta) * e1 + std::sin(theta) * e2;
    const Vec3 t = arc.normal.cross(u);
    const Vec2& m = meridian[j];
    return arc.center + big_r * u + m.y() * axis +
           m.x() * (std::cos(alpha) * u + std::sin(alpha) * t);
  };
  // The section polygon S at a station: the meridian at α = 0 (outer side) from the bottom to
  // the top, then at α = π (inner side) back down, points on the tool's axis once. An inner point
  // at or past the arc's axis (ρ ≥ R) sits on that axis, one vertex for every station.
  struct Corner {
    std::size_t j;
    double alpha;
    bool arc_axis;
  };
  std::vector<Corner> section;
  for (std::size_t j = 0; j < meridian.size(); ++j) section.push_back({j, 0.0, false});
  for (std::size_t j = meridian.size(); j-- > 0;) {
    if (on_axis(j)) continue;
    const bool clamped = meridian[j].x() >= axis_reach;
    // Clamped corners at one height (the bottom's or the top's ring and the sample at ρ = R)
    // are one point.
    if (clamped && section.back().arc_axis && meridian[section.back().j].y() == meridian[j].y()) {
      continue;
    }
    section.push_back({j, kPi, clamped});
  }
  TriangleMesh tube;
  const auto add = [](TriangleMesh& mesh, int a, int b, int c) {
    if (a != b && b != c && a != c) mesh.triangles.push_back({a, b, c});
  };
  const std::size_t n = section.size();
  std::vector<int> on_arc_axis(n, -1);
  const int rings = full ? stations : stations + 1;
  std::vector<std::vector<int>> ids(static_cast<std::size_t>(rings));
  for (int k = 0; k < rings; ++k) {
    const double theta = full ? kTwoPi * k / stations : arc.sweep * k / stations;
    for (std::size_t q = 0; q < n; ++q) {
      const Corner& c = section[q];
      if (c.arc_axis && on_arc_axis[q] >= 0) {
        ids[static_cast<std::size_t>(k)].push_back(on_arc_axis[q]);
        continue;
      }
      const int id = static_cast<int>(tube.vertices.size());
      tube.vertices.push_back(c.arc_axis ? Vec3(arc.center + meridian[c.j].y() * axis)
                                         : point(theta, c.j, c.alpha));
      if (c.arc_axis) on_arc_axis[q] = id;
      ids[static_cast<std::size_t>(k)].push_back(id);
    }
  }
  for (int k = 0; k < stations; ++k) {
    const auto& a = ids[static_cast<std::size_t>(k)];
    const auto& b = ids[static_cast<std::size_t>((k + 1) % rings)];
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t i1 = (i + 1) % n;
      add(tube, a[i], b[i], b[i1]);
      add(tube, a[i], b[i1], a[i1]);
    }
  }
  // The tool at arc angle θ over ring angles α0 + [0, span] (half or whole), its vertices on the
  // meridian plane taken from `ends` (the tube's section there) when given.
  const auto tool = [&](TriangleMesh& mesh, double theta, double alpha0, int steps,
                        const std::vector<int>* ends) {
    std::vector<std::vector<int>> grid(meridian.size());
    for (std::size_t j = 0; j < meridian.size(); ++j) {
      for (int i = 0; i <= steps; ++i) {
        const double alpha = alpha0 + kTwoPi * i / sides;
        const double turns = alpha / kPi;
        const bool meridional = std::abs(turns - std::round(turns)) <= tol::kRelative;
        int id = -1;
        if (ends != nullptr && (on_axis(j) || meridional)) {
          const bool outer = static_cast<long>(std::round(turns)) % 2 == 0;
          for (std::size_t q = 0; q < n && id < 0; ++q) {
            if (section[q].j == j && (on_axis(j) || (section[q].alpha == 0.0) == outer)) {
              id = (*ends)[q];
            }
          }
        } else if (on_axis(j) && i > 0) {
          id = grid[j].front();
        } else if (steps == sides && i == steps) {
          id = grid[j].front();  // the whole ring closes on itself
        } else {
          id = static_cast<int>(mesh.vertices.size());
          mesh.vertices.push_back(point(theta, j, alpha));
        }
        grid[j].push_back(id);
      }
    }
    // Both halves wound as one tool, (α, j) the same way round; the tube's end sections run the
    // other way.
    for (std::size_t j = 0; j + 1 < meridian.size(); ++j) {
      for (int i = 0; i < steps; ++i) {
        const auto q = static_cast<std::size_t>(i);
        add(mesh, grid[j][q], grid[j][q + 1], grid[j + 1][q + 1]);
        add(mesh, grid[j][q], grid[j + 1][q + 1], grid[j + 1][q]);
      }
    }
  };
  std::vector<TriangleMesh> result;
  if (glued || full) {
    if (!full) {
      tool(tube, 0.0, kPi, sides / 2, &ids.front());       // behind the start
      tool(tube, arc.sweep, 0.0, sides / 2, &ids.back());  // ahead of the end
    }
    result.push_back(std::move(tube));
  } else {
    // The wedge's end faces: the sections, convex (between the concave R + ρ(z) and the convex
    // max(0, R − ρ(z))), the start's in the section's order.
    // Fanned from their centroids: a corner may be in line with both its neighbours.
    for (const bool start : {true, false}) {
      const std::vector<int>& ring = start ? ids.front() : ids.back();
      Vec3 centre = Vec3::Zero();
      for (const int id : ring) centre += tube.vertices[static_cast<std::size_t>(id)];
      const int c = static_cast<int>(tube.vertices.size());
      tube.vertices.push_back(centre / static_cast<double>(n));
      for (std::size_t i = 0; i < n; ++i) {
        const int a = ring[i], b = ring[(i + 1) % n];
        if (start) {
          add(tube, c, a, b);
        } else {
          add(tube, c, b, a);
        }
      }
    }
    result.push_back(std::move(tube));
    for (const double theta : {0.0, arc.sweep}) {
      TriangleMesh whole;
      tool(whole, theta, 0.0, sides, nullptr);
      result.push_back(std::move(whole));
    }
  }
  for (TriangleMesh& mesh : result) {
    if (mesh.volume() < 0.0) {
      for (auto& t : mesh.triangles) std::swap(t[1], t[2]);
    }
  }
  return result;
}

double cutter_volume(const Cutter& cutter) {
  return over_profile(cutter, [](double rho) { return M_PI * rho * rho; });
}

double line_swept_volume(const Cutter& cutter, const Vec3& d) {
  const double length = d.norm();
  if (!(length > 0.0)) return cutter_volume(cutter);
  return cutter_volume(cutter) + length * shadow_area(cutter, d / length);
}

double planar_arc_swept_volume(const Cutter& cutter, double radius, double sweep) {
  return over_profile(cutter, [&](double rho) { return arc_swept_area(radius, rho, sweep); });
}

}  // namespace cwe

#pragma once
// The 2-D outline of a cutter in the (radius ρ, height z) half-plane, revolved about z to make the
// cutter surface. ρ ≥ 0 is the distance from the tool axis, z the height above the tool tip.
//
// A Profile is a chain of line segments and circular arcs that
//  - starts on the axis at the tip, (0, 0);
//  - rises monotonically: z never decreases along any piece (so the cutter solid is
//    { 0 ≤ z ≤ height, ρ ≤ radius_at(z) } and every horizontal section is one disc);
//  - stays at ρ ≥ 0 and ends at the top edge (ρ_top, height) with height > 0;
//  - is continuous: each piece starts where the previous one ends (within tol::kInputLength;
//    end points are then snapped together).
// The cutter solid is closed by the flat top disc at z = height. Pieces are traversed from the
// tip upwards, so the solid lies to the left and the outward normal is the tangent turned
// clockwise: (t_z, -t_ρ). Aras 2008 §5.2 builds its generic cutter from three such pieces.

#include <limits>
#include <string>
#include <vector>

#include "cwe/geometry/interval.hpp"
#include "cwe/geometry/vec.hpp"

namespace cwe {

// One piece of a profile. Points are (ρ, z).
struct ProfileSegment {
  enum class Kind { kLine, kArc };

  Kind kind = Kind::kLine;
  Vec2 start = Vec2::Zero();
  Vec2 end = Vec2::Zero();
  // Arcs only: centre and radius; the arc runs from start to end counter-clockwise in the
  // (ρ, z) plane when `counterclockwise`, clockwise otherwise, and is at most a half circle.
  Vec2 center = Vec2::Zero();
  double radius = 0.0;
  bool counterclockwise = true;

  static ProfileSegment line(const Vec2& from, const Vec2& to);
  // Arc from `from` to `to` about `center` (radius from `from`); counter-clockwise or not.
  static ProfileSegment arc(const Vec2& from, const Vec2& to, const Vec2& center,
                            bool counterclockwise);

  double length() const;
  // Point at fraction u ∈ [0, 1] of the piece's length.
  Vec2 point_at(double u) const;
  // Unit tangent (direction of travel) and outward unit normal (t_z, -t_ρ) at fraction u.
  Vec2 tangent_at(double u) const;
  Vec2 normal_at(double u) const;
  // Start and end angle of an arc, radians, atan2 about the centre (end adjusted so that the
  // sweep end - start has the sign of the direction).
  double start_angle() const;
  double end_angle() const;
  // The ρ of this piece at height z (z within the piece's height range). For an arc the branch
  // is the one the arc lies on: the right of its centre when it turns counter-clockwise (the
  // profile rises), the left otherwise. Horizontal lines return the larger ρ.
  double radius_at(double z) const;
  double min_z() const;
  double max_z() const;
  double max_radius() const;
  bool is_horizontal() const;  // a line with start.z == end.z
  bool is_vertical() const;    // a line with start.ρ == end.ρ

  // Closest point of the piece to q, as the fraction u and the distance.
  struct Closest {
    double u = 0.0;
    double distance = 0.0;
  };
  Closest closest(const Vec2& q) const;
};

class Profile {
 public:
  // Checks the rules above and throws cwe::InputError naming the offending piece (by index from
  // 1, and `source` for the message) when one is broken.
  explicit Profile(std::vector<ProfileSegment> segments, const std::string& source = "profile");

  const std::vector<ProfileSegment>& segments() const { return segments_; }
  double height() const { return segments_.back().end.y(); }
  double top_radius() const { return segments_.back().end.x(); }
  double max_radius() const;
  double length() const;  // total arc length of the outline (tip to top edge)

  // Largest ρ of the solid at height z ∈ [0, height]; 0 outside.
  double radius_at(double z) const;
  // The heights where the solid is at least r wide: one interval for a convex profile (the
  // radius is then concave in z), the hull of them otherwise; empty if none. Up to a radius
  // where no piece's answer has begun to change (a flat end's radius, say), the answer is kept.
  Interval heights_reaching(double r) const;
  // The lowest of those heights (heights_reaching(r).lo), 0 if there are none. Sweeps ask it
  // for every ray they cull; a profile that starts with a quarter ball answers it for r up to
  // the ball's radius in closed form, with the same numbers.
  double lowest_reaching(double r) const;
  // Closed membership of a point (ρ, z) in the revolved solid.
  bool contains(double rho, double z) const;
  // The signed distance from (ρ, z) to the solid's surface (the outline or the top disc),
  // negative inside, mm.
  double signed_distance(double rho, double z) const;

  // The piece and fraction nearest to q, and the distance.
  struct Location {
    int segment = 0;
    double u = 0.0;
    double distance = 0.0;
  };
  Location closest(const Vec2& q) const;

 private:
  std::vector<ProfileSegment> segments_;
  // The open height range of the flutes' cylinder, if the profile has one, and its radius
  // (radius_at's answer there without a walk over the pieces; lo ≥ hi when there is none).
  double cylinder_lo_ = 0.0, cylinder_hi_ = 0.0, cylinder_radius_ = 0.0;
  // The radius R of a first piece that is the quarter circle about (0, R) from the tip to
  // (R, R) (a ball end's), 0 otherwise.
  double foot_ball_radius_ = 0.0;
  // heights_reaching(r) for every r ≤ reach_all_ (−∞ where a piece's answer changes everywhere).
  double reach_all_ = -std::numeric_limits<double>::infinity();
  Interval reach_all_heights_;
};

}  // namespace cwe

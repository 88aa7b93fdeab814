#pragma once
// Exact ray chords through the volume a convex cutter sweeps along a linear move with a constant
// axis (3-axis and 3+2 moves): the removal primitive of the tri-dexel workpiece.
//
// The swept volume SV = T ⊕ [0, 1]·D of a convex tool T translated by D is convex, so a line
// meets it in one interval. Its boundary is covered by the tool at the start, the tool at the end
// and the tool's shadow boundary swept along D (Aras 2008 ch. 4): on each smooth patch the
// grazing curve (N·D = 0: sin φ = -n_z D_z / (n_ρ D_x) in the move's TCS), and at each profile
// vertex (a joint, the tip or the top edge, where the normal jumps) the vertex circle. Every point
// of these surfaces is a point of the tool at some instant, so it lies in SV; the chord is
// therefore exactly the hull of the ray's crossings with them:
//  - the tool at both ends: per profile piece, the frustum, ball or torus-with-core solid;
//  - swept vertex circles: with n = d × D, n·(C(φ) - o) = 0 is a sin φ + b cos φ + c = 0;
//  - swept grazing curves of lines: the generator is straight, so the crossing is linear;
//  - swept grazing curves of arcs (sphere, torus: Aras 2008 eq. 4.54): the crossing function of
//    the arc angle is sampled at points fixed per move and each sign change refined by Brent's
//    method.
// Rays along D (n = 0) need only the two tool chords. Crossings are taken only where the sweep
// parameter λ ∈ [0, 1].
//
// Closed forms for the common 3-axis case (tool axis +Z, also exact): every horizontal section
// of a tool of revolution about a vertical axis is a disc of radius R(h), the profile's radius at
// height h above the tip. So
//  - a level move (D horizontal) sweeps, at each height, the 2-D capsule of radius R(h) about the
//    tip's path: a horizontal ray's chord is the ray ∩ capsule; a vertical ray at distance r from
//    the path meets the heights where R(h) ≥ r (an interval, R being concave);
//  - an axial move (D along the axis: plunge, retract) sweeps, at height z, the disc of the
//    largest R over the heights the tool passes there; a vertical ray meets the heights where
//    R(h) ≥ r, widened by the move.
// `generic_chord` always takes the general route; tests hold the closed forms to it.

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "cwe/geometry/aabb.hpp"
#include "cwe/geometry/interval.hpp"
#include "cwe/geometry/ray.hpp"
#include "cwe/tool/cutter.hpp"

namespace cwe {

class LinearSweep {
 public:
  // The sweep of `cutter` with unit `axis` from tip `start` to tip `end`. The cutter must be
  // convex (every APT cutter is): InputError otherwise.
  // The sweep keeps a reference to the cutter, which must outlive it.
  LinearSweep(const Cutter& cutter, const Vec3& start, const Vec3& end, const Vec3& axis);
  LinearSweep(Cutter&&, const Vec3&, const Vec3&, const Vec3&) = delete;

  // The interval of ray parameters inside the swept volume (empty if the ray misses it).
  Interval chord(const Ray& ray) const;
  // The chords of rays that differ only in their origin's coordinate along world axis `across`:
  // chords[k] = chord(ray with origin[across] = at[k]), the same numbers, with what the rays share
  // (the case, and for a row of horizontal rays at one height the tool's radius) found once.
  void chords(Ray ray, int across, std::span<const double> at, std::span<Interval> chords) const;
  // What chords() of such a row depends on besides `at`, where that is one number: for a row of
  // level rays along world X or Y at one height, the tool's radius there (-1 where the tool does
  // not reach that height). Rows of one key have the same chords at the same `at`. NaN for any
  // other row.
  double row_key(const Ray& ray, int across) const;
  // The extent along `across` of the rays of such a row whose chords may not be empty: for
  // vertical rays and a tool standing along +Z, the capsule of the tool's largest radius (with
  // more than the allowance chord() gives it) about the tip's path in plan; the whole line for
  // any other row.
  Interval row_span(const Ray& ray, int across) const;
  // The same chord by the general construction only (no closed-form shortcut).
  Interval generic_chord(const Ray& ray) const;

  // A ball end standing along +Z (a ball under a cylinder at least as tall): on a ray along X
  // or Y at least kBallClearance·R above both of the ball's centres, at a height the cylinder
  // spans over the whole move, the ball's capsule lies well inside the cylinder's section, and
  // chord() takes the section's chord alone (see ball_chord): the same bits.
  static constexpr double kBallClearance = 0.05;

  // A box containing the swept volume.
  const Aabb& bounds() const { return bounds_; }
  // What the sweep was made of.
  const Cutter& cutter() const { return *cutter_; }
  const Vec3& start() const { return start_; }
  const Vec3& end() const { return end_; }
  Vec3 axis() const { return tcs_.z(); }

  // An interval of ray parameters holding the chord, far cheaper than chord() where has_reach():
  // for a tool standing along +Z on a climbing or descending move, a vertical ray's chord starts
  // no lower than the tip path's lowest point plus the height where the tool is as wide as the
  // ray's plan distance from that path. Elsewhere the whole line.
  bool has_reach() const { return mode_ == Mode::kGeneric && vertical_axis_; }
  Interval reach(const Ray& ray) const;

 private:
  enum class Mode { kGeneric, kLevel, kAxial };
  static constexpr int kArcSamples = 24;

  // Rays of direction d along world X or Y on a level move, which chords() finds in closed form
  // (`along`: 0 for X, 1 for Y); and the tool's radius at height z above its tip there, where
  // the tool reaches that height.
  bool level_axis_rays(const Vec3& d, int& along) const;
  bool level_radius(double z, double& r) const;

  // A swept grazing generator of a line piece: the segment a–b of the tool at the start (TCS).
  struct Generator {
    Vec3 a, b;
  };
  // The grazing curve of an arc piece on one branch, sampled at fixed arc fractions.
  struct GrazingSamples {
    int segment = 0;
    int branch = 0;
    std::array<Vec3, kArcSamples + 1> point;
    std::array<bool, kArcSamples + 1> exists{};
    // Per sample interval k (from sample k - 1 to k): no point of the curve exists inside it.
    std::array<bool, kArcSamples + 1> none_between{};
  };

  Vec3 grazing_point(int segment, int branch, double u, bool& exists) const;
  Interval level_chord(const Ray& ray) const;
  // Level mode: a ray along world axis `along` (0 or 1; `sign` its direction's component) at a
  // height where the tool's radius is r.
  Interval level_axis_chord(const Vec3& o, int along, double sign, double r) const;
  // Level mode: a vertical ray through plan point q and height oz, its direction's z component
  // dz.
  Interval level_vertical_chord(const Vec2& q, double oz, double dz) const;
  Interval axial_chord(const Ray& ray) const;
  // A ball end standing along +Z, moved in any direction, on a ray o + t·d along X, Y or Z (see
  // ball_radius_). With A ≥ 0 the ray runs along +X, +Y or +Z (A its axis, d that unit vector),
  // and its components known here spare what multiplies by 1 or divides by d's length 1: the
  // same numbers as with A = -1 (any such d). `level`, if given, keeps the section of the swept
  // cylinder last made, for the next horizontal ray whose height gives the same one (rays at one
  // height; rays at heights the cylinder spans over the whole move).
  struct BallLevel;
  template <int A>
  Interval ball_chord(const Vec3& o, const Vec3& d, BallLevel* level = nullptr) const;
  template <int A>
  void ball_chords(Ray ray, int across, std::span<const double> at,
                   std::span<Interval> chords) const;
  // Whether chord() returns the empty interval for the ray before its construction: rays a
  // tool standing along +Z cannot reach, by plan distance (vertical rays) or height (rays
  // along X or Y). `vertical` and `horizontal` classify the ray as chord() does. `last`, if
  // given, keeps the lowest height reached at the last plan offset asked, for the next ray at
  // the same offset (a row of rays along Y up the height).
  struct Floor {
    bool made = false;
    std::uint64_t gap = 0;  // the offset's bits
    double z = 0.0;
  };
  bool out_of_reach(const Ray& ray, bool vertical, bool horizontal, Floor* last = nullptr) const;
  // Squared plan distance from a point to the tip's path (vertical tools).
  double plan_gap2(const Vec3& p) const;
  // Level mode: the extent along world axis `along` (0 or 1) of the capsule of radius r about
  // the tip's path, on the horizontal line through o parallel to that axis.
  Interval capsule_span(const Vec3& o, int along, double r) const;

  const Cutter* cutter_;
  Frame tcs_;   // at the start tip: z the axis, x the lateral feed (or a fixed fallback)
  Vec3 delta_;  // D in TCS coordinates
  Aabb bounds_;
  double lateral_ = 0.0;  // |D_xy| in the TCS
  double phase_ = 0.0;    // D_x sin φ + D_y cos φ = lateral·sin(φ + phase)
  std::vector<Vec2> vertices_;
  std::vector<Generator> generators_;
  std::vector<GrazingSamples> arcs_;
  // Arcs centred on the axis (ball ends): their grazing curve is a great circle square to the
  // feed, which sweeps a cylinder; its crossings with a ray come in closed form.
  struct SpherePiece {
    double center_z = 0.0;
    double radius = 0.0;
    double z0 = 0.0, z1 = 0.0;  // the piece's height range
  };
  std::vector<SpherePiece> spheres_;
  // Closed-form modes (tool axis +Z): the tips in world coordinates, the height of the widest
  // section and the tip's path in plan.
  Mode mode_ = Mode::kGeneric;
  bool vertical_axis_ = false;  // the tool stands along +Z (any move direction)
  double plan_radius_ = 0.0;    // the tool's largest radius
  Vec3 start_, end_;
  double widest_height_ = 0.0;
  Vec2 path_start_ = Vec2::Zero(), path_along_ = Vec2::UnitX();
  double path_length_ = 0.0;
  // A ball end (a quarter circle about (0, R), then the cylinder of radius R up to the top h)
  // standing along +Z with h ≥ 2R: the tool is the union of the whole ball and the cylinder,
  // both convex, so the sweep is the union of the ball's capsule about the centre's path and
  // the cylinder swept along D, and a ray's chord is the hull of its chords through the two.
  // 0 for other tools.
  double ball_radius_ = 0.0, ball_top_ = 0.0;
  // What a ball end's chords share on a move: the ball's centre at both ends, the feed D and
  // |D|², and for rays along +X, +Y and +Z their part square to D and its length squared.
  std::array<Vec3, 2> ball_centres_;
  Vec3 ball_feed_ = Vec3::Zero();
  double ball_feed2_ = 0.0;
  std::array<Vec3, 3> ball_square_;
  std::array<double, 3> ball_square2_{};
};

}  // namespace cwe
